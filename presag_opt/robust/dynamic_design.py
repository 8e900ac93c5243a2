"""Dynamic robust pre-sag: the parabolic S that minimises a risk measure of σ/F_m (or σ) over a band
of static forces × speeds, by batched simulation, and its installation tolerance by simulation.

Problem
    min over S of  ρ({L_k(S)}),  L_k = σ_k/F_m,k (or σ_k) at the grid points k of the band,
    ρ the worst case, the mean or CVaR_α (:class:`~presag_opt.robust.scenarios.Risk`, the same
    measures as the quasi-static design), subject at every point to the steady-arm uplift limit and
    to contact kept, F_m,k − 3σ_k > 0 (EN 50367's statistical minimum), for S in a range.

Search (:func:`dynamic_robust_presag`)
    Simulate two starting pre-sags (the quasi-static designs, or one and a step from it); then
    repeatedly minimise the history surrogate (:mod:`presag_opt.robust.surrogate`) through every
    simulated pre-sag on a fine grid of S (a quarter of the resolution apart, within reach of the
    simulated ones) and simulate its minimiser, until the minimiser lies within ``presag_tolerance`` of
    a simulated pre-sag and at least three are simulated (two give the surrogate's curvature only if
    the model is linear in S; if the minimiser is a start, the other start mirrored about it is
    simulated). The answer is the best simulated pre-sag, with its simulated statistics; the
    surrogate only chooses where to simulate. Each pre-sag costs one form-finding and one batch; the
    two starts (and the two tolerance ends) run side by side with the evaluator's worker processes.

Tolerance (:func:`dynamic_tolerance`)
    The S interval around the minimiser of the worst case W(S) = max_k L_k(S) in which W stays within
    (1 + τ) of its minimum and the limits hold; each end not already next to a simulated pre-sag is
    simulated once and the interval taken again from the surrogate through those runs, so its ends
    are interpolated between simulated pre-sags.

References
----------
Schick, Liu, Stichel, Railway Sciences (2025), doi:10.1108/RS-05-2025-0016, sections 5.2 and 6
(σ/F_m as the quality measure, steady-arm uplift limit 83.5 mm, overfitting to one force).
EN 50367:2012+A1:2016 (F_m, σ, statistical minimum F_m − 3σ).
"""

from __future__ import annotations

import time as wallclock
from dataclasses import dataclass

import numpy as np

from presag_opt.design.speed_range import STEADY_ARM_UPLIFT_LIMIT
from presag_opt.errors import ConvergenceError, ModelError
from presag_opt.robust.band_evaluation import OBJECTIVES, BandEvaluator, BandStatistics
from presag_opt.robust.operating_grid import OperatingGrid
from presag_opt.robust.scenarios import Risk
from presag_opt.robust.surrogate import HistorySurrogate
from presag_opt.robust.tolerance import check_within
from presag_opt.system.quantity import quantity, validate_fields


@dataclass(frozen=True, kw_only=True)
class DynamicObjective:
    """What a dynamic design minimises and the limits it must keep.

    Attributes
    ----------
    loss : {"sigma-over-fm", "sigma"}
        Loss at each operating point: σ/F_m [-] or σ [N].
    risk : Risk
        How the points' losses are aggregated (weights of the grid: uniform over the band).
    uplift_limit : float
        Largest steady-arm uplift allowed at any point. [m] (shown in mm)
    """

    loss: str = "sigma-over-fm"
    risk: Risk = Risk()
    uplift_limit: float = quantity("length", 1.0, 1000.0, display="mm", default=STEADY_ARM_UPLIFT_LIMIT)

    def __post_init__(self) -> None:
        validate_fields(self)
        if self.loss not in OBJECTIVES:
            raise ModelError(f"objective = {self.loss!r} is not one of {', '.join(OBJECTIVES)}")

    def value(self, statistics: BandStatistics, weights: np.ndarray) -> float:
        """The risk measure of the points' losses. [- or N]

        Parameters
        ----------
        statistics : BandStatistics
            Contact-force statistics at the grid points.
        weights : ndarray
            Probability of each grid point (they sum to 1). [-]
        """
        return self.risk.value(statistics.losses(self.loss), weights)

    def worst_case(self, statistics: BandStatistics) -> float:
        """The largest loss over the points. [- or N]"""
        return float(statistics.losses(self.loss).max())

    def feasible(self, statistics: BandStatistics) -> bool:
        """Uplift within the limit and F_m − 3σ > 0 at every point."""
        return bool(np.all(statistics.uplift_max <= self.uplift_limit) and np.all(statistics.statistical_min > 0.0))


