"""Robust pre-sag over a band of mean contact forces, and installation tolerance bands.

The paper warns that a pre-sag tuned to one narrow contact force overfits (Schick, Liu & Stichel
2025, section 6). This module designs the pre-sag for the whole band instead.

Quasi-static pantograph path. A constant upward force F moving slowly along a span lifts the
contact wire at the contact point to

    h(x; d, F) = z_CW(x; d) + F · e(x; F),

with z_CW the form-found contact-wire height for the pre-sag design d and e the elasticity at the
force F (interpolated between computed force levels). Its peak-to-peak value over a span,
R(d, F) = max_x h − min_x h, is the waviness the pre-sag cancels. The form-found geometry is affine
in the dropper target heights — the sensitivity comes from the CasADi Jacobian of the form-finding
equations (:func:`presag_opt.static.equilibrium.dropper_height_sensitivity`; the prediction of a
70 mm geometry from a 30 mm one is exact to 0.2 μm) — so R is convex in d, and

- minimax:  min_d max_k R(d, F_k),
- mean:     min_d Σ_k π_k R(d, F_k),
- CVaR_α:   min_d CVaR_α over the scenarios (Rockafellar & Uryasev 2000),

are linear programs (solved with cvxpy and Clarabel, built once with the scenario uplift profiles as
parameters, so re-solves reuse the compilation). With several analysed spans, a scenario's loss is
the waviness of its worst span.

Design shapes: ``parabola`` — one relative pre-sag S_rel for every span (S ∝ span length, Swedish
practice); ``per-dropper`` — one depth per dropper (optionally symmetric in each span) with
buildability limits (depth range, kink angle at each dropper, minimum dropper length) and heights on
a construction step, rounded as described in :func:`robust_presag`.

References
----------
Schick, Liu, Stichel, Railway Sciences (2025), doi:10.1108/RS-05-2025-0016, sections 4.1 and 6.
R. T. Rockafellar, S. Uryasev, "Optimization of conditional value-at-risk", Journal of Risk 2(3)
(2000) 21–41.
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass, field

import cvxpy as cp
import numpy as np
import scipy.sparse as sp

from presag_opt.errors import ConvergenceError, ModelError
from presag_opt.presag import OperatingBand, SectionElasticity, interpolate_elasticity, mean_contact_force
from presag_opt.static.equilibrium import EquilibriumState, dropper_height_sensitivity
from presag_opt.system.quantity import quantity, validate_fields

SHAPES = ("parabola", "per-dropper")

SENSITIVITY_CUTOFF = 1e-9
"""Geometry sensitivities smaller than this are round-off of the implicit-function solve. [m/m]"""


# ----- force scenarios ----------------------------------------------------------------------------


@dataclass(frozen=True, kw_only=True)
class ForceScenarios:
    """Mean contact forces the design must serve, with probabilities.

    Attributes
    ----------
    forces : ndarray
        Mean contact forces F_m. [N]
    weights : ndarray
        Probability of each force (sums to 1). [-]
    """

    forces: np.ndarray
    weights: np.ndarray

    def __post_init__(self) -> None:
        forces = np.asarray(self.forces, dtype=float)
        weights = np.asarray(self.weights, dtype=float)
        if forces.ndim != 1 or len(forces) == 0 or forces.shape != weights.shape:
            raise ModelError("force scenarios: give one weight per force, at least one force")
        if not np.all(np.isfinite(forces)) or np.any(forces <= 0.0):
            raise ModelError(f"force scenarios: forces {forces.min():g}…{forces.max():g} N must be positive")
        if np.any(weights < 0.0) or not math.isclose(weights.sum(), 1.0, rel_tol=1e-9):
            raise ModelError("force scenarios: weights must be non-negative and sum to 1")
        object.__setattr__(self, "forces", forces)
        object.__setattr__(self, "weights", weights)

    @classmethod
    def band(cls, low: float, high: float, count: int = 17) -> "ForceScenarios":
        """Evenly spaced forces over [low, high], equally likely.

        Parameters
        ----------
        low, high : float
            The F_m band. [N]
        count : int
            Number of forces (the minimax design is exact at them; 17 puts them < 5 N apart on
            the case study's 70–148 N band). [-]
        """
        if not (math.isfinite(low) and math.isfinite(high)) or not 0.0 < low < high:
            raise ModelError(
                f"F_m band = [{low:g}, {high:g}] N is empty or inverted; give 0 < low < high in N"
            )
        if not 2 <= count <= 200:
            raise ModelError(f"count = {count} is outside the valid range [2, 200]")
        forces = np.linspace(low, high, count)
        return cls(forces=forces, weights=np.full(count, 1.0 / count))

    @classmethod
    def from_operating_band(cls, band: OperatingBand, static_points: int = 8, speed_points: int = 8) -> "ForceScenarios":
        """F_m = F_stat + α_ae v² for F_stat and v uniform and independent over the band.

        A tensor grid of midpoints (``static_points`` × ``speed_points`` equally likely cells);
        forces closer than 0.01 N are merged.
        """
        f_stat = band.static_force_low + (np.arange(static_points) + 0.5) / static_points * (
            band.static_force_high - band.static_force_low
        )
        speed = band.speed_low + (np.arange(speed_points) + 0.5) / speed_points * (band.speed_high - band.speed_low)
        forces = np.array([mean_contact_force(f, v, band.aero_coefficient) for f in f_stat for v in speed])
        rounded, inverse = np.unique(np.round(forces, 2), return_inverse=True)
        weights = np.bincount(inverse, minlength=len(rounded)) / len(forces)
        return cls(forces=rounded, weights=weights)


@dataclass(frozen=True, kw_only=True)
class Risk:
    """How the scenarios' waviness is aggregated.

    Attributes
    ----------
    measure : {"minimax", "mean", "cvar"}
        Worst case, expected value, or conditional value-at-risk.
    level : float
        CVaR level α (mean of the worst 1 − α share); unused otherwise. [-]
    """

    measure: str = "minimax"
    level: float = 0.9

    def __post_init__(self) -> None:
        if self.measure not in ("minimax", "mean", "cvar"):
            raise ModelError(f"risk = {self.measure!r} is not one of minimax, mean, cvar:LEVEL")
        if not 0.0 <= self.level < 1.0:
            raise ModelError(f"risk level = {self.level:g} is outside the valid range [0, 1)")

    @classmethod
    def parse(cls, text: str) -> "Risk":
        """``minimax``, ``mean`` or ``cvar:0.9``."""
        if text.startswith("cvar"):
            _, _, level = text.partition(":")
            try:
                value = float(level or 0.9)
            except ValueError:
                raise ModelError(f"risk = {text!r}: write cvar:LEVEL with LEVEL in [0, 1), e.g. cvar:0.9") from None
            return cls(measure="cvar", level=value)
        return cls(measure=text)

    @property
    def label(self) -> str:
        """``minimax``, ``mean`` or ``cvar:0.90``."""
        return f"cvar:{self.level:.2f}" if self.measure == "cvar" else self.measure


@dataclass(frozen=True, kw_only=True)
class Buildability:
    """Limits of a per-dropper pre-sag profile that a line crew can build.

    Attributes
    ----------
    step : float
        Construction step of the dropper heights; 0 for none. [m]
    max_depth_rel : float
        Largest depth below the support level, relative to the span length. [-]
    max_kink : float
        Largest change of contact-wire slope at a dropper. [-] (shown in ‰)
    min_dropper_length : float
        Shortest dropper. [m]
    symmetric : bool
        Same depth at mirror-image droppers of a span.
    """

    step: float = quantity("length", 0.0, 50.0, display="mm", default=0.005)
    max_depth_rel: float = quantity("ratio", 0.0, 5.0, display="‰", default=0.004)
    max_kink: float = quantity("ratio", 0.0, 50.0, display="‰", default=0.003)
    min_dropper_length: float = quantity("length", 0.0, 2000.0, display="mm", default=0.15)
    symmetric: bool = True

    def __post_init__(self) -> None:
        validate_fields(self, prefix="buildability.")


# ----- the path model -----------------------------------------------------------------------------


@dataclass(frozen=True)
class PathModel:
    """Quasi-static pantograph path of the analysed spans, affine in the dropper heights.

    Built from a form-found state and the elasticity curves of its analysed spans (computed at that
    geometry). Heights are measured from the state's contact-wire support level.

    Attributes
    ----------
    state : EquilibriumState
        The reference geometry.
    section : SectionElasticity
        Elasticity curves at force levels, one study per analysed span.
    node_span : ndarray of int
        Analysed span of each path point (mast nodes appear once per adjacent analysed span).
    node_position : ndarray
        Position of each path point from its span's first mast. [m]
    base_height : ndarray
        Contact-wire height at each path point in the reference geometry. [m]
    sensitivity : ndarray
        ∂h/∂(dropper depth) of each path point for the analysed spans' droppers (depth positive
        downwards). [m/m]
    dropper_span, dropper_fraction : ndarray
        Span and relative position x/l of each design dropper. [-]
    reference_depth : ndarray
        Depth of each design dropper in the reference geometry. [m]
    dropper_length : ndarray
        Length of each design dropper in the reference geometry. [m]
    length_sensitivity : ndarray
        ∂(dropper length)/∂(depth) of each design dropper for each depth. [m/m]
    """

    state: EquilibriumState
    section: SectionElasticity
    node_span: np.ndarray
    node_position: np.ndarray
    base_height: np.ndarray
    sensitivity: np.ndarray
    dropper_span: np.ndarray
    dropper_fraction: np.ndarray
    reference_depth: np.ndarray
    dropper_length: np.ndarray
    length_sensitivity: np.ndarray
    _problems: dict = field(default_factory=dict, repr=False, compare=False)

    @property
    def spans(self) -> tuple[int, ...]:
        """Analysed spans, from 0."""
        return self.section.spans

    @property
    def sparse_sensitivity(self) -> sp.csr_matrix:
        """:attr:`sensitivity` without its round-off entries (below 1e-9 m/m).

        A node feels only the droppers of its own span (the masts are held at their height), but the
        implicit-function solve leaves round-off everywhere; dropping it keeps the LP sparse.
        """
        if "sparse_sensitivity" not in self._problems:
            dense = np.where(np.abs(self.sensitivity) < SENSITIVITY_CUTOFF, 0.0, self.sensitivity)
            self._problems["sparse_sensitivity"] = sp.csr_matrix(dense)
        return self._problems["sparse_sensitivity"]

    @property
    def span_lengths(self) -> np.ndarray:
        """Length of each analysed span. [m]"""
        return self.section.span_lengths

    def parabola_depths(self, presag_rel: float) -> np.ndarray:
        """Dropper depths of a parabolic pre-sag S_rel·l in every analysed span. [m]"""
        lengths = np.asarray(self.state.catenary.layout.span_lengths)[self.dropper_span]
        t = self.dropper_fraction
        return presag_rel * lengths * 4.0 * t * (1.0 - t)

    def uplift(self, forces: np.ndarray) -> np.ndarray:
        """F·e(x; F) at every path point for every force (K × points). [m]"""
        out = np.empty((len(forces), len(self.node_span)))
        for s_index, study in enumerate(self.section.studies):
            sel = self.node_span == study.span
            for k, force in enumerate(forces):
                curve = interpolate_elasticity(study.nonlinear, float(force))
                out[k, sel] = force * curve.at(self.node_position[sel])
        return out

    def heights(self, depths: np.ndarray, forces: np.ndarray, uplift: np.ndarray | None = None) -> np.ndarray:
        """Path height h at every point for every force (K × points). [m]

        ``uplift`` may pass :meth:`uplift` of the same forces, computed once for many designs.
        """
        z = self.base_height + self.sensitivity @ (np.asarray(depths) - self.reference_depth)
        return z[None, :] + (self.uplift(forces) if uplift is None else uplift)

    def waviness(self, depths: np.ndarray, forces: np.ndarray, uplift: np.ndarray | None = None) -> np.ndarray:
        """Peak-to-peak path height R of every analysed span for every force (K × spans). [m]"""
        h = self.heights(depths, forces, uplift)
        return np.column_stack([np.ptp(h[:, self.node_span == s], axis=1) for s in self.spans])


def build_path_model(state: EquilibriumState, section: SectionElasticity) -> PathModel:
    """Assemble the path model of a form-found state and its elasticity curves.

    Parameters
    ----------
    state : EquilibriumState
        Form-found geometry; ``section`` must have been computed on it.
    section : SectionElasticity
        Elasticity curves at force levels covering the forces to be studied.
    """
    disc = state.discretisation
    if section.catenary != state.catenary:
        raise ModelError("path model: the elasticity curves were computed on another geometry than the state")
    spans = section.spans
    design = np.flatnonzero(np.isin(disc.dropper_span, spans))
    sens_all = dropper_height_sensitivity(state)[:, design]  # ∂z/∂(target height)
    node_span, node_pos, nodes = [], [], []
    for s in spans:
        lo, hi = disc.mast_station[s], disc.mast_station[s + 1]
        k = np.flatnonzero((disc.cw_station >= lo - 1e-9) & (disc.cw_station <= hi + 1e-9))
        nodes.append(disc.cw_nodes[k])
        node_span.append(np.full(len(k), s))
        node_pos.append(disc.cw_station[k] - lo)
    nodes = np.concatenate(nodes)
    lengths = np.asarray(state.catenary.layout.span_lengths)[disc.dropper_span[design]]
    drop_cw = disc.axial.node_a[disc.dropper_elements[design]]
    drop_mw = disc.axial.node_b[disc.dropper_elements[design]]
    support = state.catenary.contact_wire_height
    # depth = support − target height, so ∂/∂depth = −∂/∂target
    return PathModel(
        state=state,
        section=section,
        node_span=np.concatenate(node_span),
        node_position=np.concatenate(node_pos),
        base_height=state.positions[nodes, 2] - support,
        sensitivity=-sens_all[nodes],
        dropper_span=disc.dropper_span[design],
        dropper_fraction=disc.dropper_position[design] / lengths,
        reference_depth=support - state.positions[drop_cw, 2],
        dropper_length=state.dropper_lengths()[design],
        length_sensitivity=-(sens_all[drop_mw] - sens_all[drop_cw]),
    )


# ----- results ------------------------------------------------------------------------------------


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
        cvxpy/Clarabel status of the solve (``not solved`` for a given design).
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
        """Probability-weighted mean R. [m]"""
        return float(np.asarray(weights) @ self.waviness)


@dataclass(frozen=True, kw_only=True)
class ToleranceBand:
    """Interval of parabolic pre-sag whose objective stays within a share of the best.

    Attributes
    ----------
    low, high : float
        Ends of the interval of S_rel. [-]
    best : float
        S_rel at the optimum. [-]
    best_objective : float
        The optimum of the objective (worst-case R over the forces considered). [m]
    within : float
        Allowed loss relative to ``best_objective``. [-]
    forces : ndarray
        Forces the objective covers. [N]
    """

    low: float
    high: float
    best: float
    best_objective: float
    within: float
    forces: np.ndarray

    @property
    def width(self) -> float:
        """high − low. [-]"""
        return self.high - self.low


# ----- optimisation -------------------------------------------------------------------------------


def _risk_objective(loss: cp.Expression, weights: cp.Parameter, risk: Risk) -> tuple[cp.Expression, list]:
    """Objective and extra constraints of a risk measure over scenario losses ``loss`` (K,)."""
    if risk.measure == "minimax":
        return cp.max(loss), []
    if risk.measure == "mean":
        return weights @ loss, []
    eta = cp.Variable()
    excess = cp.Variable(loss.shape[0], nonneg=True)
    return eta + (weights @ excess) / (1.0 - risk.level), [excess >= loss - eta]


def _design_map(path: PathModel, shape: str, symmetric: bool) -> tuple[np.ndarray, np.ndarray]:
    """Depths as an affine map of the design variables: depths = M @ variables + c."""
    n = len(path.dropper_span)
    if shape == "parabola":
        return path.parabola_depths(1.0)[:, None], np.zeros(n)
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


def _span_kinks(path: PathModel) -> list[tuple[np.ndarray, np.ndarray]]:
    """For every analysed span: dropper indices and positions (with the masts, depth 0)."""
    out = []
    for s in path.spans:
        idx = np.flatnonzero(path.dropper_span == s)
        out.append((idx, path.dropper_fraction[idx] * path.state.catenary.layout.span_lengths[s]))
    return out


def _problem(path: PathModel, shape: str, risk: Risk, n_scenarios: int, build: Buildability | None):
    """The LP, built once per (shape, risk, scenario count, buildability) and cached on the path."""
    key = (shape, risk.label, n_scenarios, build)
    if key in path._problems:
        return path._problems[key]
    symmetric = build.symmetric if (build and shape == "per-dropper") else False
    design_map, offset = _design_map(path, shape, symmetric)
    variables = cp.Variable(design_map.shape[1])
    depths = design_map @ variables + offset
    uplift = cp.Parameter((n_scenarios, len(path.node_span)), name="uplift")
    weights = cp.Parameter(n_scenarios, nonneg=True, name="weights")
    # The contact-wire heights are one variable shared by all scenarios, so the (sparse) geometry
    # sensitivity enters the LP once and not once per scenario.
    z = cp.Variable(len(path.node_span))
    heights = np.ones((n_scenarios, 1)) @ cp.reshape(z, (1, z.shape[0]), order="C") + uplift
    spans = path.spans
    incidence = np.column_stack([(path.node_span == s).astype(float) for s in spans])
    top = cp.Variable((n_scenarios, len(spans)))
    bottom = cp.Variable((n_scenarios, len(spans)))
    constraints = [
        z == path.base_height - path.sensitivity @ path.reference_depth + path.sparse_sensitivity @ depths,
        heights <= top @ incidence.T,
        heights >= bottom @ incidence.T,
    ]
    loss = cp.Variable(n_scenarios)
    constraints.append(loss[:, None] @ np.ones((1, len(spans))) >= top - bottom)
    objective, extra = _risk_objective(loss, weights, risk)
    constraints += extra
    if shape == "parabola":
        constraints.append(variables >= 0.0)
    else:
        build = build or Buildability()
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
    path._problems[key] = (problem, variables, depths, uplift, weights, design_map)
    return path._problems[key]


def _solve(problem: cp.Problem) -> str:
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


def _objective_value(waviness: np.ndarray, weights: np.ndarray, risk: Risk) -> float:
    """The risk measure of scenario losses, evaluated exactly (the LP's objective). [m]"""
    if risk.measure == "minimax":
        return float(waviness.max())
    if risk.measure == "mean":
        return float(weights @ waviness)
    # CVaR of a discrete distribution: min over η of η + E[(L − η)+]/(1 − α), attained at a loss value.
    return float(min(eta + weights @ np.maximum(waviness - eta, 0.0) / (1.0 - risk.level) for eta in waviness))


def evaluate_design(
    path: PathModel, depths: np.ndarray, scenarios: ForceScenarios, *, shape: str, risk: Risk,
    presag_rel: float | None = None, **extra,
) -> RobustDesign:
    """Waviness of a given design over the scenarios (exact, no optimisation)."""
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
        objective=_objective_value(waviness, scenarios.weights, risk),
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
    levels = path.section.force_levels
    if scenarios.forces.min() < levels[0] or scenarios.forces.max() > levels[-1]:
        raise ModelError(
            f"scenario forces {scenarios.forces.min():g}…{scenarios.forces.max():g} N lie outside the computed "
            f"elasticity force levels [{levels[0]:g}, {levels[-1]:g}] N"
        )
    build = (buildability or Buildability()) if shape == "per-dropper" else None
    problem, variables, depths, uplift, weights, design_map = _problem(path, shape, risk, len(scenarios.forces), build)
    uplift.value = path.uplift(scenarios.forces)
    weights.value = scenarios.weights
    status = _solve(problem)
    if shape == "parabola":
        presag_rel = float(variables.value[0])
        return evaluate_design(path, path.parabola_depths(presag_rel), scenarios, shape=shape, risk=risk,
                               presag_rel=presag_rel, solver_status=status)
    continuous = evaluate_design(path, depths.value, scenarios, shape=shape, risk=risk)
    rounded, how = _round_to_step(path, variables.value, design_map, scenarios, risk, build)
    return evaluate_design(path, rounded, scenarios, shape=shape, risk=risk, solver_status=status,
                           continuous_objective=continuous.objective, rounding=how)


def _violation(path: PathModel, depths: np.ndarray, build: Buildability) -> float:
    """Largest excess of a profile over the buildability limits (0 if it meets them all). [m or -]"""
    lengths = np.asarray(path.state.catenary.layout.span_lengths)[path.dropper_span]
    excess = [
        np.max(-depths, initial=0.0),
        np.max(depths - build.max_depth_rel * lengths, initial=0.0),
        np.max(build.min_dropper_length
               - (path.dropper_length + path.length_sensitivity @ (depths - path.reference_depth)), initial=0.0),
    ]
    for idx, pos in _span_kinks(path):
        length = path.state.catenary.layout.span_lengths[int(path.dropper_span[idx[0]])]
        full = np.concatenate([[0.0], depths[idx], [0.0]])
        slope = np.diff(full) / np.diff(np.concatenate([[0.0], pos, [length]]))
        excess.append(np.max(np.abs(np.diff(slope)) - build.max_kink, initial=0.0))
    worst = max(excess)
    return worst if worst > 1e-9 else 0.0


def _round_to_step(path, values, design_map, scenarios, risk, build: Buildability) -> tuple[np.ndarray, str]:
    """Put the design on the construction step: best (limit violation, objective) by enumeration
    (at most 12 free depths) or by a greedy descent from the nearest rounding."""
    if build.step == 0.0:
        return design_map @ values, "none"

    uplift = path.uplift(scenarios.forces)

    def score(v):
        d = design_map @ v
        return (_violation(path, d, build),
                _objective_value(path.waviness(d, scenarios.forces, uplift).max(axis=1), scenarios.weights, risk))

    if len(values) <= 12:
        low = np.floor(values / build.step + 1e-9) * build.step
        candidates = (low + np.asarray(ups) for ups in itertools.product((0.0, build.step), repeat=len(values)))
        best = min(candidates, key=score)
        how = "exhaustive"
    else:
        best = np.round(values / build.step) * build.step
        best_score = score(best)
        improved = True
        while improved:
            improved = False
            for i in range(len(best)):
                for delta in (-build.step, build.step):
                    trial = best.copy()
                    trial[i] += delta
                    trial_score = score(trial)
                    if trial_score < best_score and (trial_score[0] < best_score[0] or trial_score[1] < best_score[1] - 1e-12):
                        best, best_score, improved = trial, trial_score, True
        how = "greedy"
    if score(best)[0] > 0.0:
        raise ModelError(
            f"robust pre-sag: no rounding of the profile to the {build.step * 1e3:g} mm construction step meets the "
            "buildability limits (relax max_kink or the step)"
        )
    return design_map @ best, how


def tolerance_band(
    path: PathModel, scenarios: ForceScenarios, within: float = 0.10
) -> ToleranceBand:
    """Interval of parabolic S_rel whose worst-case waviness stays within ``within`` of the best.

    Two LPs over the same constraints: minimise and maximise S_rel subject to
    max_k R(S_rel, F_k) ≤ (1 + within)·R*, with R* the minimax optimum. The worst-case waviness is
    convex in S_rel, so the feasible set is exactly this interval.

    Parameters
    ----------
    path : PathModel
        Path model.
    scenarios : ForceScenarios
        Forces covered (a single force gives the tolerance of a design for that force alone).
    within : float
        Allowed relative loss, e.g. 0.10 for 10 %. [-]
    """
    if not 0.0 < within <= 2.0:
        raise ModelError(f"within = {within * 100:g} % is outside the valid range (0, 200] %")
    best = robust_presag(path, scenarios, shape="parabola", risk=Risk())
    key = ("tolerance", len(scenarios.forces))
    if key not in path._problems:
        s = cp.Variable()
        uplift = cp.Parameter((len(scenarios.forces), len(path.node_span)))
        bound = cp.Parameter(nonneg=True)
        shape = path.sensitivity @ path.parabola_depths(1.0)
        z = path.base_height - path.sensitivity @ path.reference_depth + shape * s
        heights = np.ones((len(scenarios.forces), 1)) @ cp.reshape(z, (1, z.shape[0]), order="C") + uplift
        incidence = np.column_stack([(path.node_span == sp).astype(float) for sp in path.spans])
        top = cp.Variable((len(scenarios.forces), len(path.spans)))
        bottom = cp.Variable((len(scenarios.forces), len(path.spans)))
        constraints = [heights <= top @ incidence.T, heights >= bottom @ incidence.T, top - bottom <= bound, s >= 0]
        path._problems[key] = (cp.Problem(cp.Minimize(s), constraints), cp.Problem(cp.Maximize(s), constraints),
                               s, uplift, bound)
    lower, upper, s, uplift, bound = path._problems[key]
    uplift.value = path.uplift(scenarios.forces)
    # a hair above (1 + within)·R* so the optimum itself is always feasible despite solver tolerance
    bound.value = (1.0 + within) * best.worst_case_waviness * (1 + 1e-7) + 1e-9
    _solve(lower)
    low = float(s.value)
    _solve(upper)
    high = float(s.value)
    return ToleranceBand(low=low, high=high, best=best.presag_rel, best_objective=best.worst_case_waviness,
                         within=within, forces=scenarios.forces)


# ----- the study behind `presag robust` and `presag tolerance` -------------------------------------


@dataclass(frozen=True, kw_only=True)
class RobustStudy:
    """Robust and nominal designs of one section over a force band, with tolerance bands.

    Attributes
    ----------
    catenary_name : str
        System.
    path : PathModel
        Path model at the final reference geometry.
    scenarios : ForceScenarios
        The forces (and probabilities) designed for. [N]
    robust : RobustDesign
        The design for the chosen shape and risk.
    robust_parabola : RobustDesign
        The minimax parabola (the one the tolerance band refers to).
    nominal : RobustDesign
        The quasi-static Δe rule at the band centre, S = F_c·Δe(F_c), evaluated over the band.
    tolerance : ToleranceBand
        S_rel interval of the robust parabola within ``within`` of its worst-case optimum.
    nominal_tolerance : ToleranceBand
        The same for a design for the band centre alone (worst case over the single force F_c).
    reference_span : float
        Span length the absolute pre-sag is quoted for. [m]
    """

    catenary_name: str
    path: PathModel
    scenarios: ForceScenarios
    robust: RobustDesign
    robust_parabola: RobustDesign
    nominal: RobustDesign
    tolerance: ToleranceBand
    nominal_tolerance: ToleranceBand
    reference_span: float

    def to_dict(self) -> dict:
        """JSON-ready summary in mm, ‰ and N."""
        l_ref = self.reference_span
        weights = self.scenarios.weights
        return {
            "catenary": self.catenary_name,
            "fm_band_N": [float(self.scenarios.forces.min()), float(self.scenarios.forces.max())],
            "shape": self.robust.shape,
            "risk": self.robust.risk,
            "reference_span_m": l_ref,
            "presag_mm": self.robust.presag_rel * l_ref * 1e3,
            "presag_rel_permille": self.robust.presag_rel * 1e3,
            "dropper_depths_mm": (self.robust.depths * 1e3).tolist(),
            "worst_case_waviness_mm": self.robust.worst_case_waviness * 1e3,
            "mean_waviness_mm": self.robust.mean_waviness(weights) * 1e3,
            "objective_mm": self.robust.objective * 1e3,
            "continuous_objective_mm": None if self.robust.continuous_objective is None
            else self.robust.continuous_objective * 1e3,
            "rounding": self.robust.rounding,
            "nominal_presag_mm": self.nominal.presag_rel * l_ref * 1e3,
            "nominal_worst_case_waviness_mm": self.nominal.worst_case_waviness * 1e3,
            "nominal_mean_waviness_mm": self.nominal.mean_waviness(weights) * 1e3,
            "tolerance_mm": [self.tolerance.low * l_ref * 1e3, self.tolerance.high * l_ref * 1e3],
            "tolerance_within": self.tolerance.within,
            "nominal_tolerance_mm": [self.nominal_tolerance.low * l_ref * 1e3, self.nominal_tolerance.high * l_ref * 1e3],
            "solver_status": self.robust.solver_status,
        }


def robust_study(
    catenary,
    fm_band: tuple[float, float],
    *,
    shape: str = "parabola",
    risk: Risk | None = None,
    buildability: Buildability | None = None,
    within: float = 0.10,
    scenarios: ForceScenarios | None = None,
    relinearise: bool = True,
    progress=None,
) -> RobustStudy:
    """Design the pre-sag of a section for a band of mean contact forces.

    Steps: form-find the model's geometry; compute the elasticity curves of the analysed spans at
    force levels bracketing the band (active-set method); solve the minimax parabola; then, as the
    paper finds the elasticity is best taken near the optimal pre-sag (its Fig. 5b: 16 % error at
    179 N from the 30 mm geometry, 2 % from 70 mm), form-find again at that pre-sag, recompute the
    curves and solve again (``relinearise``); finally the requested shape and risk, the nominal Δe
    rule at the band centre and both tolerance bands on the final geometry.

    Parameters
    ----------
    catenary : Catenary
        System model (its pre-sag is the first reference geometry).
    fm_band : (float, float)
        Mean contact force band. [N]
    shape, risk, buildability
        See :func:`robust_presag`.
    within : float
        Tolerance-band loss. [-]
    scenarios : ForceScenarios, optional
        Defaults to 17 equally likely forces over the band.
    relinearise : bool
        Recompute geometry and elasticity at the first robust pre-sag.
    progress : callable, optional
        Called with a short message before each expensive step.
    """
    from presag_opt.presag import force_levels_for_band, section_elasticity
    from presag_opt.static.equilibrium import form_find

    low, high = fm_band
    scenarios = scenarios or ForceScenarios.band(low, high)
    risk = risk or Risk()
    levels = force_levels_for_band(min(low, scenarios.forces.min()), max(high, scenarios.forces.max()))

    def path_at(cat):
        if progress:
            progress(f"{cat.name}: form-finding at S_rel = {cat.presag_rel * 1e3:.3f} ‰")
        state = form_find(cat)
        if progress:
            progress(f"{cat.name}: elasticity at {', '.join(f'{f:g}' for f in levels)} N")
        return build_path_model(state, section_elasticity(state, force_levels=levels, elasticity_method="active-set"))

    path = path_at(catenary)
    if relinearise:
        first = robust_presag(path, scenarios)
        path = path_at(catenary.with_presag(first.presag_rel))
    parabola = robust_presag(path, scenarios)
    design = parabola if (shape == "parabola" and risk.measure == "minimax") else robust_presag(
        path, scenarios, shape=shape, risk=risk, buildability=buildability
    )
    centre = 0.5 * (low + high)
    nominal_rel = path.section.presag(centre, "delta-e").presag_rel_mean
    nominal = evaluate_design(path, path.parabola_depths(nominal_rel), scenarios, shape="parabola", risk=risk,
                              presag_rel=nominal_rel, risk_label="nominal")
    single = ForceScenarios(forces=np.array([centre]), weights=np.array([1.0]))
    lengths = catenary.layout.span_lengths
    reference = lengths[path.spans[0]] if len(set(lengths)) == 1 else max(lengths)
    return RobustStudy(
        catenary_name=catenary.name,
        path=path,
        scenarios=scenarios,
        robust=design,
        robust_parabola=parabola,
        nominal=nominal,
        tolerance=tolerance_band(path, scenarios, within),
        nominal_tolerance=tolerance_band(path, single, within),
        reference_span=float(reference),
    )


# ----- dynamic check ------------------------------------------------------------------------------


@dataclass(frozen=True, kw_only=True)
class DynamicRun:
    """One simulated run of a design: operating point and EN 50367 statistics.

    Attributes
    ----------
    design : str
        Design label.
    presag : float
        Mid-span pre-sag on the reference span. [m]
    static_force : float
        Static uplift force. [N]
    speed : float
        Train speed. [m/s]
    beta : float
        Speed over contact-wire wave speed. [-]
    mean_force : float
        Mean contact force F_m over the analysed section. [N]
    sigma_over_mean : float
        σ/F_m. [-]
    uplift_max : float
        Largest steady-arm uplift in the analysed section. [m]
    loss_of_contact : float
        Share of time without contact. [-]
    """

    design: str
    presag: float
    static_force: float
    speed: float
    beta: float
    mean_force: float
    sigma_over_mean: float
    uplift_max: float
    loss_of_contact: float


@dataclass(frozen=True, kw_only=True)
class DynamicCheck:
    """Dynamic runs of several designs over a grid of static forces and speeds.

    Attributes
    ----------
    runs : tuple of DynamicRun
        Every run.
    beta_limit : float
        Speed ratio separating the quasi-static regime (the paper's 0.4). [-]
    """

    runs: tuple[DynamicRun, ...]
    beta_limit: float = 0.4

    def summary(self) -> list[dict]:
        """Per design and regime: worst and mean σ/F_m, largest uplift, runs counted."""
        rows = []
        for design in dict.fromkeys(r.design for r in self.runs):
            for regime, inside in (("beta < %.2g" % self.beta_limit, True), ("beta >= %.2g" % self.beta_limit, False)):
                runs = [r for r in self.runs if r.design == design and (r.beta < self.beta_limit) == inside]
                if not runs:
                    continue
                ratio = np.array([r.sigma_over_mean for r in runs])
                rows.append({
                    "design": design,
                    "presag_mm": runs[0].presag * 1e3,
                    "regime": regime,
                    "runs": len(runs),
                    "worst_sigma_over_Fm": float(ratio.max()),
                    "mean_sigma_over_Fm": float(ratio.mean()),
                    "uplift_max_mm": float(max(r.uplift_max for r in runs) * 1e3),
                    "loss_of_contact_max_pct": float(max(r.loss_of_contact for r in runs) * 100),
                })
        return rows


def dynamic_check(
    catenary,
    designs: dict[str, float],
    *,
    pantograph,
    static_forces,
    speeds,
    aero_coefficient: float,
    reference_span: float,
    settings=None,
    progress=None,
) -> DynamicCheck:
    """Simulate each parabolic design over a grid of static forces and speeds.

    Parameters
    ----------
    catenary : Catenary
        System model; each design is form-found with its own pre-sag.
    designs : dict
        Label -> relative pre-sag S_rel. [-]
    pantograph : Pantograph
        Pantograph model.
    static_forces : sequence of float
        Static uplift forces. [N]
    speeds : sequence of float
        Train speeds. [m/s]
    aero_coefficient : float
        α_ae. [N/(m/s)²]
    reference_span : float
        Span the pre-sag is quoted on. [m]
    settings : SimulationSettings, optional
        Numerical settings of the simulator.
    progress : callable, optional
        Called with a short message before each run.
    """
    from presag_opt.dynamics.simulate import simulate
    from presag_opt.static.equilibrium import form_find

    runs = []
    for label, presag_rel in designs.items():
        state = form_find(catenary.with_presag(presag_rel))
        for force in static_forces:
            for speed in speeds:
                if progress:
                    progress(f"{label}: F_stat {force:g} N, {speed * 3.6:g} km/h")
                result = simulate(state, pantograph, speed=speed, static_force=force,
                                  aero_coefficient=aero_coefficient, settings=settings)
                stats = result.statistics
                runs.append(DynamicRun(
                    design=label,
                    presag=presag_rel * reference_span,
                    static_force=float(force),
                    speed=float(speed),
                    beta=float(result.to_dict()["beta"]),
                    mean_force=stats.mean_force,
                    sigma_over_mean=stats.sigma_over_mean,
                    uplift_max=result.uplift_max,
                    loss_of_contact=stats.loss_of_contact,
                ))
    return DynamicCheck(runs=tuple(runs))
