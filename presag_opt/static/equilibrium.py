"""A static equilibrium of a catenary section: the state, and the model it belongs to.

An :class:`EquilibriumState` holds node coordinates and element parameters of one equilibrium of a
:class:`StaticModel` (a discretisation and its potential). :meth:`EquilibriumState.solve` re-solves
the equilibrium under extra loads (droppers free to go slack) by Newton's method
(:mod:`presag_opt.static.equilibrium_newton`); :meth:`EquilibriumState.tangent_stiffness` gives the linear
stiffness at the state. What a state computes once is kept in its :class:`StateMemo`. States come
from form-finding (:func:`presag_opt.static.form_finding.form_find`) or, for a lone wire, from
:func:`lone_wire_state`.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np
import scipy.sparse as sp

from presag_opt.static.banded_solver import Factor
from presag_opt.static.discretisation import (
    STEADY_ARM,
    Discretisation,
    StaticSettings,
    discretise,
    discretise_lone_wire,
)
from presag_opt.static.equilibrium_newton import NewtonTerms, newton_equilibrium, newton_solve
from presag_opt.static.potential import PhysicalParameters, PotentialFunctions, build_potential
from presag_opt.static.solver_statistics import FormFindingStatistics
from presag_opt.system.catenary import Catenary
from presag_opt.system.components import Damping, Wire

if TYPE_CHECKING:
    from presag_opt.static.linearised import TensionOnlyStructure


@dataclass(slots=True)
class StateMemo:
    """What an :class:`EquilibriumState` computes once and keeps (not part of its value): one declared
    slot per quantity, each None until first asked for.

    Attributes
    ----------
    stiffness : ndarray or None
        Nonzeros of the tangent stiffness (:meth:`EquilibriumState.tangent_stiffness`). [N/m]
    factor : Factor or None
        Its factorisation (:meth:`EquilibriumState.factorised_stiffness`).
    newton_terms : NewtonTerms or None
        What the Newton solve that produced the state leaves for one that starts from it.
    dropper_sensitivity : ndarray or None
        ∂z/∂z_target of every node for each dropper target
        (:func:`presag_opt.static.form_finding.dropper_height_sensitivity`). [m/m]
    tension_only : TensionOnlyStructure or None
        The structure linearised with tension-only droppers
        (:meth:`presag_opt.static.linearised.TensionOnlyStructure.of`).
    unit_load_terms : dict
        Per set of stations (the stations' bytes): the compliance and dropper influence of a unit
        load at each station (:mod:`presag_opt.elasticity`'s active-set method). [m/N], [m/N]
    """

    stiffness: np.ndarray | None = None
    factor: Factor | None = None
    newton_terms: NewtonTerms | None = None
    dropper_sensitivity: np.ndarray | None = None
    tension_only: TensionOnlyStructure | None = None
    unit_load_terms: dict = field(default_factory=dict)


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
    form_finding : FormFindingStatistics or None
        How the form-finding that produced it went (None for a state re-solved under a load).
    """

    model: StaticModel
    positions: np.ndarray
    params: PhysicalParameters
    applied_load: np.ndarray
    iterations: int = 0
    form_finding: FormFindingStatistics | None = field(default=None, compare=False)
    memo: StateMemo = field(default_factory=StateMemo, init=False, repr=False, compare=False)
    """What the state computes once (not part of its value)."""

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
        """Along-track component of the force in each element of a wire (group). [N]

        Parameters
        ----------
        group : int
            Wire (element group) index. [-]
        """
        ax = self.discretisation.axial
        sel = ax.group == group
        d = self.positions[ax.node_b[sel]] - self.positions[ax.node_a[sel]]
        return self.axial_forces()[sel] * np.linalg.norm(d[:, :2], axis=1) / np.linalg.norm(d, axis=1)

    def dropper_forces(self) -> np.ndarray:
        """Tensile force of each dropper, in along-track order. [N]"""
        return self.axial_forces()[self.discretisation.dropper_elements]

    def slack_dropper_count(self) -> int:
        """Droppers carrying no tension (slack, or at the point of going slack). [-]"""
        return int(np.count_nonzero(self.dropper_forces() <= 0.0))

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
        if self.memo.stiffness is None:
            self.memo.stiffness, _ = self.model.functions.hessian_values(self.positions.ravel(), self.params)
        return self.memo.stiffness

    def factorised_stiffness(self) -> Factor:
        """Factorisation of :meth:`tangent_stiffness` (computed once per state)."""
        if self.memo.factor is None:
            self.memo.factor = self.model.functions.solver.factorise(self._stiffness_values())
        return self.memo.factor

    def out_of_balance(self) -> np.ndarray:
        """Out-of-balance force on the free degrees of freedom. [N]"""
        return self.model.functions.gradient(self.positions.ravel(), self.params)[self.model.functions.free_dofs]

    # ----- re-solving ---------------------------------------------------------------------------

    def solve(self, load: np.ndarray, start: EquilibriumState | None = None) -> EquilibriumState:
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
        terms = start.memo.newton_terms
        if terms is not None:
            # The start's out-of-balance force moves by the change of the external force; its
            # factorisation does not depend on the load.
            free = self.model.functions.free_dofs
            terms = NewtonTerms(terms.gradient + (start.params.nodal_force - params.nodal_force)[free], terms.factor)
        settings = self.discretisation.settings
        x, iterations, final = newton_solve(self.model, params, start.positions.ravel(), settings, terms)
        state = EquilibriumState(self.model, x.reshape(-1, 3), params, np.asarray(load, dtype=float), iterations)
        state.memo.newton_terms = final
        return state

def _replace_force(params: PhysicalParameters, force: np.ndarray) -> PhysicalParameters:
    return PhysicalParameters(**{**params.__dict__, "nodal_force": force})

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


__all__ = [
    "STEADY_ARM",
    "DropperScheduleRow",
    "EquilibriumState",
    "StateMemo",
    "StaticModel",
    "lone_wire_state",
    "static_model",
]
