"""Form-finding and static equilibrium of a catenary section.

:func:`form_find` computes the dropper lengths, steady-arm settings (and spring references) that put
the contact wire at its target geometry under gravity, with both wires at their balance-weight
tension, and returns the :class:`EquilibriumState`. :meth:`EquilibriumState.solve` re-solves the
equilibrium under extra loads (droppers free to go slack) by Newton's method on the potential energy;
:meth:`EquilibriumState.tangent_stiffness` gives the linear stiffness at the state.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass, field, fields

import numpy as np
import scipy.sparse as sp

from presag_opt.errors import ConvergenceError, ModelError
from presag_opt.static import cache
from presag_opt.static.banded_solver import Factor
from presag_opt.static.discretisation import (
    CONTACT_WIRE,
    DROPPER,
    MESSENGER_WIRE,
    STEADY_ARM,
    Discretisation,
    StaticSettings,
    discretise,
    discretise_lone_wire,
)
from presag_opt.static.symbolic import (
    PhysicalParameters,
    PotentialFunctions,
    build_potential,
    solve_form_finding,
    target_height_sensitivity,
)
from presag_opt.system.catenary import Catenary, Damping, Wire


@dataclass(frozen=True)
class StaticModel:
    """A discretised catenary with its compiled potential-energy functions (built once, reused)."""

    discretisation: Discretisation
    functions: PotentialFunctions


def static_model(catenary: Catenary, settings: StaticSettings | None = None) -> StaticModel:
    """Discretise a catenary and build its CasADi functions (cached per catenary and settings)."""
    return _static_model(catenary, settings or StaticSettings())


@functools.lru_cache(maxsize=16)
def _static_model(catenary: Catenary, settings: StaticSettings) -> StaticModel:
    disc = discretise(catenary, settings)
    return StaticModel(disc, build_potential(disc))


@dataclass(frozen=True, kw_only=True)
class DropperScheduleRow:
    """One dropper as a line crew needs it.

    Attributes
    ----------
    span : int
        Span number, counted from 1 at the start of the section. [-]
    position_m : float
        Distance from the span's first mast. [m]
    length_mm : float
        Dropper length between the clamp points, unloaded (cut length), rounded to 1 mm. [mm]
    installed_length_mm : float
        Length between the clamp points under the static load. [mm]
    force_N : float
        Static tensile force. [N]
    """

    span: int
    position_m: float
    length_mm: float
    installed_length_mm: float
    force_N: float


@dataclass(frozen=True)
class EquilibriumState:
    """A static equilibrium of a catenary section.

    Attributes
    ----------
    model : StaticModel
        Discretisation and compiled functions.
    positions : ndarray, shape (n_nodes, 3)
        Node coordinates. [m]
    params : PhysicalParameters
        Element lengths, stiffnesses and the external nodal forces of this state.
    applied_load : ndarray
        Nodal forces applied on top of gravity and the balance weights. [N]
    iterations : int
        Solver iterations that produced this state. [-]
    """

    model: StaticModel
    positions: np.ndarray
    params: PhysicalParameters
    applied_load: np.ndarray
    iterations: int = 0
    _cache: dict = field(default_factory=dict, repr=False, compare=False)

    # ----- derived quantities -------------------------------------------------------------------

    @property
    def discretisation(self) -> Discretisation:
        """The discretisation."""
        return self.model.discretisation

    @property
    def catenary(self) -> Catenary:
        """The system model."""
        return self.model.discretisation.catenary

    def element_lengths(self) -> np.ndarray:
        """Current length of every axial element. [m]"""
        ax = self.discretisation.axial
        return np.linalg.norm(self.positions[ax.node_b] - self.positions[ax.node_a], axis=1)

    def axial_forces(self) -> np.ndarray:
        """Tensile force of every axial element (zero in a slack dropper). [N]"""
        stretch = self.element_lengths() - self.params.unstretched_length
        force = self.params.axial_stiffness * stretch
        slack = (self.params.slack_allowed > 0) & (force < 0)
        return np.where(slack, 0.0, force)

    def horizontal_tension(self, group: int) -> np.ndarray:
        """Along-track component of the force in each element of a wire (group). [N]"""
        ax = self.discretisation.axial
        sel = ax.group == group
        d = self.positions[ax.node_b[sel]] - self.positions[ax.node_a[sel]]
        return self.axial_forces()[sel] * np.linalg.norm(d[:, :2], axis=1) / np.linalg.norm(d, axis=1)

    def dropper_forces(self) -> np.ndarray:
        """Tensile force of each dropper, in along-track order. [N]"""
        return self.axial_forces()[self.discretisation.dropper_elements]

    def dropper_lengths(self) -> np.ndarray:
        """Current length of each dropper between its clamps. [m]"""
        return self.element_lengths()[self.discretisation.dropper_elements]

    def steady_arm_forces(self) -> np.ndarray:
        """Tensile force of each steady arm. [N]"""
        return self.axial_forces()[self.discretisation.arm_elements]

    def steady_arm_angles(self) -> np.ndarray:
        """Inclination of each steady arm, positive with the pivot above the clamp. [rad]"""
        disc = self.discretisation
        ax = disc.axial
        d = self.positions[ax.node_b[disc.arm_elements]] - self.positions[ax.node_a[disc.arm_elements]]
        return np.arctan2(d[:, 2], np.linalg.norm(d[:, :2], axis=1))

    def dropper_schedule(self) -> list[DropperScheduleRow]:
        """The dropper schedule: span, position, cut length and force of every dropper."""
        disc = self.discretisation
        lengths = self.dropper_lengths()
        unstretched = self.params.unstretched_length[disc.dropper_elements]
        forces = self.dropper_forces()
        return [
            DropperScheduleRow(
                span=int(span) + 1,
                position_m=float(pos),
                length_mm=float(np.round(l0 * 1e3)),
                installed_length_mm=float(length * 1e3),
                force_N=float(f),
            )
            for span, pos, l0, length, f in zip(disc.dropper_span, disc.dropper_position, unstretched, lengths, forces)
        ]

    # ----- linear algebra -------------------------------------------------------------------------

    def tangent_stiffness(self) -> sp.csc_matrix:
        """Tangent stiffness on the free degrees of freedom at this state. [N/m]"""
        return self.model.functions.solver.matrix(self._stiffness_values())

    def _stiffness_values(self) -> np.ndarray:
        if "stiffness" not in self._cache:
            self._cache["stiffness"], _ = self.model.functions.hessian_values(self.positions.ravel(), self.params)
        return self._cache["stiffness"]

    def factorised_stiffness(self) -> Factor:
        """Factorisation of :meth:`tangent_stiffness` (computed once per state)."""
        if "factor" not in self._cache:
            self._cache["factor"] = self.model.functions.solver.factorise(self._stiffness_values())
        return self._cache["factor"]

    def out_of_balance(self) -> np.ndarray:
        """Out-of-balance force on the free degrees of freedom. [N]"""
        return self.model.functions.gradient(self.positions.ravel(), self.params)[self.model.functions.free_dofs]

    # ----- re-solving ---------------------------------------------------------------------------

    def solve(self, load: np.ndarray, start: "EquilibriumState | None" = None) -> "EquilibriumState":
        """Equilibrium under an extra nodal load, droppers free to go slack.

        Parameters
        ----------
        load : ndarray, shape (3 n_nodes,)
            Extra nodal forces on top of gravity and the balance weights. [N]
        start : EquilibriumState, optional
            State to start Newton's method from (default: this state).

        Raises
        ------
        ConvergenceError
            If Newton's method does not reach the force tolerance.
        """
        params = _replace_force(self.params, self.params.nodal_force - self.applied_load + load)
        start = start or self
        terms = start._cache.get("terms")
        if terms is not None:
            # The start's out-of-balance force moves by the change of the external force; its
            # factorisation does not depend on the load.
            free = self.model.functions.free_dofs
            terms = NewtonTerms(terms.gradient + (start.params.nodal_force - params.nodal_force)[free], terms.factor)
        x, iterations, final = _newton(self.model, params, start.positions.ravel(), self.discretisation.settings, terms)
        state = EquilibriumState(self.model, x.reshape(-1, 3), params, np.asarray(load, dtype=float), iterations)
        state._cache["terms"] = final
        return state


def _replace_force(params: PhysicalParameters, force: np.ndarray) -> PhysicalParameters:
    return PhysicalParameters(**{**params.__dict__, "nodal_force": force})


ROUND_OFF_FACTOR = 16.0
"""Multiple of machine epsilon in the round-off floor of the force tolerance. [-]"""


def force_tolerance(params: PhysicalParameters, x: np.ndarray, settings: StaticSettings) -> float:
    """Out-of-balance force accepted at equilibrium. [N]

    ``settings.force_tolerance``, but never below the round-off of the nodal forces: an element of
    stiffness k between nodes at coordinates of size |x| cannot balance better than about
    ε·k·|x| (ε machine epsilon); short stiff elements far from the origin reach 1e-4 N.
    """
    floor = ROUND_OFF_FACTOR * np.finfo(float).eps * float(params.axial_stiffness.max()) * float(np.abs(x).max())
    return max(settings.force_tolerance, floor)


def newton_equilibrium(
    model: StaticModel, params: PhysicalParameters, x0: np.ndarray, settings: StaticSettings
) -> tuple[np.ndarray, int]:
    """Minimise the potential energy by Newton's method with a backtracking line search.

    Slack droppers make the energy only once differentiable; the generalised (semi-smooth) Newton
    step with the current active set converges in a few iterations, and the line search guards the
    steps where the set changes. A factorisation of the tangent stiffness is kept while its steps
    reduce the out-of-balance force a hundredfold or more (:data:`REFACTORISE_RATE`): the converged
    state meets the same force tolerance, and an elasticity curve needs one factorisation per point
    instead of three (its values move by 4e-8 relative, measured on ST 9,8/9,8 at 50–250 N).

    Returns
    -------
    x : ndarray
        Equilibrium coordinates. [m]
    iterations : int
        Newton iterations used. [-]

    Raises
    ------
    ConvergenceError
        If the largest out-of-balance force stays above ``settings.force_tolerance``.
    """
    x, iterations, _ = _newton(model, params, x0, settings)
    return x, iterations


@dataclass(frozen=True)
class NewtonTerms:
    """What a Newton solve leaves for the next one that starts where it ended.

    Attributes
    ----------
    gradient : ndarray
        Out-of-balance force on the free DOFs at the solution, under its loads. [N]
    factor : Factor or None
        The last factorised tangent stiffness (of an iterate near the solution), or None if the
        solve needed none (it started at equilibrium). [N/m]
    """

    gradient: np.ndarray
    factor: Factor | None


REFACTORISE_RATE = 0.01
"""A Newton step that leaves more than this share of the out-of-balance force makes the next step
use a new factorisation of the tangent stiffness; faster steps keep the old one (the chord method:
each step costs a solve instead of a factorisation, and the iteration still stops only at the force
tolerance). [-]"""


def _newton(
    model: StaticModel,
    params: PhysicalParameters,
    x0: np.ndarray,
    settings: StaticSettings,
    terms: NewtonTerms | None = None,
) -> tuple[np.ndarray, int, NewtonTerms]:
    """:func:`newton_equilibrium`, optionally started from the gradient at ``x0`` under ``params`` and a
    factorisation near ``x0`` (``terms``), returning the same at the solution.

    The factorisation is kept while the steps it gives converge fast (:data:`REFACTORISE_RATE`) and
    renewed at the current iterate otherwise, so the solution meets the same force tolerance as
    Newton's method, mostly at the cost of one back-substitution per step.
    """
    funcs = model.functions
    free = funcs.free_dofs
    x = x0.copy()
    tolerance = force_tolerance(params, x, settings)
    if terms is None:
        grad, factor = funcs.gradient(x, params)[free], None
    else:
        grad, factor = terms.gradient, terms.factor
    residual = np.abs(grad).max(initial=0.0)
    renew = factor is None
    for iteration in range(settings.max_newton_iterations):
        if residual <= tolerance:
            return x, iteration, NewtonTerms(grad, factor)
        if renew:
            factor = _factorise(funcs, x, params, iteration)
        step = -factor.solve(grad)
        alpha, energy = 1.0, None
        while True:
            trial = x.copy()
            trial[free] += alpha * step
            new_grad = funcs.gradient(trial, params)[free]
            new_residual = np.abs(new_grad).max(initial=0.0)
            if new_residual < 0.5 * residual or alpha < 1e-3:
                break
            # Armijo test on the energy, for steps that change the set of slack droppers.
            energy = funcs.energy(x, params) if energy is None else energy
            if funcs.energy(trial, params) - energy <= 1e-4 * alpha * float(grad @ step) + 1e-12 * abs(energy):
                break
            alpha *= 0.5
        renew = new_residual > REFACTORISE_RATE * residual
        x, grad, residual = trial, new_grad, new_residual
    if residual <= tolerance:
        return x, settings.max_newton_iterations, NewtonTerms(grad, factor)
    raise ConvergenceError(
        f"equilibrium did not converge: largest out-of-balance force {residual:.3g} N after "
        f"{settings.max_newton_iterations} Newton iterations (tolerance {tolerance:.3g} N)",
        {"residual_N": residual, "iterations": settings.max_newton_iterations},
    )


def _factorise(funcs, x: np.ndarray, params: PhysicalParameters, iteration: int) -> Factor:
    """Factorisation of the tangent stiffness at ``x``; a singular one raises ConvergenceError."""
    hess, _ = funcs.hessian_values(x, params)
    try:
        return funcs.solver.factorise(hess)
    except RuntimeError as exc:
        raise ConvergenceError(f"equilibrium: singular tangent stiffness ({exc})", {"iteration": iteration}) from None


def lone_wire_state(
    wire: Wire,
    length: float,
    settings: StaticSettings | None = None,
    *,
    support_stiffness: float | None = None,
    damping: Damping | None = None,
) -> EquilibriumState:
    """Equilibrium of a lone wire supported at both ends (see :func:`discretise_lone_wire`), under gravity.

    The simulator runs on such a state when its supports are springs (``support_stiffness``); with
    pinned ends it serves the static analytic checks.

    Parameters
    ----------
    wire : Wire
        Tension, mass, EA and EI. A massless wire stays straight.
    length : float
        Distance between the supports. [m]
    settings : StaticSettings, optional
        Numerical settings.
    support_stiffness : float, optional
        Vertical stiffness of each end support; None pins the ends. [N/m]
    damping : Damping, optional
        Structural damping for dynamic analysis (None: the dynamic model's default).
    """
    settings = settings or StaticSettings()
    disc = discretise_lone_wire(wire, length, settings, support_stiffness=support_stiffness, damping=damping)
    model = StaticModel(disc, build_potential(disc))
    params = PhysicalParameters(
        axial_stiffness=disc.axial.stiffness,
        unstretched_length=disc.axial.design_length / (1.0 + wire.tension / wire.axial_stiffness),
        slack_allowed=np.zeros(len(disc.axial)),
        bending_stiffness=disc.bending.bending_stiffness,
        spring_stiffness=disc.spring_stiffness,
        spring_reference=disc.design_positions.ravel()[disc.spring_dofs],
        nodal_force=disc.gravity_force() + disc.termination_force,
    )
    x, iterations = newton_equilibrium(model, params, disc.design_positions.ravel(), settings)
    return EquilibriumState(model, x.reshape(-1, 3), params, np.zeros(disc.n_dofs), iterations)


def form_find(catenary: Catenary, settings: StaticSettings | None = None) -> EquilibriumState:
    """Find the dropper lengths and support settings that give the target contact-wire geometry.

    Target: the contact wire at its designed height at every support and on the pre-sag parabola
    (zero at the masts, ``presag_rel · l`` at mid-span) at every dropper, at its stagger at every
    steady arm, under gravity, with both wires at their balance-weight tension. Solved with IPOPT
    as one square system (see :func:`presag_opt.static.symbolic.solve_form_finding`). With a cache
    directory set (:func:`presag_opt.static.cache.use_cache`), a state form-found before for the
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
        state = _state_from_arrays(static_model(catenary, settings), cache.load(key))
        if state is not None:
            return state
    state = _form_find(catenary, settings)
    if key is not None:
        cache.store(key, _state_arrays(state))
    return state


FORM_FIND_SECONDS = (1.5, 8.5, 12_000, 1.4)
"""Rough wall time of :func:`form_find` on one core of a 2-core 2026 virtual machine, as
a + b·(n/n_ref)^p with n the node count: measured 3 s at 2 400 nodes, 4 s at 4 800, 15 s at 12 000
(ST 9,8/9,8 ideal at 0.5, 0.25 and 0.1 m elements). [s], [s], [-], [-]"""


def form_find_estimate(catenary: Catenary, settings: StaticSettings | None = None) -> tuple[int, float]:
    """Node count and a rough wall time of :func:`form_find` (0 s when the state is cached).

    Parameters
    ----------
    catenary : Catenary
        System model.
    settings : StaticSettings, optional
        Numerical settings (the element length sets the node count).

    Returns
    -------
    n_nodes : int
        Nodes of the discretisation. [-]
    seconds : float
        Expected time, from :data:`FORM_FIND_SECONDS`; an order of magnitude, not a promise. [s]
    """
    settings = settings or StaticSettings()
    n_nodes = discretise(catenary, settings).n_nodes
    if cache.active_directory() is not None and cache.contains(cache.state_key(catenary, settings)):
        return n_nodes, 0.0
    a, b, n_ref, power = FORM_FIND_SECONDS
    return n_nodes, a + b * (n_nodes / n_ref) ** power


_PARAMETER_FIELDS = tuple(f.name for f in fields(PhysicalParameters))


def _state_arrays(state: EquilibriumState) -> dict[str, np.ndarray]:
    """The numeric content of a state, for the cache."""
    return {"positions": state.positions, "applied_load": state.applied_load,
            "iterations": np.array(state.iterations), **{f"params_{n}": getattr(state.params, n) for n in _PARAMETER_FIELDS}}


def _state_from_arrays(model: StaticModel, arrays: dict[str, np.ndarray] | None) -> EquilibriumState | None:
    """A state from cached arrays, or None when they are missing or do not fit the model."""
    if arrays is None:
        return None
    disc = model.discretisation
    try:
        params = PhysicalParameters(**{n: arrays[f"params_{n}"] for n in _PARAMETER_FIELDS})
        state = EquilibriumState(model, arrays["positions"], params, arrays["applied_load"], int(arrays["iterations"]))
    except (KeyError, TypeError, ValueError):
        return None
    expected = {"positions": (disc.n_nodes, 3), "applied_load": (disc.n_dofs,),
                "params_axial_stiffness": (len(disc.axial),), "params_unstretched_length": (len(disc.axial),),
                "params_nodal_force": (disc.n_dofs,)}
    if any(arrays[name].shape != shape for name, shape in expected.items()):
        return None
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
    :func:`presag_opt.static.symbolic.target_height_sensitivity`). Column j is the change of every
    contact-wire node height per metre the target at dropper j is raised: 1 at that dropper, the
    span between it and its neighbours following (with the small coupling that bending adds).

    Returns
    -------
    ndarray, shape (n_nodes, n_droppers)
        ∂z/∂z_target of every node for the droppers in along-track order. [m/m]
    """
    disc = state.discretisation
    if "dropper_sensitivity" not in state._cache:
        full = target_height_sensitivity(
            disc, state.params, _horizontal_wire_tension(disc), _target_dofs(disc), state.positions
        )
        state._cache["dropper_sensitivity"] = full[:, : len(disc.dropper_elements)]
    return state._cache["dropper_sensitivity"]


def _horizontal_wire_tension(disc: Discretisation) -> np.ndarray:
    """Horizontal tension of every wire segment in the design state (0 for other elements). [N]

    A balance weight pulls with T along the track; where the end chord of a wire is turned by φ
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


__all__ = [
    "DropperScheduleRow",
    "EquilibriumState",
    "StaticModel",
    "dropper_height_sensitivity",
    "form_find",
    "lone_wire_state",
    "newton_equilibrium",
    "static_model",
    "STEADY_ARM",
]
