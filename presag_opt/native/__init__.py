"""Compiled code: C built on the user's machine, and the numba twins that stand in for it.

The lowest layer of the package above :mod:`presag_opt.errors`: nothing here imports the physics
(the batch simulator's one driver loop, :func:`presag_opt.dynamics.batch.kernel.advance`, takes the C
sweeps of :mod:`~presag_opt.native.sweeps` as function pointers). Every C library gives the numbers of its
fallback to the last bit; only the speed differs. Without a C compiler, or with
compiling turned off in the runtime (:mod:`presag_opt.runtime`; ``PRESAG_NO_COMPILE=1``), the fallbacks run.

Modules
-------
compiler
    :func:`build`: compiles a C source with ``$CC`` into the user's cache folder, keyed by a hash of
    the source, the flags, the compiler and the processor (an edited source is a new library);
    :func:`compiling_disabled` (the runtime's :attr:`~presag_opt.runtime.Runtime.compile`).
banded, ``banded.c``
    The banded Cholesky solve with many right-hand sides, its back-end (``"lapack"``,
    ``"compiled"``, ``"numba"`` or ``"auto"``) an explicit argument chosen per call.
banded_numba
    The numba twin of ``banded.c``, and the backward substitution the batch simulator's step calls.
casadi_elements
    The static model's axial element functions as the C code CasADi generates for them.
sweeps, ``sweeps.c``
    The batch simulator's three sweeps over all DOFs in C, handed to the kernel as function pointers.
jit
    numba compilation of the batch kernel, with on-disk caches keyed by every source file a compiled
    function depends on (an edit anywhere it reaches recompiles it).
"""

from presag_opt.native.compiler import build, compiling_disabled

__all__ = ["build", "compiling_disabled"]
