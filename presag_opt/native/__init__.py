"""Compiled code: C built on the user's machine, and the numba twins that stand in for it.

The lowest layer of the package above :mod:`presag_opt.errors`: nothing here imports the physics
(except the batch simulator's driver loop in :mod:`~presag_opt.native.sweeps`, which calls the numba
kernel's per-step functions between its C sweeps).

Modules
-------
compiler
    :func:`build`: compiles a C source with ``$CC`` into the user's cache folder, keyed by a hash of
    the source, the flags, the compiler and the processor; :func:`compiling_disabled`
    (``PRESAG_NO_COMPILE``).
sweeps, ``sweeps.c``
    The batch simulator's three sweeps over all DOFs in C, and the numba driver loop that calls them.
"""

from presag_opt.native.compiler import COMPILE_ENV_OFF, build, compiling_disabled

__all__ = ["COMPILE_ENV_OFF", "build", "compiling_disabled"]
