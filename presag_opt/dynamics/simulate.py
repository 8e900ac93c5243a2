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

import dataclasses
import time as wallclock
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Literal

import numpy as np
import scipy.sparse as sp

from presag_opt.dynamics.numerics import numerics_for_speed, resolution_warnings
from presag_opt.dynamics.integrator import NO_FORCE, IntegratorSettings, NonlinearForce, State, integrate, step_count
from presag_opt.dynamics.pantograph import FrictionRegularisation, Pantograph
from presag_opt.dynamics.statistics import ContactForceStatistics, contact_force_statistics, lowpass_filter
from presag_opt.dynamics.structure import StructuralModel, StructureSettings, structural_model
from presag_opt.errors import ModelError
from presag_opt.speed import doppler_factor
from presag_opt.static.discretisation import StaticSettings
from presag_opt.static.equilibrium import EquilibriumState, form_find
from presag_opt.system.catenary import Catenary
from presag_opt.system.quantity import quantity, validate_fields

DROPPER_RECORDS = ("analysed", "all")
NUMERICS = ("fixed", "auto")


@dataclass(frozen=True, kw_only=True)
class SimulationSettings:
    """Numerical settings and the analysis window of a dynamic simulation (no physics).

    Attributes
    ----------
    integrator : IntegratorSettings
        Time step, scheme and solution method; default HHT-α, α = −0.005, 2 ms (see module notes).
    static : StaticSettings
        Settings of the static model (element length) used when a catenary has to be form-found.
    structure : StructureSettings
        Damping band of the structural model.
    friction : FrictionRegularisation
        Regularisation of the pantographs' dry friction.
    analysed_spans : int
        Number of central spans analysed. [-]
    lead_in_spans : int
        Spans the leading pantograph runs before the analysed section. [-]
    run_out : float
        Time the rear pantograph runs past the analysed section: data for the zero-phase filter,
        whose 20 Hz Butterworth impulse response falls below 1e-4 of its peak within 0.2 s. [s]
    cutoff_frequency : float
        Low-pass cut-off of the contact force. [Hz]
    droppers : {"analysed", "all"}
        Droppers whose forces are recorded: those of the analysed section, or all.
    numerics : {"fixed", "auto"}
        ``"fixed"``: ``static.element_length`` and ``integrator.time_step`` as given; ``"auto"``: both
        from the speed (:func:`~presag_opt.dynamics.numerics.numerics_for_speed`).
    """

    integrator: IntegratorSettings = field(
        default_factory=lambda: IntegratorSettings(scheme="hht", hht_alpha=-0.005)
    )
    static: StaticSettings = field(default_factory=StaticSettings)
    structure: StructureSettings = field(default_factory=StructureSettings)
    friction: FrictionRegularisation = field(default_factory=FrictionRegularisation)
    analysed_spans: int = quantity("count", 1, 200, default=2)
    lead_in_spans: int = quantity("count", 0, 200, default=2)
    run_out: float = quantity("time", 0.0, 10.0, default=0.25)
    cutoff_frequency: float = quantity("frequency", 1.0, 200.0, display="Hz", default=20.0)
    droppers: Literal["analysed", "all"] = "analysed"
    numerics: Literal["fixed", "auto"] = "fixed"

    def __post_init__(self) -> None:
        validate_fields(self)
        for name in ("analysed_spans", "lead_in_spans"):
            value = getattr(self, name)
            if value != int(value):
                raise ModelError(f"{name} = {value!r} is not a whole number")
            object.__setattr__(self, name, int(value))
        if self.droppers not in DROPPER_RECORDS:
            raise ModelError(f"droppers = {self.droppers!r} is not one of {', '.join(map(repr, DROPPER_RECORDS))}")
        if self.numerics not in NUMERICS:
            raise ModelError(f"numerics = {self.numerics!r} is not one of {', '.join(map(repr, NUMERICS))}")

    def with_fixed_numerics(
        self, *, element_length: float | None = None, time_step: float | None = None
    ) -> SimulationSettings:
        """These settings with ``numerics = "fixed"`` at the given element length [m] and time step [s]
        (each None: the paper's 0.5 m and 2 ms)."""
        return dataclasses.replace(
            self,
            numerics="fixed",
            static=dataclasses.replace(self.static, element_length=element_length or 0.5),
            integrator=dataclasses.replace(self.integrator, time_step=time_step or 2e-3),
        )

    def for_speed(self, speed: float, wave_speed: float) -> SimulationSettings:
        """The settings of a run at ``speed`` [m/s] on a wire of ``wave_speed`` [m/s]: with
        ``numerics = "auto"`` the element length and time step from the speed, otherwise ``self``."""
        if self.numerics != "auto":
            return self
        chosen = numerics_for_speed(speed, wave_speed, self.cutoff_frequency)
        return dataclasses.replace(
            self,
            static=dataclasses.replace(self.static, element_length=chosen.element_length),
            integrator=dataclasses.replace(self.integrator, time_step=chosen.time_step),
        )


