"""Fast solves with the catenary's symmetric stiffness matrices.

A catenary is a long, thin structure: ordered along the track (reverse Cuthill–McKee), its stiffness
matrix is a band a few dozen entries wide. :class:`BandedSolver` finds that ordering once for a fixed
sparsity pattern and then factorises new values with LAPACK's banded Cholesky (O(n b²)), which is
much faster than a general sparse LU on the natural node numbering. A matrix that is not positive
definite (an unstable or not yet converged state) is factorised by SuperLU instead; both give the
exact solution of the same linear system.
"""

from __future__ import annotations

import ctypes
import functools
import sys
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import scipy.linalg as sla
import scipy.sparse as sp
import scipy.sparse.linalg as spla
from scipy.sparse.csgraph import reverse_cuthill_mckee

from presag_opt.static import native


@dataclass(frozen=True)
class BandedSolver:
    """Reusable ordering and index maps for one symmetric sparsity pattern.

    Attributes
    ----------
    pattern : scipy.sparse.csc_matrix
        The sparsity pattern (values ignored).
    permutation : ndarray of int
        New order of the rows/columns. [-]
    bandwidth : int
        Lower bandwidth after reordering. [-]
    """

    pattern: sp.csc_matrix
    permutation: np.ndarray
    bandwidth: int
    _band_rows: np.ndarray
    _band_cols: np.ndarray
    _lower: np.ndarray

    @classmethod
    def for_pattern(cls, pattern: sp.csc_matrix) -> "BandedSolver":
        """Analyse a symmetric sparsity pattern once."""
        pattern = sp.csc_matrix(pattern)
        perm = reverse_cuthill_mckee(pattern, symmetric_mode=True)
        inverse = np.empty_like(perm)
        inverse[perm] = np.arange(len(perm))
        # Entries of the CSC data array in their original order.
        rows = inverse[pattern.indices]
        cols = inverse[np.repeat(np.arange(pattern.shape[1]), np.diff(pattern.indptr))]
        lower = rows >= cols
        bandwidth = int((rows - cols)[lower].max(initial=0))
        return cls(pattern, perm, bandwidth, rows[lower] - cols[lower], cols[lower], np.flatnonzero(lower))

    def matrix(self, data: np.ndarray) -> sp.csc_matrix:
        """The matrix with the pattern and the given nonzero values."""
        return sp.csc_matrix((data, self.pattern.indices, self.pattern.indptr), shape=self.pattern.shape)

    def factorise(self, data: np.ndarray) -> "Factor":
        """Factorise the matrix with nonzero values ``data`` (in the pattern's CSC order)."""
        n = self.pattern.shape[0]
        band = np.zeros((self.bandwidth + 1, n))
        band[self._band_rows, self._band_cols] = data[self._lower]
        try:
            return Factor(self, cholesky=sla.cholesky_banded(band, lower=True, check_finite=False))
        except np.linalg.LinAlgError:
            return Factor(self, lu=spla.splu(self.matrix(data), permc_spec="COLAMD"))


@dataclass(frozen=True)
class Factor:
    """A factorised stiffness matrix: banded Cholesky, or SuperLU when not positive definite."""

    solver: BandedSolver
    cholesky: np.ndarray | None = None
    lu: object | None = None

    @property
    def positive_definite(self) -> bool:
        """Whether the matrix was positive definite (factorised by Cholesky)."""
        return self.cholesky is not None

    def solve(self, rhs: np.ndarray) -> np.ndarray:
        """Solve K u = rhs for one right-hand side or the columns of a 2-D array."""
        if self.cholesky is None:
            return self.lu.solve(rhs)
        perm = self.solver.permutation
        out = np.empty_like(rhs, dtype=float)
        if rhs.ndim == 2 and _compiled_solve_pays(rhs.shape[0], rhs.shape[1]):
            out[perm] = _banded_cholesky_solve(self.cholesky, np.ascontiguousarray(rhs[perm], dtype=float))
        else:
            out[perm] = sla.cho_solve_banded((self.cholesky, True), rhs[perm], check_finite=False)
        return out


MANY_RIGHT_HAND_SIDES = 16
"""Right-hand sides from which :func:`_banded_cholesky_solve` beats LAPACK's column-by-column solve
(4× at 84 columns of the 31-span section). [-]"""

FIRST_USE_WORK = 2e6
"""Without the C library: rows × right-hand sides, summed over a process's many-column solves, from
which the numba kernel is used (its first use costs about 0.5 s: importing numba and loading the
cached kernel). Measured on the 10-span section (7 239 rows, bandwidth 20): LAPACK 0.49 ms and the
kernel 0.16 ms per column. One span of an ideal section (7 239 × 121, its influence columns
7 239 × 90) stays with LAPACK; a long mixed section (about 21 000 rows × 121 columns a span)
switches at its first span, since its 29 spans would pay for the kernel many times over. [-]"""

SOURCE = Path(__file__).with_name("banded.c")
FLAGS = ("-O3", "-march=native", "-ffp-contract=off")
"""Compiler flags of ``banded.c``: tuned to this processor, every operation rounded on its own as in
numba (no fused multiply-add, no fast-math)."""

_lapack_work = 0.0
"""Rows × right-hand sides solved so far in this process by LAPACK in many-column solves. [-]"""


@functools.cache
def _compiled_solve() -> Callable | None:
    """``presag_banded_cholesky_solve`` of the C library built from ``banded.c``, or None (no compiler,
    or ``PRESAG_NO_COMPILE``; see :mod:`presag_opt.static.native`)."""
    library = native.build("banded", SOURCE.read_text(), FLAGS)
    if library is None:
        return None
    function = ctypes.CDLL(str(library)).presag_banded_cholesky_solve
    pointer, count = ctypes.c_void_p, ctypes.c_int64
    function.argtypes = [pointer, pointer, pointer, count, count, count, count]
    function.restype = None
    return function


def _compiled_solve_pays(rows: int, columns: int) -> bool:
    """Whether to solve ``columns`` right-hand sides of ``rows`` rows with the compiled solve: from
    :data:`MANY_RIGHT_HAND_SIDES` columns with the C library (loading it costs a millisecond), and
    with the numba kernel once :data:`FIRST_USE_WORK` is reached."""
    global _lapack_work
    if columns < MANY_RIGHT_HAND_SIDES:
        return False
    if _compiled_solve() is not None or "presag_opt.static.kernels" in sys.modules:
        return True
    _lapack_work += rows * columns
    return _lapack_work >= FIRST_USE_WORK


def _banded_cholesky_solve(band: np.ndarray, rhs: np.ndarray) -> np.ndarray:
    """Solve L Lᵀ x = rhs with L in LAPACK's lower band storage (``band[i − j, j] = L[i, j]``), all
    columns of ``rhs`` in one sweep (LAPACK's ``pbtrs`` takes them one at a time, at level-2 speed):
    with the C library of ``banded.c`` where it is built, else with the numba kernel (the same
    numbers to the last bit)."""
    x = np.array(rhs, dtype=float, order="C")
    factor = np.ascontiguousarray(band.T)
    solve = _compiled_solve()
    if solve is not None:
        scratch = np.empty(x.shape[1])
        solve(factor.ctypes.data, x.ctypes.data, scratch.ctypes.data, factor.shape[0], factor.shape[1], x.shape[1],
              x.shape[1])
        return x
    from presag_opt.static.kernels import banded_cholesky_solve  # numba is imported only when needed

    banded_cholesky_solve(factor, x, x.shape[1])
    return x
