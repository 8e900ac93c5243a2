"""The batch simulator's sweeps over all DOFs as compiled C (``sweeps.c``), called from numba.

:func:`presag_opt.dynamics.batch.kernel.advance` spends nearly all of a step in three sweeps over the
catenary's DOFs, over the bands' nonzero entries (:mod:`presag_opt.dynamics.batch.band_rows`). Written in
numba, each run keeps its accumulator in memory, and the load-add-store chain through it costs about
15 processor cycles per entry however many runs share the step. ``sweeps.c`` does the same
operations in the same order with the runs in blocks of eight whose accumulators stay in vector
registers; it gives the same numbers to the last bit (``tests/dynamics/test_native_sweeps.py``), and
a batch of 10 runs of the paper's grid takes 10.2 s with it against 17.2 s in numba
(``benchmarks/bench_batch.py``).

The library is built once per machine by :func:`presag_opt.native.build` (``-O3
-march=native -ffp-contract=off``: tuned to the processor, no fused multiply-add, no fast-math) and
loaded into the process with ctypes; :func:`sweeps` hands its functions to the kernel as function
pointers, and :func:`forward_sweep`, :func:`backward_sweep` and :func:`update_sweep` call them with the
arguments of the numba sweeps, so that the one driver loop,
:func:`presag_opt.dynamics.batch.kernel.advance`, takes either kind. Without a compiler, or with
compiling turned off in the runtime (``PRESAG_NO_COMPILE=1``), :func:`available` is False, :func:`sweeps` gives None, and the kernel takes (and only then
compiles) the numba sweeps.

The run arrays the sweeps read have a run dimension padded to whole blocks (:func:`lanes_for`);
the padding lanes are swept too and never read.
"""

from __future__ import annotations

import ctypes
import functools
from pathlib import Path
from typing import NamedTuple

from presag_opt import native
from presag_opt.native.jit import kernel_part

LANES = 8
"""Runs per block of the compiled sweeps (``LANES`` in ``sweeps.c``). [-]"""

SOURCE = Path(__file__).with_name("sweeps.c")

FLAGS = ("-O3", "-march=native", "-ffp-contract=off")
"""Compiler flags: optimised for this processor, with every multiplication and addition rounded
on its own as in numba (no contraction into fused multiply-adds)."""

_P, _I, _D = ctypes.c_size_t, ctypes.c_int64, ctypes.c_double  # pointer (as the address), int64, double
SIGNATURES = {
    "presag_forward_sweep": (_P, _P, _P, _I, _I, _P, _P, _P, _P, _P, _P, _D, _D, _P, _P, _P, _P, _P, _P, _P, _P, _P,
                             _I, _I),
    "presag_backward_sweep": (_P, _P, _P, _P, _P, _I, _I, _I, _I),
    "presag_update_sweep": (_I, _P, _P, _P, _P, _P, _I, _P, _P, _P, _P, _P, _I, _I, _I, _D, _D, _D, _D, _D, _D, _D,
                            _D, _P, _P, _P, _I, _P),
}
"""The functions of ``sweeps.c`` the kernel calls and their argument types (all return void)."""


class CSweeps(NamedTuple):
    """The C sweeps as function pointers, which the kernel takes as arguments (numba calls them
    through the pointer; their type is their signature, so one compiled kernel serves the library's
    functions and the stand-ins alike)."""

    forward: object
    backward: object
    update: object


def available() -> bool:
    """Whether the compiled sweeps are built for this machine (False without a C compiler or with
    compiling turned off in the runtime in force, :attr:`presag_opt.runtime.Runtime.compile`)."""
    return native.build("sweeps", SOURCE.read_text(), FLAGS) is not None


@functools.cache
def _loaded(path: str) -> CSweeps:
    library = ctypes.CDLL(path)
    functions = []
    for name, arguments in SIGNATURES.items():
        function = getattr(library, name)
        function.argtypes, function.restype = arguments, None
        functions.append(function)
    return CSweeps(*functions)


def sweeps() -> CSweeps | None:
    """The C sweeps for the kernel: the built library's functions, or None without one (the kernel
    then compiles and runs its numba sweeps)."""
    library = native.build("sweeps", SOURCE.read_text(), FLAGS)
    return _loaded(str(library)) if library is not None else None


