"""Robust pre-sag as a linear program over the force scenarios (minimax, mean, CVaR).

The paper warns that a pre-sag tuned to one narrow contact force overfits (section 6); the designs
here serve the whole band instead. The path waviness R is convex in the dropper depths
(:mod:`presag_opt.robust.path`), so

- minimax:  min_d max_k R(d, F_k),
- mean:     min_d Σ_k π_k R(d, F_k),
- CVaR_α:   min_d CVaR_α over the scenarios (Rockafellar & Uryasev 2000),

are convex. With several analysed spans, a scenario's loss is the waviness of its worst span.

Design shapes: ``parabola`` — one relative pre-sag S_rel for every span (S ∝ span length, Swedish
practice), whose objective is a convex function of that one number, minimised exactly by
:mod:`presag_opt.robust.parabola`; ``per-dropper`` — one depth per dropper (optionally symmetric in
each span) within the limits of :mod:`presag_opt.robust.buildability`, a linear program (solved with
cvxpy and Clarabel, built once with the scenario uplift profiles as parameters, so re-solves reuse the
compilation), put on the construction step by :mod:`presag_opt.robust.rounding`. The tolerance
interval is :mod:`presag_opt.robust.tolerance`.

References
----------
Schick, Liu, Stichel, Railway Sciences (2025), doi:10.1108/RS-05-2025-0016, sections 4.1 and 6.
R. T. Rockafellar, S. Uryasev, "Optimization of conditional value-at-risk", Journal of Risk 2(3)
(2000) 21–41.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from presag_opt.errors import ConvergenceError, ModelError
from presag_opt.robust.buildability import Buildability, _span_kinks
from presag_opt.robust.parabola import ParabolaObjective
from presag_opt.robust.path import PathModel
from presag_opt.robust.rounding import _round_to_step
from presag_opt.robust.scenarios import ForceScenarios, Risk

if TYPE_CHECKING:
    import cvxpy as cp

SHAPES = ("parabola", "per-dropper")


@dataclass(frozen=True, kw_only=True)
class RobustDesign:
    """A pre-sag design and how its waviness spreads over the force scenarios.

    Attributes
    ----------
    shape : str
        ``parabola`` or ``per-dropper``.
    risk : str
        Risk measure it was optimised for (``nominal`` for a design not optimised here).
    presag_rel : float
        Relative pre-sag (parabola); for a per-dropper profile the mean over the analysed spans of
        the mid-span depth over span length. [-]
    depths : ndarray
        Depth of every analysed dropper below the support level. [m]
    forces : ndarray
        Scenario forces. [N]
    waviness : ndarray
        Waviness R of the worst analysed span at each scenario force. [m]
    objective : float
        Value of the risk measure. [m]
    continuous_objective : float or None
        Objective before rounding to the construction step (per-dropper only). [m]
    rounding : str
        How the profile was put on the construction step (``none``, ``exhaustive``, ``greedy``).
    solver_status : str
        Status of the optimisation: Clarabel's through cvxpy for a per-dropper profile, ``optimal`` for
        the exact search of a parabola, ``not solved`` for a given design.
    """

    shape: str
    risk: str
    presag_rel: float
    depths: np.ndarray
    forces: np.ndarray
    waviness: np.ndarray
    objective: float
    continuous_objective: float | None = None
    rounding: str = "none"
    solver_status: str = "not solved"

    @property
    def worst_case_waviness(self) -> float:
        """Largest R over the scenarios. [m]"""
        return float(self.waviness.max())

    def mean_waviness(self, weights: np.ndarray) -> float:
        """Probability-weighted mean R. [m]

        Parameters
        ----------
        weights : ndarray, shape (K,)
            Probability of each force scenario (they sum to 1). [-]
        """
        return float(np.asarray(weights) @ self.waviness)


def _risk_objective(loss: cp.Expression, weights: cp.Parameter, risk: Risk) -> tuple[cp.Expression, list]:
    """Objective and extra constraints of a risk measure over scenario losses ``loss`` (K,)."""
    import cvxpy as cp  # on first use: importing it takes about a second

    if risk.measure == "minimax":
        return cp.max(loss), []
    if risk.measure == "mean":
        return weights @ loss, []
    eta = cp.Variable()
    excess = cp.Variable(loss.shape[0], nonneg=True)
    return eta + (weights @ excess) / (1.0 - risk.level), [excess >= loss - eta]


def _design_map(path: PathModel, symmetric: bool) -> tuple[np.ndarray, np.ndarray]:
    """Depths of a per-dropper profile as an affine map of the design variables: depths = M @ variables + c."""
    n = len(path.dropper_span)
    if not symmetric:
        return np.eye(n), np.zeros(n)
    columns, seen = [], {}
    for i in range(n):
        key = (int(path.dropper_span[i]), round(min(path.dropper_fraction[i], 1 - path.dropper_fraction[i]), 9))
        if key not in seen:
            seen[key] = len(columns)
            columns.append(np.zeros(n))
        columns[seen[key]][i] = 1.0
    return np.column_stack(columns), np.zeros(n)


def _peak_to_peak(path: PathModel, z: cp.Expression, uplift: cp.Parameter) -> tuple[cp.Expression, list]:
    """Upper bound of the path waviness of every scenario and analysed span, as LP constraints.

    Parameters
    ----------
    path : PathModel
        Path model.
    z : cvxpy expression, shape (points,)
        Contact-wire height at every path point. [m]
    uplift : cvxpy parameter, shape (scenarios, points)
        F·e(x; F) of every scenario at every path point. [m]

    Returns
    -------
    spread : cvxpy expression, shape (scenarios, spans)
        top − bottom, an upper bound of R that is tight at the optimum. [m]
    constraints : list
        Every path height of a span between its ``bottom`` and ``top`` variables.
    """
    import cvxpy as cp  # on first use: importing it takes about a second

    n_scenarios = uplift.shape[0]
    heights = np.ones((n_scenarios, 1)) @ cp.reshape(z, (1, z.shape[0]), order="C") + uplift
    incidence = np.column_stack([(path.node_span == s).astype(float) for s in path.spans])
    top = cp.Variable((n_scenarios, len(path.spans)))
    bottom = cp.Variable((n_scenarios, len(path.spans)))
    return top - bottom, [heights <= top @ incidence.T, heights >= bottom @ incidence.T]


def _problem(path: PathModel, risk: Risk, n_scenarios: int, build: Buildability):
    """The per-dropper LP, built once per (risk, scenario count, buildability) and kept with the path."""
    return path.problem("robust", ("per-dropper", risk.label, n_scenarios, build),
                        lambda: _build_problem(path, risk, n_scenarios, build))


def _build_problem(path: PathModel, risk: Risk, n_scenarios: int, build: Buildability):
    import cvxpy as cp  # on first use: importing it takes about a second

    design_map, offset = _design_map(path, build.symmetric)
    variables = cp.Variable(design_map.shape[1])
    depths = design_map @ variables + offset
    uplift = cp.Parameter((n_scenarios, len(path.node_span)), name="uplift")
    weights = cp.Parameter(n_scenarios, nonneg=True, name="weights")
    # The contact-wire heights are one variable shared by all scenarios, so the (sparse) geometry
    # sensitivity enters the LP once and not once per scenario.
    z = cp.Variable(len(path.node_span))
    spread, bounds = _peak_to_peak(path, z, uplift)
    constraints = [
        z == path.base_height - path.sensitivity @ path.reference_depth + path.sparse_sensitivity @ depths,
        *bounds,
    ]
    loss = cp.Variable(n_scenarios)
    constraints.append(loss[:, None] @ np.ones((1, len(path.spans))) >= spread)
    objective, extra = _risk_objective(loss, weights, risk)
    constraints += extra
    lengths = np.asarray(path.state.catenary.layout.span_lengths)[path.dropper_span]
    constraints += [depths >= 0.0, depths <= build.max_depth_rel * lengths]
    constraints.append(
        path.dropper_length + path.length_sensitivity @ (depths - path.reference_depth) >= build.min_dropper_length
    )
    for idx, pos in _span_kinks(path):
        length = path.state.catenary.layout.span_lengths[int(path.dropper_span[idx[0]])]
        full_pos = np.concatenate([[0.0], pos, [length]])
        full = cp.hstack([cp.Constant(np.zeros(1)), depths[idx], cp.Constant(np.zeros(1))])
        slope = cp.multiply(full[1:] - full[:-1], 1.0 / np.diff(full_pos))
        constraints.append(cp.abs(slope[1:] - slope[:-1]) <= build.max_kink)
    problem = cp.Problem(cp.Minimize(objective), constraints)
    if not problem.is_dpp():
        raise AssertionError("robust pre-sag LP must be DPP (parameters enter affinely)")
    return problem, variables, depths, uplift, weights, design_map


def _solve(problem: cp.Problem) -> str:
    import cvxpy as cp  # on first use: importing it takes about a second

    try:
        problem.solve(solver=cp.CLARABEL)
    except cp.error.SolverError as exc:
        raise ConvergenceError(f"robust pre-sag: Clarabel failed ({exc})", {"status": problem.status}) from None
    if problem.status == cp.INFEASIBLE:
        raise ModelError(
            "robust pre-sag: the buildability limits leave no feasible profile (check max_depth, max_kink, "
            "min_dropper_length)"
        )
    if problem.status != cp.OPTIMAL:
        raise ConvergenceError(f"robust pre-sag: solver status {problem.status!r}", {"status": problem.status})
    return problem.status


def check_forces(path: PathModel, scenarios: ForceScenarios) -> None:
    """Refuse scenario forces outside the force levels whose elasticity the path model holds.

    Parameters
    ----------
    path : PathModel
        Path model of the section.
    scenarios : ForceScenarios
        Mean contact forces designed for. [N]

    Raises
    ------
    ModelError
        A force below the lowest or above the highest level (the elasticity is not extrapolated).
    """
    levels = path.section.force_levels
    if scenarios.forces.min() < levels[0] or scenarios.forces.max() > levels[-1]:
        raise ModelError(
            f"scenario forces {scenarios.forces.min():g}…{scenarios.forces.max():g} N lie outside the computed "
            f"elasticity force levels [{levels[0]:g}, {levels[-1]:g}] N"
        )


def evaluate_design(
    path: PathModel, depths: np.ndarray, scenarios: ForceScenarios, *, shape: str, risk: Risk,
    presag_rel: float | None = None, **extra,
) -> RobustDesign:
    """Waviness of a given design over the scenarios (exact, no optimisation).

    Parameters
    ----------
    path : PathModel
        Linear model of the contact path.
    depths : ndarray, shape (n_droppers,)
        Pre-sag depth at each dropper of the analysed spans. [m]
    scenarios : ForceScenarios
        Mean-force scenarios and their probabilities.
    shape : str
        Label of the design's shape (e.g. ``"parabola"``).
    risk : Risk
        How the scenarios' waviness is aggregated.
    presag_rel : float, optional
        Relative pre-sag to report (None: the mean mid-span depth over span length of ``depths``). [-]
    """
    waviness = path.waviness(depths, scenarios.forces).max(axis=1)
    if presag_rel is None:
        mid = [np.interp(0.5, path.dropper_fraction[path.dropper_span == s], depths[path.dropper_span == s]) / length
               for s, length in zip(path.spans, path.span_lengths)]
        presag_rel = float(np.mean(mid))
    return RobustDesign(
        shape=shape,
        risk=extra.pop("risk_label", risk.label),
        presag_rel=float(presag_rel),
        depths=np.asarray(depths, dtype=float),
        forces=scenarios.forces,
        waviness=waviness,
        objective=risk.value(waviness, scenarios.weights),
        **extra,
    )


def robust_presag(
    path: PathModel,
    scenarios: ForceScenarios,
    *,
    shape: str = "parabola",
    risk: Risk | None = None,
    buildability: Buildability | None = None,
) -> RobustDesign:
    """Pre-sag that minimises a risk measure of the path waviness over the force scenarios.

    Parameters
    ----------
    path : PathModel
        Path model of the section.
    scenarios : ForceScenarios
        Forces and probabilities; the forces must lie inside the elasticity force levels.
    shape : {"parabola", "per-dropper"}
        One S_rel for all spans, or one depth per dropper.
    risk : Risk, optional
        Default minimax.
    buildability : Buildability, optional
        Limits of a per-dropper profile. The LP is solved continuously; the depths are then put on
        the construction step: with at most 12 free depths, every combination of rounding each one
        down or up is evaluated exactly and the best one that satisfies the limits is kept; with
        more, each is rounded to the nearest step and then, one at a time, moved a step up or down
        while that lowers the objective (greedy). The result reports both objectives.

    Raises
    ------
    ModelError
        Unknown shape, forces outside the computed force levels, infeasible buildability limits.
    ConvergenceError
        If Clarabel does not report an optimal solution.
    """
    risk = risk or Risk()
    if shape not in SHAPES:
        raise ModelError(f"shape = {shape!r} is not one of {', '.join(SHAPES)}")
    check_forces(path, scenarios)
    if shape == "parabola":
        presag_rel, _ = ParabolaObjective.of(path, scenarios, risk).minimum()
        return evaluate_design(path, path.parabola_depths(presag_rel), scenarios, shape=shape, risk=risk,
                               presag_rel=presag_rel, solver_status="optimal")
    build = buildability or Buildability()
    problem, variables, depths, uplift, weights, design_map = _problem(path, risk, len(scenarios.forces), build)
    uplift.value = path.uplift(scenarios.forces)
    weights.value = scenarios.weights
    status = _solve(problem)
    continuous = evaluate_design(path, depths.value, scenarios, shape=shape, risk=risk)
    rounded, how = _round_to_step(path, variables.value, design_map, scenarios, risk, build)
    return evaluate_design(path, rounded, scenarios, shape=shape, risk=risk, solver_status=status,
                           continuous_objective=continuous.objective, rounding=how)
