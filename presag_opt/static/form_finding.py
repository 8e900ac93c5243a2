"""Form-finding: the dropper lengths and support settings that give the target contact-wire geometry.

:func:`form_find` runs the passes (the form-finding equations solved by IPOPT,
:mod:`presag_opt.static.form_finding_solver`, then a Newton relaxation of the full model,
:mod:`presag_opt.static.equilibrium_newton`), checks the result and returns the
:class:`~presag_opt.static.equilibrium.EquilibriumState`, reading it from the cache of form-found
states (:mod:`presag_opt.static.cache`) when one is set, with its solver statistics
(:mod:`presag_opt.static.solver_statistics`). :func:`check_form_finding_inputs` refuses, before any
solve, a section that has no form-found state. :func:`dropper_height_sensitivity` is how the
form-found heights move with the dropper targets.
"""

from __future__ import annotations

import time

import numpy as np

from presag_opt.errors import ConvergenceError, ModelError
from presag_opt.static import cache
from presag_opt.static.discretisation import (
    CONTACT_WIRE,
    DROPPER,
    MESSENGER_WIRE,
    STITCH_WIRE,
    Discretisation,
    StaticSettings,
)
from presag_opt.static.equilibrium import EquilibriumState, static_model
from presag_opt.static.equilibrium_newton import force_tolerance, newton_equilibrium
from presag_opt.static.form_finding_equations import target_height_sensitivity
from presag_opt.static.form_finding_solver import interrupts_kept, solve_form_finding
from presag_opt.static.potential import PhysicalParameters
from presag_opt.static.solver_statistics import FormFindingStatistics, record
from presag_opt.system.catenary import Catenary


def form_find(catenary: Catenary, settings: StaticSettings | None = None) -> EquilibriumState:
    """Find the dropper lengths and support settings that give the target contact-wire geometry.

    Target: the contact wire at its designed height at every support and on the pre-sag parabola
    (zero at the masts, ``presag_rel · l`` at mid-span) at every dropper (stitch droppers too), at
    its stagger at every steady arm, under gravity, with both wires at their balance-weight tension
    and any stitch wire at its given (horizontal) tension: like the wires' segments, the stitch
    wire's get the unstretched lengths that carry that tension in the form-found shape. Solved with IPOPT
    as one square system (see :func:`presag_opt.static.form_finding_solver.solve_form_finding`). With a cache
    folder in the runtime in force (:attr:`presag_opt.runtime.Runtime.state_cache`), a state form-found before for the
    same catenary, settings and code is read back instead. The state carries the solve's statistics
    (:attr:`~presag_opt.static.equilibrium.EquilibriumState.form_finding`), also given to an open
    :func:`~presag_opt.static.solver_statistics.recording`.

    Parameters
    ----------
    catenary : Catenary
        System model.
    settings : StaticSettings, optional
        Numerical settings.

    Returns
    -------
    EquilibriumState
        The form-found equilibrium (droppers tension-only from here on).

    Raises
    ------
    ConvergenceError
        If IPOPT fails or the result misses the equilibrium or geometry tolerance.
    ModelError
        If ``catenary`` is not a :class:`Catenary` (e.g. a model name); before any solve, what
        :func:`check_form_finding_inputs` refuses; after it, a dropper that would have to push or is
        shorter than ``settings.min_dropper_length``.
    """
    if not isinstance(catenary, Catenary):
        hint = " (load a model first: form_find(load_catenary(name)))" if isinstance(catenary, str) else ""
        raise ModelError(f"catenary must be a Catenary, not {type(catenary).__name__} {catenary!r}{hint}")
    settings = settings or StaticSettings()
    if not isinstance(settings, StaticSettings):
        raise ModelError(f"settings must be a StaticSettings, not {type(settings).__name__}")
    key = cache.state_key(catenary, settings) if cache.active_directory() is not None else None
    # CasADi swallows a Ctrl-C that lands inside it (building the model's functions, the solver, the
    # solve) and goes on: kept here and raised once the work returns (form_finding_solver.interrupts_kept)
    with interrupts_kept():
        if key is not None:
            state = cache.state_from_arrays(static_model(catenary, settings), cache.load(key))
            if state is not None:
                record(state.form_finding)
                return state
        state = _form_find(catenary, settings)
    record(state.form_finding)
    if key is not None:
        cache.store(key, cache.state_arrays(state))
    return state


