"""Implicit time integration of ``M a + C v + K u + f_nl(u, v, t) = f_ext(t)``.

Schemes: Newmark average acceleration (γ = 1/2, β = 1/4; energy-conserving, no numerical damping)
and HHT-α (α in [-1/3, 0]; γ = 1/2 - α, β = (1 - α)²/4), which damps high frequencies. With
``s = 1 + α``, step n -> n+1 solves for u = u_(n+1)

    R(u) = M a(u) + s [C v(u) + K u + f_nl(u, v(u), t_(n+1))] - α r_n - s f_(n+1) + α f_n = 0,

    a(u) = a0 (u - ũ),   v(u) = ṽ + a1 (u - ũ),   a0 = 1/(β Δt²),   a1 = γ/(β Δt),

where ũ = u_n + Δt v_n + Δt² (1/2 - β) a_n, ṽ = v_n + Δt (1 - γ) a_n and r_n = C v_n + K u_n + f_nl,n.
Newton's matrix is ``K_eff + s·E T Eᵀ`` with the constant ``K_eff = a0 M + s (K + a1 C)`` and the
tangent ``T = ∂f_nl/∂u + a1 ∂f_nl/∂v`` on the few DOFs ``E`` the nonlinear forces act on.

Two ways to solve it, chosen by :attr:`IntegratorSettings.method`:

``"fast"``
    ``K_eff`` is factorised once. Each Newton correction uses the Sherman–Morrison–Woodbury identity
    with columns ``K_eff⁻¹ e_j`` kept in a small cache (the pantograph DOFs recur every step; the
    contact-wire DOFs under a moving pantograph recur for a few steps), and the residual is updated on
    the nonlinear DOFs only.
``"reference"``
    Straightforward: every iteration assembles and factorises the full Newton matrix and evaluates
    the full residual. For benchmarks and cross-checks.

References
----------
N. M. Newmark, "A method of computation for structural dynamics", J. Eng. Mech. Div. ASCE 85 (1959)
67–94. H. M. Hilber, T. J. R. Hughes, R. L. Taylor, "Improved numerical dissipation for time
integration algorithms in structural dynamics", Earthq. Eng. Struct. Dyn. 5 (1977) 283–292,
doi:10.1002/eqe.4290050306. W. W. Hager, "Updating the inverse of a matrix", SIAM Review 31 (1989)
221–239, doi:10.1137/1031049 (Woodbury identity).
"""

from __future__ import annotations

import time as wallclock
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import Literal

import numpy as np
import scipy.sparse as sp
from scipy.sparse.linalg import splu

from presag_opt.dynamics.assembly import newmark_predictor
from presag_opt.dynamics.laws import scheme_constants
from presag_opt.dynamics.step_solvers import (
    NO_FORCE,
    EquationOfMotion,
    FactorisedSolver,
    NonlinearForce,
    NonlinearForceFunction,
    ReferenceSolver,
    StepTerms,
    full_residual,
    norm,
)
from presag_opt.errors import ConvergenceError, ModelError
from presag_opt.system.quantity import quantity, validate_fields

SCHEMES = ("newmark", "hht")
METHODS = ("fast", "reference")

@dataclass(frozen=True, kw_only=True)
class IntegratorSettings:
    """Numerical settings of the time integration (separate from the physical model).

    Attributes
    ----------
    time_step : float
        Constant time step. [s]
    scheme : {"newmark", "hht"}
        Average-acceleration Newmark, or HHT-α with numerical damping.
    hht_alpha : float
        HHT α in [-1/3, 0]; more negative damps high frequencies more (used by ``"hht"`` only). [-]
    tolerance : float
        Newton stops when the largest residual entry is below ``tolerance`` times the largest force
        term of the step's equations. [-]
    max_iterations : int
        Newton corrections allowed per step before :class:`ConvergenceError`. [-]
    method : {"fast", "reference"}
        Constant factorisation with low-rank corrections, or full refactorisation every iteration.
    """

    time_step: float = quantity("time", 1e-3, 100.0, display="ms", default=2e-3)
    scheme: Literal["newmark", "hht"] = "newmark"
    hht_alpha: float = quantity("ratio", -1.0 / 3.0, 0.0, default=-0.05)
    tolerance: float = quantity("ratio", 1e-14, 1e-3, default=1e-10)
    max_iterations: int = quantity("count", 1, 100, default=25)
    method: Literal["fast", "reference"] = "fast"

    def __post_init__(self) -> None:
        validate_fields(self)
        if self.scheme not in SCHEMES:
            raise ModelError(f"scheme = {self.scheme!r} is not one of {', '.join(map(repr, SCHEMES))}")
        if self.method not in METHODS:
            raise ModelError(f"method = {self.method!r} is not one of {', '.join(map(repr, METHODS))}")
        if self.max_iterations != int(self.max_iterations):
            raise ModelError(f"max_iterations = {self.max_iterations!r} is not a whole number")

