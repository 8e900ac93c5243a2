"""The tolerance job: how exactly a line crew must build the pre-sag, ``presag tolerance``.

Three answers from one robust study of the band's F_m band: the pre-sag interval within a loss of the
robust optimum (no errors given); the distribution of the design's worst case over random
installation errors (``dropper_error_mm``; quasi-static, or simulated with ``dynamic=True``); or the
largest per-dropper error whose P95 stays within the loss (``find_dropper_tolerance=True``).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

from presag_opt.design.band import CASE_STUDY_BAND, OperatingBand
from presag_opt.display import html_summary
from presag_opt.errors import ModelError
from presag_opt.jobs.band import check_band_speed
from presag_opt.jobs.options import (
    DYNAMIC_MONTE_CARLO_SAMPLES,
    ELEMENT_LENGTH,
    MAX_INSTALLATION_ERROR_MM,
    MAX_MONTE_CARLO_SAMPLES,
    MONTE_CARLO_SAMPLES,
    ROBUST_MODEL,
    WITHIN_PERCENT,
    WORKERS,
)
from presag_opt.system.catenary import Catenary
from presag_opt.units import KMH

if TYPE_CHECKING:
    from presag_opt.dynamics.pantograph import Pantograph
    from presag_opt.robust.dynamic_monte_carlo import DynamicMonteCarloResult
    from presag_opt.robust.monte_carlo import DropperTolerance, MonteCarloResult
    from presag_opt.robust.operating_grid import OperatingGrid
    from presag_opt.robust.study import RobustStudy

@dataclass(frozen=True, kw_only=True)
class ToleranceAnswer:
    """The installation tolerance of a band's robust design.

    Attributes
    ----------
    study : RobustStudy
        The quasi-static robust study: its ``tolerance`` is the pre-sag interval within the loss.
    presag_rel : float
        The design's pre-sag S_rel examined (the robust parabola's, or the one given). [-]
    monte_carlo : MonteCarloResult, DynamicMonteCarloResult or None
        The worst case over realisations of the installation errors (None: the interval only).
    dropper_tolerance : DropperTolerance or None
        The largest per-dropper error within the loss (``find_dropper_tolerance``).
    grid : OperatingGrid or None
        The simulated static forces × speeds (dynamic Monte Carlo).
    pantograph : str
        The pantograph simulated (dynamic Monte Carlo; "" otherwise).
    """

    study: RobustStudy
    presag_rel: float
    monte_carlo: MonteCarloResult | DynamicMonteCarloResult | None = None
    dropper_tolerance: DropperTolerance | None = None
    grid: OperatingGrid | None = None
    pantograph: str = ""

    @property
    def presag_mm(self) -> float:
        """The design's mid-span pre-sag on the reference span. [mm]"""
        return self.presag_rel * self.study.reference_span * 1e3

    @property
    def dynamic(self) -> bool:
        """Whether the Monte Carlo simulated every realisation."""
        return self.grid is not None

    def to_dict(self) -> dict:
        """JSON-ready summary in mm and N (the command line's ``--json``; without a Monte Carlo, the robust
        study's interval)."""
        study, span = self.study, self.study.reference_span
        if self.monte_carlo is None:
            data = study.to_dict()
            return {k: data[k] for k in ("catenary", "fm_band_N", "reference_span_m", "presag_mm",
                                         "worst_case_waviness_mm", "tolerance_mm", "tolerance_within",
                                         "centre_optimum_presag_mm", "centre_optimum_tolerance_mm",
                                         "nominal_presag_mm", "nominal_worst_case_waviness_mm")}
        data = self._dynamic_dict() if self.dynamic else self._quasi_static_dict()
        errors = self.monte_carlo.errors
        data.update(catenary=study.catenary_name, reference_span_m=span, presag_mm=self.presag_mm,
                    samples=self.samples_drawn, seed=self.monte_carlo.seed, distribution=errors.distribution,
                    height_error_mm=errors.contact_wire_height * 1e3,
                    s_interval_mm=[study.tolerance.low * span * 1e3, study.tolerance.high * span * 1e3],
                    s_interval_within=study.tolerance.within)
        return data

    @property
    def samples_drawn(self) -> int:
        """Realisations drawn (finished or not). [-]"""
        mc = self.monte_carlo
        return 0 if mc is None else mc.samples + len(getattr(mc, "failures", ()))

    def _quasi_static_dict(self) -> dict:
        mc, study = self.monte_carlo, self.study
        data = {"kind": "quasi-static", "measure": "worst-case waviness R over the F_m band", "unit": "mm",
                "fm_band_N": [float(study.scenarios.forces.min()), float(study.scenarios.forces.max())],
                "dropper_error_mm": mc.errors.dropper_length * 1e3,
                "nominal_worst_case": mc.nominal_worst_case * 1e3,
                **{f"p{k}": p.to_dict(1e3) for k, p in mc.percentiles.items()},
                "confidence": mc.confidence}
        found = self.dropper_tolerance
        if found is not None:
            data.update(largest_dropper_error_mm=found.tolerance * 1e3, within=found.within,
                        held_percentile=found.level, resolution_mm=found.resolution * 1e3)
        return data

    def _dynamic_dict(self) -> dict:
        mc, grid = self.monte_carlo, self.grid
        sig = mc.percentiles["worst_sigma_over_fm"]
        return {"kind": "dynamic", "measure": "worst σ/F_m over the grid", "unit": "-",
                "grid": {"static_forces_N": list(grid.static_forces), "speeds_kmh": [v / KMH for v in grid.speeds]},
                "pantograph": self.pantograph, "dropper_error_mm": mc.errors.dropper_length * 1e3,
                "nominal_worst_case": mc.nominal.worst_sigma_over_fm,
                **{f"p{k}": p.to_dict() for k, p in sig.items()},
                "smallest_statistical_min_N": {"nominal": mc.nominal.smallest_statistical_min,
                                               **{f"p{k}": p.to_dict() for k, p in
                                                  mc.percentiles["smallest_statistical_min"].items()}},
                "largest_uplift_mm": {"nominal": mc.nominal.largest_uplift * 1e3,
                                      **{f"p{k}": p.to_dict(1e3) for k, p in mc.percentiles["largest_uplift"].items()}},
                "slack_droppers_at_rest": {"realisations": sum(r.slack_at_rest > 0 for r in mc.realisations),
                                           "most": max((r.slack_at_rest for r in mc.realisations), default=0)},
                "confidence": 0.95, "wall_time_s": mc.wall_time, "workers": mc.workers,
                "samples_used": mc.samples, "failed": len(mc.failures),
                "failures": [{"realisation": e.index, "reason": e.failure} for e in mc.failures],
                "store": mc.store}

    def worst_cases(self):
        """The worst case of every realisation: waviness [mm] or σ/F_m [-] (dynamic)."""
        if self.monte_carlo is None:
            raise ModelError("this answer has no Monte Carlo; give dropper_error_mm (or find_dropper_tolerance=True)")
        if self.dynamic:
            return self.monte_carlo.values("worst_sigma_over_fm")
        return self.monte_carlo.worst_case * 1e3

    def failure_summary(self) -> str:
        """One line on the realisations that failed ("" if none, and always for the quasi-static Monte Carlo)."""
        return self.monte_carlo.failure_summary() if self.dynamic else ""

    def table(self) -> list[dict]:
        """The error-free worst case and the percentiles with their 95 % intervals as rows (without a Monte
        Carlo: the robust study's designs)."""
        if self.monte_carlo is None:
            return self.study.table()
        data = self.to_dict()
        unit = "" if data["unit"] == "-" else f" [{data['unit']}]"
        rows = [{"": "error-free", f"value{unit}": data["nominal_worst_case"], "CI low": None, "CI high": None}]
        return rows + [{"": f"P{k}", f"value{unit}": data[f"p{k}"]["value"], "CI low": data[f"p{k}"]["ci"][0],
                        "CI high": data[f"p{k}"]["ci"][1]} for k in (50, 90, 95, 99)]

    def to_frame(self):
        """:meth:`table` as a pandas DataFrame."""
        from presag_opt.display import data_frame

        return data_frame(self.table())

    def _repr_html_(self) -> str:
        data, span = self.to_dict(), self.study.reference_span
        low, high = self.study.tolerance.low * span * 1e3, self.study.tolerance.high * span * 1e3
        interval = (f"pre-sag interval within {self.study.tolerance.within * 100:g} % of the robust optimum: "
                    f"{low:.1f}–{high:.1f} mm")
        if self.monte_carlo is None:
            return html_summary(f"Installation tolerance of S = {self.presag_mm:.1f} mm on {span:g} m",
                                [f"{self.study.catenary_name}; {interval}"], self.table())
        lines = [f"{data['kind']} Monte Carlo, {data['measure']}; errors per dropper {data['dropper_error_mm']:.2f} mm, "
                 f"per mast height {data['height_error_mm']:.2f} mm ({data['distribution']}), seed {data['seed']}",
                 interval]
        if self.dropper_tolerance is not None:
            lines.insert(0, f"largest dropper error with P{data['held_percentile']} within {data['within'] * 100:g} %: "
                            f"{data['largest_dropper_error_mm']:.2f} mm")
        return html_summary(f"Installation errors by Monte Carlo: S = {self.presag_mm:.1f} mm on {span:g} m, "
                            f"{data['samples']} realisations", lines, self.table())