@dataclass(frozen=True, kw_only=True)
class SearchSettings:
    """Numerical settings of the dynamic search (no physics).

    Attributes
    ----------
    presag_low, presag_high : float
        Range of S searched, on the reference span. [m] (shown in mm)
    presag_tolerance : float
        The search stops when the surrogate's minimiser lies this close to a simulated pre-sag;
        also the resolution of the tolerance ends. [m] (shown in mm)
    first_step : float
        Distance of the second starting pre-sag from the first, when only one is given (or the two
        lie within twice ``presag_tolerance``); the surrogate is minimised within this much of the
        simulated pre-sags, or within their spread if that is larger. [m] (shown in mm)
    max_evaluations : int
        Most pre-sags simulated by the search (the tolerance ends come on top). [-]
    """

    presag_low: float = quantity("length", 0.0, 600.0, display="mm", default=0.0)
    presag_high: float = quantity("length", 0.0, 600.0, display="mm", default=0.150)
    presag_tolerance: float = quantity("length", 0.01, 20.0, display="mm", default=0.5e-3)
    first_step: float = quantity("length", 0.1, 100.0, display="mm", default=0.010)
    max_evaluations: int = quantity("count", 2, 100, default=12)

    def __post_init__(self) -> None:
        validate_fields(self, prefix="search.")
        if self.presag_high <= self.presag_low:
            raise ModelError(
                f"search range {self.presag_low * 1e3:g}:{self.presag_high * 1e3:g} mm is empty; give LOW < HIGH"
            )


@dataclass(frozen=True, kw_only=True)
class DynamicRobustDesign:
    """The dynamic robust parabolic pre-sag of a band, and what the search cost.

    Attributes
    ----------
    presag_rel : float
        Chosen relative pre-sag S_rel (a simulated one). [-]
    reference_span : float
        Span the pre-sag is quoted on in mm. [m]
    loss, risk : str
        The loss (``sigma-over-fm`` or ``sigma``) and the risk measure.
    objective : float
        Risk measure of the losses at the chosen S (simulated). [- or N]
    worst_case_objective : float
        Largest loss over the grid at the chosen S (simulated). [- or N]
    statistics : BandStatistics
        Simulated statistics at the chosen S.
    uplift_limit : float
        Steady-arm uplift limit kept. [m]
    evaluated : tuple of BandStatistics
        Every pre-sag simulated when the search ended, in the order simulated.
    runs_used : int
        Simulation runs when the search ended (the starting pre-sags included). [-]
    wall_time : float
        Wall time of the search. [s]
    at_range_end : bool
        Whether the chosen S lies at an end of the search range (the optimum may lie beyond it).
    grid : OperatingGrid
        The operating points.
    warnings : tuple of str
        Under-resolution warnings of the runs, and a note when the optimum lies at a range end.
    """

    presag_rel: float
    reference_span: float
    loss: str
    risk: str
    objective: float
    worst_case_objective: float
    statistics: BandStatistics
    uplift_limit: float
    evaluated: tuple[BandStatistics, ...]
    runs_used: int
    wall_time: float
    at_range_end: bool
    grid: OperatingGrid
    warnings: tuple[str, ...] = ()

    @property
    def presag(self) -> float:
        """Mid-span pre-sag on the reference span. [m]"""
        return self.presag_rel * self.reference_span

    @property
    def uplift_max(self) -> float:
        """Largest steady-arm uplift over the grid at the chosen S. [m]"""
        return float(self.statistics.uplift_max.max())


