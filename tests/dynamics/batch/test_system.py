"""The batch's shared arrays: the bands of a symmetric matrix and the columns of K_eff⁻¹."""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from presag_opt.dynamics.batch import system as batch_system


def test_the_lower_band_in_a_given_order():
    a = np.array([[4.0, 1.0, 0.0, 0.5], [1.0, 5.0, 2.0, 0.0], [0.0, 2.0, 6.0, 3.0], [0.5, 0.0, 3.0, 7.0]])
    order = np.array([3, 0, 1, 2])
    band = batch_system._lower_band(sp.csc_matrix(a), order, 3)
    permuted = a[np.ix_(order, order)]
    for k in range(4):
        for j in range(4 - k):
            assert band[k, j] == permuted[j + k, j]
    assert band.shape == (4, 4)


def test_the_influence_columns_solve_k_eff(synthetic_batch):
    batch = synthetic_batch()
    dofs = np.array([0, 2, 5])
    columns = batch_system._influence_columns(batch.shared.factor_band, dofs)
    np.testing.assert_allclose(columns @ batch.k_cat, np.eye(6)[dofs], rtol=0, atol=1e-12)  # K_eff symmetric
    many = np.arange(6).repeat(30)[: batch_system.INFLUENCE_BLOCK + 5]  # more than one block of unit loads
    assert np.array_equal(batch_system._influence_columns(batch.shared.factor_band, many)[-1],
                          batch_system._influence_columns(batch.shared.factor_band, many[-1:])[0])
