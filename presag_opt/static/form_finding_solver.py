"""The form-finding equations solved with IPOPT: the method, and its options.

:func:`solve_form_finding` hands the square system of :mod:`presag_opt.static.form_finding_equations`
to IPOPT (through CasADi's ``nlpsol``) as a feasibility problem (zero objective) with the options
:data:`IPOPT_OPTIONS`, and returns a :class:`FormFindingSolution`. The solver is built once per
topology and options and kept by the process (:data:`SOLVERS_KEPT`): the numbers of a problem are
parameters of its equations, so a second form-finding of the same structure (another sample of a
screening, the next pass, a re-solve) only runs IPOPT.
"""

from __future__ import annotations

import functools
import os
import signal
import threading
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass

import casadi as ca
import numpy as np

from presag_opt.errors import ConvergenceError
from presag_opt.static.discretisation import Discretisation
from presag_opt.static.equilibrium_newton import round_off_force
from presag_opt.static.form_finding_equations import (
    SYSTEMS_KEPT,
    FormFindingTopology,
    form_finding_problem,
    topology_system,
)
from presag_opt.static.potential import PhysicalParameters


@dataclass(frozen=True, kw_only=True)
class FormFindingSolution:
    """What the form-finding NLP returns (numeric).

    Attributes
    ----------
    positions : ndarray, shape (n_nodes, 3)
        Equilibrium coordinates including the steady-arm pivots. [m]
    dropper_unstretched_length : ndarray
        Unstretched length of each dropper. [m]
    spring_reference : ndarray
        Unloaded position of each ground spring. [m]
    iterations : int
        IPOPT iterations, over every solve. [-]
    restarts : int
        Solves begun again after one that failed. [-]
    """

    positions: np.ndarray
    dropper_unstretched_length: np.ndarray
    spring_reference: np.ndarray
    iterations: int
    restarts: int = 0

IPOPT_OPTIONS = (
    ("print_level", 0),
    ("sb", "yes"),
    ("tol", 1e-8),
    ("max_iter", 100),
    ("hessian_approximation", "limited-memory"),
    ("linear_solver", "mumps"),
)
"""IPOPT's options for the form-finding solve: silent; converged at a scaled residual of 1e-8 (and an
equation violation of :data:`EQUATION_TOLERANCE`, see :func:`solve_form_finding`); at most 100
iterations; limited-memory Hessian (the system is square, the objective zero); MUMPS."""

RESTART_OPTIONS = (("hessian_approximation", "exact"), ("max_iter", 100))
"""What a solve that did not converge is begun again with, from the same start: the exact Hessian of
the equations (CasADi's, a second method rather than more iterations of the first; building it costs
about as much as the first solve). Counted as a restart (:attr:`FormFindingSolution.restarts`)."""

SCALED_VIOLATION = 1e-5
"""IPOPT's ``constr_viol_tol`` on the equations as it sees them, g·c/τ with c this value and τ the
violation accepted (:data:`EQUATION_TOLERANCE` or the round-off, see :func:`solve_form_finding`):
τ is a parameter of the problem rather than an option of the solver, so one solver serves every
problem of a topology. IPOPT scales each equation to a largest gradient of 100 at its start
(gradient-based scaling, with no factor below 1e-8). The equations' largest gradients lie between
about 8e3 N/m (string stiffness) and 1e9 N/m (the messenger-wire pins on curves) on the built-in
models and the sections of a surveyed line, and τ between 1e-6 N and about 5e-4 N (the round-off of
a long section), so c/τ lies between 0.02 and 10 and every scaled equation still has a largest
gradient between 100 and 1e10: IPOPT's scaling absorbs c/τ and it iterates as on g itself. [N]"""

SOLVERS_KEPT = SYSTEMS_KEPT
"""IPOPT solvers a process keeps, per topology and options (least recently used dropped first; as
many as :data:`~presag_opt.static.form_finding_equations.SYSTEMS_KEPT`: a restart's solver is rare). [-]"""

EQUATION_TOLERANCE = 1e-6
"""Largest violation of a form-finding equation accepted, unless the round-off of the nodal forces
(:func:`~presag_opt.static.equilibrium_newton.round_off_force`) is larger: IPOPT then stops at the round-off
instead of iterating on it (the Newton relaxation that follows meets the force tolerance). [N]"""


