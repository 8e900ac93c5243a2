"""The dynamic robust pre-sag for a fleet: the operating grid with one more axis, the pantograph.

A line sees several pantograph types, and trains that run with two raised pantographs. The fleet's
operating points are every (pantograph type, static force, speed) of the band's grid — with a
second pantograph at a spacing, each pantograph of a train is a point of its own — and the design
is the same risk measure (minimax, mean, CVaR, :class:`~presag_opt.robust.scenarios.Risk`) over the
longer list of losses: a type's points carry its fleet share times the grid's trapezoidal weight
(split equally between the pantographs of a train). :class:`FleetEvaluator` simulates a pre-sag for
every type (one :class:`~presag_opt.robust.band_evaluation.BandEvaluator` per type) and joins the
results, so the search, the surrogate and the tolerance of :mod:`presag_opt.robust.dynamic_design`
run on the fleet unchanged. :func:`fleet_robust_presag` designs for the fleet and sets each type's
own optimum beside it, with that optimum's worst case over the whole fleet.
"""

from __future__ import annotations

import math
import time as wallclock
from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np

from presag_opt.design.band import KMH
from presag_opt.dynamics.pantograph import Pantograph
from presag_opt.dynamics.settings import SimulationSettings
from presag_opt.errors import ModelError
from presag_opt.processes import WorkerPolicy, worker_pool
from presag_opt.robust.band_evaluation import (
    BandEvaluation,
    BandEvaluator,
    BandStatistics,
    simulate_band,
)
from presag_opt.robust.dynamic_design import (
    DynamicObjective,
    DynamicRobustDesign,
    DynamicTolerance,
    SearchSettings,
    dynamic_robust_presag,
    dynamic_tolerance,
)
from presag_opt.robust.operating_grid import OperatingGrid
from presag_opt.robust.tolerance import check_within
from presag_opt.system.catenary import Catenary


@dataclass(frozen=True, kw_only=True)
class FleetGrid:
    """The fleet's operating points: every pantograph type × every point of a grid.

    Attributes
    ----------
    grid : OperatingGrid
        Static forces × speeds of the band. [N], [m/s]
    names : tuple of str
        Pantograph types. [-]
    shares : tuple of float
        Share of the fleet's passages of each type (sums to 1). [-]
    pantographs_per_train : int
        1, or 2 with a second raised pantograph. [-]
    """

    grid: OperatingGrid
    names: tuple[str, ...]
    shares: tuple[float, ...]
    pantographs_per_train: int = 1

    def __post_init__(self) -> None:
        shares = np.asarray(self.shares, dtype=float)
        if len(shares) != len(self.names) or len(shares) == 0:
            raise ModelError(f"fleet shares: give one share per pantograph ({len(self.names)}), got {len(shares)}")
        if np.any(~np.isfinite(shares)) or np.any(shares < 0.0) or not math.isclose(shares.sum(), 1.0, rel_tol=1e-9):
            raise ModelError(f"fleet shares {list(shares)} must be non-negative and sum to 1")
        if self.pantographs_per_train not in (1, 2):
            raise ModelError(f"pantographs per train = {self.pantographs_per_train} is not 1 or 2")

    @property
    def static_forces(self) -> tuple[float, ...]:
        """Static forces of the grid. [N]"""
        return self.grid.static_forces

    @property
    def speeds(self) -> tuple[float, ...]:
        """Speeds of the grid. [m/s]"""
        return self.grid.speeds

    @property
    def aero_coefficient(self) -> float:
        """α_ae. [N/(m/s)²]"""
        return self.grid.aero_coefficient

    @property
    def mean_force_band(self) -> tuple[float, float]:
        """Nominal F_m at the lowest and highest point. [N]"""
        return self.grid.mean_force_band

    @property
    def points_per_type(self) -> int:
        """Points of one type: grid points × pantographs per train. [-]"""
        return len(self.grid.points()) * self.pantographs_per_train

    @property
    def weights(self) -> np.ndarray:
        """Probability of each point, type by type in the order of :attr:`names`. [-]"""
        per_point = np.repeat(self.grid.weights, self.pantographs_per_train) / self.pantographs_per_train
        return np.concatenate([share * per_point for share in self.shares])

    def of_type(self, values: np.ndarray, k: int) -> np.ndarray:
        """The entries of type ``k`` from an array over all points.

        Parameters
        ----------
        values : ndarray
            One value per point of the fleet grid, type after type. [any unit]
        k : int
            Index of the type. [-]

        Returns
        -------
        ndarray
            The values of the points of type ``k``. [unit of ``values``]
        """
        n = self.points_per_type
        return np.asarray(values)[k * n : (k + 1) * n]


