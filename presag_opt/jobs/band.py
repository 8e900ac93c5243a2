"""The jobs on an operating band: ``recommend``, ``robust_design`` and ``dynamic_robust_design``.

Each is what its command runs (``presag recommend``, ``presag robust``, ``presag
robust --dynamic``), with its parameters and defaults, in the designer's units; each calls
:func:`~presag_opt.pipeline.band.answer_band` once and returns its
:class:`~presag_opt.pipeline.band.BandAnswer`, whose decision is the same whichever job asks.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from pathlib import Path
from typing import TYPE_CHECKING

from presag_opt.design.band import CASE_STUDY_BAND, OperatingBand
from presag_opt.design.recommendation import CASE_STUDY_MODELS
from presag_opt.errors import ModelError
from presag_opt.jobs.options import (
    DROPPER_STEP_MM,
    ELASTICITY_STEP,
    ELEMENT_LENGTH,
    ROBUST_MODEL,
    UPLIFT_LIMIT_MM,
    WITHIN_PERCENT,
    WORKERS,
)
from presag_opt.system.catenary import Catenary

if TYPE_CHECKING:
    from presag_opt.dynamics.pantograph import Pantograph
    from presag_opt.dynamics.settings import SimulationSettings
    from presag_opt.pipeline.band import BandAnswer


def decision_settings(within_percent: float, uplift_limit_mm: float, crew_tolerance_mm: float | None,
                      dropper_error_mm: float | None = None, study: str | Path | None = None) -> dict:
    """The pipeline's keyword arguments of the decision from the designer's units (mm, %).

    Parameters
    ----------
    within_percent : float
        Allowed loss of the tolerance intervals. [%]
    uplift_limit_mm : float
        Steady-arm uplift limit. [mm]
    crew_tolerance_mm : float or None
        The crew's build tolerance of the mid-span pre-sag, ±. [mm]
    dropper_error_mm : float or None
        Instead of the crew tolerance: σ of each dropper's cut length; the crew tolerance is then the P95
        of the mid-span pre-sag error of a Monte Carlo. [mm]
    study : str or Path, optional
        A stored validity study (``presag sweep``).

    Raises
    ------
    ModelError
        Both a crew tolerance and a dropper error.
    """
    from presag_opt.robust.installation import InstallationErrors

    if crew_tolerance_mm is not None and dropper_error_mm is not None:
        raise ModelError("give the crew tolerance or the dropper error to derive it from, not both")
    return {
        "within": within_percent / 100.0,
        "uplift_limit": uplift_limit_mm * 1e-3,
        "crew": None if crew_tolerance_mm is None else crew_tolerance_mm * 1e-3,
        "installation_errors": (None if dropper_error_mm is None
                                else InstallationErrors(dropper_length=dropper_error_mm * 1e-3)),
        "study": study,
    }


def check_band_speed(band: OperatingBand, models: Sequence, allow_supercritical: bool,
                     accept: str = "allow_supercritical=True") -> None:
    """Refuse a band whose top speed is at or above β = 0.7 on any model, before any work.

    Parameters
    ----------
    band : OperatingBand
        The band. [N], [m/s]
    models : sequence of Catenary, str or Path
        The catenaries, or their model names or files.
    allow_supercritical : bool
        Accept such a speed.
    accept : str
        The setting that accepts it, named in the refusal.
    """
    from presag_opt.speed import check_speed_limit
    from presag_opt.system.loader import load_catenary

    if allow_supercritical:
        return
    for model in models:
        catenary = model if isinstance(model, Catenary) else load_catenary(model)
        check_speed_limit(band.speed_high, catenary.contact_wire.wave_speed, accept=accept)


def recommend(
    models: Sequence[str | Path | Catenary] = CASE_STUDY_MODELS,
    band: OperatingBand = CASE_STUDY_BAND,
    *,
    within_percent: float = WITHIN_PERCENT,
    uplift_limit_mm: float = UPLIFT_LIMIT_MM,
    crew_tolerance_mm: float | None = None,
    dropper_error_mm: float | None = None,
    study: str | Path | None = None,
    dynamic_robust: bool = False,
    method: str = "delta-e",
    force_levels: Sequence[float] | None = None,
    step: float = ELASTICITY_STEP,
    elasticity_method: str = "active-set",
    element_length: float = ELEMENT_LENGTH,
    workers: int = WORKERS,
    span_length: float | None = None,
    recompute: bool = False,
    allow_supercritical: bool = False,
    progress: Callable[[str], None] | None = None,
) -> BandAnswer:
    """Which pre-sag to build for an operating band: the job of ``presag recommend``.

    The quasi-static Δe rule over the band on every model, the quasi-static robust design of the first
    with its tolerance, on request a stored validity study, the dynamic robust design and the crew
    tolerance by Monte Carlo; one decision from them all.

    Parameters
    ----------
    models : sequence of str, Path or Catenary
        Catenary models (built-in names, files or catenaries); the first is also the one of the robust
        designs. Default: the case study's ideal and mixed ST 9,8/9,8 sections.
    band : OperatingBand
        Static forces, speeds and α_ae (:meth:`OperatingBand.from_kmh`). Default: the case study's.
    within_percent : float
        Allowed loss of the tolerance intervals. [%]
    uplift_limit_mm : float
        Steady-arm uplift limit. [mm]
    crew_tolerance_mm : float, optional
        The crew's build tolerance of the mid-span pre-sag, ± (default: the assumed 2.5). [mm]
    dropper_error_mm : float, optional
        Instead: σ of each dropper's cut length, the crew tolerance then from a Monte Carlo. [mm]
    study : str or Path, optional
        A stored validity study (``presag sweep``).
    dynamic_robust : bool
        Also run the dynamic robust design of the first model (about half a minute for the case study).
    method : {"delta-e", "mid-mast"}
        Variant of the quasi-static rule.
    force_levels : sequence of float, optional
        Elasticity force levels (default: 50 N steps around the band). [N]
    step : float
        Point spacing of the elasticity curves. [m]
    elasticity_method : {"active-set", "newton"}
        Nonlinear elasticity method.
    element_length : float
        Longest element of the static model. [m]
    workers : int
        Processes of the dynamic robust design. [-]
    span_length : float, optional
        Span the pre-sag is stated on in mm (default: the first model's spans if all equal, else 60). [m]
    recompute : bool
        Also recompute the Δe rule at its own pre-sag geometry.
    allow_supercritical : bool
        Accept a top speed at or above β = 0.7 of a model's wave speed.
    progress : callable, optional
        Called with a short message before each expensive step.

    Returns
    -------
    BandAnswer
        Every method's result and the one decision (``answer.decision``); shows itself in a notebook.

    Examples
    --------
    The case study (form-found states come from the cache of the runtime in force):

    >>> from presag_opt import recommend
    >>> answer = recommend(["st_9.8_ideal"])
    >>> print(answer.decision.headline())
    Pre-sag to build (provisional): 0.93 ‰ = 56 mm on 60 m (quasi-static robust design)
    """
    from presag_opt.pipeline.band import DynamicOptions, StaticNumerics, answer_band

    check_band_speed(band, models, allow_supercritical)
    numerics = StaticNumerics(element_length=element_length, step=step, elasticity_method=elasticity_method,
                              force_levels=None if force_levels is None else tuple(force_levels))
    return answer_band(models, band, method=method, numerics=numerics, recompute=recompute,
                       dynamic=DynamicOptions(workers=workers) if dynamic_robust else None, span_length=span_length,
                       progress=progress,
                       **decision_settings(within_percent, uplift_limit_mm, crew_tolerance_mm, dropper_error_mm, study))


def robust_design(
    model: str | Path | Catenary = ROBUST_MODEL,
    band: OperatingBand = CASE_STUDY_BAND,
    *,
    shape: str = "parabola",
    risk: str = "minimax",
    step_mm: float = DROPPER_STEP_MM,
    asymmetric: bool = False,
    within_percent: float = WITHIN_PERCENT,
    uplift_limit_mm: float = UPLIFT_LIMIT_MM,
    crew_tolerance_mm: float | None = None,
    dropper_error_mm: float | None = None,
    study: str | Path | None = None,
    element_length: float = ELEMENT_LENGTH,
    allow_supercritical: bool = False,
    progress: Callable[[str], None] | None = None,
) -> BandAnswer:
    r"""The pre-sag that minimises the waviness over the band, and the band's decision: the job of
    ``presag robust``.

    Parameters
    ----------
    model : str, Path or Catenary
        The catenary. Default: the case study's ideal section.
    band : OperatingBand
        Static forces, speeds and α_ae (:meth:`OperatingBand.from_kmh`). Default: the case study's.
    shape : {"parabola", "per-dropper"}
        One pre-sag per span, or every dropper height free.
    risk : str
        ``minimax``, ``mean`` or ``cvar:LEVEL`` such as ``cvar:0.9``.
    step_mm : float
        Construction step of per-dropper heights. [mm]
    asymmetric : bool
        Allow per-dropper profiles that are not symmetric.
    within_percent : float
        Allowed loss of the tolerance intervals. [%]
    uplift_limit_mm : float
        Steady-arm uplift limit. [mm]
    crew_tolerance_mm : float, optional
        The crew's build tolerance of the mid-span pre-sag, ± (default: the assumed 2.5). [mm]
    dropper_error_mm : float, optional
        Instead: σ of each dropper's cut length, the crew tolerance then from a Monte Carlo. [mm]
    study : str or Path, optional
        A stored validity study (``presag sweep``).
    element_length : float
        Longest element of the static model. [m]
    allow_supercritical : bool
        Accept a top speed at or above β = 0.7 of the model's wave speed.
    progress : callable, optional
        Called with a short message before each expensive step.

    Returns
    -------
    BandAnswer
        The robust study (``answer.robust``) and the decision.

    Notes
    -----
    The robust pre-sag minimises the risk measure of the waviness R_k of the contact-wire path under each
    mean force F_k of the band, h_k = z(x; S) + F_k e(x; F_k) (the equations and the other risk measures
    in :func:`~presag_opt.robust.lp.robust_presag`):

    .. math::

        \min_{S}\; \max_k R_k(S), \qquad R_k(S) = \max_x h_k(x; S) - \min_x h_k(x; S).

    Examples
    --------
    The case study's ideal section; S on its 60 m spans:

    >>> from presag_opt import robust_design
    >>> study = robust_design().robust
    >>> span = study.reference_span
    >>> print(f"S = {study.robust.presag_rel * span * 1e3:.1f} mm, tolerance {study.tolerance.low * span * 1e3:.1f}–"
    ...       f"{study.tolerance.high * span * 1e3:.1f} mm")
    S = 55.8 mm, tolerance 50.9–58.3 mm
    """
    from presag_opt.pipeline.band import StaticNumerics, answer_band
    from presag_opt.robust import Buildability, Risk

    build = Buildability(step=step_mm * 1e-3, symmetric=not asymmetric) if shape == "per-dropper" else None
    check_band_speed(band, [model], allow_supercritical)
    return answer_band([model], band, shape=shape, risk=Risk.parse(risk), buildability=build,
                       numerics=StaticNumerics(element_length=element_length), progress=progress,
                       **decision_settings(within_percent, uplift_limit_mm, crew_tolerance_mm, dropper_error_mm, study))


def dynamic_robust_design(
    model: str | Path | Catenary = ROBUST_MODEL,
    band: OperatingBand = CASE_STUDY_BAND,
    *,
    pantograph: str | Path | Pantograph | None = None,
    objective: str = "sigma-over-fm",
    risk: str = "minimax",
    grid_points: tuple[int, int] = (4, 3),
    within_percent: float = WITHIN_PERCENT,
    uplift_limit_mm: float = UPLIFT_LIMIT_MM,
    crew_tolerance_mm: float | None = None,
    dropper_error_mm: float | None = None,
    study: str | Path | None = None,
    element_length: float = ELEMENT_LENGTH,
    workers: int = WORKERS,
    settings: SimulationSettings | None = None,
    allow_supercritical: bool = False,
    progress: Callable[[str], None] | None = None,
) -> BandAnswer:
    r"""The parabolic pre-sag chosen by simulation over the band's static forces × speeds, and the band's
    decision made with it: the job of ``presag robust --dynamic`` (about half a minute for the case study on
    two cores).

    Parameters
    ----------
    model : str, Path or Catenary
        The catenary. Default: the case study's ideal section.
    band : OperatingBand
        The band (simulated from 50 km/h, the paper's lowest grid speed).
    pantograph : str, Path or Pantograph, optional
        Pantograph model (default: the case study's two-mass pantograph with friction).
    objective : {"sigma-over-fm", "sigma"}
        Loss at each operating point.
    risk : str
        ``minimax``, ``mean`` or ``cvar:LEVEL``.
    grid_points : (int, int)
        Simulated static forces and speeds across the band. [-]
    workers : int
        Processes that simulate pre-sags side by side. [-]
    settings : SimulationSettings, optional
        Numerics of the runs (default: automatic numerics from the speed; the command line's).
    within_percent : float
        Allowed loss of the tolerance intervals. [%]
    uplift_limit_mm : float
        Steady-arm uplift limit. [mm]
    crew_tolerance_mm : float, optional
        The crew's build tolerance of the mid-span pre-sag, ± (default: the assumed 2.5). [mm]
    dropper_error_mm : float, optional
        Instead: σ of each dropper's cut length, the crew tolerance then from a Monte Carlo. [mm]
    study : str or Path, optional
        A stored validity study (``presag sweep``).
    element_length : float
        Longest element of the static model. [m]
    allow_supercritical : bool
        Accept a top speed at or above β = 0.7 of the model's wave speed.
    progress : callable, optional
        Called with a short message before each expensive step.

    Returns
    -------
    BandAnswer
        The dynamic robust study (``answer.dynamic``) and the decision.

    Notes
    -----
    At each operating point j the loss is the standard deviation of the contact force over its mean,
    and the design minimises its risk over the grid, keeping the steady-arm uplift :math:`u_j` within
    its limit and the statistical minimum positive:

    .. math::

        \min_S\; \max_j \frac{\sigma_j(S)}{F_{m,j}} \quad\text{subject to}\quad u_j(S) \le u_{\lim},\;
        F_{m,j} - 3\sigma_j(S) > 0.

    Examples
    --------
    >>> from presag_opt import dynamic_robust_design
    >>> answer = dynamic_robust_design()  # doctest: +SKIP
    >>> print(answer.decision.headline())  # doctest: +SKIP
    """
    from presag_opt.pipeline.band import DynamicOptions, StaticNumerics, answer_band
    from presag_opt.robust import Risk

    static_points, speed_points = grid_points
    if static_points != int(static_points) or speed_points != int(speed_points):
        raise ModelError(f"grid_points = {grid_points}: give two whole numbers, static forces and speeds, e.g. (4, 3)")
    check_band_speed(band, [model], allow_supercritical)
    options = {} if pantograph is None else {"pantograph": pantograph}
    dynamic = DynamicOptions(objective=objective, risk=Risk.parse(risk), static_points=int(static_points),
                             speed_points=int(speed_points), workers=workers, settings=settings, **options)
    return answer_band([model], band, numerics=StaticNumerics(element_length=element_length), dynamic=dynamic,
                       progress=progress,
                       **decision_settings(within_percent, uplift_limit_mm, crew_tolerance_mm, dropper_error_mm, study))
