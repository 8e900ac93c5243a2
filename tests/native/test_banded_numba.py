"""The numba substitutions: the backward half alone solves Lᵀ y = x, and only the leading columns
asked for are touched. (Its equality with banded.c and LAPACK: test_banded.py.)

Tolerance: a triangular solve with a diagonally dominant factor (condition number below 10) is
backward stable; against SciPy's dense triangular solve the entries agree to 1e-13 of max|y|
(summation order differs), while a wrong index moves them by O(1).
"""

from __future__ import annotations

import numpy as np
import scipy.linalg as sla

from presag_opt.native.banded_numba import backward_substitution, banded_cholesky_solve

N, WIDTH = 60, 4


def _factor_by_rows():
    rng = np.random.default_rng(3)
    factor = rng.uniform(-0.5, 0.5, (N, WIDTH))
    factor[:, 0] = 3.0 + rng.uniform(0.0, 1.0, N)
    for j in range(N):  # entries beyond the matrix's edge are never read: make them loud
        factor[j, N - j:] = np.nan if N - j < WIDTH else factor[j, N - j:]
    return factor


def _lower(factor):
    lower = np.zeros((N, N))
    for j in range(N):
        for k in range(min(WIDTH, N - j)):
            lower[j + k, j] = factor[j, k]
    return lower


def test_the_backward_half_solves_the_transposed_factor():
    factor = _factor_by_rows()
    x = np.random.default_rng(4).normal(size=(N, 5))
    y = x.copy()
    backward_substitution(factor, y, 5)
    expected = sla.solve_triangular(_lower(factor).T, x, lower=False)
    assert np.abs(y - expected).max() <= 1e-13 * np.abs(expected).max()


def test_only_the_leading_columns_are_solved():
    factor = _factor_by_rows()
    x = np.random.default_rng(5).normal(size=(N, 6))
    y = x.copy()
    banded_cholesky_solve(factor, y, 4)
    lower = _lower(factor)
    expected = sla.cho_solve((lower, True), x[:, :4])
    assert np.abs(y[:, :4] - expected).max() <= 1e-13 * np.abs(expected).max()
    assert np.array_equal(y[:, 4:], x[:, 4:])
