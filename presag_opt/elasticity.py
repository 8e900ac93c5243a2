"""Elasticity of the contact wire along a span: uplift per unit upward point force.

Two independent methods:

- :func:`linear_elasticity` — from the tangent stiffness K at the form-found equilibrium (the
  Hessian of the CasADi potential): one sparse factorisation, one solve per contact-wire node of the
  span, then e(x) = N(x)ᵀ C N(x) + h t(1 − t)/T_CW with C the compliance block of those nodes, N the
  linear shape functions and the last term the string deflection inside the loaded element
  (:meth:`~presag_opt.static.discretisation.Discretisation.cw_element_compliance`), at any number of
  positions.
- :func:`nonlinear_elasticity` — equilibrium re-solved with the force F applied at each position,
  droppers free to go slack: e(x; F) = Δz(x)/F. Dropper unloading near the masts is the physical
  nonlinearity (Schick, Liu & Stichel 2025, Fig. 3).

Summary values follow the paper's notation: e_mid at mid-span, e_mast at the supports (mean of the
span's two ends), e_max, e_min, Δe = e_max − e_min, and the uniformity u = (e_max − e_min)/(e_max + e_min).

References
----------
Schick, Liu, Stichel, "Validity range of a quasi-static method for adjusting the pre-sag of simple
railway catenary systems", Railway Sciences (2025), doi:10.1108/RS-05-2025-0016, section 4.1, eq. (5).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from concurrent.futures import as_completed
from dataclasses import dataclass

import numpy as np

from presag_opt.errors import ModelError
from presag_opt.processes import WorkerPolicy, pool_available, worker_pool
from presag_opt.static.equilibrium import EquilibriumState
from presag_opt.static.linearised import TensionOnlyStructure

DEFAULT_FORCES = (50.0, 100.0, 150.0, 200.0)
"""Force levels of the nonlinear elasticity curves. [N]"""


@dataclass(frozen=True, kw_only=True)
class ElasticityCurve:
    """Elasticity along one span.

    Attributes
    ----------
    span : int
        Span index, from 0. [-]
    span_length : float
        Length of the span. [m]
    force : float or None
        Force of a nonlinear curve; None for the linear (tangent-stiffness) curve. [N]
    position : ndarray
        Distance from the span's first mast. [m]
    elasticity : ndarray
        Uplift per unit force at each position. [m/N]
    slack_droppers : ndarray of int or None
        Number of slack droppers in the section with the force at each position (nonlinear only).
    """

    span: int
    span_length: float
    force: float | None
    position: np.ndarray
    elasticity: np.ndarray
    slack_droppers: np.ndarray | None = None

    def at(self, position: float | np.ndarray) -> float | np.ndarray:
        """Elasticity interpolated at positions from the span's first mast. [m/N]"""
        return np.interp(position, self.position, self.elasticity)

    @property
    def e_mid(self) -> float:
        """Elasticity at mid-span. [m/N]"""
        return float(self.at(0.5 * self.span_length))

    @property
    def e_mast(self) -> float:
        """Elasticity at the supports: mean of the span's two ends. [m/N]"""
        return float(0.5 * (self.elasticity[0] + self.elasticity[-1]))

    @property
    def e_max(self) -> float:
        """Largest elasticity along the span. [m/N]"""
        return float(self.elasticity.max())

    @property
    def e_min(self) -> float:
        """Smallest elasticity along the span. [m/N]"""
        return float(self.elasticity.min())

    @property
    def delta_e(self) -> float:
        """Δe = e_max − e_min. [m/N]"""
        return self.e_max - self.e_min

    @property
    def uniformity(self) -> float:
        """u = (e_max − e_min)/(e_max + e_min). [-]"""
        return self.delta_e / (self.e_max + self.e_min)

    def summary_mm_per_N(self) -> dict[str, float | None]:
        """Summary values in mm/N (and the force in N), for tables and JSON."""
        return {
            "force_N": self.force,
            "e_mid_mm_per_N": self.e_mid * 1e3,
            "e_mast_mm_per_N": self.e_mast * 1e3,
            "e_max_mm_per_N": self.e_max * 1e3,
            "e_min_mm_per_N": self.e_min * 1e3,
            "delta_e_mm_per_N": self.delta_e * 1e3,
            "uniformity": self.uniformity,
        }


