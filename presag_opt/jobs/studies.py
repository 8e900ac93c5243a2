"""The study jobs: ``sensitivity``, ``tolerance`` (Monte Carlo of installation errors), ``validity``
(a study store in, β* out) and ``simulate`` (one pantograph run), in the designer's units."""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from pathlib import Path
from typing import TYPE_CHECKING

from presag_opt.design.band import CASE_STUDY_BAND, OperatingBand
from presag_opt.jobs.band import check_band_speed
from presag_opt.jobs.options import ELEMENT_LENGTH, MONTE_CARLO_SAMPLES, ROBUST_MODEL, WITHIN_PERCENT, WORKERS
from presag_opt.system.catenary import Catenary
from presag_opt.units import KMH

if TYPE_CHECKING:
    from presag_opt.dynamics.pantograph import Pantograph
    from presag_opt.dynamics.settings import SimulationSettings
    from presag_opt.dynamics.simulate import SimulationResult
    from presag_opt.robust.monte_carlo import MonteCarloResult
    from presag_opt.sensitivity.analysis import SensitivityResult
    from presag_opt.studies.validity_results import ValidityResult

SENSITIVITY_CASE = "case_study_st98"
"""The case of ``sensitivity`` by default: the case study's ST 9,8/9,8 line."""


def sensitivity_study(
    case: str | Path = SENSITIVITY_CASE,
    *,
    quantity: str,
    method: str = "morris",
    inputs: Sequence[str] | None = None,
    ranges: Sequence[str] = (),
    samples: int | None = None,
    seed: int = 0,
    workers: int = WORKERS,
    scheduler: str | None = None,
    out: str | Path | None = None,
    announce: Callable[[str], None] | None = None,
    progress: Callable[[str], None] | None = None,
) -> SensitivityResult:
    """Global sensitivity of one result of a case to its assumed inputs: the job of ``presag sensitivity``.

    Parameters
    ----------
    case : str or Path
        Case file or built-in case name.
    quantity : str
        The result analysed: ``recommendation``, ``robust``, ``dynamic-robust``, ``dynamic:V1,V2``,
        ``minima:V`` or ``validity:V1,V2,...`` (speeds in km/h).
    method : {"morris", "sobol", "spread"}
        Morris screening, Sobol indices, or the result's mean and spread only.
    inputs : sequence of str, optional
        Dotted input names (default: every assumed input the result depends on).
    ranges : sequence of str
        ``NAME=LOW:HIGH`` in the model file's unit (adds the input).
    samples : int, optional
        Morris trajectories (default 10) or Sobol base sample, a power of two (default 64). [-]
    seed : int
        Seed of the design and of the bootstrap. [-]
    workers : int
        Local worker processes (not with ``scheduler``). [-]
    scheduler : str, optional
        A Dask scheduler address to run the evaluations on.
    out : str or Path, optional
        Folder of the resumable stores (a killed analysis computes only what it did not keep).
    announce : callable, optional
        Told what the analysis will cost before it starts.
    progress : callable, optional
        Called with a short message as the work goes on.

    Returns
    -------
    SensitivityResult
        The ranking of the inputs (``result.indices``); shows itself in a notebook.

    Examples
    --------
    >>> from presag_opt import sensitivity
    >>> result = sensitivity(quantity="recommendation", samples=4)  # doctest: +SKIP
    """
    from presag_opt.sensitivity import sensitivity_analysis

    return sensitivity_analysis(case, output=quantity, method=method, inputs=inputs, ranges=ranges, samples=samples,
                                seed=seed, workers=workers, scheduler=scheduler, out=out, announce=announce,
                                progress=progress)


def tolerance(
    model: str | Path | Catenary = ROBUST_MODEL,
    band: OperatingBand = CASE_STUDY_BAND,
    *,
    dropper_error_mm: float,
    height_error_mm: float = 0.0,
    distribution: str = "normal",
    samples: int = MONTE_CARLO_SAMPLES,
    seed: int = 0,
    presag_mm: float | None = None,
    within_percent: float = WITHIN_PERCENT,
    element_length: float = ELEMENT_LENGTH,
    allow_supercritical: bool = False,
    progress: Callable[[str], None] | None = None,
) -> MonteCarloResult:
    """The installation tolerance as a line crew makes it: the quasi-static Monte Carlo of ``presag
    tolerance --monte-carlo``.

    Independent errors of each dropper's length and of each mast's contact-wire and messenger-wire
    support heights are drawn ``samples`` times; the result is the distribution of the design's
    worst-case waviness over the band's F_m.

    Parameters
    ----------
    model : str, Path or Catenary
        The catenary. Default: the case study's ideal section.
    band : OperatingBand
        Static forces, speeds and α_ae. Default: the case study's.
    dropper_error_mm : float
        Size of each dropper's length error: σ (normal) or t of ±t (uniform). [mm]
    height_error_mm : float
        Size of each mast's contact-wire and messenger-support height errors. [mm]
    distribution : {"normal", "uniform"}
        Distribution of the errors.
    samples : int
        Realisations. [-]
    seed : int
        Seed of the draws. [-]
    presag_mm : float, optional
        The design's pre-sag on the reference span (default: the robust parabola of the band). [mm]
    within_percent : float
        Allowed loss of the robust study's tolerance interval. [%]
    element_length : float
        Longest element of the static model. [m]
    allow_supercritical : bool
        Accept a top speed at or above β = 0.7 of the wave speed.
    progress : callable, optional
        Called with a short message as the work goes on.

    Returns
    -------
    MonteCarloResult
        The worst-case waviness of every realisation and its percentiles with confidence intervals.

    Examples
    --------
    >>> from presag_opt import tolerance
    >>> result = tolerance(dropper_error_mm=2.0, samples=2000)
    >>> print(f"P95 of the worst-case waviness: {result.percentiles[95].value * 1e3:.0f} mm")
    P95 of the worst-case waviness: ... mm
    """
    from presag_opt.robust.installation import InstallationErrors
    from presag_opt.robust.monte_carlo import QuasiStaticMonteCarlo
    from presag_opt.robust.study import robust_study
    from presag_opt.static.discretisation import StaticSettings
    from presag_opt.system.loader import load_catenary

    catenary = model if isinstance(model, Catenary) else load_catenary(model)
    check_band_speed(band, [catenary], allow_supercritical)
    errors = InstallationErrors(dropper_length=dropper_error_mm * 1e-3, contact_wire_height=height_error_mm * 1e-3,
                                messenger_height=height_error_mm * 1e-3, distribution=distribution)
    study = robust_study(catenary, band.mean_force_band(), within=within_percent / 100.0, progress=progress,
                         settings=StaticSettings(element_length=element_length))
    presag_rel = study.robust_parabola.presag_rel if presag_mm is None else presag_mm * 1e-3 / study.reference_span
    if progress:
        progress(f"{samples} realisations of the installation errors")
    mc = QuasiStaticMonteCarlo(study.path, study.path.parabola_depths(presag_rel), study.scenarios)
    return mc.run(errors, samples=samples, seed=seed)


