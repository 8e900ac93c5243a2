"""How the laws enter a step's equations (:mod:`presag_opt.dynamics.assembly`), and that both engines
use these functions and no copy of them."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sp

from presag_opt.dynamics import assembly
from presag_opt.dynamics.integrator import IntegratorSettings
from presag_opt.dynamics.laws import scheme_constants

SCHEME = scheme_constants(IntegratorSettings(time_step=2e-3, scheme="hht", hht_alpha=-0.05))


def test_the_newmark_predictor_and_update_are_the_schemes_definitions():
    dt, c = SCHEME.time_step, SCHEME
    gamma = 0.5 - c.alpha
    beta = (1.0 - c.alpha) ** 2 / 4.0
    u, v, a = np.array([1e-3, -2e-3]), np.array([0.1, 0.05]), np.array([3.0, -1.0])
    u_pred, v_pred = assembly.newmark_predictor(u, v, a, c)
    np.testing.assert_allclose(u_pred, u + dt * v + dt**2 * (0.5 - beta) * a, rtol=1e-14)
    np.testing.assert_allclose(v_pred, v + dt * (1.0 - gamma) * a, rtol=1e-14)
    delta = np.array([2e-5, -1e-5])
    acceleration, velocity = assembly.newmark_update(delta, v_pred, c)
    np.testing.assert_allclose(acceleration, delta / (beta * dt**2), rtol=1e-14)
    np.testing.assert_allclose(velocity, v_pred + gamma * dt * acceleration, rtol=1e-14)
    # numbers and arrays alike: the batch kernel calls them on numbers
    assert assembly.newmark_predictor(u[0], v[0], a[0], c) == (u_pred[0], v_pred[0])


def test_the_penetration_is_measured_to_the_wires_chord():
    # head at 5.302 m + 1 mm, nodes at 5.300 and 5.304 m moved up 1 and 3 mm, the head a quarter along
    penetration = assembly.head_penetration(5.302, 1e-3, 0.75, 5.300, 1e-3, 0.25, 5.304, 3e-3)
    assert penetration == pytest.approx(5.303 - (0.75 * 5.301 + 0.25 * 5.307), abs=1e-15)


@pytest.mark.parametrize("gradient", [(-0.25, -0.75, 1.0), (1.0, -1.0), (1.0,), tuple(np.linspace(-0.6, 0.6, 6))])
def test_a_contribution_is_f_dg_and_k_dg_dgT(gradient):
    force, tangent = np.empty(len(gradient)), np.empty((len(gradient), len(gradient)))
    assembly.force_contribution(120.0, 5e4, gradient, force, tangent)
    g = np.array(gradient)
    np.testing.assert_allclose(force, 120.0 * g, rtol=1e-15)
    np.testing.assert_allclose(tangent, 5e4 * np.outer(g, g), rtol=1e-15, atol=0.0)
    assert np.array_equal(tangent, tangent.T)


def test_the_effective_matrix_of_sparse_and_dense_matrices():
    mass, damping, stiffness = np.diag([2.0, 3.0]), np.array([[4.0, -1.0], [-1.0, 4.0]]), np.array([[9.0, -3.0], [-3.0, 9.0]])
    expected = SCHEME.a0 * mass + SCHEME.s * (stiffness + SCHEME.a1 * damping)
    np.testing.assert_allclose(assembly.effective_stiffness(mass, damping, stiffness, SCHEME), expected, rtol=1e-15)
    sparse = assembly.effective_stiffness(sp.csr_matrix(mass), sp.csr_matrix(damping), sp.csr_matrix(stiffness), SCHEME)
    np.testing.assert_allclose(sparse.toarray(), expected, rtol=1e-15)


def test_the_batch_compiles_these_functions_and_no_copy():
    from presag_opt.dynamics.batch import forces, predictor, update

    assert predictor.newmark_predictor.py_func is assembly.newmark_predictor
    assert update.newmark_update.py_func is assembly.newmark_update
    assert forces.head_penetration.py_func is assembly.head_penetration
    assert forces.force_contribution.py_func is assembly.force_contribution


def test_the_single_run_engine_calls_them():
    from presag_opt.dynamics import integrator, pantograph, simulate, step_solvers, structure

    assert integrator.newmark_predictor is assembly.newmark_predictor
    assert step_solvers.newmark_update is assembly.newmark_update
    assert step_solvers.effective_stiffness is assembly.effective_stiffness
    assert simulate.head_penetration is assembly.head_penetration
    assert simulate.force_contribution is structure.force_contribution is pantograph.force_contribution \
        is assembly.force_contribution
