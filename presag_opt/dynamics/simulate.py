"""Dynamic pantograph–catenary interaction: time integration and EN 50367 statistics.

:func:`simulate` runs one or several pantographs (on one train, at given spacings) at constant speed
under a catenary linearised about its static equilibrium (:mod:`presag_opt.dynamics.structure`) and
returns the time histories and contact-force statistics as a :class:`SimulationResult`.

The run
    The analysed section is the ``analysed_spans`` central spans of the section (for 10 spans and
    2 analysed spans: spans 5 and 6, counted from 1). The leading pantograph starts ``lead_in_spans``
    spans before it, at a mast, the others behind it at their spacings; all start from static
    contact: pressed against the wire at rest with the mean uplift force F_up = F_stat + α_ae v²
    (the static equilibrium of wire, droppers and pantograph under that force, droppers
    tension-only). Then the contact points move at the train speed. The run ends when the rear
    pantograph is ``run_out`` seconds past the analysed section, so that the zero-phase filter has
    data beyond the window. Each pantograph's statistics are taken over the time it spends in the
    analysed section.

Contact
    Unilateral penalty contact between each pantograph head and the contact wire at the moving
    contact point x(t) = x0 + v t. The wire height there is interpolated linearly between the two
    nodes of the element under the head, from the static height (which carries the pre-sag and the
    sag between droppers) plus the displacements. The linear shape functions make the wire between
    two nodes as stiff as its chord; the deflection of a tensioned wire element loaded at a point,
    h t (1 − t)/T, acts in series with the penalty spring, so the contact stiffness is
    1/(1/k_c + h t (1 − t)/T). This is the term :func:`~presag_opt.elasticity.linear_elasticity`
    adds to the nodal elasticity, so the dynamic model at crawling speed and the static elasticity
    agree between nodes too.

Pantographs
    Displacements are measured from the pressed rest state. There the stage springs carry F_up
    (the car-body spring carries nothing: F_up is the force the pantograph delivers at its working
    height); moving those static spring forces to the right-hand side leaves F_up acting on the head.
    Dry friction is regularised Coulomb friction, F0·tanh(Δv/v_reg).

Time integration
    :func:`~presag_opt.dynamics.integrator.integrate` with the catenary DOFs first, then each
    pantograph's DOFs (head first). Default: HHT-α with α = −0.005 and a 2 ms step. The paper's
    Newmark integration with "numerical damping 0.005" (ANSYS amplitude decay factor) has
    γ = 0.505 and β = 0.2525, which are HHT's γ = 1/2 − α and β = (1 − α)²/4 at α = −0.005.

References
----------
EN 50367:2012+A1:2016 (contact-force statistics, 20 Hz low-pass); EN 50318:2018 (validation of
simulation methods; analysed section away from the model ends).
Schick, Liu, Stichel, Railway Sciences (2025), doi:10.1108/RS-05-2025-0016, section 2 (Newmark,
2 ms, numerical damping 0.005, penalty contact 50 kN/m) and eq. (4) (F_m = F_stat + α_ae v²).
"""

from __future__ import annotations

import time as wallclock
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from presag_opt.dynamics import laws
from presag_opt.dynamics.assembly import force_contribution, head_penetration
from presag_opt.dynamics.integrator import State, integrate
from presag_opt.dynamics.pantograph import FrictionRegularisation, Pantograph
from presag_opt.dynamics.results import PantographHistory, SimulationResult
from presag_opt.dynamics.run_plan import (
    plan_run,
    recorded_droppers,
    route,
    run_warnings,
    static_contact,
)
from presag_opt.dynamics.settings import SimulationSettings
from presag_opt.dynamics.statistics import (
    contact_force_statistics,
    lowpass_filter,
)
from presag_opt.dynamics.step_solvers import NO_FORCE, NonlinearForce
from presag_opt.dynamics.structure import StructuralModel, structural_model
from presag_opt.static.equilibrium import EquilibriumState
from presag_opt.static.form_finding import form_find
from presag_opt.system.catenary import Catenary


@dataclass(frozen=True)
class _Coupling:
    """One pantograph on the wire: its DOFs, head height at rest and its contact point at every step.

    The contact point's element (two contact-wire nodes), its shape-function weights and the
    element's point-load compliance are evaluated once for every time step, with the
    discretisation's :meth:`~presag_opt.static.discretisation.Discretisation.cw_shape` and
    :meth:`~presag_opt.static.discretisation.Discretisation.cw_element_compliance`.
    """

    pantograph: Pantograph
    dofs: np.ndarray
    start: float
    head_height: float
    nodes: np.ndarray  # (n_steps + 1, 2) contact-wire nodes of the element under the head
    weights: np.ndarray  # (n_steps + 1, 2) linear shape functions [-]
    compliance: np.ndarray  # (n_steps + 1,) element deflection per unit force [m/N]