class FleetEvaluator:
    """Simulates parabolic pre-sags for every pantograph type of a fleet and joins the results.

    Has the interface of :class:`~presag_opt.robust.band_evaluation.BandEvaluator` that the search
    uses (``evaluations``, ``grid``, ``reference_span``, ``runs_used``, calling and
    ``evaluate_many``), with the fleet's points.

    Parameters
    ----------
    catenary : Catenary
        System model.
    pantographs : sequence of Pantograph
        The types, distinct names.
    shares : sequence of float
        Fleet share of each type (sum 1). [-]
    grid : OperatingGrid
        Static forces × speeds of the band.
    spacing : float, optional
        Distance of a second raised pantograph behind the first, same type; None for one. [m]
    settings : SimulationSettings, optional
        Numerical settings; default automatic numerics.
    workers : int
        Processes that simulate (type, pre-sag) pairs side by side when several are asked for at
        once; 1 simulates in this process. [-]
    progress : callable, optional
        Short messages as the work goes on.
    """

    def __init__(self, catenary: Catenary, pantographs: Sequence[Pantograph], shares: Sequence[float],
                 grid: OperatingGrid, *, spacing: float | None = None, settings: SimulationSettings | None = None,
                 workers: int = 1, progress: Callable[[str], None] | None = None):
        names = tuple(p.name for p in pantographs)
        if len(set(names)) != len(names):
            raise ModelError(f"fleet: pantograph types {', '.join(names)} repeat a name; give each type once")
        if spacing is not None and not 1.0 <= spacing <= 2000.0:
            raise ModelError(f"second pantograph at {spacing:g} m is outside the valid range [1, 2000] m")
        self.grid = FleetGrid(grid=grid, names=names, shares=tuple(float(s) for s in shares),
                              pantographs_per_train=1 if spacing is None else 2)
        spacings = None if spacing is None else (float(spacing),)
        self.members = [BandEvaluator(catenary, p, grid, settings=settings, workers=workers, progress=progress,
                                      spacings=spacings) for p in pantographs]
        self.workers = int(workers)
        self.progress = progress
        self.evaluations: dict[float, BandEvaluation] = {}

    @property
    def reference_span(self) -> float:
        """Span the pre-sag is quoted on: the longest. [m]"""
        return self.members[0].reference_span

    @property
    def runs_used(self) -> int:
        """Simulation runs so far, over all types. [-]"""
        return sum(m.runs_used for m in self.members)

    def __call__(self, presag_rel: float) -> BandEvaluation:
        """Simulate one pre-sag for every type (or return it if simulated before)."""
        return self.evaluate_many([presag_rel])[0]

    def evaluate_many(self, presags) -> list[BandEvaluation]:
        """Simulate several pre-sags for every type (what a type has simulated before is reused).

        Parameters
        ----------
        presags : sequence of float
            Relative pre-sags S_rel. [-]

        Returns
        -------
        list of BandEvaluation
            One per pre-sag, in order, joined over the types.
        """
        presags = [float(s) for s in presags]
        new = [s for s in dict.fromkeys(presags) if s not in self.evaluations]
        pairs = [(m, s) for m in self.members for s in new if s not in m.evaluations]
        if self.workers > 1 and len(pairs) > 1:
            count = min(self.workers, len(pairs))
            if self.progress:
                self.progress(f"{len(pairs)} (pantograph, pre-sag) pairs in {count} processes")
            # spawn, not fork: the command line's progress display runs a thread
            with worker_pool(count, WorkerPolicy.PICKLED) as pool:
                futures = [pool.submit(simulate_band, m.catenary, m.pantograph, m.grid, m.settings, m.static_settings,
                                       s, None, m.spacings) for m, s in pairs]
                results = [f.result() for f in futures]
            for (m, s), evaluation in zip(pairs, results):
                m._keep(s, evaluation)
        if new:
            parts = [member.evaluate_many(new) for member in self.members]
            for i, s in enumerate(new):
                self.evaluations[s] = _joined(s, [part[i] for part in parts])
                if self.progress:
                    self.progress(self._summary(self.evaluations[s].statistics))
        return [self.evaluations[s] for s in presags]


    def _summary(self, statistics: BandStatistics) -> str:
        """One line on a simulated pre-sag: each type's largest σ/F_m and uplift."""
        ratio = statistics.sigma / statistics.mean_force
        parts = [f"{name} {self.grid.of_type(ratio, k).max():.4f}, {self.grid.of_type(statistics.uplift_max, k).max() * 1e3:.1f} mm"
                 for k, name in enumerate(self.grid.names)]
        return f"fleet at S = {statistics.presag_rel * self.reference_span * 1e3:.2f} mm: worst σ/F_m, uplift: " + "; ".join(parts)