def validity(store: str | Path, *, select: Mapping[str, float] | None = None,
             pantograph: str | None = None) -> ValidityResult:
    """The validity limit β* of the quasi-static pre-sag rule from a study store: the job of ``presag
    validity``.

    Parameters
    ----------
    store : str or Path
        A netCDF store written by ``presag sweep``.
    select : mapping of str to float, optional
        Value of each swept extra parameter of the study. [SI]
    pantograph : {"leading", "trailing"}, optional
        The pantograph of a two-pantograph study (default: the trailing one).

    Returns
    -------
    ValidityResult
        β*, the fit S_dyn = S_stat + k·β^a, the optimal pre-sag per speed ratio and the uplift.

    Examples
    --------
    >>> from presag_opt import validity
    >>> result = validity("paper_grid_st98.nc")  # doctest: +SKIP
    >>> result.beta_limit  # doctest: +SKIP
    """
    from presag_opt.studies.store import open_store
    from presag_opt.studies.validity_analysis import pantograph_view, validity_analysis

    dataset, view = pantograph_view(open_store(store), pantograph)
    return validity_analysis(dataset, dict(select or {}), view)


def simulate(
    model: str | Path | Catenary,
    pantograph: str | Path | Pantograph,
    *,
    speed_kmh: float,
    static_force: float,
    aero_coefficient_kmh: float = 0.0,
    settings: SimulationSettings | None = None,
    allow_supercritical: bool = False,
) -> SimulationResult:
    """One pantograph run under a catenary at constant speed, with the EN 50367 statistics.

    Parameters
    ----------
    model : str, Path or Catenary
        The catenary (built-in name, file or object).
    pantograph : str, Path or Pantograph
        The pantograph (built-in name, file or object).
    speed_kmh : float
        Train speed. [km/h]
    static_force : float
        Static uplift force. [N]
    aero_coefficient_kmh : float
        Aerodynamic uplift coefficient α_ae: F_m = F_stat + α_ae v². [N/(km/h)²]
    settings : SimulationSettings, optional
        Numerics and analysis window (default: those of :class:`~presag_opt.dynamics.settings.SimulationSettings`).
    allow_supercritical : bool
        Accept a speed at or above β = 0.7 of the wave speed.

    Returns
    -------
    SimulationResult
        Time histories and statistics over the analysed spans (``result.statistics``).

    Examples
    --------
    Five 60 m spans of the case study's system at 90 km/h, with coarse fixed numerics for a quick look
    (the default, automatic numerics resolve the speed; the run warns that these do not):

    >>> from presag_opt import load_catenary, simulate
    >>> from presag_opt.dynamics.settings import SimulationSettings
    >>> from presag_opt.system.catenary import SpanLayout
    >>> five = load_catenary("st_9.8_ideal").with_layout(SpanLayout(span_lengths=(60.0,) * 5))
    >>> quick = SimulationSettings(analysed_spans=1, lead_in_spans=1).with_fixed_numerics(element_length=1.0,
    ...                                                                                 time_step=4e-3)
    >>> run = simulate(five, "case_study_2mass_friction", speed_kmh=90, static_force=70,
    ...                aero_coefficient_kmh=0.00097, settings=quick)
    >>> print(f"F_m = {run.to_dict()['Fm_N']:.1f} N (F_stat + α_ae v² = 77.9 N)")
    F_m = 77.9 N (F_stat + α_ae v² = 77.9 N)
    """
    from presag_opt.dynamics.pantograph import Pantograph, load_pantograph
    from presag_opt.dynamics.simulate import simulate as run
    from presag_opt.speed import check_speed_limit
    from presag_opt.system.loader import load_catenary

    catenary = model if isinstance(model, Catenary) else load_catenary(model)
    if not allow_supercritical:
        check_speed_limit(speed_kmh * KMH, catenary.contact_wire.wave_speed)
    panto = pantograph if isinstance(pantograph, Pantograph) else load_pantograph(pantograph)
    return run(catenary, panto, speed=speed_kmh * KMH, static_force=static_force,
               aero_coefficient=aero_coefficient_kmh / KMH**2, settings=settings)