@dataclass(frozen=True, kw_only=True)
class DynamicTolerance:
    """Installation tolerance by simulation: the S interval whose worst case stays near its minimum.

    Attributes
    ----------
    low, high : float
        Ends of the S_rel interval. [-]
    within : float
        Allowed loss τ relative to ``worst_case_min``. [-]
    worst_case_min : float
        Smallest worst case over S (on the surrogate through the simulated pre-sags). [- or N]
    runs_used : int
        Runs simulated for the ends. [-]
    wall_time : float
        [s]
    """

    low: float
    high: float
    within: float
    worst_case_min: float
    runs_used: int
    wall_time: float


def dynamic_robust_presag(
    evaluator: BandEvaluator,
    objective: DynamicObjective | None = None,
    *,
    starts: tuple[float, ...],
    search: SearchSettings | None = None,
) -> DynamicRobustDesign:
    """Choose the parabolic pre-sag that minimises a risk measure of σ/F_m (or σ) over a band.

    See the module notes for the problem and the search.

    Parameters
    ----------
    evaluator : BandEvaluator
        Simulates pre-sags over the band's grid (and keeps every one it simulated).
    objective : DynamicObjective, optional
        Loss, risk measure and uplift limit; default worst case of σ/F_m, 83.5 mm.
    starts : tuple of float
        One or two starting S_rel, e.g. the quasi-static robust design and the Δe rule. [-]
    search : SearchSettings, optional
        Range, resolution and limits of the search.

    Returns
    -------
    DynamicRobustDesign

    Raises
    ------
    ModelError
        No S in the range keeps the uplift within the limit, or contact (the message names the
        smallest uplift, or the largest F_m − 3σ, reached), or bad arguments.
    ConvergenceError
        A form-finding or a run failed, or the search did not settle within ``max_evaluations``.
    """
    objective = objective or DynamicObjective()
    search = search or SearchSettings()
    started = wallclock.perf_counter()
    span = evaluator.reference_span
    low, high = search.presag_low / span, search.presag_high / span
    tol, step = search.presag_tolerance / span, search.first_step / span
    if not 1 <= len(starts) <= 2:
        raise ModelError(f"give one or two starting pre-sags, not {len(starts)}")
    starts = tuple(float(np.clip(s, low, high)) for s in starts)
    if len(starts) == 1 or abs(starts[1] - starts[0]) < 2.0 * tol:
        starts = (starts[0], starts[0] + step if starts[0] + step <= high else starts[0] - step)
    evaluator.evaluate_many(starts)
    weights = evaluator.grid.weights
    while True:
        surrogate = HistorySurrogate(list(evaluator.evaluations.values()))
        simulated = surrogate.presags
        reach = max(step, simulated[-1] - simulated[0])
        candidates = _candidates(max(low, simulated[0] - reach), min(high, simulated[-1] + reach), tol, simulated)
        curve = [surrogate.at(s) for s in candidates]
        ok = np.array([objective.feasible(c) for c in curve])
        if not ok.any():
            target = _least_infeasible(curve, objective)
            if np.min(np.abs(simulated - target)) <= tol:
                _raise_infeasible(evaluator, objective, low, high)
            _evaluate_within_budget(evaluator, target, search)
            continue
        values = np.array([objective.value(c, weights) if f else np.inf for c, f in zip(curve, ok)])
        best = candidates[int(np.argmin(values))]
        nearest = simulated[int(np.argmin(np.abs(simulated - best)))]
        if abs(nearest - best) <= tol and objective.feasible(evaluator(nearest).statistics):
            if len(simulated) >= 3:
                break
            # Two pre-sags give the surrogate its curvature only if the model is linear in S: measure it
            # with a third one, the other start mirrored about the minimiser.
            other = simulated[simulated != nearest][0]
            best = float(np.clip(2.0 * nearest - other, low, high))
            if np.min(np.abs(simulated - best)) <= tol:
                best = 0.5 * (nearest + other)
        _evaluate_within_budget(evaluator, best, search)
    # the best simulated pre-sag: the surrogate's minimiser lies within the tolerance of a simulated one
    chosen = min((e.statistics for e in evaluator.evaluations.values() if objective.feasible(e.statistics)),
                 key=lambda s: objective.value(s, weights))
    at_end = min(chosen.presag_rel - low, high - chosen.presag_rel) <= tol
    notes = [w for e in evaluator.evaluations.values() for w in e.warnings]
    if at_end:
        notes.append(f"the optimum lies at the end of the search range {search.presag_low * 1e3:g}–"
                     f"{search.presag_high * 1e3:g} mm; the best pre-sag may lie beyond it")
    return DynamicRobustDesign(
        presag_rel=chosen.presag_rel,
        reference_span=span,
        loss=objective.loss,
        risk=objective.risk.label,
        objective=objective.value(chosen, weights),
        worst_case_objective=objective.worst_case(chosen),
        statistics=chosen,
        uplift_limit=objective.uplift_limit,
        evaluated=tuple(e.statistics for e in evaluator.evaluations.values()),
        runs_used=evaluator.runs_used,
        wall_time=wallclock.perf_counter() - started,
        at_range_end=at_end,
        grid=evaluator.grid,
        warnings=tuple(dict.fromkeys(notes)),
    )


