"""Woodbury's last step against a direct solve of the updated system (an independent method)."""

from __future__ import annotations

import numpy as np
import pytest

from presag_opt.errors import ConvergenceError
from presag_opt.static.woodbury import woodbury_update


def _system(seed: int, n: int = 12, k: int = 3):
    rng = np.random.default_rng(seed)
    a = rng.normal(size=(n, n))
    a = a @ a.T + n * np.eye(n)  # symmetric positive definite, well conditioned
    dofs = rng.choice(n, size=k, replace=False)
    r = rng.normal(size=n)
    return a, dofs, r


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_the_tangent_form_solves_the_updated_system(seed):
    """(A + E T Eᵀ) w = r with capacitance I + T Z_SS (the integrator's form), T singular allowed."""
    a, dofs, r = _system(seed)
    t = np.random.default_rng(seed + 10).normal(size=(len(dofs), len(dofs)))
    t[:, 0] = 0.0  # a DOF without tangent: T is singular, the C⁻¹ form could not be used
    e = np.zeros((len(r), len(dofs)))
    e[dofs, range(len(dofs))] = 1.0
    x = np.linalg.solve(a, r)
    z = np.linalg.solve(a, e)
    w, _ = woodbury_update(x, z, np.eye(len(dofs)) + t @ z[dofs, :], t @ x[dofs], singular="singular")
    direct = np.linalg.solve(a + e @ t @ e.T, r)
    # both are backward-stable solves of a matrix with condition number below ~10: 1e-12 of |w|
    np.testing.assert_allclose(w, direct, rtol=0, atol=1e-12 * np.max(np.abs(direct)))


@pytest.mark.parametrize("seed", [3, 4])
def test_the_textbook_form_removes_springs(seed):
    """(A − G D Gᵀ) w = r with capacitance Gᵀ A⁻¹ G − D⁻¹ (the tension-only droppers' form)."""
    a, dofs, r = _system(seed)
    g = np.random.default_rng(seed).normal(size=(len(r), 2))
    d = np.array([0.5, 0.8])  # small against A's eigenvalues (≥ n): the updated matrix stays regular
    x = np.linalg.solve(a, r)
    z = np.linalg.solve(a, g)
    w, y = woodbury_update(x, z, g.T @ z - np.diag(1.0 / d), g.T @ x, singular="singular")
    direct = np.linalg.solve(a - g @ np.diag(d) @ g.T, r)
    np.testing.assert_allclose(w, direct, rtol=0, atol=1e-12 * np.max(np.abs(direct)))
    # y is the springs' force change: w = x − Z y, so A w = r − G y and G y = −G D Gᵀ w
    np.testing.assert_allclose(y, -d * (g.T @ direct), rtol=1e-11)


def test_a_singular_capacitance_raises_the_callers_message():
    with pytest.raises(ConvergenceError, match="the tangent cancels"):
        woodbury_update(np.ones(2), np.eye(2), np.zeros((2, 2)), np.ones(2), singular="the tangent cancels")


def test_an_empty_update_leaves_the_solution():
    x = np.array([1.0, -2.0])
    w, y = woodbury_update(x, np.zeros((2, 0)), np.zeros((0, 0)), np.zeros(0), singular="singular")
    assert np.array_equal(w, x) and y.shape == (0,)
