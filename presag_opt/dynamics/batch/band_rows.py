"""The nonzero entries of the batch kernel's bands, row by row, in the order its sweeps add them.

A catenary's stiffness matrix is a narrow band in reverse Cuthill–McKee order, but most of the band
is empty: its elements couple neighbouring nodes only, so a row of K of the case study holds about
10 nonzero entries of the 41 its bandwidth of 20 allows, and the Cholesky factor of K_eff about 10 of
21 (the factor fills in only between the first and last nonzero of a profile). A sweep over the full
band spends three quarters of its arithmetic multiplying by exact zeros. The kernel's sweeps
(:mod:`presag_opt.dynamics.batch.kernel` in numba and ``sweeps.c``) read instead the lists built here: the
same products, added in the same order, less the ones whose matrix entry is exactly zero. For a
finite vector that changes no number (a ± 0·x = a, up to the sign of a zero result).

Three lists, each a :class:`BandRows` (a compressed-row form: the entries of row j are
``start[j]:start[j + 1]``):

* :func:`symmetric_rows` — the off-diagonal entries of a symmetric matrix given by its lower band:
  row j's entries right of the diagonal (k = 1 … bw), then left of it (k = 1 … bw), as the products
  C ṽ + K ũ are summed;
* :func:`lower_rows` — a factor's row j left of the diagonal, L[j, j − k] for k = 1 … bw (the
  forward substitution);
* :func:`upper_rows` — the transposed factor's row j right of the diagonal, L[j + k, j] for
  k = 1 … bw (the backward substitution).

The diagonals stay in the bands (``band[:, 0]``). Bands are stored by rows, ``band[j, k] = A[j + k, j]``.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np


class BandRows(NamedTuple):
    """Nonzero off-diagonal entries of a banded matrix by rows (C order, as ``sweeps.c`` reads them).

    Attributes
    ----------
    start : ndarray of int64, shape (n + 1,)
        Row j's entries are ``start[j]:start[j + 1]``. [-]
    column : ndarray of int64, shape (nnz,)
        Column of each entry (a banded position). [-]
    value : ndarray, shape (nnz,)
        The entries. [unit of the matrix]
    """

    start: np.ndarray
    column: np.ndarray
    value: np.ndarray


def _rows(rows: np.ndarray, columns: np.ndarray, values: np.ndarray, rank: np.ndarray, n: int) -> BandRows:
    """Entries sorted by row, and within a row by ``rank``; exact zeros dropped."""
    keep = values != 0.0
    rows, columns, values, rank = rows[keep], columns[keep], values[keep], rank[keep]
    order = np.lexsort((rank, rows))
    start = np.zeros(n + 1, dtype=np.int64)
    np.cumsum(np.bincount(rows, minlength=n), out=start[1:])
    return BandRows(start=start, column=np.ascontiguousarray(columns[order], dtype=np.int64),
                    value=np.ascontiguousarray(values[order], dtype=float))


def _entries(band: np.ndarray):
    """Row j, offset k and value band[j, k] of every stored off-diagonal entry inside the matrix."""
    n, width = band.shape
    j, k = np.meshgrid(np.arange(n, dtype=np.int64), np.arange(1, width, dtype=np.int64), indexing="ij")
    inside = j + k < n
    return j[inside], k[inside], band[:, 1:][inside]


def symmetric_rows(band: np.ndarray) -> BandRows:
    """Off-diagonal nonzeros of the symmetric matrix whose lower band is ``band``: row j's entries
    A[j, j + k] for k = 1 … bw, then A[j, j − k] for k = 1 … bw.

    Parameters
    ----------
    band : ndarray, shape (n, bw + 1)
        Lower band by rows, ``band[j, k] = A[j + k, j]``. [unit of the matrix]
    """
    n, width = band.shape
    j, k, value = _entries(band)
    # A[j + k, j] is entry (j, j + k) right of row j's diagonal and entry (j + k, j) left of row j + k's
    return _rows(np.concatenate([j, j + k]), np.concatenate([j + k, j]), np.concatenate([value, value]),
                 np.concatenate([k, width + k]), n)


def lower_rows(factor: np.ndarray) -> BandRows:
    """Nonzeros of a lower-triangular factor left of its diagonal: row j's L[j, j − k], k = 1 … bw.

    Parameters
    ----------
    factor : ndarray, shape (n, bw + 1)
        The factor by rows, ``factor[j, k] = L[j + k, j]``. [unit of the factor]
    """
    j, k, value = _entries(factor)
    return _rows(j + k, j, value, k, factor.shape[0])


def upper_rows(factor: np.ndarray) -> BandRows:
    """Nonzeros of the transposed factor right of its diagonal: row j's Lᵀ[j, j + k] = L[j + k, j],
    k = 1 … bw.

    Parameters
    ----------
    factor : ndarray, shape (n, bw + 1)
        The factor by rows, ``factor[j, k] = L[j + k, j]``. [unit of the factor]
    """
    j, k, value = _entries(factor)
    return _rows(j, j + k, value, k, factor.shape[0])
