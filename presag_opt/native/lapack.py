"""A dense linear solve for the batch kernel: LAPACK's ``dgesv`` called directly from numba.

The kernel's Woodbury correction solves a small dense system (a few unknowns) per Newton
iteration. ``np.linalg.solve`` compiled by numba calls the same LAPACK routine (SciPy's
``cython_lapack.dgesv``, on a copy of the matrix in column order), but compiling its checks and
error messages cost about 4 s of the kernel's cold compile. :func:`solve_by_columns` calls the
routine itself on a matrix the caller writes in column order: the same routine on the same numbers,
so the same result to the last bit (``tests/native/test_lapack.py``).

The routine is called by name (a symbol registered with LLVM when this module is imported), not by
an address baked into the machine code, so the kernel that calls it stays in numba's on-disk cache
and finds the routine again in the next process.
"""

from __future__ import annotations

import llvmlite.binding as llvm
import numpy as np
import scipy.linalg.lapack
from numba import types
from numba.extending import get_cython_function_address

from presag_opt.native.jit import kernel_part

_SYMBOL = "presag_opt_dgesv"
llvm.add_symbol(_SYMBOL, get_cython_function_address("scipy.linalg.cython_lapack", "dgesv"))
_dgesv = types.ExternalFunction(_SYMBOL, types.void(*([types.voidptr] * 8)))
"""dgesv(n, nrhs, a, lda, ipiv, b, ldb, info), every argument by address (Fortran convention)."""


def _solve_in_python(matrix: np.ndarray, rhs: np.ndarray, pivots: np.ndarray | None = None,
                     integers: np.ndarray | None = None) -> int:
    """:func:`solve_by_columns` called from Python: the same routine through SciPy's wrapper (which
    keeps its own pivots)."""
    *_, x, info = scipy.linalg.lapack.dgesv(matrix.T, rhs, overwrite_a=True)  # matrix.T: A in Fortran order
    rhs[:] = x
    return int(info)


def _solve_by_columns(matrix, rhs, pivots, integers):
    """Solve A x = b in place with LAPACK's dgesv (LU with partial pivoting); returns LAPACK's
    ``info``: 0 solved, > 0 A is singular (``rhs`` then holds no solution). Allocates nothing: the
    pivots and the routine's integer arguments are the caller's arrays.

    Parameters
    ----------
    matrix : ndarray, shape (n, n), C order
        A stored by columns: ``matrix[m, i]`` is A[i, m]; overwritten by its LU factors. [unit of A]
    rhs : ndarray, shape (n,)
        b on entry, x on return. [unit of b]
    pivots : ndarray of int32, shape (n,) or longer
        Receives the row interchanges. [-]
    integers : ndarray of int32, shape (3,)
        Receives the order n, the number of right-hand sides (1) and LAPACK's ``info``. [-]
    """
    order, one, info = integers[0:1], integers[1:2], integers[2:3]
    order[0], one[0], info[0] = rhs.shape[0], 1, 0
    _dgesv(order.ctypes, one.ctypes, matrix.ctypes, order.ctypes, pivots.ctypes, rhs.ctypes, order.ctypes, info.ctypes)
    return info[0]


solve_by_columns = kernel_part(_solve_by_columns, _solve_in_python)