@dataclass(frozen=True, kw_only=True)
class Operation:
    """Operating point of a run: train speed, uplift force and pantograph spacings.

    Attributes
    ----------
    speed : float
        Train speed. [m/s]
    static_force : float
        Static uplift force of each pantograph. [N]
    aero_coefficient : float
        Aerodynamic uplift coefficient α_ae of F_m = F_stat + α_ae v². [N/(m/s)²]
    spacings : tuple of float or None
        Distances between consecutive pantographs, front to rear; None for a single pantograph. [m]
    """

    speed: float = quantity("speed", 0.0, 600.0, display="km/h", low_open=True)
    static_force: float = quantity("force", 0.0, 500.0, low_open=True)
    aero_coefficient: float = quantity("aero_coefficient", 0.0, 0.01, display="N/(km/h)^2", default=0.0)
    spacings: tuple[float, ...] | None = quantity("length", 1.0, 2000.0, default=None, allow_none=True)

    def __post_init__(self) -> None:
        if self.spacings is not None:
            spacings = tuple(float(s) for s in self.spacings)
            object.__setattr__(self, "spacings", spacings or None)
        validate_fields(self)

    @property
    def uplift_force(self) -> float:
        """Mean uplift force F_stat + α_ae v² of each pantograph. [N]"""
        return self.static_force + self.aero_coefficient * self.speed**2

    @property
    def offsets(self) -> np.ndarray:
        """Distance of each pantograph behind the leading one. [m]"""
        return np.concatenate([[0.0], np.cumsum(self.spacings or ())])


@dataclass(frozen=True, kw_only=True)
class PantographHistory:
    """Time histories and statistics of one pantograph.

    Attributes
    ----------
    name : str
        Pantograph model name.
    offset : float
        Distance behind the leading pantograph. [m]
    position : ndarray
        Station of the contact point (distance from the first mast). [m]
    contact_force : ndarray
        Raw contact force. [N]
    contact_force_filtered : ndarray
        Contact force low-pass filtered (zero phase) at the cut-off frequency. [N]
    wire_uplift : ndarray
        Contact-wire uplift at the contact point from the static equilibrium. [m]
    displacement : ndarray, shape (n_times, n_stages)
        Displacement of each stage (head first) from the pressed rest state, z up. [m]
    velocity : ndarray, shape (n_times, n_stages)
        Velocity of each stage. [m/s]
    window : tuple of float
        Times the contact point enters and leaves the analysed section. [s]
    statistics : ContactForceStatistics
        Statistics over ``window``.
    """

    name: str
    offset: float
    position: np.ndarray
    contact_force: np.ndarray
    contact_force_filtered: np.ndarray
    wire_uplift: np.ndarray
    displacement: np.ndarray
    velocity: np.ndarray
    window: tuple[float, float]
    statistics: ContactForceStatistics