def span_positions(state: EquilibriumState, span: int, step: float) -> np.ndarray:
    """Positions from the span's first mast, both ends included, no more than ``step`` apart. [m]"""
    disc = state.discretisation
    n_spans = len(disc.mast_station) - 1
    if isinstance(span, bool) or not isinstance(span, (int, np.integer)) or not 0 <= span < n_spans:
        raise ModelError(
            f"span = {span!r} is outside the valid range [0, {n_spans - 1}] (span index from 0: 0 is the first span)"
        )
    if not 0.01 <= step <= 10.0:
        raise ModelError(f"step = {step:g} m is outside the valid range [0.01, 10] m")
    length = disc.mast_station[span + 1] - disc.mast_station[span]
    return np.linspace(0.0, length, int(np.ceil(length / step - 1e-9)) + 1)


def linear_elasticity(state: EquilibriumState, span: int | None = None, step: float = 0.1) -> ElasticityCurve:
    """Linear elasticity of a span from the tangent stiffness at the equilibrium state.

    Parameters
    ----------
    state : EquilibriumState
        Form-found (or loaded) equilibrium.
    span : int, optional
        Span index from 0 (0 is the first span, ``n_spans − 1`` the last); default the central span.
    step : float
        Largest distance between evaluation points. [m]

    Returns
    -------
    ElasticityCurve
        With ``force`` None.
    """
    disc = state.discretisation
    span = disc.catenary.layout.central_span if span is None else span
    positions = span_positions(state, span, step)
    stations = disc.mast_station[span] + positions
    local, vertical, rows = _vertical_load_shapes(state, stations)
    compliance = _node_rows(state.factorised_stiffness().solve(vertical), rows)
    elasticity = np.einsum("pi,ij,pj->p", local, compliance, local) + disc.cw_element_compliance(stations)
    return ElasticityCurve(
        span=span,
        span_length=float(positions[-1]),
        force=None,
        position=positions,
        elasticity=elasticity,
    )


METHODS = ("newton", "active-set")


