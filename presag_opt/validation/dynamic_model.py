"""Checks of the dynamic model against independent references: crawling speed, a moving force on a
tensioned string, and convergence in element length and time step.

- :func:`crawling_check`: at crawling speed a pantograph of constant force F lifts the contact wire by
  F·e(x), e the static (tangent-stiffness) elasticity: the simulator against the static model.
- :func:`moving_force_on_string`: the time integrator on a lumped-mass tensioned string against the
  closed-form modal solution of a constant force crossing a string (:func:`string_under_moving_force`).
- :func:`convergence_study`: contact-force statistics of a case on a ladder of element lengths and
  time steps.

The EN 50318-style reference ranges are in :mod:`presag_opt.validation.en50318`.

References
----------
L. Frýba, *Vibration of Solids and Structures under Moving Loads*, 3rd ed., Thomas Telford (1999),
the chapter on the string (moving constant force, undamped case).
"""

from __future__ import annotations

import dataclasses
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from presag_opt.dynamics.batch import simulate_many
from presag_opt.dynamics.case import SimulationCase
from presag_opt.dynamics.integrator import IntegratorSettings, integrate
from presag_opt.dynamics.pantograph import Pantograph, PantographStage
from presag_opt.dynamics.settings import OperatingPoint, SimulationSettings
from presag_opt.dynamics.simulate import simulate
from presag_opt.elasticity import linear_elasticity
from presag_opt.errors import ModelError
from presag_opt.static.discretisation import StaticSettings
from presag_opt.static.equilibrium import EquilibriumState
from presag_opt.static.form_finding import form_find
from presag_opt.units import KMH

CONSTANT_FORCE_PANTOGRAPH = Pantograph(
    name="constant force (no frame spring, no friction)",
    stages=(
        PantographStage(name="head", mass=7.2, stiffness=4200.0, damping=10.0),
        PantographStage(name="frame", mass=15.0, damping=90.0),
    ),
)
"""A pantograph whose quasi-static contact force is exactly its uplift force (the case study's masses,
head spring and dampers, no frame spring and no friction)."""


@dataclass(frozen=True, kw_only=True)
class CrawlingCheck:
    """Contact-wire uplift under a crawling pantograph against contact force × static elasticity.

    Attributes
    ----------
    speed : float
        Train speed. [m/s]
    beta : float
        Speed ratio v/c_CW. [-]
    static_force : float
        Uplift force of the pantograph. [N]
    position : ndarray
        Contact point from the first mast of the analysed span. [m]
    contact_force : ndarray
        Contact force there. [N]
    uplift : ndarray
        Simulated contact-wire uplift under the pantograph. [m]
    expected : ndarray
        Contact force times the tangent-stiffness elasticity at the same position. [m]
    any_slack : bool
        Whether a dropper went slack (then the linear elasticity does not apply).
    """

    speed: float
    beta: float
    static_force: float
    position: np.ndarray
    contact_force: np.ndarray
    uplift: np.ndarray
    expected: np.ndarray
    any_slack: bool

    @property
    def max_relative_error(self) -> float:
        """Largest |uplift / expected − 1| over the span. [-]"""
        return float(np.max(np.abs(self.uplift / self.expected - 1.0)))

    @property
    def force_deviation(self) -> float:
        """Largest |contact force / static force − 1|. [-]"""
        return float(np.max(np.abs(self.contact_force / self.static_force - 1.0)))