@dataclass(frozen=True, kw_only=True)
class SimulationResult:
    """Result of :func:`simulate`.

    Attributes
    ----------
    catenary_name : str
        Name of the catenary.
    operation : Operation
        Speed, static force, aerodynamic coefficient and spacings.
    wave_speed : float
        Contact-wire wave speed sqrt(T/ρ). [m/s]
    speed_ratio : float
        β = v / c. [-]
    doppler_factor : float
        (c − v)/(c + v). [-]
    time : ndarray
        Sample times. [s]
    pantographs : tuple of PantographHistory
        Front to rear.
    analysed_spans : tuple of int
        Spans (from 0) of the analysed section.
    analysed_section : tuple of float
        Stations where the analysed section starts and ends. [m]
    support_station : ndarray
        Station of every mast. [m]
    support_uplift : ndarray, shape (n_times, n_masts)
        Contact-wire uplift at every steady arm / support from the static equilibrium. [m]
    dropper_station : ndarray
        Station of each recorded dropper. [m]
    dropper_span : ndarray of int
        Span (from 0) of each recorded dropper. [-]
    dropper_force : ndarray, shape (n_times, n_recorded)
        Tensile force of each recorded dropper; zero when slack. [N]
    dropper_static_force : ndarray
        Static force of each recorded dropper. [N]
    newton_iterations : ndarray of int
        Newton corrections per time step. [-]
    stepping_time : float
        Wall-clock time of the time stepping. [s]
    total_time : float
        Wall-clock time of the whole call (form-finding included if it ran). [s]
    settings : SimulationSettings
        Settings used.
    warnings : tuple of str
        One line per numerical setting that under-resolves the run (see :func:`run_warnings`).
    """

    catenary_name: str
    operation: Operation
    wave_speed: float
    speed_ratio: float
    doppler_factor: float
    time: np.ndarray
    pantographs: tuple[PantographHistory, ...]
    analysed_spans: tuple[int, ...]
    analysed_section: tuple[float, float]
    support_station: np.ndarray
    support_uplift: np.ndarray
    dropper_station: np.ndarray
    dropper_span: np.ndarray
    dropper_force: np.ndarray
    dropper_static_force: np.ndarray
    newton_iterations: np.ndarray
    stepping_time: float
    total_time: float
    settings: SimulationSettings
    warnings: tuple[str, ...] = ()

    @property
    def statistics(self) -> ContactForceStatistics:
        """Contact-force statistics of the leading pantograph."""
        return self.pantographs[0].statistics

    @property
    def analysed_supports(self) -> np.ndarray:
        """Indices of the masts inside the analysed section (both ends included)."""
        start, end = self.analysed_section
        return np.flatnonzero((self.support_station >= start - 1e-9) & (self.support_station <= end + 1e-9))

    @property
    def uplift_max(self) -> float:
        """Largest contact-wire uplift at a steady arm / support of the analysed section. [m]"""
        return float(self.support_uplift[:, self.analysed_supports].max())

    @property
    def slack(self) -> np.ndarray:
        """True where a recorded dropper is slack, shape (n_times, n_recorded)."""
        return self.dropper_force <= 0.0

    def to_dict(self) -> dict:
        """Headline numbers with units in the key names (the ``--json`` output of the CLI)."""
        op = self.operation
        out = {
            "catenary": self.catenary_name,
            "pantograph": self.pantographs[0].name,
            "speed_kmh": op.speed * 3.6,
            "static_force_N": op.static_force,
            "aero_force_N": op.uplift_force - op.static_force,
            **self.statistics.to_dict(),
            "uplift_max_mm": self.uplift_max * 1e3,
            "beta": self.speed_ratio,
            "doppler_factor": self.doppler_factor,
            "wave_speed_kmh": self.wave_speed * 3.6,
            "analysed_spans": [s + 1 for s in self.analysed_spans],
            "analysed_section_m": list(self.analysed_section),
            "slack_droppers_max": int(self.slack.sum(axis=1).max()) if self.slack.size else 0,
            "time_step_ms": self.settings.integrator.time_step * 1e3,
            "wall_time_s": self.total_time,
            "warnings": list(self.warnings),
        }
        if len(self.pantographs) > 1:
            out["pantographs"] = [
                {"name": p.name, "offset_m": p.offset, **p.statistics.to_dict()} for p in self.pantographs
            ]
        return out


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


