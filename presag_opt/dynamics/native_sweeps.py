"""The batch simulator's sweeps over all DOFs as compiled C (``sweeps.c``), called from numba.

:func:`presag_opt.dynamics.kernel.advance` spends nearly all of a step in three sweeps over the
catenary's DOFs. Written in numba, each run keeps its accumulator in memory, and the
load-add-store chain through it costs about 15 processor cycles per band entry however many runs
share the step: a 12-run step of the case study (8 502 DOFs, bandwidth 20) takes 4.5 ms, a 1-run step
2.3 ms. ``sweeps.c`` does the same operations in the same order with the runs in blocks of eight
whose accumulators stay in vector registers; it gives the same numbers to the last bit
(``tests/dynamics/test_native_sweeps.py``) and takes 2.3 ms for the 12-run step, 1.4 ms for the
1-run step (``benchmarks/bench_batch.py`` compares whole batches: about 2.2 times faster).

The library is built once per machine by :func:`presag_opt.static.native.build` (``-O3
-march=native -ffp-contract=off``: tuned to the processor, no fused multiply-add, no fast-math) and
loaded into the process. :func:`forward_sweep`, :func:`backward_sweep` and :func:`update_sweep` call
its functions by name with the arguments of the numba sweeps, and the one driver loop,
:func:`presag_opt.dynamics.kernel.advance`, takes either kind. Without a compiler, or with
``PRESAG_NO_COMPILE=1``, :func:`available` is False and the kernel takes the numba sweeps
(:func:`link` then stands in for the C symbols, so the kernel still compiles).

The run arrays the sweeps read have a run dimension padded to whole blocks (:func:`lanes_for`);
the padding lanes are swept too and never read.
"""

from __future__ import annotations

import ctypes
import functools
import os
import sys
from pathlib import Path

from numba import types

from presag_opt.dynamics.jit import inline
from presag_opt.static import native

LANES = 8
"""Runs per block of the compiled sweeps (``LANES`` in ``sweeps.c``). [-]"""

SOURCE = Path(__file__).with_name("sweeps.c")

FLAGS = ("-O3", "-march=native", "-ffp-contract=off")
"""Compiler flags: optimised for this processor, with every multiplication and addition rounded
on its own as in numba (no contraction into fused multiply-adds)."""

SYMBOLS = ("presag_forward_sweep", "presag_backward_sweep", "presag_update_sweep")
"""The functions of ``sweeps.c`` the kernel calls."""

_pointer = types.uintp
_forward = types.ExternalFunction(SYMBOLS[0], types.void(
    _pointer, _pointer, _pointer, types.int64, types.int64, types.float64, types.float64, _pointer, _pointer,
    _pointer, _pointer, _pointer, _pointer, _pointer, _pointer, _pointer, types.int64, types.int64))
_backward = types.ExternalFunction(SYMBOLS[1], types.void(
    _pointer, _pointer, types.int64, types.int64, types.int64, types.int64))
_update = types.ExternalFunction(SYMBOLS[2], types.void(
    types.int64, _pointer, _pointer, _pointer, _pointer, _pointer, types.int64, _pointer, _pointer, _pointer,
    _pointer, _pointer, types.int64, types.int64, types.int64, types.float64, types.float64, types.float64,
    types.float64, types.float64, types.float64, types.float64, types.float64, _pointer, _pointer, _pointer,
    types.int64, _pointer))


@functools.cache
def available() -> bool:
    """Whether the compiled sweeps are built and loaded into this process (False without a C
    compiler or with ``PRESAG_NO_COMPILE`` set)."""
    library = native.build("sweeps", SOURCE.read_text(), FLAGS)
    if library is None:
        return False
    import llvmlite.binding as llvm

    llvm.load_library_permanently(str(library))
    loaded = ctypes.CDLL(str(library))
    for name in SYMBOLS:  # ahead of any stand-in that link() registered before
        llvm.add_symbol(name, ctypes.cast(getattr(loaded, name), ctypes.c_void_p).value)
    return True


@ctypes.CFUNCTYPE(None)
def _missing() -> None:  # pragma: no cover - the kernel calls the C sweeps only when they are available
    sys.stderr.write("presag_opt: the compiled sweeps were called but are not built\n")
    os.abort()


def link() -> None:
    """Make the C sweeps' symbols resolvable, so that the kernel (which holds both kinds of sweeps)
    compiles and loads: the built library's, or, where none is loaded, a stand-in that is never
    called (the kernel takes the numba sweeps whenever :func:`available` is False). Call it after
    :func:`available`."""
    import llvmlite.binding as llvm

    for name in SYMBOLS:
        if llvm.address_of_symbol(name) is None:
            llvm.add_symbol(name, ctypes.cast(_missing, ctypes.c_void_p).value)


def lanes_for(n_runs: int) -> int:
    """The run dimension of the arrays the compiled sweeps read: ``n_runs`` padded to whole blocks. [-]"""
    return -(-n_runs // LANES) * LANES


@inline
def _lanes(work, active):
    """The lanes a sweep of ``active`` runs covers: whole blocks, within the padded run dimension."""
    return min(work.delta.shape[1], -(-active // LANES) * LANES)


@inline
def forward_sweep(scalars, shared, state, work, active):
    """:func:`presag_opt.dynamics.kernel.forward_sweep` in C."""
    sh = shared
    n, width = sh.factor_band.shape
    _forward(sh.stiffness_band.ctypes.data, sh.factor_band.ctypes.data, sh.mass.ctypes.data, n, width,
             scalars.rayleigh_alpha, scalars.scheme.s, state.q.ctypes.data, state.v.ctypes.data, state.r.ctypes.data,
             sh.candidate_index.ctypes.data, work.linear.ctypes.data, work.g.ctypes.data, work.scale.ctypes.data,
             work.first_residual.ctypes.data, work.delta.ctypes.data, work.delta.shape[1], _lanes(work, active))


@inline
def backward_sweep(shared, work, active):
    """The backward substitution of K_eff δ_lin = g in C (numba's is
    :func:`presag_opt.static.kernels.backward_substitution`)."""
    n, width = shared.factor_band.shape
    _backward(shared.factor_band.ctypes.data, work.delta.ctypes.data, n, width, work.delta.shape[1],
              _lanes(work, active))


@inline
def update_sweep(step, scalars, shared, runs, state, out, work, active):
    """:func:`presag_opt.dynamics.kernel.update_sweep` in C."""
    c, sh = scalars.scheme, shared
    _update(sh.mass.shape[0], sh.mass.ctypes.data, sh.columns.ctypes.data, work.phi_count.ctypes.data,
            work.phi_column.ctypes.data, work.phi_coefficient.ctypes.data, work.phi_column.shape[1],
            state.u.ctypes.data, state.v.ctypes.data, state.q.ctypes.data, state.r.ctypes.data,
            work.delta.ctypes.data, work.delta.shape[1], _lanes(work, active), active, c.a0, c.velocity_update,
            c.time_step, c.displacement_predictor, c.velocity_predictor, c.s, c.alpha, scalars.rayleigh_beta,
            sh.support_row.ctypes.data, out.status.ctypes.data, runs.n_steps.ctypes.data, step,
            out.uplift_max.ctypes.data)