def _check_size(name: str, value: float | None, low: float, high: float, unit: str) -> None:
    if value is not None and not (math.isfinite(value) and low <= value <= high):
        raise ModelError(f"{name} = {value:g} {unit} is outside the valid range [{low:g}, {high:g}] {unit}".replace("  ", " "))


def tolerance(
    model: str | Path | Catenary = ROBUST_MODEL,
    band: OperatingBand = CASE_STUDY_BAND,
    *,
    dropper_error_mm: float | None = None,
    height_error_mm: float = 0.0,
    distribution: str = "normal",
    samples: int | None = None,
    seed: int = 0,
    presag_mm: float | None = None,
    within_percent: float = WITHIN_PERCENT,
    find_dropper_tolerance: bool = False,
    dynamic: bool = False,
    pantograph: str | Path | Pantograph | None = None,
    grid_points: tuple[int, int] = (4, 3),
    workers: int = WORKERS,
    store: str | Path | None = None,
    element_length: float = ELEMENT_LENGTH,
    allow_supercritical: bool = False,
    announce: Callable[[str], None] | None = None,
    progress: Callable[[str], None] | None = None,
) -> ToleranceAnswer:
    """The installation tolerance as a line crew makes it: the job of ``presag tolerance`` (with and without
    ``--monte-carlo``).

    The robust study of the band's F_m band gives the pre-sag interval within ``within_percent`` of its
    worst-case optimum. With ``dropper_error_mm``, independent errors of each dropper's length and of each
    mast's contact-wire and messenger-wire support heights are drawn ``samples`` times, and the answer
    carries the distribution of the design's worst case: the waviness over the band's F_m
    (quasi-static, about a second), or with ``dynamic=True`` σ/F_m, F_m − 3σ and the steady-arm uplift
    over the band's static forces × speeds simulated for every realisation (tens of minutes).

    Parameters
    ----------
    model : str, Path or Catenary
        The catenary. Default: the case study's ideal section.
    band : OperatingBand
        Static forces, speeds and α_ae. Default: the case study's.
    dropper_error_mm : float, optional
        Size of each dropper's length error: σ (normal) or t of ±t (uniform), in [0, 100]. [mm]
    height_error_mm : float
        Size of each mast's contact-wire and messenger-support height errors, in [0, 100]. [mm]
    distribution : {"normal", "uniform"}
        Distribution of the errors.
    samples : int, optional
        Realisations (default 10 000 quasi-static, 100 dynamic). [-]
    seed : int
        Seed of the draws. [-]
    presag_mm : float, optional
        The design's pre-sag on the reference span (default: the robust parabola of the band). [mm]
    within_percent : float
        Allowed loss of the tolerance interval and of the held P95 (``find_dropper_tolerance``). [%]
    find_dropper_tolerance : bool
        Search the largest dropper error whose P95 of the worst-case waviness stays within the loss of
        the error-free design (quasi-static; no ``dropper_error_mm``).
    dynamic : bool
        Simulate every realisation over the band's grid (from 50 km/h, the paper's lowest grid speed).
    pantograph : str, Path or Pantograph, optional
        Pantograph of the dynamic Monte Carlo (default: the case study's two-mass pantograph with friction).
    grid_points : (int, int)
        Simulated static forces and speeds across the band (dynamic). [-]
    workers : int
        Processes that simulate realisations side by side (dynamic). [-]
    store : str or Path, optional
        Folder keeping every finished realisation of the dynamic Monte Carlo (default: one in the cache): a
        killed run, started again with the same inputs, simulates only the rest.
    element_length : float
        Longest element of the static model. [m]
    allow_supercritical : bool
        Accept a top speed at or above β = 0.7 of the wave speed.
    announce : callable, optional
        Told what the dynamic Monte Carlo will cost before it starts, when that is long.
    progress : callable, optional
        Called with a short message as the work goes on.

    Returns
    -------
    ToleranceAnswer
        The robust study and its interval, and the Monte Carlo when errors were given; shows itself in a
        notebook.

    Examples
    --------
    >>> from presag_opt import tolerance
    >>> answer = tolerance(dropper_error_mm=2.0, samples=2000)
    >>> p95 = answer.monte_carlo.percentiles[95].value
    >>> print(f"P95 of the worst-case waviness: {p95 * 1e3:.0f} mm")
    P95 of the worst-case waviness: ... mm
    """
    from presag_opt.robust.installation import InstallationErrors
    from presag_opt.robust.study import robust_study
    from presag_opt.static.discretisation import StaticSettings
    from presag_opt.system.loader import load_catenary

    if find_dropper_tolerance and dynamic:
        raise ModelError("find_dropper_tolerance is quasi-static; drop dynamic")
    if find_dropper_tolerance and dropper_error_mm is not None:
        raise ModelError("find_dropper_tolerance searches the dropper error; drop dropper_error_mm")
    if dropper_error_mm is None and not find_dropper_tolerance and (dynamic or samples is not None):
        raise ModelError("the Monte Carlo needs dropper_error_mm (or find_dropper_tolerance=True)")
    _check_size("dropper_error_mm", dropper_error_mm, 0.0, MAX_INSTALLATION_ERROR_MM, "mm")
    _check_size("height_error_mm", height_error_mm, 0.0, MAX_INSTALLATION_ERROR_MM, "mm")
    _check_size("samples", samples, 1, MAX_MONTE_CARLO_SAMPLES, "")
    if samples is not None and samples != int(samples):
        raise ModelError(f"samples = {samples!r} is not a whole number; valid range [1, {MAX_MONTE_CARLO_SAMPLES}]")
    _check_size("presag_mm", presag_mm, 0.0, 1000.0, "mm")
    catenary = model if isinstance(model, Catenary) else load_catenary(model)
    check_band_speed(band, [catenary], allow_supercritical)
    study = robust_study(catenary, band.mean_force_band(), within=within_percent / 100.0, progress=progress,
                         settings=StaticSettings(element_length=element_length))
    presag_rel = study.robust_parabola.presag_rel if presag_mm is None else presag_mm * 1e-3 / study.reference_span
    if dropper_error_mm is None and not find_dropper_tolerance:
        return ToleranceAnswer(study=study, presag_rel=presag_rel)
    errors = InstallationErrors(dropper_length=(dropper_error_mm or 0.0) * 1e-3,
                                contact_wire_height=height_error_mm * 1e-3, messenger_height=height_error_mm * 1e-3,
                                distribution=distribution)
    if dynamic:
        return _dynamic(catenary, band, study, presag_rel, errors, pantograph=pantograph, grid_points=grid_points,
                        samples=DYNAMIC_MONTE_CARLO_SAMPLES if samples is None else samples, seed=seed,
                        workers=workers, store=store, announce=announce, progress=progress)
    from presag_opt.robust.monte_carlo import QuasiStaticMonteCarlo, largest_dropper_tolerance

    samples = MONTE_CARLO_SAMPLES if samples is None else samples
    if progress:
        progress("linearised installation response of the section")
    mc = QuasiStaticMonteCarlo(study.path, study.path.parabola_depths(presag_rel), study.scenarios)
    if find_dropper_tolerance:
        if progress:
            progress(f"bisection of the dropper error on {samples} realisations")
        found = largest_dropper_tolerance(mc, errors, within=within_percent / 100.0, samples=samples, seed=seed)
        return ToleranceAnswer(study=study, presag_rel=presag_rel, monte_carlo=found.at_tolerance,
                               dropper_tolerance=found)
    if progress:
        progress(f"{samples} realisations of the installation errors")
    return ToleranceAnswer(study=study, presag_rel=presag_rel, monte_carlo=mc.run(errors, samples=samples, seed=seed))


