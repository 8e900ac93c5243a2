"""The IPOPT solve of the form-finding equations: it holds the targets and gives droppers that carry
the wire, and a solve that IPOPT cannot finish raises with IPOPT's status (the balance of the result
is checked through form_find in test_form_finding.py)."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from presag_opt.errors import ConvergenceError
from presag_opt.static import form_finding, form_finding_solver
from presag_opt.static.discretisation import StaticSettings
from presag_opt.static.equilibrium import static_model
from presag_opt.static.potential import PhysicalParameters
from presag_opt.system.catenary import SpanLayout
from presag_opt.system.loader import load_catenary


def _first_pass(disc):
    """The inputs of form-finding's first IPOPT solve of ``disc``, from form_find's own helpers."""
    ax = disc.axial
    x_design = disc.design_positions.ravel()
    params = PhysicalParameters(
        axial_stiffness=ax.stiffness, unstretched_length=ax.design_length.copy(), slack_allowed=np.zeros(len(ax)),
        bending_stiffness=disc.bending.bending_stiffness, spring_stiffness=disc.spring_stiffness,
        spring_reference=x_design[disc.spring_dofs], nodal_force=disc.gravity_force() + disc.termination_force,
    )
    return disc, params, form_finding._horizontal_wire_tension(disc), form_finding._target_dofs(disc), x_design


@pytest.fixture(scope="module")
def problem():
    """The first pass of form-finding of three coarse spans."""
    catenary = load_catenary("st_9.8_ideal").with_layout(SpanLayout(span_lengths=(60.0, 60.0, 60.0)))
    return _first_pass(static_model(catenary, StaticSettings(element_length=1.0)).discretisation)


def test_the_solution_holds_the_targets_and_balances_the_equations(problem):
    """Targets are substituted, so they hold exactly; the equations to IPOPT's constraint tolerance."""
    disc, params, tension, targets, x_design = problem
    solution = form_finding_solver.solve_form_finding(disc, params, tension, targets, x_design)
    x = solution.positions.ravel()
    assert np.array_equal(x[targets], x_design[targets])
    assert len(solution.dropper_unstretched_length) == len(disc.dropper_elements)
    assert np.all(solution.dropper_unstretched_length > 0.0)
    assert 0 < solution.iterations <= dict(form_finding_solver.IPOPT_OPTIONS)["max_iter"]
    # the droppers carry the contact wire: each is stretched between its clamps in the solution
    ax, drops = disc.axial, disc.dropper_elements
    clamps = np.linalg.norm(solution.positions[ax.node_b[drops]] - solution.positions[ax.node_a[drops]], axis=1)
    assert np.all(solution.dropper_unstretched_length < clamps)


def test_an_unfinished_solve_is_begun_again_with_the_exact_hessian_and_counted(problem, monkeypatch):
    disc, params, tension, targets, x_design = problem
    reference = form_finding_solver.solve_form_finding(*problem)
    assert reference.restarts == 0
    options = tuple((k, 1 if k == "max_iter" else v) for k, v in form_finding_solver.IPOPT_OPTIONS)
    monkeypatch.setattr(form_finding_solver, "IPOPT_OPTIONS", options)  # the first solve stops after one iteration
    solution = form_finding_solver.solve_form_finding(*problem)
    assert solution.restarts == 1 and solution.iterations > 1
    # the same solution, to IPOPT's tolerance on these equations (1e-6 N on droppers of about 1e6 N/m)
    np.testing.assert_allclose(solution.dropper_unstretched_length, reference.dropper_unstretched_length, rtol=0,
                               atol=1e-9)


def test_a_solve_that_does_not_finish_after_its_restart_raises_with_the_ipopt_status(problem, monkeypatch):
    for name in ("IPOPT_OPTIONS", "RESTART_OPTIONS"):
        options = tuple((k, 1 if k == "max_iter" else v) for k, v in getattr(form_finding_solver, name))
        monkeypatch.setattr(form_finding_solver, name, options)
    with pytest.raises(ConvergenceError, match=r"form-finding did not converge: IPOPT status 'Maximum_Iterations_"
                                               r"Exceeded' after 2 iterations \(a restart with the exact Hessian"):
        form_finding_solver.solve_form_finding(*problem)