def _joined(presag_rel: float, parts: list[BandEvaluation]) -> BandEvaluation:
    return BandEvaluation(
        statistics=BandStatistics(
            presag_rel=presag_rel,
            mean_force=np.concatenate([p.statistics.mean_force for p in parts]),
            sigma=np.concatenate([p.statistics.sigma for p in parts]),
            uplift_max=np.concatenate([p.statistics.uplift_max for p in parts]),
        ),
        histories=tuple(h for p in parts for h in p.histories),
        loss_of_contact=np.concatenate([p.loss_of_contact for p in parts]),
        wall_time=sum(p.wall_time for p in parts),
        warnings=tuple(dict.fromkeys(w for p in parts for w in p.warnings)),
    )


@dataclass(frozen=True, kw_only=True)
class TypeOptimum:
    """One pantograph type's own dynamic optimum and how it serves the fleet.

    Attributes
    ----------
    name : str
        Pantograph type.
    share : float
        Its fleet share. [-]
    design : DynamicRobustDesign
        The optimum over its own points.
    fleet_objective, fleet_worst_case : float
        The fleet's risk measure and worst loss at that pre-sag (simulated). [- or N]
    fleet_uplift_max : float
        Largest uplift over the fleet's points at that pre-sag. [m]
    fleet_feasible : bool
        Whether the fleet's limits hold there.
    """

    name: str
    share: float
    design: DynamicRobustDesign
    fleet_objective: float
    fleet_worst_case: float
    fleet_uplift_max: float
    fleet_feasible: bool


@dataclass(frozen=True, kw_only=True)
class FleetDesign:
    """The dynamic robust pre-sag of a fleet, each type's own optimum beside it.

    Attributes
    ----------
    fleet : DynamicRobustDesign
        The design over the fleet's points.
    tolerance : DynamicTolerance
        Its S interval within the loss (worst case over the fleet).
    per_type : tuple of TypeOptimum
        Each type's own optimum.
    grid : FleetGrid
        The fleet's points.
    spacing : float or None
        Second pantograph's distance. [m]
    wall_time : float
        [s]
    """

    fleet: DynamicRobustDesign
    tolerance: DynamicTolerance
    per_type: tuple[TypeOptimum, ...]
    grid: FleetGrid
    spacing: float | None
    wall_time: float

    def to_dict(self) -> dict:
        """JSON-ready summary in mm, N, km/h."""
        span = self.fleet.reference_span
        fleet_stats = self.fleet.statistics
        return {
            "presag_mm": self.fleet.presag * 1e3,
            "reference_span_m": span,
            "objective_name": self.fleet.loss,
            "risk": self.fleet.risk,
            "objective": self.fleet.objective,
            "worst_case_objective": self.fleet.worst_case_objective,
            "uplift_max_mm": self.fleet.uplift_max * 1e3,
            "tolerance_mm": [self.tolerance.low * span * 1e3, self.tolerance.high * span * 1e3],
            "tolerance_within": self.tolerance.within,
            "pantographs": list(self.grid.names),
            "fleet_shares": list(self.grid.shares),
            "second_pantograph_at_m": self.spacing,
            "grid": {"static_forces_N": list(self.grid.static_forces),
                     "speeds_kmh": [v / KMH for v in self.grid.speeds]},
            "fleet_worst_case_by_type": {
                name: float(self.grid.of_type(fleet_stats.losses(self.fleet.loss), k).max())
                for k, name in enumerate(self.grid.names)},
            "per_pantograph": [{
                "pantograph": t.name, "share": t.share, "own_presag_mm": t.design.presag * 1e3,
                "own_worst_case_objective": t.design.worst_case_objective,
                "fleet_worst_case_objective": t.fleet_worst_case, "fleet_objective": t.fleet_objective,
                "fleet_uplift_max_mm": t.fleet_uplift_max * 1e3, "fleet_limits_kept": t.fleet_feasible,
            } for t in self.per_type],
            "runs_used": self.fleet.runs_used,
            "wall_time_s": self.wall_time,
            "warnings": list(self.fleet.warnings),
        }


