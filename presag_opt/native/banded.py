"""The banded Cholesky solve with many right-hand sides, its back-end an explicit choice.

Given the Cholesky factor L of a symmetric positive definite band matrix (LAPACK's lower band
storage, ``band[i − j, j] = L[i, j]``), :func:`cholesky_solve` solves L Lᵀ x = b for one or many
right-hand sides with one of three back-ends:

``"lapack"``
    SciPy's ``cho_solve_banded`` (LAPACK ``pbtrs``): one column at a time, at level-2 speed.
``"compiled"``
    ``banded.c``, built on this machine by :func:`presag_opt.native.build`: all columns in one sweep
    over the band, the columns innermost (4× LAPACK at 84 columns of the 31-span section).
``"numba"``
    :func:`presag_opt.native.banded_numba.banded_cholesky_solve`, the same operations in the same
    order as ``banded.c``: the same numbers to the last bit (``tests/native/test_banded.py``), at the
    cost of importing numba (about half a second) on first use.

The LAPACK solve and the two sweeps agree to round-off, not to the last bit (their sums run in
another order). ``"auto"`` (the default) picks one from the problem and the environment only, the
same way whatever ran before in the process (:func:`choose`): LAPACK below
:data:`MANY_RIGHT_HAND_SIDES` columns; else the C library where it can be built; else numba when the
solve is large enough to pay for importing it (:data:`NUMBA_WORK`); else LAPACK.
"""

from __future__ import annotations

import ctypes
import functools
from collections.abc import Callable
from pathlib import Path

import numpy as np
import scipy.linalg as sla

from presag_opt import runtime
from presag_opt.errors import ModelError
from presag_opt.native import compiler

BACKENDS = ("auto", "lapack", "compiled", "numba")
"""Back-ends of :func:`cholesky_solve`."""

MANY_RIGHT_HAND_SIDES = 16
"""Right-hand sides from which ``"auto"`` leaves LAPACK's column-by-column solve for a sweep over
all columns (4× faster at 84 columns of the 31-span section). [-]"""

NUMBA_WORK = 2e6
"""Without the C library: rows × right-hand sides of one solve from which ``"auto"`` takes the numba
kernel (its first use in a process costs about 0.5 s: importing numba and loading the cached
kernel). Measured on the 10-span section (7 239 rows, bandwidth 20): LAPACK 0.49 ms and the kernel
0.16 ms per column. One span of an ideal section (7 239 × 121) stays with LAPACK; a span of a long
mixed section (about 21 000 rows × 121 columns) takes numba. [-]"""

SOURCE = Path(__file__).with_name("banded.c")
FLAGS = ("-O3", "-march=native", "-ffp-contract=off")
"""Compiler flags of ``banded.c``: tuned to this processor, every operation rounded on its own as in
numba (no fused multiply-add, no fast-math)."""


def compiled_available() -> bool:
    """Whether the C back-end can be used here (a working compiler, ``PRESAG_NO_COMPILE`` unset)."""
    library = compiler.build("banded", SOURCE.read_text(), FLAGS)
    return library is not None and _loaded_solve(library) is not None


def choose(rows: int, columns: int, backend: str = "auto") -> str:
    """The back-end a solve of ``columns`` right-hand sides of ``rows`` rows uses.

    Parameters
    ----------
    rows : int
        Rows of the system. [-]
    columns : int
        Right-hand sides (1 for a vector). [-]
    backend : {"auto", "lapack", "compiled", "numba"}
        The requested back-end; ``"auto"`` decides from ``rows``, ``columns`` and whether the C
        library can be built (never from what ran before in the process).

    Returns
    -------
    str
        ``"lapack"``, ``"compiled"`` or ``"numba"``.

    Raises
    ------
    ModelError
        If ``backend`` is unknown, or ``"compiled"`` is asked for where the C library cannot be built.
    """
    if backend not in BACKENDS:
        raise ModelError(f"backend = {backend!r} is not one of {', '.join(BACKENDS)}")
    if backend == "compiled" and not compiled_available():
        raise ModelError(
            f"backend = 'compiled' needs the C library of banded.c, which cannot be built here (no C compiler "
            f"${{CC}}, or the runtime turns compiling off: {runtime.NO_COMPILE_ENV}); use backend = 'auto', 'lapack' or 'numba'"
        )
    if backend != "auto":
        return backend
    if columns < MANY_RIGHT_HAND_SIDES:
        return "lapack"
    if compiled_available():
        return "compiled"
    return "numba" if rows * columns >= NUMBA_WORK else "lapack"


def cholesky_solve(band: np.ndarray, rhs: np.ndarray, backend: str = "auto") -> np.ndarray:
    """Solve L Lᵀ x = rhs for one right-hand side or the columns of a 2-D array.

    Parameters
    ----------
    band : ndarray, shape (b + 1, n)
        The Cholesky factor L in LAPACK's lower band storage, ``band[i − j, j] = L[i, j]``.
        [sqrt of the matrix's unit]
    rhs : ndarray, shape (n,) or (n, m)
        Right-hand side(s). [unit of the right-hand side]
    backend : {"auto", "lapack", "compiled", "numba"}
        See :func:`choose`.

    Returns
    -------
    ndarray
        The solution, shaped like ``rhs``. [unit of the right-hand side / unit of the matrix]
    """
    rhs = np.asarray(rhs)
    columns = rhs.shape[1] if rhs.ndim == 2 else 1
    chosen = choose(rhs.shape[0], columns, backend)
    if chosen == "lapack":
        return sla.cho_solve_banded((band, True), rhs, check_finite=False)
    x = np.array(rhs.reshape(rhs.shape[0], columns), dtype=float, order="C")
    factor = np.ascontiguousarray(band.T)  # by rows: factor[j, k] = L[j + k, j]
    if chosen == "compiled":
        solve = _library_function(SOURCE.read_text())
        scratch = np.empty(columns)
        solve(factor.ctypes.data, x.ctypes.data, scratch.ctypes.data, factor.shape[0], factor.shape[1], columns,
              columns)
    else:
        from presag_opt.native.banded_numba import banded_cholesky_solve  # numba is imported only when used

        banded_cholesky_solve(factor, x, columns)
    return x.reshape(rhs.shape)


def load_solve(library: Path) -> Callable:
    """``presag_banded_cholesky_solve`` of a library built from ``banded.c`` (or an edited copy of it),
    with its argument types set: (factor, x, scratch pointers; n, width, ld, columns)."""
    function = ctypes.CDLL(str(library)).presag_banded_cholesky_solve
    pointer, count = ctypes.c_void_p, ctypes.c_int64
    function.argtypes = [pointer, pointer, pointer, count, count, count, count]
    function.restype = None
    return function


def _library_function(source: str) -> Callable | None:
    """The C solve built from ``source`` (the library named by the source text itself), or None if it
    cannot be built."""
    library = compiler.build("banded", source, FLAGS)
    return None if library is None else _loaded_solve(library)


@functools.cache
def _loaded_solve(library: Path) -> Callable:
    """:func:`load_solve` once per library file and process (loading a library twice gives the same functions)."""
    return load_solve(library)