@dataclass(frozen=True, kw_only=True)
class State:
    """Displacements, velocities and accelerations of all DOFs at one instant.

    Attributes
    ----------
    displacement : numpy.ndarray
        [m]
    velocity : numpy.ndarray
        [m/s]
    acceleration : numpy.ndarray or None
        [m/s²]; None lets :func:`integrate` compute it from the equation of motion.
    """

    displacement: np.ndarray
    velocity: np.ndarray
    acceleration: np.ndarray | None = None


@dataclass(frozen=True, kw_only=True)
class IntegrationResult:
    """Time histories of the recorded DOFs.

    Attributes
    ----------
    time : numpy.ndarray
        Time of each record, shape (n_steps + 1,). [s]
    dofs : numpy.ndarray
        Recorded DOF indices (columns of the arrays below). [-]
    displacement : numpy.ndarray
        Shape (n_steps + 1, len(dofs)). [m]
    velocity : numpy.ndarray
        Shape (n_steps + 1, len(dofs)). [m/s]
    acceleration : numpy.ndarray
        Shape (n_steps + 1, len(dofs)). [m/s²]
    observed : numpy.ndarray or None
        What ``observe`` returned at each time, shape (n_steps + 1, m). [as returned]
    iterations : numpy.ndarray
        Newton corrections taken in each step, shape (n_steps,). [-]
    final_state : State
        Full state at the last time, to continue a run.
    wall_time : float
        Wall-clock time spent stepping. [s]
    """

    time: np.ndarray
    dofs: np.ndarray
    displacement: np.ndarray
    velocity: np.ndarray
    acceleration: np.ndarray
    observed: np.ndarray | None
    iterations: np.ndarray
    final_state: State
    wall_time: float

    @property
    def steps_per_second(self) -> float:
        """Integration speed. [1/s]"""
        return len(self.iterations) / max(self.wall_time, 1e-12)