def crawling_check(
    state: EquilibriumState,
    *,
    speed: float = KMH,
    static_force: float = 60.0,
    time_step: float = 7e-3,
    pantograph: Pantograph = CONSTANT_FORCE_PANTOGRAPH,
) -> CrawlingCheck:
    """Run a constant-force pantograph slowly over the middle span of a section and compare the
    contact-wire uplift with F·e(x) from the tangent stiffness.

    At β = v/c_CW well below 0.1 the moving-load correction (order β²) is negligible. The analysed
    span is the middle one, entered at its first mast (no lead-in), every dropper recorded.

    Parameters
    ----------
    state : EquilibriumState
        Form-found section, e.g. three spans.
    speed : float
        Train speed. [m/s]
    static_force : float
        Uplift force; small enough that no dropper slackens. [N]
    time_step : float
        Integration time step; below the contact limit of the pantograph head. [s]
    pantograph : Pantograph
        A pantograph without frame spring or friction.

    Returns
    -------
    CrawlingCheck
    """
    settings = SimulationSettings(analysed_spans=1, lead_in_spans=0, droppers="all",
                                  integrator=IntegratorSettings(time_step=time_step))
    result = simulate(state, pantograph, speed=speed, static_force=static_force, settings=settings)
    run = result.pantographs[0]
    start, end = result.analysed_section
    inside = (run.position >= start) & (run.position <= end)
    masts = np.asarray(result.support_station)
    span = int(np.argmin(np.abs(masts - start)))
    elasticity = linear_elasticity(state, span=span, step=0.1).at(run.position[inside] - start)
    return CrawlingCheck(
        speed=float(speed), beta=float(result.speed_ratio), static_force=float(static_force),
        position=run.position[inside] - start, contact_force=run.contact_force[inside],
        uplift=run.wire_uplift[inside], expected=run.contact_force[inside] * elasticity,
        any_slack=bool(result.slack.any()),
    )


def string_under_moving_force(
    x: float | np.ndarray, t: np.ndarray, *, speed: float, tension: float, mass_per_length: float,
    length: float, force: float, terms: int = 4000,
) -> np.ndarray:
    """Deflection w(x, t) of a fixed-fixed string under a constant force entering at x = 0 at t = 0.

    Modal solution with sin(jπx/l), ω_j = jπc/l, Ω_j = jπv/l and zero initial conditions,
    q_j = 2P / (ρ l (ω_j² − Ω_j²)) · (sin Ω_j t − (Ω_j/ω_j) sin ω_j t), valid while the force is on
    the string (0 ≤ vt ≤ l). The sum of the sin Ω_j t parts is the static deflection line under the
    force divided by (1 − β²), taken in closed form so that only the free-vibration part is summed
    as a series (its terms fall as 1/j²).

    Parameters
    ----------
    x : float or ndarray
        Station of the observed point, or one station per time (e.g. under the force, x = v t). [m]
    t : ndarray
        Times. [s]
    speed : float
        Speed of the force, below the wave speed. [m/s]
    tension : float
        String tension. [N]
    mass_per_length : float
        [kg/m]
    length : float
        Distance between the fixed ends. [m]
    force : float
        The moving force, positive in the direction of w. [N]
    terms : int
        Modes summed in the free-vibration part. [-]

    Returns
    -------
    ndarray
        Deflection in the direction of the force. [m]

    References
    ----------
    L. Frýba (1999), the chapter on the string (moving constant force, undamped case).
    """
    wave_speed = np.sqrt(tension / mass_per_length)
    beta = speed / wave_speed
    a = speed * np.asarray(t)
    static = np.where(x <= a, force * x * (length - a), force * a * (length - x)) / (tension * length)
    j = np.arange(1, terms + 1)[:, None]
    omega = j * np.pi * wave_speed / length
    amplitude = 2.0 * force * beta / (mass_per_length * length * omega**2 * (1.0 - beta**2))
    shape = np.sin(j * np.pi * np.asarray(x, dtype=float)[None, ...] / length)
    free = (amplitude * np.sin(omega * a[None, :] / speed) * shape).sum(axis=0)
    return static / (1.0 - beta**2) - free


@dataclass(frozen=True)
class LumpedString:
    """Lumped-mass tensioned string with both ends fixed (interior nodes only).

    Attributes
    ----------
    mass, stiffness : scipy.sparse.csr_matrix
        M [kg] and K [N/m] over the interior nodes.
    x : ndarray
        Node positions along the string. [m]
    element_length : float
        [m]
    """

    mass: sp.csr_matrix
    stiffness: sp.csr_matrix
    x: np.ndarray
    element_length: float