class _Interaction:
    """Contact, friction and dropper forces of the coupled system (the integrator's callbacks)."""

    def __init__(
        self, model: StructuralModel, couplings: list[_Coupling], time_step: float, friction: FrictionRegularisation
    ):
        self.model = model
        self.couplings = couplings
        self.time_step = time_step
        self.friction = friction

    def contact(
        self, coupling: _Coupling, u: np.ndarray, t: float
    ) -> tuple[np.ndarray, np.ndarray, float, float, float]:
        """Wire nodes, shape weights, element compliance [m/N], contact stiffness [N/m] and penetration [m].

        The penetration is measured to the chord between the element's nodes; the element's own
        deflection is in series with the penalty spring, inside the contact stiffness. ``t`` is a
        multiple of the time step (the integrator's step and record times).
        """
        step = int(round(t / self.time_step))
        nodes, weights, compliance = coupling.nodes[step], coupling.weights[step], coupling.compliance[step]
        height, displacement = self.model.cw_height[nodes], u[self.model.cw_z[nodes]]
        penetration = head_penetration(coupling.head_height, u[coupling.dofs[0]], weights[0], height[0],
                                       displacement[0], weights[1], height[1], displacement[1])
        stiffness = laws.contact_stiffness(coupling.pantograph.contact.stiffness, compliance)
        return nodes, weights, compliance, stiffness, penetration

    def force(self, u: np.ndarray, v: np.ndarray, t: float) -> NonlinearForce:
        """All nonlinear forces at (u, v, t), for the integrator."""
        parts = []
        for coupling in self.couplings:
            nodes, weights, _, stiffness, penetration = self.contact(coupling, u, t)
            n_dofs = 2 + len(coupling.dofs)
            force, tangent, damping = np.zeros(n_dofs), np.zeros((n_dofs, n_dofs)), np.zeros((n_dofs, n_dofs))
            force_contribution(laws.contact_force(stiffness, penetration), laws.contact_tangent(stiffness, penetration),
                               (-weights[0], -weights[1], 1.0), force[:3], tangent[:3, :3])
            if coupling.pantograph.has_friction:
                friction, slope = coupling.pantograph.friction_force(v[coupling.dofs], self.friction)
                force[2:] += friction
                damping[2:, 2:] = slope
            parts.append(
                NonlinearForce(
                    dofs=np.concatenate([self.model.cw_z[nodes], coupling.dofs]),
                    force=force,
                    stiffness=tangent,
                    damping=damping,
                )
            )
        parts.append(self.model.dropper_slack_force(u, v))
        return _stack(parts)

    def observe(self, t: float, u: np.ndarray, v: np.ndarray, recorded_droppers: np.ndarray) -> np.ndarray:
        """Contact forces, wire uplifts at the contact points, recorded dropper forces, support uplifts."""
        forces, uplifts = [], []
        for coupling in self.couplings:
            nodes, weights, compliance, stiffness, penetration = self.contact(coupling, u, t)
            force = laws.contact_force(stiffness, penetration)
            forces.append(force)
            uplifts.append(weights @ u[self.model.cw_z[nodes]] + compliance * force)
        droppers = self.model.dropper_force(u, v)[recorded_droppers]
        return np.concatenate([forces, uplifts, droppers, u[self.model.support_z]])


def _stack(parts: list[NonlinearForce]) -> NonlinearForce:
    """One NonlinearForce from several (block-diagonal tangents; repeated DOFs add up)."""
    parts = [p for p in parts if len(p.dofs)]
    if len(parts) <= 1:
        return parts[0] if parts else NO_FORCE
    dofs = np.concatenate([p.dofs for p in parts])
    n = len(dofs)
    stiffness, damping = np.zeros((n, n)), np.zeros((n, n))
    start = 0
    for p in parts:
        end = start + len(p.dofs)
        stiffness[start:end, start:end] = p.stiffness
        if p.damping is not None:
            damping[start:end, start:end] = p.damping
        start = end
    return NonlinearForce(
        dofs=dofs, force=np.concatenate([p.force for p in parts]), stiffness=stiffness, damping=damping
    )


