"""Compiled kernels of the static model (numba); imported only by the solves that use them."""

from __future__ import annotations

import numpy as np
from numba import njit


@njit(cache=True)
def banded_cholesky_solve(band: np.ndarray, rhs: np.ndarray) -> np.ndarray:  # pragma: no cover - compiled
    """Forward and back substitution with a banded Cholesky factor, every right-hand side at once.

    Parameters
    ----------
    band : ndarray, shape (b + 1, n)
        Lower band storage of L: ``band[i − j, j] = L[i, j]`` for 0 ≤ i − j ≤ b (C order).
    rhs : ndarray, shape (n, m)
        Right-hand sides (C order: the innermost loop runs along a row, over the m columns).

    Returns
    -------
    ndarray, shape (n, m)
        x with L Lᵀ x = rhs.
    """
    width = band.shape[0] - 1
    n, m = rhs.shape
    x = rhs.copy()
    for i in range(n):
        for k in range(max(0, i - width), i):
            factor = band[i - k, k]
            for c in range(m):
                x[i, c] -= factor * x[k, c]
        for c in range(m):
            x[i, c] /= band[0, i]
    for i in range(n - 1, -1, -1):
        for k in range(i + 1, min(n, i + width + 1)):
            factor = band[k - i, i]
            for c in range(m):
                x[i, c] -= factor * x[k, c]
        for c in range(m):
            x[i, c] /= band[0, i]
    return x