def dynamic_tolerance(
    evaluator: BandEvaluator, objective: DynamicObjective | None = None, *, within: float = 0.10,
    search: SearchSettings | None = None,
) -> DynamicTolerance:
    """S interval around the minimiser of the worst case W(S) in which W ≤ (1 + τ)·min W, limits kept.

    The interval is read from the surrogate through the simulated pre-sags (at least two, e.g.
    those of :func:`dynamic_robust_presag`); each end farther than a quarter of ``first_step`` from
    every simulated pre-sag (and not at the search range) is simulated once and the interval read again,
    so that its ends are interpolated between simulated pre-sags rather than extrapolated.

    Parameters
    ----------
    evaluator : BandEvaluator
        With the simulated pre-sags.
    objective : DynamicObjective, optional
        Loss and limits (its risk measure is not used: the interval is about the worst case).
    within : float
        τ, in (0, 2]. [-]
    search : SearchSettings, optional
        Range and resolution.
    """
    objective = objective or DynamicObjective()
    search = search or SearchSettings()
    check_within(within)
    started, runs = wallclock.perf_counter(), evaluator.runs_used
    span = evaluator.reference_span
    low, high, tol = search.presag_low / span, search.presag_high / span, search.presag_tolerance / span
    ends, minimum = _tolerance_ends(evaluator, objective, within, low, high, tol)
    simulated = np.array(list(evaluator.evaluations))
    near = 0.25 * search.first_step / span
    missing = [e for e in ends if np.min(np.abs(simulated - e)) > near and tol < e - low and tol < high - e]
    evaluator.evaluate_many(missing)
    if missing:
        ends, minimum = _tolerance_ends(evaluator, objective, within, low, high, tol)
    return DynamicTolerance(low=ends[0], high=ends[1], within=within, worst_case_min=minimum,
                            runs_used=evaluator.runs_used - runs, wall_time=wallclock.perf_counter() - started)