def lumped_string(*, tension: float, mass_per_length: float, length: float, element_length: float) -> LumpedString:
    """Assemble a tensioned string of elements k = T/h with lumped masses ρh at the nodes.

    Independent of the catenary discretisation, so that the integrator is checked on its own.

    Parameters
    ----------
    tension : float
        [N]
    mass_per_length : float
        [kg/m]
    length : float
        Distance between the fixed ends. [m]
    element_length : float
        Target element length; rounded so that whole elements fit. [m]
    """
    n_elements = round(length / element_length)
    h = length / n_elements
    n = n_elements - 1
    k = tension / h
    stiffness = sp.diags([-k * np.ones(n - 1), 2 * k * np.ones(n), -k * np.ones(n - 1)], [-1, 0, 1], format="csr")
    mass = sp.diags(mass_per_length * h * np.ones(n), format="csr")
    return LumpedString(mass=mass, stiffness=stiffness, x=h * np.arange(1, n + 1), element_length=h)


@dataclass(frozen=True, kw_only=True)
class MovingForceCheck:
    """Mid-point deflection of a string under a moving force: integrator against the modal series.

    Attributes
    ----------
    beta : float
        Speed of the force over the wave speed. [-]
    element_length, time_step : float
        Discretisation. [m], [s]
    time : ndarray
        Times while the force crosses the string. [s]
    numerical, analytic : ndarray
        Mid-point deflection from the integrator and from :func:`string_under_moving_force`. [m]
    static_mid : float
        P·l/(4T), the static mid-point deflection with the force there: the error scale. [m]
    """

    beta: float
    element_length: float
    time_step: float
    time: np.ndarray
    numerical: np.ndarray
    analytic: np.ndarray
    static_mid: float

    @property
    def max_error(self) -> float:
        """Largest |numerical − analytic| relative to ``static_mid``. [-]"""
        return float(np.abs(self.numerical - self.analytic).max() / self.static_mid)

    @property
    def rms_error(self) -> float:
        """RMS of numerical − analytic relative to ``static_mid``. [-]"""
        return float(np.sqrt(np.mean((self.numerical - self.analytic) ** 2)) / self.static_mid)