@contextmanager
def interrupts_kept() -> Iterator[None]:
    """Keep a Ctrl-C or SIGTERM that arrives during a CasADi call: CasADi turns it into a failed solve
    (status ``NonIpopt_Exception_Thrown``), which would otherwise be restarted like any other failure.
    Inside the block both signals are recorded and passed on to the handlers in force; at its end a
    recorded one raises :class:`KeyboardInterrupt`. Outside the main thread (where no handler can be
    set) the block changes nothing."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    received: list[int] = []
    previous = {number: signal.getsignal(number) for number in (signal.SIGINT, signal.SIGTERM)}

    def record(number: int, frame: object) -> None:
        if previous[number] == signal.SIG_IGN:
            return
        received.append(number)
        if callable(previous[number]):
            previous[number](number, frame)  # e.g. raises KeyboardInterrupt, which CasADi swallows

    try:
        for number in previous:
            signal.signal(number, record)
        yield
    finally:
        for number, handler in previous.items():
            signal.signal(number, handler)
    if signal.SIGTERM in received and previous[signal.SIGTERM] == signal.SIG_DFL:
        os.kill(os.getpid(), signal.SIGTERM)  # the default action, now that the default is back
    if received:
        raise KeyboardInterrupt


def solve_form_finding(
    disc: Discretisation,
    params: PhysicalParameters,
    wire_tension: np.ndarray,
    target_dofs: np.ndarray,
    x_design: np.ndarray,
) -> FormFindingSolution:
    """Solve the form-finding equations with IPOPT.

    The wire nodes keep their designed position along the wire (droppers vertical, clamps where the
    design puts them), so every wire element acts as a string of constant horizontal tension H:
    energy ``H l_h + H/(2 l_h₀) (Δz)²`` with ``l_h`` its horizontal length. Unknowns: the heights
    of the wire nodes, their sideways (in-plan, across the wire) positions, the dropper unstretched
    lengths, the force of every steady arm on its clamp (across the track and vertically, in the mast
    plane; the pivot follows on its line) and the ground-spring references. Equations: vertical and
    sideways equilibrium at every free node, equilibrium across the track at every steady-arm clamp
    (whose lateral position is the stagger), and the designed height at ``target_dofs``. The system
    is square; IPOPT solves it as a feasibility problem (zero objective), to an equation violation of
    :data:`EQUATION_TOLERANCE` or the round-off of the nodal forces, whichever is larger. A solve that
    IPOPT does not finish is begun again once with :data:`RESTART_OPTIONS`. The solvers are built once
    per topology and kept by the process (:func:`_solver`), so only the first problem of a structure
    pays for building one (about 0.6 s for the 600 m case-study section and 1.4 s for the 1.34 km
    mixed one with their equations; a solve about 0.05 s).

    Parameters
    ----------
    disc : Discretisation
        Topology.
    params : PhysicalParameters
        Parameter values; dropper lengths and spring references are starting values.
    wire_tension : ndarray
        Horizontal tension of each axial element that is a wire segment, 0 for the others. [N]
    target_dofs : ndarray of int
        Degrees of freedom (heights) that must keep their design value. [-]
    x_design : ndarray
        Design coordinates (the first-guess pivots give the arms' starting forces). [m]

    Raises
    ------
    ConvergenceError
        If IPOPT does not report success after the restart either.
    """
    problem = form_finding_problem(disc, params, wire_tension, target_dofs, x_design)
    system = problem.system
    tolerance = max(EQUATION_TOLERANCE, round_off_force(params, x_design))
    parameters = np.append(problem.parameters, SCALED_VIOLATION / tolerance)
    iterations = restarts = 0
    for options in (IPOPT_OPTIONS, (*IPOPT_OPTIONS, *RESTART_OPTIONS)):
        solver = _solver(problem.topology, system.layout, options)
        with interrupts_kept():
            result = solver(x0=problem.start, p=parameters, lbg=0, ubg=0)
        stats = solver.stats()
        iterations += int(stats.get("iter_count", 0))
        if stats.get("success", False):
            break
        restarts += 1
    else:
        raise ConvergenceError(
            f"form-finding did not converge: IPOPT status {stats.get('return_status')!r} "
            f"after {iterations} iterations (a restart with the exact Hessian included)",
            stats,
        )
    sol = np.asarray(result["x"]).ravel()
    positions = np.asarray(system.coordinates(sol, problem.parameters)).ravel()
    start = len(system.z_unknown) + system.n_side + 2 * system.n_arm
    return FormFindingSolution(
        positions=positions.reshape(-1, 3),
        dropper_unstretched_length=sol[start : start + system.n_drop],
        spring_reference=sol[start + system.n_drop :],
        iterations=iterations,
        restarts=restarts,
    )


@functools.lru_cache(maxsize=SOLVERS_KEPT)
def _solver(topology: FormFindingTopology, layout: tuple[tuple[str, int], ...],
            options: tuple[tuple[str, object], ...]) -> ca.Function:
    """IPOPT on the equations of ``topology`` (:func:`~presag_opt.static.form_finding_equations.topology_system`),
    scaled by a last parameter (see :data:`SCALED_VIOLATION`), with ``options`` (later entries win).

    Built once per topology and options and kept by the process, like the equations: a memo keyed
    by structure and options alone (never by numbers), bounded by :data:`SOLVERS_KEPT`. The restart's
    solver is built only when a solve needs it.
    """
    system = topology_system(topology, layout)
    scale = ca.SX.sym("equation_scale")
    problem = {"x": system.unknowns, "p": ca.vertcat(system.parameters, scale), "f": ca.SX(0),
               "g": system.equations * scale}
    # Only x is read: CasADi's multipliers after the solve (lam_x, lam_p and the function nlp_grad
    # they need, a reverse pass over the equations) are not built; a third of the build time.
    return ca.nlpsol("form_finding", "ipopt", problem,
                     {"print_time": False, "calc_lam_p": False, "calc_lam_x": False, "no_nlp_grad": True,
                      "ipopt": {**dict(options), "constr_viol_tol": SCALED_VIOLATION}})