def integrate(
    mass: sp.spmatrix,
    damping: sp.spmatrix,
    stiffness: sp.spmatrix,
    *,
    duration: float,
    settings: IntegratorSettings | None = None,
    external_force: Callable[[float], np.ndarray] | None = None,
    nonlinear_force: NonlinearForceFunction | None = None,
    initial_state: State | None = None,
    record_dofs: Sequence[int] | None = None,
    observe: Callable[[float, np.ndarray, np.ndarray], np.ndarray] | None = None,
) -> IntegrationResult:
    """Integrate ``M a + C v + K u + f_nl(u, v, t) = f_ext(t)`` from ``t = 0`` over ``duration``.

    Parameters
    ----------
    mass, damping, stiffness : scipy.sparse matrix
        M [kg], C [N·s/m] and K [N/m], square, all of the same size n.
    duration : float
        Simulated time; rounded up to whole time steps. [s]
    settings : IntegratorSettings, optional
        Scheme, time step, tolerances and method; defaults to ``IntegratorSettings()``.
    external_force : callable, optional
        ``f_ext(t [s]) -> (n,) array`` [N]; zero if not given.
    nonlinear_force : callable, optional
        ``f_nl(u [m], v [m/s], t [s]) -> NonlinearForce`` on the left-hand side [N]; zero if not given.
    initial_state : State, optional
        State at ``t = 0``; at rest (all zero) if not given. A missing acceleration is computed from
        the equation of motion, which needs a non-singular mass matrix.
    record_dofs : sequence of int, optional
        DOFs whose histories are kept; all DOFs if not given (mind the memory for large models). [-]
    observe : callable, optional
        ``observe(t [s], u [m], v [m/s]) -> (m,) array`` evaluated at every record time, e.g. the
        contact force. [as returned]

    Returns
    -------
    IntegrationResult
        Histories of the recorded DOFs and of ``observe``, Newton iterations and the final state.

    Raises
    ------
    ModelError
        Inconsistent matrix sizes, a non-positive duration or a singular mass matrix.
    ConvergenceError
        A step's Newton iteration did not converge within ``settings.max_iterations``; ``stats``
        holds the step, time and residual history.
    """
    settings = settings or IntegratorSettings()
    system = _build_system(mass, damping, stiffness, external_force, nonlinear_force, settings)
    n = system.mass.shape[0]
    n_steps = step_count(duration, settings.time_step)
    solver = FactorisedSolver(system) if settings.method == "fast" else ReferenceSolver(system)
    u, v, a, internal = _initial_state(system, initial_state, n)
    dofs = np.arange(n) if record_dofs is None else np.asarray(record_dofs, dtype=int)
    recorder = _Recorder(n_steps, dofs, observe)
    recorder.record(0, 0.0, u, v, a)
    force = np.asarray(system.external_force(0.0), dtype=float)
    start = wallclock.perf_counter()
    for index in range(n_steps):
        t_next = (index + 1) * settings.time_step
        step = _predict(system, u, v, a, internal, force, t_next)
        u, nl, iterations, residual = _solve_step(system, solver, step, settings, index)
        a, v = step.kinematics(u, system.c)
        if system.c.alpha != 0.0:
            # r_(n+1) from the step's own residual R = M a + s r − rhs: no further K u, C v products.
            internal = (residual + step.rhs - system.inertia(a)) / system.c.s
        force = step.forcing
        recorder.record(index + 1, t_next, u, v, a, iterations)
    return recorder.result(State(displacement=u, velocity=v, acceleration=a), wallclock.perf_counter() - start)


def _build_system(
    mass: sp.spmatrix,
    damping: sp.spmatrix,
    stiffness: sp.spmatrix,
    external_force: Callable[[float], np.ndarray] | None,
    nonlinear_force: NonlinearForceFunction | None,
    settings: IntegratorSettings,
) -> EquationOfMotion:
    matrices = [sp.csr_matrix(m, dtype=float) for m in (mass, damping, stiffness)]
    n = matrices[0].shape[0]
    for name, m in zip(("mass", "damping", "stiffness"), matrices):
        if m.shape != (n, n):
            raise ModelError(f"{name} matrix has shape {m.shape}; all three must be square and {n} x {n}")
    zero = np.zeros(n)
    return EquationOfMotion(
        *matrices,
        external_force=external_force or (lambda t: zero),
        nonlinear_force=nonlinear_force or (lambda u, v, t: NO_FORCE),
        c=scheme_constants(settings),
    )


def step_count(duration: float, time_step: float) -> int:
    """Number of time steps that cover ``duration`` [s] at ``time_step`` [s] (rounded up). [-]

    Parameters
    ----------
    duration : float
        Simulated time. [s]
    time_step : float
        Time step. [s]
    """
    if not duration > 0.0:
        raise ModelError(f"duration = {duration!r} s must be positive")
    return int(np.ceil(duration / time_step - 1e-9))