def simulate(
    system: Catenary | EquilibriumState,
    pantograph: Pantograph | Sequence[Pantograph],
    *,
    speed: float,
    static_force: float,
    aero_coefficient: float = 0.0,
    spacings: Sequence[float] | None = None,
    settings: SimulationSettings | None = None,
) -> SimulationResult:
    """Simulate pantographs running under a catenary at constant speed.

    Parameters
    ----------
    system : Catenary or EquilibriumState
        The catenary (form-found here with ``settings.static``) or a form-found state (reused, e.g.
        across the runs of a parametric study).
    pantograph : Pantograph or sequence of Pantograph
        One model for every pantograph, or one per pantograph, front to rear.
    speed : float
        Train speed; must be below the contact-wire wave speed (a warning above 0.7 of it). [m/s]
    static_force : float
        Static uplift force of each pantograph. [N]
    aero_coefficient : float
        Aerodynamic uplift coefficient: F_m = F_stat + α_ae v². [N/(m/s)²]
    spacings : sequence of float, optional
        Distances between consecutive pantographs, front to rear. [m]
    settings : SimulationSettings, optional
        Numerical settings and analysis window.

    Returns
    -------
    SimulationResult
        Time histories and the statistics over the analysed section.

    Raises
    ------
    ModelError
        Bad operating point (non-positive force or speed, speed at or above the wave speed), a time
        step too large for a pantograph's contact stiffness, a section too short for the lead-in,
        the analysed spans and the train, or a pantograph list that does not match the spacings.
        All are found before the catenary is form-found (see :func:`plan_run`).
    ConvergenceError
        If the initial static contact or a time step does not converge.
    """
    started = wallclock.perf_counter()
    settings = settings or SimulationSettings()
    plan = plan_run(
        system, pantograph, speed=speed, static_force=static_force, aero_coefficient=aero_coefficient,
        spacings=spacings, settings=settings,
    )
    settings = plan.settings
    state = system if isinstance(system, EquilibriumState) else form_find(system, settings.static)
    model = structural_model(state, settings=settings.structure)
    operation, pantographs = plan.operation, plan.pantographs

    n_c = model.n_dofs
    sizes = [p.n_dofs for p in pantographs]
    first_dof = n_c + np.concatenate([[0], np.cumsum(sizes)[:-1]]).astype(int)
    n = n_c + sum(sizes)
    mass = sp.block_diag([model.mass] + [p.mass_matrix() for p in pantographs], format="csr")
    damping = sp.block_diag([model.damping] + [p.damping_matrix() for p in pantographs], format="csr")
    stiffness = sp.block_diag([model.stiffness] + [p.stiffness_matrix() for p in pantographs], format="csr")

    dt = settings.integrator.time_step
    times = dt * np.arange(plan.step_count(dt) + 1)  # the integrator's record times
    u0_catenary, paths = static_contact(state, model, plan, times)
    u0 = np.zeros(n)
    u0[:n_c] = u0_catenary
    couplings = [
        _Coupling(p, dof + np.arange(p.n_dofs), float(x), path.head_height, path.nodes, path.weights, path.compliance)
        for p, dof, x, path in zip(pantographs, first_dof, plan.starts, paths)
    ]
    uplift = operation.uplift_force
    disc = state.discretisation
    interaction = _Interaction(model, couplings, dt, settings.friction)
    external = np.zeros(n)
    external[[c.dofs[0] for c in couplings]] = uplift

    recorded = recorded_droppers(model, plan.analysed_section, settings)
    result = integrate(
        mass,
        damping,
        stiffness,
        duration=plan.duration,
        settings=settings.integrator,
        external_force=lambda t: external,
        nonlinear_force=interaction.force,
        initial_state=State(displacement=u0, velocity=np.zeros(n), acceleration=np.zeros(n)),
        record_dofs=np.concatenate([c.dofs for c in couplings]),
        observe=lambda t, u, v: interaction.observe(t, u, v, recorded),
    )

    time = result.time
    n_p = len(couplings)
    observed = result.observed
    forces, wire_uplifts = observed[:, :n_p], observed[:, n_p : 2 * n_p]
    dropper_force = observed[:, 2 * n_p : 2 * n_p + len(recorded)]
    support_uplift = observed[:, 2 * n_p + len(recorded) :]
    histories = []
    column = 0
    for i, coupling in enumerate(couplings):
        window = plan.window(i)
        stages = slice(column, column + len(coupling.dofs))
        column += len(coupling.dofs)
        histories.append(
            PantographHistory(
                name=coupling.pantograph.name,
                offset=float(operation.offsets[i]),
                position=coupling.start + operation.speed * time,
                contact_force=forces[:, i],
                contact_force_filtered=lowpass_filter(time, forces[:, i], cutoff=settings.cutoff_frequency),
                wire_uplift=wire_uplifts[:, i],
                displacement=result.displacement[:, stages],
                velocity=result.velocity[:, stages],
                window=window,
                statistics=contact_force_statistics(
                    time, forces[:, i], window_start=window[0], window_end=window[1], cutoff=settings.cutoff_frequency
                ),
            )
        )
    return SimulationResult(
        catenary_name=route(system)[0],
        operation=operation,
        wave_speed=plan.wave_speed,
        speed_ratio=plan.speed_ratio,
        doppler_factor=plan.doppler_factor,
        time=time,
        pantographs=tuple(histories),
        analysed_spans=plan.analysed_spans,
        analysed_section=plan.analysed_section,
        support_station=disc.mast_station.copy(),
        support_uplift=support_uplift,
        dropper_station=model.droppers.station[recorded],
        dropper_span=model.droppers.span[recorded],
        dropper_force=dropper_force,
        dropper_static_force=model.droppers.preload[recorded],
        newton_iterations=result.iterations,
        stepping_time=result.wall_time,
        total_time=wallclock.perf_counter() - started,
        settings=settings,
        warnings=run_warnings(state, plan),
    )
