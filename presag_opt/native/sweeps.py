"""The batch simulator's sweeps over all DOFs as compiled C (``sweeps.c``), called from numba.

:func:`presag_opt.dynamics.kernel.advance` spends nearly all of a step in three sweeps over the
catenary's DOFs. Written in numba, each run keeps its accumulator in memory, and the
load-add-store chain through it costs about 15 processor cycles per band entry however many runs
share the step: a 12-run step of the case study (8 502 DOFs, bandwidth 20) takes 4.5 ms, a 1-run step
2.3 ms. ``sweeps.c`` does the same operations in the same order with the runs in blocks of eight
whose accumulators stay in vector registers; it gives the same numbers to the last bit
(``tests/dynamics/test_native_sweeps.py``) and takes 2.3 ms for the 12-run step, 1.4 ms for the
1-run step (``benchmarks/bench_batch.py`` compares whole batches: about 2.2 times faster).

The library is built once per machine by :func:`presag_opt.native.build` (``-O3
-march=native -ffp-contract=off``: tuned to the processor, no fused multiply-add, no fast-math) and
loaded into the process, and the numba kernel :func:`advance` calls its functions by name; numba
caches that kernel like the others. Without a compiler, or with ``PRESAG_NO_COMPILE=1``,
:func:`available` is False and the simulator uses :func:`presag_opt.dynamics.kernel.advance`.

The run arrays the sweeps read have a run dimension padded to whole blocks (:func:`lanes_for`);
the padding lanes are swept too and never read.
"""

from __future__ import annotations

import functools
from pathlib import Path

from numba import njit, types

from presag_opt import native
from presag_opt.dynamics.kernel import finish_step, newton_steps, start_step, update_constants

LANES = 8
"""Runs per block of the compiled sweeps (``LANES`` in ``sweeps.c``). [-]"""

SOURCE = Path(__file__).with_name("sweeps.c")

FLAGS = ("-O3", "-march=native", "-ffp-contract=off")
"""Compiler flags: optimised for this processor, with every multiplication and addition rounded
on its own as in numba (no contraction into fused multiply-adds)."""

_pointer = types.uintp
_forward = types.ExternalFunction("presag_forward_sweep", types.void(
    _pointer, _pointer, _pointer, types.int64, types.int64, types.float64, types.float64, _pointer, _pointer,
    _pointer, _pointer, _pointer, _pointer, _pointer, _pointer, _pointer, types.int64, types.int64))
_backward = types.ExternalFunction("presag_backward_sweep", types.void(
    _pointer, _pointer, types.int64, types.int64, types.int64, types.int64))
_update = types.ExternalFunction("presag_update_sweep", types.void(
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
    return True


def lanes_for(n_runs: int) -> int:
    """The run dimension of the arrays the compiled sweeps read: ``n_runs`` padded to whole blocks. [-]"""
    return -(-n_runs // LANES) * LANES


@njit(cache=True)
def advance(first_step, last_step, scalars, shared, runs, state, out, work, scratch):
    """:func:`presag_opt.dynamics.kernel.advance` with its three sweeps in compiled C (same arguments,
    same results; the catenary's run arrays padded to :func:`lanes_for` runs)."""
    rayleigh_alpha, rayleigh_beta, dt, hht_alpha = scalars[0], scalars[1], scalars[2], scalars[3]
    stiffness_band, factor_band, mass, columns = shared[0], shared[1], shared[2], shared[8]
    candidate_index, support_row = shared[21], shared[23]
    n_steps = runs[0]
    u, v, q, r = state[0], state[1], state[2], state[3]
    uplift_max, status = out[1], out[3]
    delta, g, linear, scale, first_residual = work[0], work[1], work[2], work[3], work[4]
    phi_count, phi_column, phi_coefficient = work[5], work[6], work[7]
    n, width = factor_band.shape
    ld = delta.shape[1]
    s, a0, c_v, c_a, c_g = update_constants(scalars)
    for step in range(first_step, last_step + 1):
        active = start_step(step, runs, out, work)
        if active == 0:
            break
        lanes = min(ld, -(-active // LANES) * LANES)
        _forward(stiffness_band.ctypes.data, factor_band.ctypes.data, mass.ctypes.data, n, width, rayleigh_alpha, s,
                 q.ctypes.data, v.ctypes.data, r.ctypes.data, candidate_index.ctypes.data, linear.ctypes.data,
                 g.ctypes.data, scale.ctypes.data, first_residual.ctypes.data, delta.ctypes.data, ld, lanes)
        _backward(factor_band.ctypes.data, delta.ctypes.data, n, width, ld, lanes)
        newton_steps(step, active, scalars, shared, runs, state, out, work, scratch)
        _update(n, mass.ctypes.data, columns.ctypes.data, phi_count.ctypes.data, phi_column.ctypes.data,
                phi_coefficient.ctypes.data, phi_column.shape[1], u.ctypes.data, v.ctypes.data, q.ctypes.data,
                r.ctypes.data, delta.ctypes.data, ld, lanes, active, a0, c_g, dt, c_a, c_v, s, hht_alpha,
                rayleigh_beta, support_row.ctypes.data, status.ctypes.data, n_steps.ctypes.data, step,
                uplift_max.ctypes.data)
        finish_step(step, active, runs, out)