def _initial_state(
    system: EquationOfMotion, state: State | None, n: int
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Initial u [m], v [m/s], a [m/s²] and internal force r = C v + K u + f_nl [N].

    A missing acceleration comes from M a = f_ext - r.
    """
    u = np.zeros(n) if state is None else np.array(state.displacement, dtype=float)
    v = np.zeros(n) if state is None else np.array(state.velocity, dtype=float)
    internal = system.internal_force(u, v, system.nonlinear_force(u, v, 0.0))
    if state is not None and state.acceleration is not None:
        return u, v, np.array(state.acceleration, dtype=float), internal
    try:
        return u, v, splu(system.mass.tocsc()).solve(system.external_force(0.0) - internal), internal
    except RuntimeError:
        raise ModelError(
            "the mass matrix is singular (DOFs without mass): give initial_state with an acceleration"
        ) from None


def _predict(
    system: EquationOfMotion, u: np.ndarray, v: np.ndarray, a: np.ndarray, internal: np.ndarray, force: np.ndarray, t_next: float
) -> StepTerms:
    """Predictors ũ, ṽ and the right-hand side s f_(n+1) - α f_n + α r_n of the step to ``t_next``."""
    c = system.c
    forcing = np.asarray(system.external_force(t_next), dtype=float)
    rhs = c.s * forcing - c.alpha * force + c.alpha * internal if c.alpha else forcing
    u_pred, v_pred = newmark_predictor(u, v, a, c)
    return StepTerms(time=t_next, u_pred=u_pred, v_pred=v_pred, forcing=forcing, rhs=rhs)


def _solve_step(
    system: EquationOfMotion, solver: FactorisedSolver | ReferenceSolver, step: StepTerms, settings: IntegratorSettings, index: int
) -> tuple[np.ndarray, NonlinearForce, int, np.ndarray]:
    """Newton iteration for u_(n+1), starting from the predictor ũ. Returns u, f_nl, iterations and
    the final residual."""
    c = system.c
    u = step.u_pred
    nl = system.nonlinear_force(u, step.v_pred, step.time)
    residual, scale = full_residual(system, step, u, nl)
    limit = settings.tolerance * scale
    history = [norm(residual)]
    for iteration in range(settings.max_iterations + 1):
        if history[-1] <= limit:
            return u, nl, iteration, residual
        if iteration == settings.max_iterations or not np.isfinite(history[-1]):
            break
        tangent = nl.tangent(c.a1)
        delta = solver.correction(-residual, nl.dofs, tangent)
        u = u + delta
        new = system.nonlinear_force(u, step.kinematics(u, c)[1], step.time)
        residual = solver.next_residual(step, u, nl, new, tangent, delta)
        nl = new
        history.append(norm(residual))
    raise ConvergenceError(
        f"Newton iteration did not converge in step {index + 1} (t = {step.time:.6g} s): residual "
        f"{history[-1]:.3g} N after {len(history) - 1} corrections, tolerance {limit:.3g} N",
        stats={
            "step": index + 1,
            "time": step.time,
            "iterations": len(history) - 1,
            "residual_history": history,
            "tolerance": limit,
            "method": settings.method,
            "scheme": settings.scheme,
        },
    )


@dataclass
class _Recorder:
    """Preallocated histories of the recorded DOFs."""

    n_steps: int
    dofs: np.ndarray
    observe: Callable[[float, np.ndarray, np.ndarray], np.ndarray] | None
    arrays: dict[str, np.ndarray] = field(init=False)
    observed: list[np.ndarray] = field(default_factory=list)

    def __post_init__(self) -> None:
        shape = (self.n_steps + 1, len(self.dofs))
        self.arrays = {
            "time": np.zeros(self.n_steps + 1),
            "displacement": np.zeros(shape),
            "velocity": np.zeros(shape),
            "acceleration": np.zeros(shape),
            "iterations": np.zeros(self.n_steps, dtype=int),
        }

    def record(self, index: int, t: float, u: np.ndarray, v: np.ndarray, a: np.ndarray, iterations: int = 0) -> None:
        arrays = self.arrays
        arrays["time"][index] = t
        arrays["displacement"][index] = u[self.dofs]
        arrays["velocity"][index] = v[self.dofs]
        arrays["acceleration"][index] = a[self.dofs]
        if index:
            arrays["iterations"][index - 1] = iterations
        if self.observe is not None:
            self.observed.append(np.atleast_1d(np.asarray(self.observe(t, u, v), dtype=float)))

    def result(self, final_state: State, wall_time: float) -> IntegrationResult:
        return IntegrationResult(
            **self.arrays,
            dofs=self.dofs,
            observed=np.vstack(self.observed) if self.observe is not None else None,
            final_state=final_state,
            wall_time=wall_time,
        )
