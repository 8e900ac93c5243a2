"""The two elasticity methods: the tangent stiffness (linear) and the re-solved equilibrium (nonlinear).

- :func:`linear_elasticity` — from the tangent stiffness K at the form-found equilibrium: one
  factorisation, one solve per contact-wire node of the span (all at once), then
  e(x) = N(x)ᵀ C N(x) + h t(1 − t)/T_CW with C the compliance block of those nodes, N the linear shape
  functions and the last term the string deflection inside the loaded element.
- :func:`nonlinear_elasticity` — the equilibrium with the force F applied at each position, droppers
  free to go slack: e(x; F) = Δz(x)/F, by Newton's method on the full model (``"newton"``) or on the
  structure linearised with tension-only droppers (``"active-set"``).
"""

from __future__ import annotations

import numpy as np

from presag_opt.elasticity.curves import ElasticityCurve
from presag_opt.errors import ModelError
from presag_opt.static.equilibrium import EquilibriumState
from presag_opt.static.linearised import TensionOnlyStructure, dropper_axial_force, dropper_slack


def span_positions(state: EquilibriumState, span: int, step: float) -> np.ndarray:
    """Positions from the span's first mast, both ends included, no more than ``step`` apart. [m]

    Parameters
    ----------
    state : EquilibriumState
        The equilibrium state (its discretisation).
    span : int
        Span index from 0. [-]
    step : float
        Largest spacing of the positions, 0.01 to 10. [m]
    """
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
        Span index from 0 (0 is the first span, ``n_spans − 1`` the last); default the central span. [-]
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
    local, rows = _vertical_load_shapes(state, stations)
    compliance = _node_compliance(state, rows)
    elasticity = np.einsum("pi,ij,pj->p", local, compliance, local) + disc.cw_element_compliance(stations)
    return ElasticityCurve(
        span=span,
        span_length=float(positions[-1]),
        force=None,
        position=positions,
        elasticity=elasticity,
    )


METHODS = ("newton", "active-set")


def _vertical_load_shapes(state: EquilibriumState, stations: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Shape functions at the stations over the contact-wire nodes involved, and those nodes' rows.

    Returns ``local`` (stations × nodes) and ``rows``: the free-DOF row of each node's vertical DOF,
    −1 where the node is held vertically (its uplift is zero).
    """
    disc = state.discretisation
    shape = disc.cw_shape(stations)
    nodes = np.unique(shape.indices)
    free = state.model.functions.free_dofs
    dofs = 3 * disc.cw_nodes[nodes] + 2
    rows = np.minimum(np.searchsorted(free, dofs), len(free) - 1)
    movable = free[rows] == dofs
    return shape[:, nodes].toarray(), np.where(movable, rows, -1)


def _node_compliance(state: EquilibriumState, rows: np.ndarray) -> np.ndarray:
    """Vertical compliance between the nodes: K⁻¹ at their vertical DOFs ``rows``, zero in the row
    and column of a held node (−1). [m/N]"""
    movable = rows >= 0
    out = np.zeros((len(rows), len(rows)))
    out[np.ix_(movable, movable)] = state.factorised_stiffness().inverse_block(rows[movable])
    return out


def _node_rows(matrix: np.ndarray, rows: np.ndarray) -> np.ndarray:
    """The rows of ``matrix`` at the nodes' vertical DOFs ``rows``, zero for a held node (−1)."""
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
        Span index from 0 (0 is the first span, ``n_spans − 1`` the last); default the central span. [-]
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
        slack[i] = loaded.slack_dropper_count()
        previous = loaded
    return uplift, slack


def _active_set_uplift(state: EquilibriumState, stations: np.ndarray, force: float) -> tuple[np.ndarray, np.ndarray]:
    """Nodal-interpolated uplift [m] and slack-dropper count at each station under ``force``, on the
    structure linearised with tension-only droppers (each station starts from the previous slack set)."""
    structure = TensionOnlyStructure.of(state)
    load_compliance, load_influence = _load_terms(structure, stations)
    f0 = structure.preload
    # stations where every dropper stays taut: the test slack_set makes first from an empty slack set,
    # made for all stations at once (with a taut start and no slack dropper the answer is z = 0)
    taut = ~dropper_slack(dropper_axial_force(f0, structure.stiffness, force * load_influence, 0.0, 0.0)).any(axis=1)
    uplift = np.empty(len(stations))
    slack_count = np.empty(len(stations), dtype=int)
    slack = np.zeros(len(f0), dtype=bool)
    for i, (c_pp, v_p) in enumerate(zip(load_compliance, load_influence)):
        if taut[i] and not slack.any():
            z = np.zeros(0)  # what slack_set returns at once from an empty set here
        else:
            slack, z = structure.slack_set(force * v_p, slack)
        s = np.flatnonzero(slack)
        uplift[i] = force * c_pp + v_p[s] @ f0[s] + v_p[s] @ z
        slack_count[i] = int(slack.sum())
    return uplift, slack_count


def _load_terms(structure: TensionOnlyStructure, stations: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """PᵀK⁻¹P and PᵀW for a unit load at each station; kept per set of stations, since every force
    level of a span uses the same ones."""
    state = structure.state
    cache = state.memo.unit_load_terms
    key = np.asarray(stations, dtype=float).tobytes()
    if key not in cache:
        local, rows = _vertical_load_shapes(state, stations)
        compliance = _node_compliance(state, rows)
        cache[key] = (
            np.einsum("pi,ij,pj->p", local, compliance, local),
            local @ _node_rows(structure.influence, rows),
        )
    return cache[key]