def _dynamic(catenary: Catenary, band: OperatingBand, study: RobustStudy, presag_rel: float, errors, *,
             pantograph, grid_points: tuple[int, int], samples: int, seed: int, workers: int, store,
             announce, progress) -> ToleranceAnswer:
    """The dynamic Monte Carlo of the design: its cost announced, then every realisation simulated."""
    from presag_opt.dynamics.cost import work_notice
    from presag_opt.dynamics.pantograph import Pantograph, load_pantograph
    from presag_opt.dynamics.settings import SimulationSettings
    from presag_opt.pipeline.band import CASE_STUDY_PANTOGRAPH
    from presag_opt.robust import OperatingGrid
    from presag_opt.robust.dynamic_monte_carlo import dynamic_monte_carlo
    from presag_opt.robust.dynamic_study import simulated_band
    from presag_opt.robust.operating_grid import band_work

    simulated = simulated_band(band)
    grid = OperatingGrid.from_band(simulated, static_points=int(grid_points[0]), speed_points=int(grid_points[1]))
    chosen = CASE_STUDY_PANTOGRAPH if pantograph is None else pantograph
    panto = chosen if isinstance(chosen, Pantograph) else load_pantograph(chosen)
    settings = SimulationSettings(numerics="auto")
    if announce:
        cost = band_work(catenary, panto, grid, evaluations=samples + 1, workers=workers, settings=settings)
        text = work_notice(cost)
        if text:
            announce(text)
    result = dynamic_monte_carlo(catenary, panto, grid, presag_rel, errors, samples=samples, seed=seed,
                                 workers=workers, chunk=max(1, min(4, -(-samples // workers))), settings=settings,
                                 progress=progress, store=None if store is None else Path(store))
    return ToleranceAnswer(study=study, presag_rel=presag_rel, monte_carlo=result, grid=grid,
                           pantograph=panto.name if isinstance(chosen, Pantograph) else str(chosen))