def check_form_finding_inputs(catenary: Catenary, settings: StaticSettings | None = None) -> None:
    """Refuse, before any solve, a section that has no form-found state, in one line that says where and why.

    The discretisation refuses (:func:`~presag_opt.static.discretisation.discretise`): a steady arm the
    contact wire does not pull sideways (no vertical stiffness,
    :func:`~presag_opt.static.section_geometry.steady_arm_pivots`), and a dropper that cannot be cut
    (:func:`~presag_opt.static.section_geometry.check_dropper_room`). :func:`form_find` checks the same
    first.

    Parameters
    ----------
    catenary : Catenary
        System model.
    settings : StaticSettings, optional
        Numerical settings (``min_dropper_length``).

    Raises
    ------
    ModelError
        The section cannot be form-found, with the reason.
    """
    static_model(catenary, settings or StaticSettings())


def _form_find(catenary: Catenary, settings: StaticSettings) -> EquilibriumState:
    """:func:`form_find` without the cache."""
    started = time.perf_counter()
    model = static_model(catenary, settings)  # refuses what check_form_finding_inputs refuses
    disc = model.discretisation
    ax = disc.axial
    x_design = disc.design_positions.ravel()

    wire_tension = _horizontal_wire_tension(disc)
    axial_stiffness = {CONTACT_WIRE: catenary.contact_wire.axial_stiffness,
                       MESSENGER_WIRE: catenary.messenger_wire.axial_stiffness}
    if catenary.stitch_wire is not None:
        axial_stiffness[STITCH_WIRE] = catenary.stitch_wire.axial_stiffness
    # First guess of the dropper preload: the contact-wire weight between neighbouring droppers.
    first_guess = ax.design_length.copy()
    drop_station = disc.cw_station[np.searchsorted(disc.cw_nodes, ax.node_a[disc.dropper_elements])]
    tributary = np.gradient(drop_station) if len(drop_station) > 1 else np.ones(1)
    preload = 9.81 * catenary.contact_wire.mass_per_length * np.abs(tributary)
    first_guess[disc.dropper_elements] -= preload / ax.stiffness[disc.dropper_elements]
    params = PhysicalParameters(
        axial_stiffness=ax.stiffness,
        unstretched_length=first_guess,
        slack_allowed=np.zeros(len(ax)),
        bending_stiffness=disc.bending.bending_stiffness,
        spring_stiffness=disc.spring_stiffness,
        spring_reference=x_design[disc.spring_dofs],
        nodal_force=disc.gravity_force() + disc.termination_force,
    )
    target_dofs = _target_dofs(disc)
    targets = x_design[target_dofs]
    start, aim = x_design, targets
    ipopt_iterations = newton_iterations = restarts = passes = 0
    # The form-finding equations hold the wire nodes at their places along the wires and take the
    # wires as strings; the full model's relaxation that follows lets the nodes slide and bend, and
    # moves the targets by what that leaves out (bending at the kinks in plan, next to a soft
    # push-off arm by up to about 0.1 mm). That shift hardly depends on the targets, so a further
    # pass aims at the targets less the shift the last one left, from the relaxed places.
    for _ in range(FORM_FINDING_PASSES):
        passes += 1
        solution = solve_form_finding(disc, params, wire_tension, target_dofs, start)
        params = _form_found_parameters(disc, params, solution, wire_tension, axial_stiffness)
        x, relaxation = newton_equilibrium(model, params, solution.positions.ravel(), settings)
        ipopt_iterations += solution.iterations
        restarts += solution.restarts
        newton_iterations += relaxation
        miss = x[target_dofs] - targets
        if np.abs(miss).max() <= settings.geometry_tolerance:
            break
        aim = aim - miss
        start = x.copy()
        start[target_dofs] = aim
    statistics = FormFindingStatistics(passes=passes, ipopt_iterations=ipopt_iterations,
                                       newton_iterations=newton_iterations, restarts=restarts,
                                       seconds=time.perf_counter() - started)
    state = EquilibriumState(model, x.reshape(-1, 3), params, np.zeros(disc.n_dofs),
                             ipopt_iterations + newton_iterations, statistics)
    _check_form_found(state, target_dofs, targets)
    return state