def fleet_robust_presag(
    evaluator: FleetEvaluator,
    objective: DynamicObjective | None = None,
    *,
    starts: tuple[float, ...],
    within: float = 0.10,
    search: SearchSettings | None = None,
) -> FleetDesign:
    """Design the pre-sag for the fleet, and each type's own optimum beside it.

    The fleet design is :func:`~presag_opt.robust.dynamic_design.dynamic_robust_presag` over the
    fleet's points; each type's optimum is the same search over its own points, starting from the
    same pre-sags (it reuses what the fleet search simulated for that type); then the fleet is
    simulated at each type's optimum for its worst case over the whole fleet.

    Parameters
    ----------
    evaluator : FleetEvaluator
        The fleet.
    objective : DynamicObjective, optional
        Loss, risk measure (over the fleet's weighted points) and uplift limit.
    starts : tuple of float
        One or two starting S_rel (e.g. the quasi-static robust design and the Δe rule). [-]
    within : float
        Loss of the tolerance interval. [-]
    search : SearchSettings, optional
        Range and resolution.
    """
    started = wallclock.perf_counter()
    objective = objective or DynamicObjective()
    fleet = dynamic_robust_presag(evaluator, objective, starts=starts, search=search)
    tolerance = dynamic_tolerance(evaluator, objective, within=within, search=search)
    per_type = []
    for k, member in enumerate(evaluator.members):
        own = dynamic_robust_presag(member, objective, starts=starts, search=search)
        at_own = evaluator(own.presag_rel).statistics
        per_type.append(TypeOptimum(
            name=evaluator.grid.names[k], share=evaluator.grid.shares[k], design=own,
            fleet_objective=objective.value(at_own, evaluator.grid.weights),
            fleet_worst_case=objective.worst_case(at_own), fleet_uplift_max=float(at_own.uplift_max.max()),
            fleet_feasible=objective.feasible(at_own)))
    return FleetDesign(fleet=fleet, tolerance=tolerance, per_type=tuple(per_type), grid=evaluator.grid,
                       spacing=None if evaluator.grid.pantographs_per_train == 1 else
                       evaluator.members[0].spacings[0], wall_time=wallclock.perf_counter() - started)


def fleet_robust_study(
    catenary: Catenary,
    pantographs: Sequence[Pantograph],
    band,
    *,
    shares: Sequence[float] | None = None,
    spacing: float | None = None,
    objective: DynamicObjective | None = None,
    within: float = 0.10,
    static_points: int = 4,
    speed_points: int = 3,
    settings: SimulationSettings | None = None,
    search: SearchSettings | None = None,
    workers: int = 1,
    progress: Callable[[str], None] | None = None,
) -> FleetDesign:
    """The job behind ``presag robust --dynamic --pantograph A,B,…``: grid, fleet, starts and design.

    The search starts, as for one pantograph, from the quasi-static robust parabola of the band's
    F_m range and the Δe rule at its centre (:func:`~presag_opt.robust.study.robust_study`).

    Parameters
    ----------
    catenary : Catenary
        System model.
    pantographs : sequence of Pantograph
        The fleet's types.
    band : OperatingBand
        Static forces and speeds. [N], [m/s]
    shares : sequence of float, optional
        Fleet share of each type (default equal). [-]
    spacing : float, optional
        Distance of a second raised pantograph behind the first. [m]
    objective : DynamicObjective, optional
        Loss, risk measure and uplift limit.
    within : float
        Loss of the tolerance interval, in (0, 2]. [-]
    static_points, speed_points : int
        Grid points along each axis. [-]
    settings : SimulationSettings, optional
        Numerical settings; default automatic numerics.
    search : SearchSettings, optional
        Range and resolution of the search.
    workers : int
        Processes per type when two pre-sags are asked for at once. [-]
    progress : callable, optional
        Short messages as the work goes on.
    """
    from presag_opt.robust.study import robust_study

    check_within(within)
    shares = [1.0 / len(pantographs)] * len(pantographs) if shares is None else list(shares)
    grid = OperatingGrid.from_band(band, static_points=static_points, speed_points=speed_points)
    evaluator = FleetEvaluator(catenary, pantographs, shares, grid, spacing=spacing,
                               settings=settings or SimulationSettings(numerics="auto"), workers=workers,
                               progress=progress)
    quasi = robust_study(catenary, grid.mean_force_band, within=within, progress=progress)
    return fleet_robust_presag(evaluator, objective, starts=(quasi.robust_parabola.presag_rel, quasi.nominal.presag_rel),
                               within=within, search=search)
