"""The single-run integrator's Newton corrections: the Woodbury solver against the assembled one."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest
import scipy.sparse as sp

from presag_opt.dynamics import step_solvers
from presag_opt.dynamics.laws import scheme_constants
from presag_opt.errors import ModelError


def _system(n=40):
    k = sp.diags([np.full(n, 2e4), np.full(n - 1, -1e4), np.full(n - 1, -1e4)], [0, 1, -1], format="csr")
    m = sp.diags(np.full(n, 3.0), format="csr")
    c = 0.1 * m + 1e-4 * k
    scheme = scheme_constants(SimpleNamespace(scheme="hht", hht_alpha=-0.1, time_step=1e-3))
    return step_solvers.EquationOfMotion(mass=m, damping=c.tocsr(), stiffness=k, external_force=lambda t: np.zeros(n),
                                   nonlinear_force=lambda u, v, t: step_solvers.NO_FORCE, c=scheme)


@pytest.mark.parametrize("loaded", [3, 40])
def test_the_woodbury_correction_equals_the_assembled_solve(loaded):
    """Sparse right-hand side (cached columns) and dense one (the factor), with a tangent on 3 DOFs."""
    system = _system()
    rng = np.random.default_rng(loaded)
    rhs = np.zeros(40)
    rhs[rng.choice(40, loaded, replace=False)] = rng.normal(size=loaded)
    dofs = np.array([5, 6, 30])
    tangent = 5e5 * rng.normal(size=(3, 3))
    fast = step_solvers.FactorisedSolver(system).correction(rhs, dofs, tangent)
    reference = step_solvers.ReferenceSolver(system).correction(rhs, dofs, tangent)
    # two direct solves of one system (condition ~1e2): 1e-12 of the correction
    np.testing.assert_allclose(fast, reference, rtol=0, atol=1e-12 * np.max(np.abs(reference)))


def test_without_nonlinear_dofs_the_correction_is_the_linear_solve():
    system = _system()
    rhs = np.linspace(-1.0, 1.0, 40)
    x = step_solvers.FactorisedSolver(system).correction(rhs, np.zeros(0, dtype=int), np.zeros((0, 0)))
    np.testing.assert_allclose(system.effective_matrix() @ x, rhs, rtol=0, atol=1e-12)


def test_the_cheap_residual_equals_the_full_one():
    """R(u + δ) = s (f_new − f_old − T δ) when δ solved the Newton equation from R(u)."""
    system = _system()
    c = system.c
    rng = np.random.default_rng(1)
    u_pred, v_pred = 1e-3 * rng.normal(size=40), 1e-2 * rng.normal(size=40)
    step = step_solvers.StepTerms(time=1e-3, u_pred=u_pred, v_pred=v_pred, forcing=np.zeros(40), rhs=rng.normal(size=40))
    dofs = np.array([3, 4])
    stiffness = np.array([[4e4, -4e4], [-4e4, 4e4]])
    old = step_solvers.NonlinearForce(dofs=dofs, force=np.array([1.0, -1.0]), stiffness=stiffness)
    u = u_pred.copy()
    r, _ = step_solvers.full_residual(system, step, u, old)
    solver = step_solvers.FactorisedSolver(system)
    delta = solver.correction(-r, dofs, old.tangent(c.a1))
    new = step_solvers.NonlinearForce(dofs=dofs, force=np.array([2.0, -0.5]), stiffness=stiffness)
    cheap = solver.next_residual(step, u + delta, old, new, old.tangent(c.a1), delta)
    full, scale = step_solvers.full_residual(system, step, u + delta, new)
    np.testing.assert_allclose(cheap, full, rtol=0, atol=1e-10 * scale)


def test_the_tangent_adds_the_damping_times_a1():
    k, d = np.eye(2), np.array([[0.0, 1.0], [1.0, 0.0]])
    force = step_solvers.NonlinearForce(dofs=np.array([0, 1]), force=np.zeros(2), stiffness=k, damping=d)
    np.testing.assert_array_equal(force.tangent(10.0), k + 10.0 * d)
    assert step_solvers.NonlinearForce(dofs=np.array([0]), force=np.zeros(1), stiffness=np.eye(1)).tangent(10.0) == 1.0


def test_a_force_of_the_wrong_shape_is_refused():
    with pytest.raises(ModelError, match=r"2 dofs need force of shape \(2,\)"):
        step_solvers.NonlinearForce(dofs=np.array([0, 1]), force=np.zeros(3), stiffness=np.eye(2))


def test_the_inertia_of_a_lumped_mass_is_elementwise():
    system = _system()
    a = np.linspace(0.0, 1.0, 40)
    np.testing.assert_array_equal(system.inertia(a), 3.0 * a)
    assert step_solvers.norm(np.zeros(0)) == 0.0 and step_solvers.norm(np.array([1.0, -3.0])) == 3.0