def test_an_interrupt_swallowed_during_a_solve_is_raised_after_it():
    """CasADi turns a Ctrl-C inside IPOPT into a failed solve (``NonIpopt_Exception_Thrown``), which the
    form-finding would restart; :func:`interrupts_kept` raises it once the call returns. The signal is
    sent from inside the solve (a callback of the objective), so the test does not depend on timing."""
    import signal

    import casadi as ca

    from presag_opt.static.form_finding_solver import interrupts_kept

    class Interrupting(ca.Callback):
        def __init__(self):
            ca.Callback.__init__(self)
            self.construct("interrupting", {"enable_fd": True})

        def eval(self, arg):
            signal.raise_signal(signal.SIGINT)
            return [arg[0] ** 2]

    f = Interrupting()
    x = ca.MX.sym("x")
    solver = ca.nlpsol("s", "ipopt", {"x": x, "f": f(x)}, {"print_time": False, "ipopt": {"print_level": 0}})
    # Python's own Ctrl-C handler, as in a command (a pytest-xdist worker runs with another one)
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    try:
        solver(x0=1.0)  # outside the block: swallowed, the solve just fails
        assert solver.stats()["return_status"] != "Solve_Succeeded"
        with pytest.raises(KeyboardInterrupt), interrupts_kept():
            solver(x0=1.0)
        assert signal.getsignal(signal.SIGINT) is signal.default_int_handler  # restored
    finally:
        signal.signal(signal.SIGINT, previous)


def test_an_ignored_signal_is_not_recorded_and_sigterm_reaches_its_handler():
    import signal

    from presag_opt.static.form_finding_solver import interrupts_kept

    calls = []
    previous = signal.signal(signal.SIGTERM, lambda number, frame: calls.append(number))
    try:
        with pytest.raises(KeyboardInterrupt), interrupts_kept():
            signal.raise_signal(signal.SIGTERM)
        assert calls == [signal.SIGTERM]
        signal.signal(signal.SIGTERM, signal.SIG_IGN)
        with interrupts_kept():
            signal.raise_signal(signal.SIGTERM)  # ignored: nothing raised
    finally:
        signal.signal(signal.SIGTERM, previous)


@pytest.fixture
def built(monkeypatch):
    """Counts the IPOPT solvers built (``casadi.nlpsol`` calls), from empty memos."""
    import casadi as ca

    from presag_opt.static import form_finding_equations

    form_finding_solver._solver.cache_clear()
    form_finding_equations.topology_system.cache_clear()
    calls = []
    nlpsol = ca.nlpsol
    monkeypatch.setattr(ca, "nlpsol", lambda *args, **kwargs: calls.append(args[0]) or nlpsol(*args, **kwargs))
    yield calls
    form_finding_solver._solver.cache_clear()
    form_finding_equations.topology_system.cache_clear()


def _other_numbers(disc, params, tension, x_design):
    """The same section with other numbers: 10 % more wire tension, stiffer elements (a larger round-off
    tolerance), heavier loads, the design raised 0.1 m."""
    return (disc, dataclasses.replace(params, axial_stiffness=1.3 * params.axial_stiffness,
                                      nodal_force=1.05 * params.nodal_force),
            1.1 * tension, x_design + np.tile([0.0, 0.0, 0.1], disc.n_nodes))


def test_a_second_form_finding_of_the_same_topology_reuses_its_solver(problem, built):
    """Only the numbers differ: no solver is built for the second problem, and its answer is the one a
    freshly built solver gives, to 1e-12 m (IPOPT carries nothing from one solve to the next: the
    same iterations from the same start, only the memory of the solver object is reused)."""
    disc, params, tension, targets, x_design = problem
    first = form_finding_solver.solve_form_finding(disc, params, tension, targets, x_design)
    other_disc, other_params, other_tension, other_design = _other_numbers(disc, params, tension, x_design)
    reused = form_finding_solver.solve_form_finding(other_disc, other_params, other_tension, targets, other_design)
    assert built == ["form_finding"]
    form_finding_solver._solver.cache_clear()
    fresh = form_finding_solver.solve_form_finding(other_disc, other_params, other_tension, targets, other_design)
    assert len(built) == 2
    assert np.abs(reused.positions - first.positions).max() > 1e-3  # the numbers did reach the solve
    np.testing.assert_allclose(reused.positions, fresh.positions, rtol=0, atol=1e-12)
    np.testing.assert_allclose(reused.dropper_unstretched_length, fresh.dropper_unstretched_length, rtol=0, atol=1e-12)
    np.testing.assert_allclose(reused.spring_reference, fresh.spring_reference, rtol=0, atol=1e-12)
    assert reused.iterations == fresh.iterations


def test_another_topology_builds_its_own_solver(problem, built):
    """A fourth span (other nodes and elements), or another set of targets, is another problem."""
    disc, params, tension, targets, x_design = problem
    form_finding_solver.solve_form_finding(disc, params, tension, targets, x_design)
    form_finding_solver.solve_form_finding(disc, params, tension, targets[:-1], x_design)
    assert len(built) == 2
    catenary = load_catenary("st_9.8_ideal").with_layout(SpanLayout(span_lengths=(60.0, 60.0, 60.0, 60.0)))
    longer = _first_pass(static_model(catenary, StaticSettings(element_length=1.0)).discretisation)
    solution = form_finding_solver.solve_form_finding(*longer)
    assert len(built) == 3
    assert np.array_equal(solution.positions.ravel()[longer[3]], longer[4][longer[3]])
