"""The route of a dynamic run, laid out before any time step: where each pantograph starts, which
spans are analysed, how long the run lasts, and the static contact it starts from.

:func:`plan_run` checks a run's inputs and lays out its route without form-finding (a
:class:`RunPlan`); :func:`static_contact` gives the catenary pressed by the pantographs at rest and
each pantograph's contact path (element, shape weights, element compliance) at every record time.
Both the single-run path (:func:`~presag_opt.dynamics.simulate.simulate`) and the batch engine
(:mod:`presag_opt.dynamics.batch`) use them; the route and the contact model are described in
:mod:`presag_opt.dynamics.simulate`.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from presag_opt.dynamics import laws
from presag_opt.dynamics.integrator import step_count
from presag_opt.dynamics.numerics import resolution_warnings
from presag_opt.dynamics.pantograph import Pantograph
from presag_opt.dynamics.settings import Operation, SimulationSettings
from presag_opt.dynamics.structure import StructuralModel
from presag_opt.errors import ModelError
from presag_opt.speed import doppler_factor
from presag_opt.static.equilibrium import EquilibriumState
from presag_opt.system.catenary import Catenary


def contact_path(state: EquilibriumState, stations: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Element nodes, shape weights [-] and element compliance [m/N] at contact-wire stations [m].

    Parameters
    ----------
    state : EquilibriumState
        The form-found catenary.
    stations : ndarray
        Stations along the contact wire. [m]
    """
    disc = state.discretisation
    shape = disc.cw_shape(stations)  # two stored entries per row, zeros included, nodes in order
    return shape.indices.reshape(-1, 2), shape.data.reshape(-1, 2), disc.cw_element_compliance(stations)


@dataclass(frozen=True)
class ContactPath:
    """Where one pantograph touches the wire at every record time, and its head height at rest.

    Attributes
    ----------
    nodes : ndarray of int, shape (n_times, 2)
        Contact-wire nodes of the element under the head. [-]
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
        nodes, weights, compliance = contact_path(state, x + plan.operation.speed * times)
        chord = weights[0] @ (model.cw_height[nodes[0]] + u0[model.cw_z[nodes[0]]])
        head = laws.head_height_in_contact(chord, p.contact.stiffness, compliance[0], uplift)
        paths.append(ContactPath(nodes, weights, compliance, float(head)))
    return u0, paths


@dataclass(frozen=True, kw_only=True)
class RunPlan:
    """A checked run: everything :func:`~presag_opt.dynamics.simulate.simulate` decides before the catenary is form-found.

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
        Spans (from 0) of the analysed section. [-]
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
        simulated time (which can end up to a step early at the end of the line). [s]

        Parameters
        ----------
        pantograph : int
            Pantograph, from 0, front to rear. [-]
        """
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

    Parameters are those of :func:`~presag_opt.dynamics.simulate.simulate` (``system`` a catenary, or a form-found state, which may
    be a lone wire). The leading pantograph starts ``lead_in_spans`` before
    the analysed section, the others behind it at their spacings; the run ends ``run_out`` seconds
    after the rear pantograph leaves the section.

    Parameters
    ----------
    system : Catenary or EquilibriumState
        The catenary, or a form-found state (which may be a lone wire).
    pantograph : Pantograph or sequence of Pantograph
        One model for every pantograph, or one per pantograph, front to rear.
    speed : float
        Train speed. [m/s]
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
    RunPlan

    Raises
    ------
    ModelError
        See :func:`~presag_opt.dynamics.simulate.simulate`.
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


def recorded_droppers(
    model: StructuralModel, section: tuple[float, float], settings: SimulationSettings
) -> np.ndarray:
    """Droppers whose forces a run records: all, or those inside the analysed section (``settings.droppers``).

    Parameters
    ----------
    model : StructuralModel
        Structural model of the section.
    section : (float, float)
        Start and end of the analysed section along the track. [m]
    settings : SimulationSettings
        Its ``droppers`` field chooses ``"all"`` or ``"analysed"``.

    Returns
    -------
    ndarray of int
        Indices into ``model.droppers``. [-]
    """
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