def _vertical_load_shapes(state: EquilibriumState, stations: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Shape functions at the stations over the contact-wire nodes involved, and unit vertical loads.

    Returns ``local`` (stations × nodes), ``vertical`` (free DOFs × nodes): column j is a unit
    upward force on node j, or zero where that node is held vertically (its uplift is zero), and
    ``rows``: the free-DOF row of each node's vertical DOF, −1 where it is held (``vertical.T @ A``
    is ``_node_rows(A, rows)``).
    """
    disc = state.discretisation
    shape = disc.cw_shape(stations)
    nodes = np.unique(shape.indices)
    free = state.model.functions.free_dofs
    dofs = 3 * disc.cw_nodes[nodes] + 2
    rows = np.minimum(np.searchsorted(free, dofs), len(free) - 1)
    movable = free[rows] == dofs
    vertical = np.zeros((len(free), len(nodes)))
    vertical[rows[movable], np.flatnonzero(movable)] = 1.0
    return shape[:, nodes].toarray(), vertical, np.where(movable, rows, -1)


def _node_rows(matrix: np.ndarray, rows: np.ndarray) -> np.ndarray:
    """``vertical.T @ matrix`` by row selection: the rows of the nodes' vertical DOFs, zero where held
    (a dense product with the 0/1 matrix costs a second per span of a long section)."""
    out = np.zeros((len(rows), matrix.shape[1]))
    out[rows >= 0] = matrix[rows[rows >= 0]]
    return out


def nonlinear_elasticity(
    state: EquilibriumState,
    force: float,
    span: int | None = None,
    step: float = 0.5,
    method: str = "newton",
) -> ElasticityCurve:
    """Elasticity at a force level, droppers free to go slack.

    Parameters
    ----------
    state : EquilibriumState
        Form-found equilibrium (unloaded).
    force : float
        Upward contact force. [N]
    span : int, optional
        Span index from 0 (0 is the first span, ``n_spans − 1`` the last); default the central span.
    step : float
        Largest distance between evaluation points. [m]
    method : {"newton", "active-set"}
        ``"newton"`` re-solves the full nonlinear equilibrium with the force at each position
        (Newton's method on the potential energy, each position starting from the previous one).
        ``"active-set"`` solves the structure linearised about the unloaded state with tension-only
        droppers exactly (:class:`~presag_opt.static.linearised.TensionOnlyStructure`); it neglects
        only geometric nonlinearity and is meant for bulk studies.

    Raises
    ------
    ModelError
        If the force is not positive or implausibly large, or the method is unknown.
    ConvergenceError
        If an equilibrium re-solve (or the active-set iteration) fails.
    """
    if not 0.0 < force <= 2000.0:
        raise ModelError(f"force = {force:g} N is outside the valid range (0, 2000] N")
    if method not in METHODS:
        raise ModelError(f"method = {method!r} is not one of {', '.join(METHODS)}")
    disc = state.discretisation
    span = disc.catenary.layout.central_span if span is None else span
    positions = span_positions(state, span, step)
    stations = disc.mast_station[span] + positions
    if method == "active-set":
        uplift, slack = _active_set_uplift(state, stations, force)
    else:
        uplift, slack = _newton_uplift(state, stations, force)
    return ElasticityCurve(
        span=span,
        span_length=float(positions[-1]),
        force=float(force),
        position=positions,
        elasticity=uplift / force + disc.cw_element_compliance(stations),
        slack_droppers=slack,
    )


def _newton_uplift(state: EquilibriumState, stations: np.ndarray, force: float) -> tuple[np.ndarray, np.ndarray]:
    """Nodal-interpolated uplift [m] and slack-dropper count at each station, full re-solves."""
    disc = state.discretisation
    shape = disc.cw_shape(stations)
    z0 = state.positions[disc.cw_nodes, 2]
    uplift = np.empty(len(stations))
    slack = np.empty(len(stations), dtype=int)
    previous = state
    for i, station in enumerate(stations):
        loaded = state.solve(disc.cw_load_vector(station, force), start=previous)
        uplift[i] = float((shape[i] @ (loaded.positions[disc.cw_nodes, 2] - z0))[0])
        slack[i] = int(np.count_nonzero(loaded.dropper_forces() <= 0.0))
        previous = loaded
    return uplift, slack


def _active_set_uplift(state: EquilibriumState, stations: np.ndarray, force: float) -> tuple[np.ndarray, np.ndarray]:
    """Nodal-interpolated uplift [m] and slack-dropper count at each station under ``force``, on the
    structure linearised with tension-only droppers (each station starts from the previous slack set)."""
    structure = TensionOnlyStructure.of(state)
    load_compliance, load_influence = _load_terms(structure, stations)
    f0 = structure.preload
    uplift = np.empty(len(stations))
    slack_count = np.empty(len(stations), dtype=int)
    slack = np.zeros(len(f0), dtype=bool)
    for i, (c_pp, v_p) in enumerate(zip(load_compliance, load_influence)):
        slack, z = structure.slack_set(force * v_p, slack)
        s = np.flatnonzero(slack)
        uplift[i] = force * c_pp + v_p[s] @ f0[s] + v_p[s] @ z
        slack_count[i] = int(slack.sum())
    return uplift, slack_count


def _load_terms(structure: TensionOnlyStructure, stations: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """PᵀK⁻¹P and PᵀW for a unit load at each station; kept per set of stations, since every force
    level of a span uses the same ones."""
    state = structure.state
    cache = state._cache.setdefault("active_set_loads", {})
    key = np.asarray(stations, dtype=float).tobytes()
    if key not in cache:
        local, vertical, rows = _vertical_load_shapes(state, stations)
        compliance = _node_rows(state.factorised_stiffness().solve(vertical), rows)
        cache[key] = (
            np.einsum("pi,ij,pj->p", local, compliance, local),
            local @ _node_rows(structure.influence, rows),
        )
    return cache[key]


@dataclass(frozen=True, kw_only=True)
class ElasticityStudy:
    """Elasticity curves of one span at several force levels (and optionally the linear curve).

    Attributes
    ----------
    catenary_name : str
        Name of the system.
    span : int
        Span index, from 0. [-]
    curves : tuple of ElasticityCurve
        Nonlinear curves by increasing force, then the linear curve if computed.
    warnings : tuple of str
        Curves outside the model's physical validity (see :func:`uplift_warnings`).
    """

    catenary_name: str
    span: int
    curves: tuple[ElasticityCurve, ...]
    warnings: tuple[str, ...] = ()

    @property
    def nonlinear(self) -> tuple[ElasticityCurve, ...]:
        """Curves at force levels, by increasing force."""
        return tuple(c for c in self.curves if c.force is not None)

    @property
    def linear(self) -> ElasticityCurve | None:
        """The tangent-stiffness curve, if computed."""
        return next((c for c in self.curves if c.force is None), None)

    def to_dict(self) -> dict:
        """JSON-ready content: positions in m, elasticities in mm/N."""
        first = self.curves[0]
        return {
            "catenary": self.catenary_name,
            "span": self.span + 1,
            "span_length_m": first.span_length,
            "x_m": first.position.tolist(),
            "curves": [
                {
                    **c.summary_mm_per_N(),
                    "x_m": c.position.tolist(),
                    "elasticity_mm_per_N": (c.elasticity * 1e3).tolist(),
                    **({"slack_droppers": c.slack_droppers.tolist()} if c.slack_droppers is not None else {}),
                }
                for c in self.curves
            ],
            "warnings": list(self.warnings),
        }


def elasticity_study(
    state: EquilibriumState,
    *,
    span: int | None = None,
    forces: Sequence[float] = DEFAULT_FORCES,
    step: float = 0.5,
    linear: bool = False,
    linear_step: float = 0.1,
    method: str = "newton",
    progress: Callable[[str], None] | None = None,
    workers: int = 1,
) -> ElasticityStudy:
    """Nonlinear elasticity curves at several forces, and optionally the linear curve.

    Parameters
    ----------
    state : EquilibriumState
        Form-found equilibrium.
    span : int, optional
        Span index from 0 (0 is the first span, ``n_spans − 1`` the last); default the central span.
    forces : sequence of float
        Force levels. [N]
    step : float
        Point spacing of the nonlinear curves. [m]
    linear : bool
        Also compute the linear (tangent-stiffness) curve.
    linear_step : float
        Point spacing of the linear curve. [m]
    method : {"newton", "active-set"}
        Method of the nonlinear curves (see :func:`nonlinear_elasticity`).
    progress : callable, optional
        Called with a short message as the curves are computed.
    workers : int
        Processes for the nonlinear curves (forked, so only where ``fork`` is available; the curves
        are independent, the result is the same). [-]

    Returns
    -------
    ElasticityStudy
        With ``warnings`` for curves whose uplift the model cannot represent (:func:`uplift_warnings`).
    """
    span = state.catenary.layout.central_span if span is None else span
    if not forces and not linear:
        raise ModelError("forces is empty and linear is off: nothing to compute")
    levels = sorted(forces)
    if workers > 1 and len(levels) > 1 and pool_available(WorkerPolicy.INHERITED):
        curves = _parallel_curves(state, levels, span, step, method, workers, progress)
    else:
        curves = []
        for i, force in enumerate(levels):
            if progress:
                progress(f"elasticity at {force:g} N ({i + 1}/{len(levels)})")
            curves.append(nonlinear_elasticity(state, force, span, step, method))
    if linear:
        if progress:
            progress("linear elasticity")
        curves.append(linear_elasticity(state, span, linear_step))
    return ElasticityStudy(catenary_name=state.catenary.name, span=span, curves=tuple(curves),
                           warnings=uplift_warnings(curves, state.catenary.system_height))


_FORKED_STATE: list[EquilibriumState] = []
"""The state handed to forked workers (inherited, not pickled: it holds compiled CasADi functions)."""


def _forked_curve(force: float, span: int, step: float, method: str) -> ElasticityCurve:
    return nonlinear_elasticity(_FORKED_STATE[0], force, span, step, method)


def _parallel_curves(state, levels, span, step, method, workers, progress) -> list[ElasticityCurve]:
    """The nonlinear curves of :func:`elasticity_study`, one forked process per level at a time."""
    _FORKED_STATE[:] = [state]
    try:
        with worker_pool(min(workers, len(levels)), WorkerPolicy.INHERITED) as pool:
            futures = [pool.submit(_forked_curve, force, span, step, method) for force in levels]
            for done, _ in enumerate(as_completed(futures), start=1):
                if progress:
                    progress(f"elasticity curves done: {done}/{len(levels)}")
            return [f.result() for f in futures]
    finally:
        _FORKED_STATE.clear()


def uplift_warnings(curves: Sequence[ElasticityCurve], system_height: float) -> tuple[str, ...]:
    """One line per nonlinear curve whose largest uplift F·e_max reaches the system height.

    The model has no contact between the wires: an uplift of the contact wire that reaches the
    messenger wire (the system height above it at the supports) is outside its validity. Such a
    curve is still returned, with this warning, since the elasticity up to that point is sound.

    Parameters
    ----------
    curves : sequence of ElasticityCurve
        Curves to check (the linear one has no force and is skipped).
    system_height : float
        Messenger wire above the contact wire at the supports. [m]
    """
    return tuple(
        f"F = {c.force:g} N lifts the contact wire by up to {c.force * c.e_max * 1e3:.0f} mm, beyond the system "
        f"height {system_height * 1e3:.0f} mm; the model (no contact between the wires) is not valid there"
        for c in curves
        if c.force is not None and c.force * c.e_max >= system_height
    )
