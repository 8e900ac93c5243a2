"""Fast solves with the catenary's symmetric stiffness matrices.

A catenary is a long, thin structure: ordered along the track (reverse Cuthill–McKee), its stiffness
matrix is a band a few dozen entries wide. :class:`BandedSolver` finds that ordering once for a fixed
sparsity pattern and then factorises new values with LAPACK's banded Cholesky (O(n b²)), which is
much faster than a general sparse LU on the natural node numbering. A matrix that is not positive
definite (an unstable or not yet converged state) is factorised by SuperLU instead; both give the
exact solution of the same linear system. Many right-hand sides at once go to
:func:`presag_opt.native.banded.cholesky_solve`, whose back-end (LAPACK, C or numba) is a
``backend`` argument of :meth:`Factor.solve`.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import numpy as np
import scipy.linalg as sla
import scipy.sparse as sp
import scipy.sparse.linalg as spla
from scipy.sparse.csgraph import reverse_cuthill_mckee

from presag_opt.native import banded


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
    def for_pattern(cls, pattern: sp.csc_matrix) -> BandedSolver:
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

    @cached_property
    def position(self) -> np.ndarray:
        """Place of each original row in the band order (the inverse of :attr:`permutation`). [-]"""
        position = np.empty_like(self.permutation)
        position[self.permutation] = np.arange(len(self.permutation))
        return position

    def matrix(self, data: np.ndarray) -> sp.csc_matrix:
        """The matrix with the pattern and the given nonzero values.

        Parameters
        ----------
        data : ndarray
            Nonzero values of the matrix, in the pattern's CSC order. [N/m]
        """
        return sp.csc_matrix((data, self.pattern.indices, self.pattern.indptr), shape=self.pattern.shape)

    def factorise(self, data: np.ndarray) -> Factor:
        """Factorise the matrix with nonzero values ``data`` (in the pattern's CSC order).

        Parameters
        ----------
        data : ndarray
            Nonzero values of the matrix, in the pattern's CSC order. [N/m]
        """
        n = self.pattern.shape[0]
        band = np.zeros((self.bandwidth + 1, n))
        band[self._band_rows, self._band_cols] = data[self._lower]
        try:
            return Factor(self, cholesky=sla.cholesky_banded(band, lower=True, check_finite=False))
        except np.linalg.LinAlgError:
            return Factor(self, lu=spla.splu(self.matrix(data), permc_spec="COLAMD"))


@dataclass(frozen=True)
class Factor:
    """A factorised stiffness matrix: banded Cholesky, or SuperLU when not positive definite.

    Attributes
    ----------
    solver : BandedSolver
        The solver whose pattern and permutation were factorised.
    cholesky : ndarray or None
        Lower band of the Cholesky factor (None when SuperLU factorised). [√(N/m)]
    lu : object or None
        SuperLU factorisation (``scipy.sparse.linalg.splu``) when the matrix was not positive definite.
    """

    solver: BandedSolver
    cholesky: np.ndarray | None = None
    lu: object | None = None

    @property
    def positive_definite(self) -> bool:
        """Whether the matrix was positive definite (factorised by Cholesky)."""
        return self.cholesky is not None

    def solve(self, rhs: np.ndarray, backend: str = "auto") -> np.ndarray:
        """Solve K u = rhs for one right-hand side or the columns of a 2-D array.

        Parameters
        ----------
        rhs : ndarray, shape (n,) or (n, m)
            Right-hand side(s). [N]
        backend : {"auto", "lapack", "compiled", "numba"}
            Back-end of the banded solve (:func:`presag_opt.native.banded.choose`; ignored when the
            matrix was not positive definite and SuperLU solves).

        Returns
        -------
        ndarray
            Displacements, shaped like ``rhs``. [m]
        """
        if self.cholesky is None:
            return self.lu.solve(rhs)
        perm = self.solver.permutation
        out = np.empty_like(rhs, dtype=float)
        out[perm] = banded.cholesky_solve(self.cholesky, rhs[perm], backend)
        return out

    def inverse_block(self, rows: np.ndarray, backend: str = "auto") -> np.ndarray:
        """The block K⁻¹[rows, rows]: the displacement of each of ``rows`` under a unit load on each. [m/N]

        In the band order K = L Lᵀ. A unit load on a row at or after place r0 gives L⁻¹e = 0 above r0,
        and the back substitution with Lᵀ finds the rows at or after r0 from those rows alone, so the
        trailing factor L[r0:, r0:] gives them exactly: the solves skip the rows before the first of
        ``rows`` (on a long section, for the nodes of one span, on average half the work).

        Parameters
        ----------
        rows : ndarray of int
            Rows (free DOFs) loaded and read, in any order. [-]
        backend : {"auto", "lapack", "compiled", "numba"}
            As for :meth:`solve`.

        Returns
        -------
        ndarray, shape (len(rows), len(rows))
            ``K⁻¹[rows][:, rows]``. [m/N]
        """
        rows = np.asarray(rows, dtype=int)
        columns = np.arange(len(rows))
        n = self.solver.pattern.shape[0]
        if self.cholesky is None:
            unit = np.zeros((n, len(rows)))
            unit[rows, columns] = 1.0
            return self.lu.solve(unit)[rows]
        if len(rows) == 0:
            return np.zeros((0, 0))
        place = self.solver.position[rows]
        first = int(place.min())
        unit = np.zeros((n - first, len(rows)))
        unit[place - first, columns] = 1.0
        return banded.cholesky_solve(self.cholesky[:, first:], unit, backend)[place - first]