def _target_dofs(disc: Discretisation) -> np.ndarray:
    """Heights held by form-finding: contact wire at every dropper (first, in dropper order) and at
    every support, messenger wire at spring supports."""
    drop_cw = disc.axial.node_a[disc.dropper_elements]
    mw_springs = disc.spring_dofs[np.isin(disc.spring_dofs // 3, disc.mast_mw_node)]
    return np.concatenate([3 * drop_cw + 2, 3 * disc.mast_cw_node + 2, mw_springs]).astype(int)


def dropper_height_sensitivity(state: EquilibriumState) -> np.ndarray:
    """How the node heights of a form-found state move with the dropper target heights.

    The CasADi Jacobian of the form-finding equations at the solution (implicit-function theorem,
    :func:`presag_opt.static.form_finding_equations.target_height_sensitivity`). Column j is the change of every
    contact-wire node height per metre the target at dropper j is raised: 1 at that dropper, the
    span between it and its neighbours following (with the small coupling that bending adds).

    Returns
    -------
    ndarray, shape (n_nodes, n_droppers)
        ∂z/∂z_target of every node for the droppers in along-track order. [m/m]
    """
    disc = state.discretisation
    if state.memo.dropper_sensitivity is None:
        full = target_height_sensitivity(
            disc, state.params, _horizontal_wire_tension(disc), _target_dofs(disc), state.positions
        )
        state.memo.dropper_sensitivity = full[:, : len(disc.dropper_elements)]
    return state.memo.dropper_sensitivity


def _horizontal_wire_tension(disc: Discretisation) -> np.ndarray:
    """Horizontal tension of every wire segment in the design state (0 for other elements). [N]

    Between two masts a wire is a straight chord in plan, loaded only vertically (weights, droppers)
    and across (sideways moves), so its horizontal tension H is one value per span. At a mast the
    steady arm and the messenger-wire pin hold the wire in the mast plane only, so the wire's pull
    along the track balances there: H·cos φ is the same on both sides, φ the angle of each side's
    chord to the track at that mast (stagger change, curve). At a section end the balance weight
    pulls with T along the track: H = T/cos φ. So H passes from the ends inwards, span by span; the
    mid-point anchor, which takes the difference, separates the two halves. (A stitch wire is held
    at its own tension, see below.)
    """
    ax = disc.axial
    pos = disc.design_positions
    tension = np.zeros(len(ax))
    n_spans = len(disc.mast_station) - 1
    anchor = n_spans // 2  # mast index of the mid-point anchor
    chord = np.diff(pos[disc.mast_cw_node, :2], axis=0)
    chord /= np.linalg.norm(chord, axis=1)[:, None]
    track = np.column_stack([disc.mast_normal[:, 1], -disc.mast_normal[:, 0]])  # along the track at each mast
    cos_near = np.abs(np.sum(chord * track[:-1], axis=1))  # each span's chord against the track at its first mast
    cos_far = np.abs(np.sum(chord * track[1:], axis=1))  # ... and at its second
    per_tension = np.empty(n_spans)  # H/T of every span
    per_tension[0] = 1.0 / cos_near[0]
    for span in range(1, anchor):
        per_tension[span] = per_tension[span - 1] * cos_far[span - 1] / cos_near[span]
    per_tension[-1] = 1.0 / cos_far[-1]
    for span in range(n_spans - 2, anchor - 1, -1):
        per_tension[span] = per_tension[span + 1] * cos_near[span + 1] / cos_far[span]
    span_of_node = np.clip(np.searchsorted(disc.mast_station, disc.cw_station, side="right") - 1, 0, n_spans - 1)
    for group, nodes in ((CONTACT_WIRE, disc.cw_nodes), (MESSENGER_WIRE, disc.mw_nodes)):
        segments = np.flatnonzero(ax.group == group)  # in order along the wire, segment j from node j
        if not len(segments):
            continue
        pull = float(np.linalg.norm(disc.termination_force[3 * nodes[0] : 3 * nodes[0] + 3]))
        tension[segments] = pull * per_tension[span_of_node[: len(segments)]]
    if disc.catenary is not None and disc.catenary.stitch_wire is not None:
        # A stitch wire is held at the tension given for it: form-finding finds the unstretched
        # length of each of its segments that carries that horizontal tension in the found shape.
        # The messenger wire slides along the track at the mast, so between the two clamps it
        # carries its own tension less the stitch wire's (along-track balance at each clamp).
        stitch_tension = disc.catenary.stitch_wire.tension
        tension[ax.group == STITCH_WIRE] = stitch_tension
        mw_segments = np.flatnonzero(ax.group == MESSENGER_WIRE)
        first_mw = disc.mw_nodes[0]
        for chain in disc.stitch_chains:
            tension[mw_segments[chain[0] - first_mw : chain[-1] - first_mw]] -= stitch_tension
    return tension


FORM_FINDING_PASSES = 3
"""Form-finding passes at most (one in practice; a second where the relaxation moves a target by more
than the geometry tolerance). [-]"""


def _form_found_parameters(disc, params, solution, wire_tension, axial_stiffness) -> PhysicalParameters:
    """Element lengths after a form-finding pass.

    Wire segments get the unstretched length that carries the horizontal tension H in the
    form-found shape (N = H·L/l_h and N = EA (L − L0)/L0); droppers get the solved lengths; the
    droppers become tension-only.
    """
    ax = disc.axial
    positions = solution.positions
    lengths = np.linalg.norm(positions[ax.node_b] - positions[ax.node_a], axis=1)
    horizontal = np.linalg.norm(positions[ax.node_b, :2] - positions[ax.node_a, :2], axis=1)
    unstretched = params.unstretched_length.copy()
    stiffness = params.axial_stiffness.copy()
    for group, ea in axial_stiffness.items():
        sel = ax.group == group
        force = wire_tension[sel] * lengths[sel] / horizontal[sel]
        unstretched[sel] = lengths[sel] * ea / (ea + force)
        stiffness[sel] = ea / unstretched[sel]
    unstretched[disc.dropper_elements] = solution.dropper_unstretched_length
    return PhysicalParameters(
        **{**params.__dict__, "axial_stiffness": stiffness, "unstretched_length": unstretched,
           "slack_allowed": (ax.group == DROPPER).astype(float), "spring_reference": solution.spring_reference}
    )


def _check_form_found(state: EquilibriumState, target_dofs: np.ndarray, targets: np.ndarray) -> None:
    disc = state.discretisation
    settings = disc.settings
    stretch = state.element_lengths()[disc.dropper_elements] - state.params.unstretched_length[disc.dropper_elements]
    pushing = np.flatnonzero(stretch <= 0.0)
    if len(pushing):
        i = pushing[0]
        raise ModelError(
            f"form-finding: the dropper in span {disc.dropper_span[i] + 1} at {disc.dropper_position[i]:.2f} m would "
            "have to push to hold the target geometry (pre-sag too large for this system?)"
        )
    lengths = state.dropper_lengths()
    short = np.flatnonzero(lengths < settings.min_dropper_length)
    if len(short):
        i = short[0]
        raise ModelError(
            f"form-finding: the dropper in span {disc.dropper_span[i] + 1} at {disc.dropper_position[i]:.2f} m is "
            f"{lengths[i] * 1e3:.0f} mm long, shorter than settings.min_dropper_length = "
            f"{settings.min_dropper_length * 1e3:.0f} mm (messenger wire sags too low for this system height)"
        )
    residual = np.abs(state.out_of_balance()).max()
    miss = np.abs(state.positions.ravel()[target_dofs] - targets).max()
    tolerance = force_tolerance(state.params, state.positions.ravel(), settings)
    if residual > tolerance or miss > settings.geometry_tolerance:
        raise ConvergenceError(
            f"form-finding result misses its tolerances: out-of-balance {residual:.3g} N "
            f"(tolerance {tolerance:.3g} N), geometry {miss:.3g} m (tolerance {settings.geometry_tolerance:g} m)",
            {"residual_N": residual, "geometry_error_m": miss},
        )


__all__ = ["check_form_finding_inputs", "dropper_height_sensitivity", "form_find"]
