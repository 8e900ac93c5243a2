"""The job behind ``presag robust --dynamic``: quasi-static and dynamic designs of a band of static
forces × speeds, compared by simulation, and which one to trust there.

:func:`dynamic_robust_study` checks the band against the catenary, runs the quasi-static study of
its mean-force band (:func:`~presag_opt.robust.study.robust_study`: the Δe rule at the band centre
and the quasi-static robust parabola), starts the dynamic search
(:func:`~presag_opt.robust.dynamic_design.dynamic_robust_presag`) from those two pre-sags — so both
are simulated on the band's grid anyway — and compares the three designs: objective, worst case and
mean of the loss, largest steady-arm uplift and the wall time each method costs. The recommendation
follows from the simulation, not from the speed alone: the quasi-static robust design is enough
where it lies inside the dynamic tolerance interval and keeps the limits; elsewhere the dynamic
design is the one to build. The speed ratio β and the paper's validity limit are reported beside it.
"""

from __future__ import annotations

import dataclasses
import time as wallclock
from dataclasses import dataclass

import numpy as np

from presag_opt.design.band import KMH, OperatingBand
from presag_opt.design.decision import DELTA_E_RULE, DYNAMIC_ROBUST, QUASI_STATIC_ROBUST
from presag_opt.design.evidence import DynamicRobust
from presag_opt.design.speed_range import speed_context
from presag_opt.dynamics.cost import WorkEstimate
from presag_opt.dynamics.pantograph import Pantograph
from presag_opt.dynamics.settings import SimulationSettings
from presag_opt.robust.band_evaluation import BandEvaluator, BandStatistics
from presag_opt.robust.dynamic_design import (
    DynamicObjective,
    DynamicRobustDesign,
    DynamicTolerance,
    SearchSettings,
    band_curve,
    dynamic_robust_presag,
    dynamic_tolerance,
)
from presag_opt.robust.operating_grid import OperatingGrid, band_work
from presag_opt.robust.scenarios import Risk
from presag_opt.robust.study import RobustStudy, robust_study
from presag_opt.robust.tolerance import check_within
from presag_opt.system.catenary import Catenary

DELTA_E, QUASI_STATIC, DYNAMIC = DELTA_E_RULE, QUASI_STATIC_ROBUST, DYNAMIC_ROBUST
"""The three methods compared (by the names of the decision)."""

LOWEST_SIMULATED_SPEED = 50.0 * KMH
"""Lowest speed the dynamic robust design simulates (the paper's lowest grid speed). [m/s]"""

TYPICAL_PRESAGS = 7
"""Pre-sags a dynamic robust design typically simulates (search and tolerance ends; 5 for the case
study, at most the search's 12 plus 2), for the announced cost. [-]"""


def simulated_band(band: OperatingBand) -> OperatingBand:
    """The band with its lowest speed raised to what is simulated (see the module docstring).

    Parameters
    ----------
    band : OperatingBand
        Static forces, speeds and α_ae. [N], [m/s]
    """
    floor = LOWEST_SIMULATED_SPEED if band.speed_high > LOWEST_SIMULATED_SPEED else 0.5 * band.speed_high
    return dataclasses.replace(band, speed_low=max(band.speed_low, floor))


def dynamic_cost(catenary: Catenary, pantograph: Pantograph, band: OperatingBand, *, static_points: int = 4,
                 speed_points: int = 3, workers: int = 1) -> WorkEstimate:
    """Rough cost of a dynamic robust study (:data:`TYPICAL_PRESAGS` pre-sags of the grid).

    Parameters
    ----------
    catenary : Catenary
        The system simulated.
    pantograph : Pantograph
        The pantograph.
    band : OperatingBand
        The band as simulated (:func:`simulated_band`). [N], [m/s]
    static_points, speed_points : int
        Grid points along each axis. [-]
    workers : int
        Processes simulating pre-sags side by side. [-]
    """
    grid = OperatingGrid.from_band(band, static_points=static_points, speed_points=speed_points)
    return band_work(catenary, pantograph, grid, evaluations=TYPICAL_PRESAGS, workers=workers)


@dataclass(frozen=True, kw_only=True)
class MethodResult:
    """One design method on the band, by simulation.

    Attributes
    ----------
    method : str
        :data:`DELTA_E`, :data:`QUASI_STATIC` or :data:`DYNAMIC`.
    presag_rel : float
        Its relative pre-sag. [-]
    objective : float
        The risk measure of the loss over the grid. [- or N]
    worst_case, mean : float
        Largest and weighted mean loss over the grid. [- or N]
    uplift_max : float
        Largest steady-arm uplift over the grid. [m]
    cost : float
        Wall time of the method: the quasi-static study for both quasi-static designs (they come
        from one), that study and the simulations for the dynamic one. [s]
    within_tolerance : bool
        Whether it lies inside the dynamic tolerance interval and keeps the limits.
    """

    method: str
    presag_rel: float
    objective: float
    worst_case: float
    mean: float
    uplift_max: float
    cost: float
    within_tolerance: bool


