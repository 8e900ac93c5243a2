"""Compiled code: C built on the user's machine, and the numba twins that stand in for it.

The lowest layer of the package above :mod:`presag_opt.errors`: nothing here imports the physics
(except the batch simulator's driver loop in :mod:`~presag_opt.native.sweeps`, which calls the numba
kernel's per-step functions between its C sweeps). Every C library gives the numbers of its
fallback to the last bit; only the speed differs. Without a C compiler, or with
``PRESAG_NO_COMPILE=1``, the fallbacks run.

Modules
-------
compiler
    :func:`build`: compiles a C source with ``$CC`` into the user's cache folder, keyed by a hash of
    the source, the flags, the compiler and the processor (an edited source is a new library);
    :func:`compiling_disabled` (``PRESAG_NO_COMPILE``); the cache folder's location.
banded, ``banded.c``
    The banded Cholesky solve with many right-hand sides, its back-end (``"lapack"``,
    ``"compiled"``, ``"numba"`` or ``"auto"``) an explicit argument chosen per call.
banded_numba
    The numba twin of ``banded.c``, and the backward substitution the batch simulator's step calls.
casadi_elements
    The static model's axial element functions as the C code CasADi generates for them.
sweeps, ``sweeps.c``
    The batch simulator's three sweeps over all DOFs in C, and the numba driver loop that calls them.
"""

from presag_opt.native.compiler import COMPILE_ENV_OFF, build, compiling_disabled

__all__ = ["COMPILE_ENV_OFF", "build", "compiling_disabled"]