def band_curve(evaluator: BandEvaluator, objective: DynamicObjective, resolution: float = 1e-3
               ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Objective and worst case against S on the surrogate through every simulated pre-sag, from the
    smallest simulated S to the largest (for plots and tables).

    Parameters
    ----------
    evaluator : BandEvaluator
        With at least two simulated pre-sags.
    objective : DynamicObjective
        Loss and risk measure.
    resolution : float
        Spacing of the curve on the reference span. [m]

    Returns
    -------
    presag_rel, objective, worst_case : ndarray
        S_rel [-] and the two losses [- or N].
    """
    surrogate = HistorySurrogate(list(evaluator.evaluations.values()))
    presags = _candidates(surrogate.presags[0], surrogate.presags[-1], 4.0 * resolution / evaluator.reference_span,
                          surrogate.presags)
    curve = [surrogate.at(s) for s in presags]
    weights = evaluator.grid.weights
    return (presags, np.array([objective.value(c, weights) for c in curve]),
            np.array([objective.worst_case(c) for c in curve]))


def _tolerance_ends(evaluator, objective, within, low, high, tol) -> tuple[tuple[float, float], float]:
    """Ends of the tolerance interval on the current surrogate, and the worst case's minimum."""
    surrogate = HistorySurrogate(list(evaluator.evaluations.values()))
    candidates = _candidates(low, high, tol, surrogate.presags)
    worst = np.array([objective.worst_case(c) if objective.feasible(c) else np.inf
                      for c in (surrogate.at(s) for s in candidates)])
    best = int(np.argmin(worst))
    inside = worst <= (1.0 + within) * worst[best]
    first, last = best, best
    while first > 0 and inside[first - 1]:
        first -= 1
    while last < len(candidates) - 1 and inside[last + 1]:
        last += 1
    return (float(candidates[first]), float(candidates[last])), float(worst[best])


def _candidates(low: float, high: float, tol: float, simulated: np.ndarray) -> np.ndarray:
    """A grid of S_rel a quarter of ``tol`` apart over [low, high], with the simulated pre-sags in it."""
    count = max(2, int(np.ceil((high - low) / (0.25 * tol))) + 1)
    grid = np.linspace(low, high, count)
    return np.unique(np.concatenate([grid, simulated[(simulated >= low) & (simulated <= high)]]))


def _least_infeasible(curve: list[BandStatistics], objective: DynamicObjective) -> float:
    """S_rel where the limits are missed least: the smallest uplift excess, or contact nearest kept."""
    excess = np.array([max(c.uplift_max.max() / objective.uplift_limit - 1.0, 0.0) for c in curve])
    contact = np.array([c.statistical_min.min() for c in curve])
    if excess.max() > 0.0:
        return curve[int(np.argmin(excess))].presag_rel
    return curve[int(np.argmax(contact))].presag_rel


def _raise_infeasible(evaluator: BandEvaluator, objective: DynamicObjective, low: float, high: float) -> None:
    """No pre-sag keeps the limits: name the best simulated value of the limit that fails."""
    span = evaluator.reference_span
    simulated = [e.statistics for e in evaluator.evaluations.values()]
    where = f"no pre-sag in {low * span * 1e3:g}–{high * span * 1e3:g} mm"
    smallest = min(simulated, key=lambda s: s.uplift_max.max())
    if smallest.uplift_max.max() > objective.uplift_limit:
        raise ModelError(
            f"{where} keeps the steady-arm uplift within the limit {objective.uplift_limit * 1e3:g} mm over the band: "
            f"the smallest uplift reached is {smallest.uplift_max.max() * 1e3:.1f} mm "
            f"(at S = {smallest.presag_rel * span * 1e3:.1f} mm); raise the limit or narrow the band"
        )
    kept = max(simulated, key=lambda s: s.statistical_min.min())
    raise ModelError(
        f"{where} keeps contact (F_m - 3 sigma > 0) at every point of the band: the largest F_m - 3 sigma reached "
        f"is {kept.statistical_min.min():.1f} N (at S = {kept.presag_rel * span * 1e3:.1f} mm); narrow the band"
    )


def _evaluate_within_budget(evaluator: BandEvaluator, presag_rel: float, search: SearchSettings) -> None:
    if len(evaluator.evaluations) >= search.max_evaluations:
        span = evaluator.reference_span
        done = ", ".join(f"{s * span * 1e3:.1f}" for s in evaluator.evaluations)
        raise ConvergenceError(
            f"dynamic robust pre-sag: the search did not settle within {search.max_evaluations} simulated pre-sags "
            f"({done} mm); raise max_evaluations or the tolerance",
            {"presags_mm": done},
        )
    evaluator(presag_rel)
