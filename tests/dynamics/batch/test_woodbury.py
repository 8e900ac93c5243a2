"""The batch kernel's Woodbury correction against a direct solve of the Newton equation.

On the synthetic batch (``conftest``) the corrected iterate δ = δ_lin − s Z φ must solve
(K_eff + s E T Eᵀ) δ = g − s E (f − T δ_0) from the iterate δ_0: the Newton equation, assembled and
solved densely in NumPy (an independent method).
"""

from __future__ import annotations

import numpy as np
import pytest
import scipy.linalg as sla

from presag_opt.dynamics.batch.kernel_data import PantographStep


def _setup(batch, dofs, seed):
    rng = np.random.default_rng(seed)
    sc, n = batch.scratch, batch.n
    sc.position[:] = -1
    count = len(dofs)
    sc.set_dofs[:count] = dofs
    sc.position[dofs] = np.arange(count)
    sc.set_force[:count] = 20.0 * rng.normal(size=count)
    t = 3000.0 * rng.normal(size=(count, count))
    t[:, 1] = 0.0  # a column without tangent: the kernel skips zero entries
    sc.tangent[:count, :count] = t
    delta_lin_p = 1e-3 * rng.normal(size=batch.n_p)
    pan = PantographStep(*(np.zeros(batch.n_p) for _ in range(5)), delta_lin_p)
    k_ext = sla.block_diag(batch.k_cat, batch.k_pan)
    delta_lin = np.concatenate([batch.work.delta[:n, 0], delta_lin_p])
    return count, pan, k_ext, delta_lin, t


def _iterate(batch, count, s, delta_lin):
    """δ = δ_lin − s Z φ on the extended DOFs from the kernel's φ."""
    sc, n = batch.scratch, batch.n
    z = sla.block_diag(batch.shared.columns.T, batch.shared.pantograph_inverse)
    phi = np.zeros(n + batch.n_p)
    phi[sc.phi_dofs[:count]] = sc.phi[:count]
    return delta_lin - s * z @ phi


def test_influence_reads_the_columns_and_the_pantograph_inverse(plain_parts, synthetic_batch):
    batch = synthetic_batch()
    sh, n = batch.shared, batch.n
    args = (n, sh.column_of, sh.columns, sh.pantograph_inverse)
    assert plain_parts.woodbury.influence(1, 4, *args) == pytest.approx(np.linalg.inv(batch.k_cat)[1, 4], rel=1e-14)
    assert plain_parts.woodbury.influence(7, 6, *args) == sh.pantograph_inverse[1, 0]
    assert plain_parts.woodbury.influence(2, 6, *args) == 0.0 and plain_parts.woodbury.influence(6, 2, *args) == 0.0


@pytest.mark.parametrize("seed", [0, 1])
def test_the_first_correction_solves_the_newton_equation(plain_parts, synthetic_batch, seed):
    batch = synthetic_batch()
    dofs = np.array([2, 3, 6, 7])
    count, pan, k_ext, delta_lin, t = _setup(batch, dofs, seed)
    s = batch.scalars.scheme.s
    f = batch.scratch.set_force[:count].copy()
    n_phi = plain_parts.woodbury.woodbury_correction(0, s, count, 0, 0, batch.shared, batch.work, batch.scratch, pan)
    assert n_phi == count and np.all(batch.scratch.position[dofs] == -1)
    e = np.eye(len(k_ext))[:, dofs]
    direct = np.linalg.solve(k_ext + s * e @ t @ e.T, k_ext @ delta_lin - s * e @ f)
    # dense and Woodbury solves of a system with condition ~10: 1e-11 of |δ|
    np.testing.assert_allclose(_iterate(batch, count, s, delta_lin), direct, rtol=0,
                               atol=1e-11 * np.max(np.abs(direct)))


def test_a_later_correction_starts_from_the_current_iterate(plain_parts, synthetic_batch):
    """After a first correction (φ kept), the second solves the Newton equation about δ_0."""
    batch = synthetic_batch()
    dofs = np.array([2, 3, 6, 7])
    count, pan, k_ext, delta_lin, _ = _setup(batch, dofs, 4)
    s = batch.scalars.scheme.s
    n_phi = plain_parts.woodbury.woodbury_correction(0, s, count, 0, 0, batch.shared, batch.work, batch.scratch, pan)
    delta0 = _iterate(batch, n_phi, s, delta_lin)
    count, _, _, _, t = _setup(batch, dofs, 5)  # new forces and tangent at δ_0; φ of the first kept
    f = batch.scratch.set_force[:count].copy()
    plain_parts.woodbury.woodbury_correction(0, s, count, n_phi, 1, batch.shared, batch.work, batch.scratch, pan)
    e = np.eye(len(k_ext))[:, dofs]
    direct = delta0 + np.linalg.solve(k_ext + s * e @ t @ e.T,
                                      k_ext @ (delta_lin - delta0) - s * e @ f)
    np.testing.assert_allclose(_iterate(batch, count, s, delta_lin), direct, rtol=0,
                               atol=1e-11 * np.max(np.abs(direct)))
