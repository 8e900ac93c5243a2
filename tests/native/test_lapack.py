"""The kernel's dense solve against numba's ``np.linalg.solve`` (the same LAPACK routine), to the last bit."""

from __future__ import annotations

import numba
import numpy as np
import pytest

from presag_opt.native.lapack import solve_by_columns


@numba.njit
def _direct(matrix, rhs):
    by_columns = np.ascontiguousarray(matrix.T)
    x = rhs.copy()
    pivots, integers = np.full(x.shape[0] + 2, -7, np.int32), np.full(3, -7, np.int32)  # longer, and not zeroed
    info = solve_by_columns(by_columns, x, pivots, integers)
    return x, info


@numba.njit
def _numba_solve(matrix, rhs):
    return np.linalg.solve(matrix, rhs)


@pytest.mark.parametrize("n", [1, 2, 3, 5, 9])
def test_the_direct_solve_is_numba_s_solve_to_the_last_bit(n):
    rng = np.random.default_rng(n)
    matrix = rng.standard_normal((n, n)) + 2.0 * np.eye(n)
    rhs = rng.standard_normal(n)
    x, info = _direct(matrix, rhs)
    assert info == 0
    assert np.array_equal(x, _numba_solve(matrix, rhs))
    np.testing.assert_allclose(matrix @ x, rhs, rtol=0.0, atol=1e-12 * np.abs(matrix).sum())


def test_a_singular_matrix_is_reported_not_solved():
    _, info = _direct(np.array([[1.0, 2.0], [2.0, 4.0]]), np.array([1.0, 1.0]))
    assert info > 0


def test_called_from_python_it_gives_the_same_numbers():
    rng = np.random.default_rng(7)
    matrix, rhs = rng.standard_normal((4, 4)) + 2.0 * np.eye(4), rng.standard_normal(4)
    x = rhs.copy()
    assert solve_by_columns(np.ascontiguousarray(matrix.T), x) == 0
    assert np.array_equal(x, _direct(matrix, rhs)[0])