@dataclass(frozen=True, kw_only=True)
class DynamicRobustStudy:
    """Quasi-static and dynamic designs of one band, compared by simulation.

    Attributes
    ----------
    catenary_name, pantograph_name : str
        The models.
    band : OperatingBand
        Static forces and speeds. [N], [m/s]
    beta : tuple of float
        Speed ratio v/c_CW at the ends of the speed band. [-]
    design : DynamicRobustDesign
        The dynamic design and the search's cost.
    tolerance : DynamicTolerance
        Its installation tolerance, by simulation.
    curve : tuple of ndarray
        S_rel [-], objective and worst case [- or N] on the surrogate through every simulated
        pre-sag (see :func:`~presag_opt.robust.dynamic_design.band_curve`).
    simulated : tuple of BandStatistics
        Every simulated pre-sag (search, tolerance ends, compared designs), in the order simulated.
    runs_used : int
        All simulation runs of the study. [-]
    wall_time : float
        The whole study: quasi-static designs, search, tolerance, comparison. [s]
    methods : tuple of MethodResult
        Δe rule, quasi-static robust, dynamic robust.
    uplift_limit : float
        Steady-arm uplift limit. [m]
    """

    catenary_name: str
    pantograph_name: str
    band: OperatingBand
    beta: tuple[float, float]
    design: DynamicRobustDesign
    tolerance: DynamicTolerance
    curve: tuple[np.ndarray, np.ndarray, np.ndarray]
    simulated: tuple[BandStatistics, ...]
    runs_used: int
    wall_time: float
    methods: tuple[MethodResult, ...]
    uplift_limit: float

    def method(self, name: str) -> MethodResult:
        """The result of one method by name."""
        return next(m for m in self.methods if m.method == name)

    def where(self) -> str:
        """What was simulated, in words (system, pantograph, grid)."""
        grid = self.design.grid
        return (f"{self.catenary_name} with {self.pantograph_name}, {len(grid.static_forces)} static forces "
                f"{grid.static_forces[0]:g}–{grid.static_forces[-1]:g} N × {len(grid.speeds)} speeds "
                f"{grid.speeds[0] / KMH:.0f}–{grid.speeds[-1] / KMH:.0f} km/h")

    def evidence(self) -> DynamicRobust:
        """The dynamic design and its tolerance as evidence for a decision (:mod:`presag_opt.design.evidence`)."""
        return DynamicRobust(presag_rel=self.design.presag_rel, tolerance=(self.tolerance.low, self.tolerance.high),
                             within=self.tolerance.within, uplift=self.design.uplift_max,
                             simulated=tuple((s.presag_rel, float(s.uplift_max.max())) for s in self.simulated),
                             where=self.where())

    def to_dict(self) -> dict:
        """JSON-ready summary in mm, N, km/h and s."""
        d, span = self.design, self.design.reference_span
        weights, risk = d.grid.weights, Risk.parse(d.risk)
        return {
            "catenary": self.catenary_name,
            "pantograph": self.pantograph_name,
            **self.band.to_dict(),
            "beta": list(self.beta),
            "grid": {"static_forces_N": list(d.grid.static_forces),
                     "speeds_kmh": [v / KMH for v in d.grid.speeds]},
            "objective_name": d.loss,
            "risk": d.risk,
            "reference_span_m": span,
            "presag_mm": d.presag * 1e3,
            "presag_rel_permille": d.presag_rel * 1e3,
            "objective": d.objective,
            "worst_case_objective": d.worst_case_objective,
            "mean_objective": float(weights @ d.statistics.losses(d.loss)),
            "uplift_max_mm": d.uplift_max * 1e3,
            "uplift_limit_mm": self.uplift_limit * 1e3,
            "statistical_min_N": float(d.statistics.statistical_min.min()),
            "tolerance_mm": [self.tolerance.low * span * 1e3, self.tolerance.high * span * 1e3],
            "tolerance_within": self.tolerance.within,
            "quasi_static_presag_mm": self.method(QUASI_STATIC).presag_rel * span * 1e3,
            "delta_e_presag_mm": self.method(DELTA_E).presag_rel * span * 1e3,
            "runs_used": self.runs_used,
            "search_runs": d.runs_used,
            "tolerance_runs": self.tolerance.runs_used,
            "presags_simulated": len(self.simulated),
            "search_time_s": d.wall_time,
            "wall_time_s": self.wall_time,
            "methods": [{
                "method": m.method,
                "presag_mm": m.presag_rel * span * 1e3,
                "objective": m.objective,
                "worst_case_objective": m.worst_case,
                "mean_objective": m.mean,
                "uplift_max_mm": m.uplift_max * 1e3,
                "cost_s": m.cost,
                "within_tolerance": m.within_tolerance,
            } for m in self.methods],
            "simulated": [{
                "presag_mm": s.presag_rel * span * 1e3,
                "objective": risk.value(s.losses(d.loss), weights),
                "worst_case_objective": float(s.losses(d.loss).max()),
                "uplift_max_mm": float(s.uplift_max.max() * 1e3),
            } for s in self.simulated],
            "warnings": list(d.warnings),
        }