def moving_force_on_string(
    beta: float, *, element_length: float, time_step: float, tension: float = 10e3,
    mass_per_length: float = 1.0, length: float = 60.0, force: float = 100.0,
) -> MovingForceCheck:
    """Step a lumped string under a constant moving force (Newmark, no damping) and compare the
    mid-point deflection with the modal series.

    The force is shared between the two nodes of its element by the linear shape functions.

    Parameters
    ----------
    beta : float
        Speed of the force over the wave speed sqrt(T/ρ), in (0, 1). [-]
    element_length : float
        Target element length; an even element count puts a node at mid-string. [m]
    time_step : float
        [s]
    tension, mass_per_length, length, force : float
        The string and the force (defaults: c = 100 m/s, 60 m, 100 N). [N], [kg/m], [m], [N]
    """
    if not 0.0 < beta < 1.0:
        raise ModelError(f"beta = {beta:g} is outside the valid range (0, 1)")
    string = lumped_string(tension=tension, mass_per_length=mass_per_length, length=length,
                           element_length=element_length)
    speed = beta * np.sqrt(tension / mass_per_length)
    n, h = len(string.x), string.element_length
    mid = n // 2
    if not np.isclose(string.x[mid], length / 2):
        raise ModelError(f"element_length = {element_length:g} m gives an odd element count: no node at mid-string")

    def load(t: float) -> np.ndarray:
        out = np.zeros(n)
        a = speed * t
        if 0.0 < a < length:
            k = int(a // h)
            r = a / h - k
            if k >= 1:
                out[k - 1] += force * (1.0 - r)
            if k < n:
                out[k] += force * r
        return out

    result = integrate(string.mass, sp.csr_matrix((n, n)), string.stiffness, duration=length / speed,
                       settings=IntegratorSettings(time_step=time_step, scheme="newmark"),
                       external_force=load, record_dofs=[mid])
    analytic = string_under_moving_force(string.x[mid], result.time, speed=speed, tension=tension,
                                         mass_per_length=mass_per_length, length=length, force=force)
    return MovingForceCheck(beta=float(beta), element_length=h, time_step=float(time_step), time=result.time,
                            numerical=result.displacement[:, 0], analytic=analytic,
                            static_mid=force * length / (4.0 * tension))


@dataclass(frozen=True, kw_only=True)
class ConvergenceRung:
    """Contact-force statistics of a case at one element length and time step.

    Attributes
    ----------
    element_length, time_step : float
        [m], [s]
    speeds : tuple of float
        [m/s]
    betas, std_force, mean_force, max_force : tuple of float
        Per speed: v/c_CW [-], σ [N], F_m [N], largest filtered force [N].
    seconds : float
        Wall time of the rung (form-finding and batch). [s]
    """

    element_length: float
    time_step: float
    speeds: tuple[float, ...]
    betas: tuple[float, ...]
    std_force: tuple[float, ...]
    mean_force: tuple[float, ...]
    max_force: tuple[float, ...]
    seconds: float


@dataclass(frozen=True, kw_only=True)
class ConvergenceStudy:
    """A ladder of discretisations of one case, finest last.

    Attributes
    ----------
    case_name : str
        The case.
    rungs : tuple of ConvergenceRung
        Coarsest first.
    """

    case_name: str
    rungs: tuple[ConvergenceRung, ...]

    def sigma_change(self) -> np.ndarray:
        """σ of each rung relative to the finest, minus one; shape (rungs, speeds). [-]"""
        sigma = np.array([r.std_force for r in self.rungs])
        return sigma / sigma[-1] - 1.0


def convergence_study(
    case: SimulationCase,
    speeds: Sequence[float],
    rungs: Sequence[tuple[float, float]],
    progress: Callable[[str], None] | None = None,
) -> ConvergenceStudy:
    """Run a case at several speeds on each (element length, time step) of a ladder, as one batch
    per rung on a catenary form-found at that element length.

    Parameters
    ----------
    case : SimulationCase
        Catenary, pantograph, operation and settings.
    speeds : sequence of float
        Train speeds. [m/s]
    rungs : sequence of (float, float)
        (element length [m], time step [s]), finest last.
    progress : callable, optional
        Called with a short message before each rung.
    """
    if not rungs or not speeds:
        raise ModelError("convergence_study: give at least one speed and one rung")
    out = []
    for h, dt in rungs:
        if progress:
            progress(f"{case.name}: {h:g} m elements, {dt * 1e3:g} ms")
        started = time.perf_counter()
        settings = dataclasses.replace(
            case.settings, numerics="fixed", static=StaticSettings(element_length=h),
            integrator=dataclasses.replace(case.settings.integrator, time_step=dt),
        )
        state = form_find(case.catenary, settings.static)
        points = [OperatingPoint(speed=v, static_force=case.operation.static_force,
                                 aero_coefficient=case.operation.aero_coefficient) for v in speeds]
        batch = simulate_many(state, case.pantograph, points, spacings=case.operation.spacings, settings=settings)
        stats = [r.statistics[0] for r in batch.runs]
        c = case.catenary.contact_wire.wave_speed
        out.append(ConvergenceRung(
            element_length=float(h), time_step=float(dt), speeds=tuple(float(v) for v in speeds),
            betas=tuple(float(v / c) for v in speeds), std_force=tuple(s.std_force for s in stats),
            mean_force=tuple(s.mean_force for s in stats), max_force=tuple(s.max_force for s in stats),
            seconds=time.perf_counter() - started,
        ))
    return ConvergenceStudy(case_name=case.name, rungs=tuple(out))
