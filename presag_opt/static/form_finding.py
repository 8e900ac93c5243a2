"""Form-finding: the dropper lengths and support settings that give the target contact-wire geometry.

:func:`form_find` runs the passes (the form-finding equations solved by IPOPT,
:mod:`presag_opt.static.form_finding_solver`, then a Newton relaxation of the full model,
:mod:`presag_opt.static.newton`), checks the result and returns the
:class:`~presag_opt.static.equilibrium.EquilibriumState`, reading it from the cache of form-found
states (:mod:`presag_opt.static.cache`) when one is set. :func:`dropper_height_sensitivity` is how the
form-found heights move with the dropper targets.
"""

from __future__ import annotations

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
from presag_opt.static.form_finding_equations import target_height_sensitivity
from presag_opt.static.form_finding_solver import solve_form_finding
from presag_opt.static.newton import force_tolerance, newton_equilibrium
from presag_opt.static.potential import PhysicalParameters
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
    same catenary, settings and code is read back instead.

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
        If ``catenary`` is not a :class:`Catenary` (e.g. a model name), or the geometry cannot be
        built: a dropper would have to push, or would be shorter than ``settings.min_dropper_length``.
    """
    if not isinstance(catenary, Catenary):
        hint = " (load a model first: form_find(load_catenary(name)))" if isinstance(catenary, str) else ""
        raise ModelError(f"catenary must be a Catenary, not {type(catenary).__name__} {catenary!r}{hint}")
    settings = settings or StaticSettings()
    if not isinstance(settings, StaticSettings):
        raise ModelError(f"settings must be a StaticSettings, not {type(settings).__name__}")
    key = cache.state_key(catenary, settings) if cache.active_directory() is not None else None
    if key is not None:
        state = cache.state_from_arrays(static_model(catenary, settings), cache.load(key))
        if state is not None:
            return state
    state = _form_find(catenary, settings)
    if key is not None:
        cache.store(key, cache.state_arrays(state))
    return state

def _form_find(catenary: Catenary, settings: StaticSettings) -> EquilibriumState:
    """:func:`form_find` without the cache."""
    model = static_model(catenary, settings)
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
    start = x_design
    iterations = 0
    # Pass 1 holds the wire nodes at their designed places along the wires; the 3-D relaxation
    # that follows lets them slide a little (on curves, enough to move the contact wire by a few
    # tenths of a millimetre), so a further pass starts from the relaxed places.
    for _ in range(FORM_FINDING_PASSES):
        solution = solve_form_finding(disc, params, wire_tension, target_dofs, start)
        params = _form_found_parameters(disc, params, solution, wire_tension, axial_stiffness)
        x, newton_iterations = newton_equilibrium(model, params, solution.positions.ravel(), settings)
        iterations += solution.iterations + newton_iterations
        if np.abs(x[target_dofs] - targets).max() <= settings.geometry_tolerance:
            break
        start = x.copy()
        start[target_dofs] = targets
    state = EquilibriumState(model, x.reshape(-1, 3), params, np.zeros(disc.n_dofs), iterations)
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

    A balance weight pulls with T along the track (a stitch wire, see below, with its given tension); where the end chord of a wire is turned by φ
    against the track (stagger, curve), balance along the track at the end (the steady arm lies in
    the mast plane) gives the wire a horizontal tension T/cos φ. The mid-point anchor separates the
    two halves, each set by its own end.
    """
    ax = disc.axial
    pos = disc.design_positions
    tension = np.zeros(len(ax))
    anchor = (len(disc.mast_station) - 1) // 2  # mast index of the mid-point anchor
    for group, nodes in ((CONTACT_WIRE, disc.cw_nodes), (MESSENGER_WIRE, disc.mw_nodes)):
        segments = np.flatnonzero(ax.group == group)  # in order along the wire
        if not len(segments):
            continue
        halves = []
        for end, inner in ((nodes[0], nodes[1]), (nodes[-1], nodes[-2])):
            chord = pos[end] - pos[inner]
            chord[2] = 0.0
            pull = disc.termination_force[3 * end : 3 * end + 3]
            cos_phi = float(pull @ chord) / (np.linalg.norm(pull) * np.linalg.norm(chord))
            halves.append(float(np.linalg.norm(pull)) / cos_phi)
        split = int(np.searchsorted(disc.cw_station, disc.mast_station[anchor]))
        tension[segments[:split]] = halves[0]
        tension[segments[split:]] = halves[1]
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
"""Form-finding passes at most (one on straight track, two on curves in practice). [-]"""


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


__all__ = ["dropper_height_sensitivity", "form_find"]