def dynamic_robust_study(
    catenary: Catenary,
    pantograph: Pantograph,
    band: OperatingBand,
    *,
    objective: DynamicObjective | None = None,
    within: float = 0.10,
    static_points: int = 4,
    speed_points: int = 3,
    settings: SimulationSettings | None = None,
    search: SearchSettings | None = None,
    workers: int = 1,
    quasi: RobustStudy | None = None,
    progress=None,
) -> DynamicRobustStudy:
    """Design the pre-sag of a band of static forces × speeds quasi-statically and dynamically.

    Parameters
    ----------
    catenary : Catenary
        System model.
    pantograph : Pantograph
        Pantograph model.
    band : OperatingBand
        Static force and speed band (speeds above 0 and below the wave speed). [N], [m/s]
    objective : DynamicObjective, optional
        Loss, risk measure and steady-arm uplift limit (default: worst case of σ/F_m, 83.5 mm).
    within : float
        Allowed loss τ of the tolerance interval. [-]
    static_points, speed_points : int
        Grid points along each axis of the band. [-]
    settings : SimulationSettings, optional
        Numerical settings of the runs; default automatic numerics.
    search : SearchSettings, optional
        Range and resolution of the search.
    workers : int
        Processes that simulate pre-sags side by side (the two starts, the two tolerance ends), or
        the parts of one pre-sag's grid (the search's single steps); started once for the study. [-]
    quasi : RobustStudy, optional
        The quasi-static study of the band's F_m band, where already computed (a decision computes
        it once, over the band as given); default: computed here over the simulated grid's F_m band.
    progress : callable, optional
        Called with a short message before each expensive step.

    Raises
    ------
    ModelError
        Bad input (empty or inverted band, a speed at or above the wave speed, a point the
        simulator refuses), all before any work; or no pre-sag in range keeps the limits.
    ConvergenceError
        A form-finding or a run failed during the search.
    """
    objective = objective or DynamicObjective()
    grid = OperatingGrid.from_band(band, static_points=static_points, speed_points=speed_points)
    evaluator = BandEvaluator(catenary, pantograph, grid, settings=settings, workers=workers, progress=progress)
    context = speed_context(catenary.contact_wire, band.speed_low, band.speed_high)
    check_within(within)
    started = wallclock.perf_counter()
    if quasi is None:
        quasi = robust_study(catenary, grid.mean_force_band, within=within, progress=progress)
    else:
        started -= quasi.wall_time  # the whole study's time includes the quasi-static one, computed before
    quasi_cost = quasi.wall_time
    starts = (quasi.robust_parabola.presag_rel, quasi.nominal.presag_rel)
    weights = grid.weights
    methods = []
    # one set of worker processes for the search, the tolerance and the methods' own pre-sags (a start the
    # search moved away from is simulated last, after the tolerance, so it does not shape it)
    with evaluator:
        design = dynamic_robust_presag(evaluator, objective, starts=starts, search=search)
        tolerance = dynamic_tolerance(evaluator, objective, within=within, search=search)
        for name, presag_rel, cost in ((DELTA_E, starts[1], quasi_cost), (QUASI_STATIC, starts[0], quasi_cost),
                                       (DYNAMIC, design.presag_rel,
                                        quasi_cost + design.wall_time + tolerance.wall_time)):
            stats = evaluator(presag_rel).statistics
            losses = stats.losses(objective.loss)
            methods.append(MethodResult(
                method=name, presag_rel=presag_rel, objective=objective.value(stats, weights),
                worst_case=float(losses.max()), mean=float(weights @ losses),
                uplift_max=float(stats.uplift_max.max()), cost=cost,
                within_tolerance=bool(tolerance.low <= presag_rel <= tolerance.high and objective.feasible(stats)),
            ))
    return DynamicRobustStudy(
        catenary_name=catenary.name,
        pantograph_name=pantograph.name,
        band=band,
        beta=(context.beta_low, context.beta_max),
        design=design,
        tolerance=tolerance,
        curve=band_curve(evaluator, objective),
        simulated=tuple(e.statistics for e in evaluator.evaluations.values()),
        runs_used=evaluator.runs_used,
        wall_time=wallclock.perf_counter() - started,
        methods=tuple(methods),
        uplift_limit=objective.uplift_limit,
    )