def lanes_for(n_runs: int) -> int:
    """The run dimension of the arrays the compiled sweeps read: ``n_runs`` padded to whole blocks. [-]

    Parameters
    ----------
    n_runs : int
        Runs in the batch. [-]
    """
    return -(-n_runs // LANES) * LANES


@kernel_part
def _lanes(work, active):
    """The lanes a sweep of ``active`` runs covers: whole blocks, within the padded run dimension."""
    return min(work.delta.shape[1], -(-active // LANES) * LANES)


@kernel_part
def forward_sweep(c_sweeps, scalars, shared, state, work, active):
    """:func:`presag_opt.dynamics.batch.kernel.forward_sweep` in C.

    Parameters
    ----------
    c_sweeps : CSweeps
        The C sweeps (``sweeps()``).
    scalars : Scalars
        Constants of the batch.
    shared : Shared
        What the runs of the batch share.
    state : RunState
        The runs' state.
    work : Work
        Per-step work arrays of the batch.
    active : int
        Runs the sweep covers, the first columns (rounded up to whole blocks). [-]
    """
    sh = shared
    n, width = sh.factor_band.shape
    k, lower = sh.stiffness_rows, sh.lower_rows
    c_sweeps.forward(sh.stiffness_band.ctypes.data, sh.factor_band.ctypes.data, sh.mass.ctypes.data, n, width,
                     k.start.ctypes.data, k.column.ctypes.data, k.value.ctypes.data, lower.start.ctypes.data,
                     lower.column.ctypes.data, lower.value.ctypes.data, scalars.rayleigh_alpha, scalars.scheme.s, state.q.ctypes.data, state.v.ctypes.data,
                     state.r.ctypes.data, sh.candidate_index.ctypes.data, work.linear.ctypes.data, work.g.ctypes.data,
                     work.scale.ctypes.data, work.first_residual.ctypes.data, work.delta.ctypes.data,
                     work.delta.shape[1], _lanes(work, active))


@kernel_part
def backward_sweep(c_sweeps, shared, work, active):
    """:func:`presag_opt.dynamics.batch.kernel.backward_sweep` in C: the backward substitution of
    K_eff δ_lin = g.

    Parameters
    ----------
    c_sweeps : CSweeps
        The C sweeps (``sweeps()``).
    shared : Shared
        What the runs of the batch share.
    work : Work
        Per-step work arrays of the batch.
    active : int
        Runs the sweep covers, the first columns (rounded up to whole blocks). [-]
    """
    n, width = shared.factor_band.shape
    upper = shared.upper_rows
    c_sweeps.backward(shared.factor_band.ctypes.data, upper.start.ctypes.data, upper.column.ctypes.data,
                      upper.value.ctypes.data, work.delta.ctypes.data, n, width, work.delta.shape[1],
                      _lanes(work, active))


@kernel_part
def update_sweep(c_sweeps, step, scalars, shared, runs, state, out, work, active):
    """:func:`presag_opt.dynamics.batch.kernel.update_sweep` in C.

    Parameters
    ----------
    c_sweeps : CSweeps
        The C sweeps (``sweeps()``).
    step : int
        Record (time step) being computed. [-]
    scalars : Scalars
        Constants of the batch.
    shared : Shared
        What the runs of the batch share.
    runs : Runs
        What differs between the runs.
    state : RunState
        The runs' state.
    out : Records
        The records being written.
    work : Work
        Per-step work arrays of the batch.
    active : int
        Runs the sweep covers, the first columns (rounded up to whole blocks). [-]
    """
    c, sh = scalars.scheme, shared
    c_sweeps.update(sh.mass.shape[0], sh.mass.ctypes.data, sh.columns.ctypes.data, work.phi_count.ctypes.data,
                    work.phi_column.ctypes.data, work.phi_coefficient.ctypes.data, work.phi_column.shape[1],
                    state.u.ctypes.data, state.v.ctypes.data, state.q.ctypes.data, state.r.ctypes.data,
                    work.delta.ctypes.data, work.delta.shape[1], _lanes(work, active), active, c.a0,
                    c.velocity_update, c.time_step, c.displacement_predictor, c.velocity_predictor, c.s, c.alpha,
                    scalars.rayleigh_beta, sh.support_row.ctypes.data, out.status.ctypes.data,
                    runs.n_steps.ctypes.data, step, out.uplift_max.ctypes.data)
