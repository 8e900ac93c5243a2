"""The batch kernel's compilation for a batch's argument types: on both cores the first time.

The kernel's two entry points, :func:`~presag_opt.dynamics.batch.kernel.initialise` and
:func:`~presag_opt.dynamics.batch.kernel.advance`, are compiled (or loaded from numba's cache)
before a batch calls them, by :func:`compile_kernel`. Compiled afresh, they take about 19 s of one
core, more than half of it in :func:`~presag_opt.dynamics.batch.kernel.newton_steps` (each run's
Newton iteration, which ``advance`` calls; about 11 s), which has a cache entry of its own. So the
first compilation is split over two processes: a helper compiles ``newton_steps`` into the cache
(:func:`presag_opt.native.jit.compiling_elsewhere`) while this process compiles ``initialise`` and
the parts ``advance`` calls besides it (the sweeps and the step's bookkeeping,
:func:`advance_calls`); ``advance`` itself is compiled last, with ``newton_steps`` loaded from the
cache. The machine code is the same as one process would make (each function is compiled from the
same source for the same types; a cached function is linked into its callers as numba links it
when it compiled it in the same process), so the numbers are the same to the last bit.

Nothing of this runs when ``advance`` is compiled or cached already (the common case: a warm cache
costs a look at numba's cache index), when another process is compiling the kernel (this one waits
for it on the kernel's compile locks and loads its cache), on a machine with one core, or with
compiled code turned off in the runtime (:attr:`presag_opt.runtime.Runtime.compile`): one process
then compiles everything, as before.

The types the helper compiles for are those of the batch's own arrays, and :func:`advance_calls`
lists the calls of ``advance`` with the arguments it passes: a call of ``advance`` typed
otherwise would compile its callee again in this process (time lost, the numbers unchanged);
``tests/dynamics/batch/test_compilation.py`` fails if that happens.
"""

from __future__ import annotations

from collections.abc import Callable

from presag_opt import runtime
from presag_opt.dynamics.batch import kernel
from presag_opt.native import sweeps as native
from presag_opt.native.jit import compile_once, compiling_elsewhere, is_cached, signature

FIRST_USE_NOTE = "compiling the batch kernel for its first use on this installation (about 10-20 s, once)"
"""What the progress display says while the kernel is compiled afresh."""


def compile_kernel(c_sweeps, scalars, shared, runs, state, out, work, scratch,
                   progress: Callable[[str], None] | None = None) -> None:
    """Compile (or load from the cache) the kernel's entry points for a batch's arrays (see the
    module notes).

    Parameters
    ----------
    c_sweeps : CSweeps or None
        The compiled C sweeps, or None for numba's (as :func:`~presag_opt.dynamics.batch.kernel.advance`).
    scalars, shared, runs, state, out, work, scratch : kernel_data tuples
        The batch's arrays by name (:mod:`~presag_opt.dynamics.batch.kernel_data`).
    progress : callable, optional
        Told :data:`FIRST_USE_NOTE` when the kernel is compiled afresh.
    """
    initialise_args = (scalars, shared, runs, state, out, scratch)
    advance_args = (1, 1, c_sweeps, scalars, shared, runs, state, out, work, scratch)
    if is_cached(kernel.advance, *advance_args) and is_cached(kernel.initialise, *initialise_args):
        compile_once(kernel.initialise, *initialise_args)
        compile_once(kernel.advance, *advance_args)
        return
    if progress is not None:
        progress(FIRST_USE_NOTE)
    newton_args = (1, 1, scalars, shared, runs, state, out, work, scratch)
    if not runtime.current().compile:
        compile_once(kernel.initialise, *initialise_args)
        compile_once(kernel.advance, *advance_args)
        return
    with compiling_elsewhere(kernel.newton_steps, *newton_args) as elsewhere:
        compile_once(kernel.initialise, *initialise_args)
        if elsewhere:
            for function, args in advance_calls(c_sweeps, scalars, shared, runs, state, out, work):
                function.compile(signature(function, *args))
    compile_once(kernel.newton_steps, *newton_args)  # loads what the helper compiled
    compile_once(kernel.advance, *advance_args)


def advance_calls(c_sweeps, scalars, shared, runs, state, out, work) -> list[tuple[object, tuple]]:
    """The numba functions :func:`~presag_opt.dynamics.batch.kernel.advance` calls besides
    ``newton_steps``, each with arguments of the types it passes them (a step and an active count
    are integers, ``1``).

    numba's sweeps are among them even when ``c_sweeps`` holds the C sweeps: numba prunes the branch
    of ``c_sweeps is None`` before typing only when ``c_sweeps`` is None (a tuple of pointers is
    neither None nor a literal for its pruning), so it types and compiles both kinds of sweeps.

    Parameters
    ----------
    c_sweeps, scalars, shared, runs, state, out, work
        As :func:`compile_kernel`.

    Returns
    -------
    list of (dispatcher, tuple)
        Function and arguments.
    """
    step = active = 1
    calls = [(kernel.start_step, (step, runs, out, work)),
             (kernel.forward_sweep, (scalars, shared, state, work, active)),
             (kernel.backward_sweep, (shared, work, active)),
             (kernel.update_sweep, (step, scalars, shared, runs, state, out, work, active)),
             (kernel.mark_finished_runs, (step, active, runs, out))]
    if c_sweeps is not None:
        calls += [(native.forward_sweep, (c_sweeps, scalars, shared, state, work, active)),
                  (native.backward_sweep, (c_sweeps, shared, work, active)),
                  (native.update_sweep, (c_sweeps, step, scalars, shared, runs, state, out, work, active))]
    return calls
