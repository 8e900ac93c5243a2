"""The banded substitutions in numba: the twin of ``banded.c``, and the batch simulator's back half.

A symmetric positive definite matrix ordered along the track is a narrow band; its Cholesky factor
L is stored here row by row, ``factor[j, k] = L[j + k, j]`` (the transpose of LAPACK's lower band
storage), so that the entries a substitution step reads are adjacent in memory. The right-hand sides
are the columns of a C-ordered array: the innermost loop runs over them, which vectorises when there
are several. :func:`banded_cholesky_solve` does the operations of ``banded.c`` in the same order
(the same numbers to the last bit); it is the ``"numba"`` back-end of
:func:`presag_opt.native.banded.cholesky_solve` and the batch simulator's unit solves (its columns
of K_eff⁻¹); :func:`backward_substitution` is its second half. (The batch simulator's time step
substitutes over the factor's nonzero entries only, :mod:`presag_opt.dynamics.batch.band_rows`.) Imported
only where it is used (numba loads in about a second).
"""

from __future__ import annotations

import numpy as np
from numba import njit


@njit(cache=True)
def banded_cholesky_solve(factor, x, columns):
    """Solve L Lᵀ y = x in place for the first ``columns`` columns of ``x``.

    Forward and backward substitution in dot-product form: each row is finished in one pass over
    the band rows before (after) it, the columns innermost.

    Parameters
    ----------
    factor : ndarray, shape (n, b + 1)
        The Cholesky factor by rows, ``factor[j, k] = L[j + k, j]``. [sqrt of the matrix's unit]
    x : ndarray, shape (n, m)
        Right-hand sides, overwritten by the solution. [unit of the right-hand side]
    columns : int
        How many leading columns to solve (the others are left as they are). [-]
    """
    n, width = factor.shape
    bw = width - 1
    acc = np.empty(columns)
    for j in range(n):
        for b in range(columns):
            acc[b] = x[j, b]
        for k in range(1, min(bw, j) + 1):
            value = factor[j - k, k]
            for b in range(columns):
                acc[b] -= value * x[j - k, b]
        d = factor[j, 0]
        for b in range(columns):
            x[j, b] = acc[b] / d
    backward_substitution(factor, x, columns)


@njit(cache=True)
def backward_substitution(factor, x, columns):
    """Solve Lᵀ y = x in place for the first ``columns`` columns (the second half of
    :func:`banded_cholesky_solve`).

    Parameters
    ----------
    factor : ndarray, shape (n, bw + 1)
        The Cholesky factor by rows, ``factor[j, k] = L[j + k, j]``. [sqrt of the matrix's unit]
    x : ndarray, shape (n, m)
        Forward-substituted right-hand sides L⁻¹ b in, overwritten by the solution. [unit of the solution]
    columns : int
        How many leading columns to solve (the others are left as they are). [-]
    """
    n, width = factor.shape
    bw = width - 1
    acc = np.empty(columns)
    for j in range(n - 1, -1, -1):
        for b in range(columns):
            acc[b] = x[j, b]
        for k in range(1, min(bw, n - 1 - j) + 1):
            value = factor[j, k]
            for b in range(columns):
                acc[b] -= value * x[j + k, b]
        d = factor[j, 0]
        for b in range(columns):
            x[j, b] = acc[b] / d