def _contact_path(state: EquilibriumState, stations: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Element nodes, shape weights [-] and element compliance [m/N] at contact-wire stations [m]."""
    disc = state.discretisation
    shape = disc.cw_shape(stations)  # two stored entries per row, zeros included, nodes in order
    return shape.indices.reshape(-1, 2), shape.data.reshape(-1, 2), disc.cw_element_compliance(stations)


@dataclass(frozen=True)
class ContactPath:
    """Where one pantograph touches the wire at every record time, and its head height at rest.

    Attributes
    ----------
    nodes : ndarray of int, shape (n_times, 2)
        Contact-wire nodes of the element under the head.
    weights : ndarray, shape (n_times, 2)
        Linear shape functions of the contact point. [-]
    compliance : ndarray, shape (n_times,)
        Point-load compliance of the element at the contact point. [m/N]
    head_height : float
        Height of the head at rest, pressed into the wire by the uplift force. [m]
    """

    nodes: np.ndarray
    weights: np.ndarray
    compliance: np.ndarray
    head_height: float


def static_contact(
    state: EquilibriumState, model: StructuralModel, plan: RunPlan, times: np.ndarray
) -> tuple[np.ndarray, list[ContactPath]]:
    """The run's start: the catenary pressed by the pantographs at rest, and each contact path.

    The wire's static response to the uplift forces at the start stations (droppers tension-only)
    and, per pantograph, the contact element at every record time and the head height that makes
    the contact force equal the uplift force at t = 0.

    Parameters
    ----------
    state : EquilibriumState
        The form-found catenary.
    model : StructuralModel
        Its structural model.
    plan : RunPlan
        The run.
    times : ndarray
        Record times. [s]

    Returns
    -------
    u0 : ndarray
        Catenary displacements at t = 0 from the equilibrium. [m]
    paths : list of ContactPath
        One per pantograph, front to rear.
    """
    uplift = plan.operation.uplift_force
    disc = state.discretisation
    load = sum(disc.cw_load_vector(x, uplift) for x in plan.starts)[model.global_dofs]
    u0 = model.static_response(load)
    paths = []
    for p, x in zip(plan.pantographs, plan.starts):
        nodes, weights, compliance = _contact_path(state, x + plan.operation.speed * times)
        wire = weights[0] @ (model.cw_height[nodes[0]] + u0[model.cw_z[nodes[0]]]) + compliance[0] * uplift
        paths.append(ContactPath(nodes, weights, compliance, float(wire + uplift / p.contact.stiffness)))
    return u0, paths


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
        model = self.model
        wire = weights @ (model.cw_height[nodes] + u[model.cw_z[nodes]])
        penetration = coupling.head_height + u[coupling.dofs[0]] - wire
        stiffness = 1.0 / (1.0 / coupling.pantograph.contact.stiffness + compliance)
        return nodes, weights, compliance, stiffness, penetration

    def force(self, u: np.ndarray, v: np.ndarray, t: float) -> NonlinearForce:
        """All nonlinear forces at (u, v, t), for the integrator."""
        parts = []
        for coupling in self.couplings:
            nodes, weights, _, stiffness, penetration = self.contact(coupling, u, t)
            n_stages = len(coupling.dofs)
            gradient = np.zeros(2 + n_stages)
            gradient[:2] = -weights
            gradient[2] = 1.0
            in_contact = penetration > 0.0
            force = stiffness * penetration * gradient if in_contact else np.zeros(2 + n_stages)
            tangent = stiffness * np.outer(gradient, gradient) if in_contact else np.zeros((2 + n_stages,) * 2)
            damping = np.zeros_like(tangent)
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
            force = stiffness * max(penetration, 0.0)
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


@dataclass(frozen=True, kw_only=True)
class RunPlan:
    """A checked run: everything :func:`simulate` decides before the catenary is form-found.

    Attributes
    ----------
    operation : Operation
        Validated operating point.
    pantographs : tuple of Pantograph
        One per position, front to rear.
    wave_speed : float
        Contact-wire wave speed. [m/s]
    speed_ratio : float
        β = v / c. [-]
    doppler_factor : float
        (c − v)/(c + v). [-]
    analysed_spans : tuple of int
        Spans (from 0) of the analysed section.
    analysed_section : tuple of float
        Stations where the analysed section starts and ends. [m]
    starts : ndarray
        Station of each pantograph's contact point at t = 0, front to rear. [m]
    duration : float
        Simulated time. [s]
    settings : SimulationSettings
        The run's settings (with ``numerics = "auto"``, the element length and time step of its speed).
    """

    operation: Operation
    pantographs: tuple[Pantograph, ...]
    wave_speed: float
    speed_ratio: float
    doppler_factor: float
    analysed_spans: tuple[int, ...]
    analysed_section: tuple[float, float]
    starts: np.ndarray
    duration: float
    settings: SimulationSettings

    def step_count(self, time_step: float) -> int:
        """Number of time steps of the run (its duration rounded up to whole steps). [-]

        Parameters
        ----------
        time_step : float
            [s]
        """
        return step_count(self.duration, time_step)

    def window(self, pantograph: int) -> tuple[float, float]:
        """Times the given pantograph (from 0, front to rear) is in the analysed section, within the
        simulated time (which can end up to a step early at the end of the line). [s]"""
        start, end = self.analysed_section
        speed = self.operation.speed
        return (start - self.starts[pantograph]) / speed, min((end - self.starts[pantograph]) / speed, self.duration)


def plan_run(
    system: Catenary | EquilibriumState,
    pantograph: Pantograph | Sequence[Pantograph],
    *,
    speed: float,
    static_force: float,
    aero_coefficient: float = 0.0,
    spacings: Sequence[float] | None = None,
    settings: SimulationSettings | None = None,
) -> RunPlan:
    """Check a run's inputs and lay out its route, without form-finding (fast).

    Parameters are those of :func:`simulate` (``system`` a catenary, or a form-found state, which may
    be a lone wire). The leading pantograph starts ``lead_in_spans`` before
    the analysed section, the others behind it at their spacings; the run ends ``run_out`` seconds
    after the rear pantograph leaves the section.

    Returns
    -------
    RunPlan

    Raises
    ------
    ModelError
        See :func:`simulate`.
    """
    operation = Operation(speed=speed, static_force=static_force, aero_coefficient=aero_coefficient, spacings=spacings)
    _, wave_speed, masts = route(system)
    doppler = doppler_factor(operation.speed, wave_speed)  # raises at v >= c, warns above β = 0.7
    settings = (settings or SimulationSettings()).for_speed(operation.speed, wave_speed)
    pantographs = _pantographs(pantograph, len(operation.offsets))
    for p in pantographs:
        p.check_time_step(settings.integrator.time_step)

    n_spans = len(masts) - 1
    n_analysed, lead_in = settings.analysed_spans, settings.lead_in_spans
    first = (n_spans - n_analysed) // 2
    if n_analysed > n_spans or first - lead_in < 0:
        raise ModelError(
            f"the section has {n_spans} spans: too few for {n_analysed} analysed central span(s) after "
            f"{lead_in} lead-in span(s) (analysed_spans + 2·lead_in_spans <= {n_spans})"
        )
    section = (float(masts[first]), float(masts[first + n_analysed]))
    starts = float(masts[first - lead_in]) - operation.offsets
    rear_end = section[1] + operation.speed * settings.run_out
    train = float(operation.offsets[-1])
    if starts[-1] < masts[0]:
        raise ModelError(
            f"the rear pantograph would start {-starts[-1]:.1f} m before the section: the train is {train:.1f} m "
            f"long and the leading pantograph starts at {starts[0]:.1f} m ({lead_in} lead-in span(s))"
        )
    if rear_end + train > masts[-1]:
        raise ModelError(
            f"the leading pantograph would run off the section: it must reach {rear_end + train:.1f} m "
            f"(analysed section ends at {section[1]:.1f} m, run-out {settings.run_out:g} s, train "
            f"{train:.1f} m long) but the section ends at {masts[-1]:.1f} m"
        )
    return RunPlan(
        operation=operation,
        pantographs=tuple(pantographs),
        wave_speed=wave_speed,
        speed_ratio=operation.speed / wave_speed,
        doppler_factor=doppler,
        analysed_spans=tuple(range(first, first + n_analysed)),
        analysed_section=section,
        starts=starts,
        duration=_duration(rear_end - starts[-1], float(masts[-1]) - starts[0], operation.speed, settings),
        settings=settings,
    )


def _duration(run_length: float, room: float, speed: float, settings: SimulationSettings) -> float:
    """Simulated time [s] for the rear pantograph to cover ``run_length`` [m] at ``speed`` [m/s].

    The integrator rounds the time up to whole steps; where that would carry the leading pantograph
    past the end of the line (``room`` [m] ahead of it, e.g. a lone wire run from support to
    support with no run-out), the time is cut to the whole steps that fit.
    """
    time_step = settings.integrator.time_step
    duration = run_length / speed
    steps = step_count(duration, time_step)
    if speed * steps * time_step > room + 1e-9 and steps > 1:
        return (steps - 1) * time_step
    return duration


def route(system: Catenary | EquilibriumState) -> tuple[str, float, np.ndarray]:
    """Name, contact-wire wave speed [m/s] and support stations [m] of the line a run goes along.

    Parameters
    ----------
    system : Catenary or EquilibriumState
        A catenary, or a form-found state (of a catenary or a lone wire, whose two ends are its
        supports).
    """
    if isinstance(system, Catenary):
        return system.name, system.contact_wire.wave_speed, np.concatenate([[0.0], np.cumsum(system.layout.span_lengths)])
    disc = system.discretisation
    name = system.catenary.name if system.catenary is not None else "lone wire"
    return name, disc.contact_wire.wave_speed, disc.mast_station.copy()


def run_warnings(state: EquilibriumState, plan: RunPlan) -> tuple[str, ...]:
    """One line per numerical setting of a run coarser than its speed needs.

    The element length is the longest contact-wire element of ``state`` (a state form-found for
    another speed may be coarser than this run's settings say); the time step is the plan's.

    Parameters
    ----------
    state : EquilibriumState
        The form-found catenary the run uses.
    plan : RunPlan
        The run.
    """
    element = float(np.max(np.diff(state.discretisation.cw_station)))
    return resolution_warnings(
        plan.operation.speed, plan.wave_speed, plan.settings.cutoff_frequency,
        element_length=element, time_step=plan.settings.integrator.time_step,
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


def recorded_droppers(
    model: StructuralModel, section: tuple[float, float], settings: SimulationSettings
) -> np.ndarray:
    if settings.droppers == "all":
        return np.arange(len(model.droppers))
    station = model.droppers.station
    return np.flatnonzero((station >= section[0]) & (station <= section[1]))


def _pantographs(pantograph: Pantograph | Sequence[Pantograph], count: int) -> list[Pantograph]:
    if isinstance(pantograph, Pantograph):
        return [pantograph] * count
    pantographs = list(pantograph)
    if len(pantographs) != count:
        raise ModelError(
            f"{len(pantographs)} pantograph model(s) given for {count} pantograph(s) "
            f"({count - 1} spacing(s)); give one model, or one per pantograph"
        )
    if not all(isinstance(p, Pantograph) for p in pantographs):
        raise ModelError("pantograph: every entry must be a Pantograph (see load_pantograph)")
    return pantographs
