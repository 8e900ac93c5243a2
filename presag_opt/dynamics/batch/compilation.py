"""The batch kernel's compilation for a batch's argument types: on both cores the first time.

The kernel's two entry points, :func:`~presag_opt.dynamics.batch.kernel.initialise` and
:func:`~presag_opt.dynamics.batch.kernel.advance`, are compiled (or loaded from numba's cache)
before a batch calls them, by :func:`compile_kernel`. Compiled afresh, they take about 13 s of one
core, almost half of it in :func:`~presag_opt.dynamics.batch.kernel.newton_steps` (each run's
Newton iteration, which ``advance`` calls; about 6 s), which has a cache entry of its own. So the
first compilation is split over two processes: a helper compiles ``newton_steps`` into the cache
(:func:`compiling_elsewhere`) while this process compiles ``initialise`` and
the parts ``advance`` calls besides it (the sweeps and the step's bookkeeping,
:func:`advance_calls`); ``advance`` itself is compiled last, with ``newton_steps`` loaded from the
cache. ``advance`` calls ``newton_steps``' own machine code (a
:func:`~presag_opt.native.jit.shared_kernel_function`), wherever it was compiled, so the
numbers are the same to the last bit; a warm start loads ``newton_steps`` before ``advance``.

Nothing of this runs when ``advance`` is compiled or cached already (the common case: a warm cache
costs a look at numba's cache index), on a machine with one core, or with compiled code turned off
in the runtime (:attr:`presag_opt.runtime.Runtime.compile`): one process then compiles everything,
as before. When another process holds ``newton_steps``' compile lock already (a helper the command
started when it started, :mod:`presag_opt.dynamics.batch.first_use`, or another command), no second
helper is started: this process compiles the rest meanwhile, waits for it on the lock and loads its
cache.

Interrupts: numba's compiler calls back into Python from llvmlite through ctypes, which prints an
exception raised inside such a callback and swallows it. A Ctrl-C or SIGTERM whose handler ran there
printed a traceback and the command went on (or ended with another error instead of exit 130), as the
e2e test of a SIGTERM during the first compilation saw. So every compilation and cache load here runs
with the interrupts held (:func:`presag_opt.processes.interrupts_held`) and delivered when it returns:
a Ctrl-C waits for the function being compiled (at most the 6 s of ``newton_steps`` where this
process compiles it, a few seconds otherwise); waiting for the helper is not held.

The types the helper compiles for are those of the batch's own arrays, and :func:`advance_calls`
lists the calls of ``advance`` with the arguments it passes: a call of ``advance`` typed
otherwise would compile its callee again in this process (time lost, the numbers unchanged);
``tests/dynamics/batch/test_compilation.py`` fails if that happens.
"""

from __future__ import annotations

import contextlib
import os
import pickle
import subprocess
import sys
from collections.abc import Callable, Iterator
from pathlib import Path

from numba.core.dispatcher import Dispatcher

from presag_opt import runtime
from presag_opt.dynamics.batch import kernel
from presag_opt.native import sweeps as native
from presag_opt.native.jit import compile_once, is_cached, lock_file, signature, try_lock
from presag_opt.processes import end_with_parent, interrupts_held

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
    newton_args = newton_steps_arguments(scalars, shared, runs, state, out, work, scratch)
    if is_cached(kernel.advance, *advance_args) and is_cached(kernel.initialise, *initialise_args):
        with interrupts_held():  # loading calls back from llvmlite too (see the module notes)
            compile_once(kernel.initialise, *initialise_args)
            compile_once(kernel.newton_steps, *newton_args)  # advance calls its machine code
            compile_once(kernel.advance, *advance_args)
        return
    if progress is not None:
        progress(FIRST_USE_NOTE)
    if not runtime.current().compile:
        _held(compile_once, kernel.initialise, *initialise_args)
        _held(compile_once, kernel.advance, *advance_args)
        return
    with compiling_elsewhere(kernel.newton_steps, *newton_args) as elsewhere:
        _held(compile_once, kernel.initialise, *initialise_args)
        if elsewhere:  # by a helper started here, or one started with the command (first_use)
            for function, args in advance_calls(c_sweeps, scalars, shared, runs, state, out, work):
                _held(function.compile, signature(function, *args))
    _held(compile_once, kernel.newton_steps, *newton_args)  # loads what the helper compiled
    _held(compile_once, kernel.advance, *advance_args)


def newton_steps_arguments(scalars, shared, runs, state, out, work, scratch) -> tuple:
    """The arguments :func:`~presag_opt.dynamics.batch.kernel.advance` calls
    :func:`~presag_opt.dynamics.batch.kernel.newton_steps` with, as far as their numba types go (a
    step and an active count are integers, ``1``), for a batch's arrays.

    Parameters
    ----------
    scalars, shared, runs, state, out, work, scratch : kernel_data tuples
        The batch's arrays by name (:mod:`~presag_opt.dynamics.batch.kernel_data`).

    Returns
    -------
    tuple
        ``(step, active, scalars, shared, runs, state, out, work, scratch)``.
    """
    return (1, 1, scalars, shared, runs, state, out, work, scratch)


def _held(compile_call: Callable[..., object], *args: object) -> None:
    """One compilation with Ctrl-C and SIGTERM held back until it returns, then delivered (see the
    module notes)."""
    with interrupts_held():
        compile_call(*args)


def advance_calls(c_sweeps, scalars, shared, runs, state, out, work) -> list[tuple[object, tuple]]:
    """The numba functions :func:`~presag_opt.dynamics.batch.kernel.advance` calls besides
    ``newton_steps``, each with arguments of the types it passes them (a step and an active count
    are integers, ``1``).

    numba's sweeps are among them even when ``c_sweeps`` holds the C sweeps: numba prunes the branch
    of ``c_sweeps is None`` before typing only when ``c_sweeps`` is None (a tuple of pointers is
    neither None nor a literal for its pruning), so it types and compiles both kinds of sweeps.

    Parameters
    ----------
    c_sweeps : CSweeps or None
        The compiled C sweeps, or None for numba's.
    scalars, shared, runs, state, out, work : kernel_data tuples
        The batch's arrays by name (:mod:`~presag_opt.dynamics.batch.kernel_data`).

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


@contextlib.contextmanager
def compiling_elsewhere(dispatcher: Dispatcher, *args: object) -> Iterator[bool]:
    """Compile a kernel function for the types of ``args`` in a helper process while the block runs.

    The lock of :func:`~presag_opt.native.jit.compile_once` is taken here and handed to the helper, which holds it until it
    has written the compiled code to the cache and exits: a ``compile_once`` of the same function
    and types, in this process or another, waits for it and then loads the cache. The block's value
    says whether the function is being compiled in another process: by a helper started here, or by
    one that held its lock already (a helper started with the command,
    :mod:`presag_opt.dynamics.batch.first_use`, or another command). No helper is started when the
    function is compiled or cached already, when another process is compiling it, where file locks
    are not available, or where the machine has one core.

    The helper leaves interrupts to this process and ends with it (:func:`presag_opt.processes.end_with_parent`);
    it prints nothing. Leaving the block waits for it; leaving it by an exception (Ctrl-C, SIGTERM
    turned into an interrupt) kills it first. A killed helper leaves no lock behind (a file lock
    ends with its holder) and at worst no cache entry, which the next ``compile_once`` then
    compiles.

    Parameters
    ----------
    dispatcher : numba Dispatcher
        A function made by :func:`~presag_opt.native.jit.kernel_function`, defined at the top level of an importable module.
    *args
        Arguments of the call to compile for (only their numba types matter; they must pickle).
    """
    helper, busy = None, False
    if spare_core() and not is_cached(dispatcher, *args):
        helper = start_helper(dispatcher, signature(dispatcher, *args))
        busy = helper is None and _locked_elsewhere(dispatcher)
    try:
        yield helper is not None or busy
        if helper is not None:
            helper.wait()
    finally:
        if helper is not None:
            stop_helper(helper)


def spare_core() -> bool:
    """Whether a compile helper would have a core of its own: the machine has more than one."""
    return (os.cpu_count() or 1) > 1


def stop_helper(helper: subprocess.Popen) -> None:
    """Kill a helper that is still compiling, and reap it (a finished one is only reaped)."""
    if helper.poll() is None:
        helper.kill()
    helper.wait()


def _locked_elsewhere(dispatcher: Dispatcher) -> bool:
    """Whether another process holds the kernel function's compile lock (taken and released at once
    if not)."""
    handle = lock_file(dispatcher)
    if handle is None:
        return False
    with handle:
        return not try_lock(handle)


def start_helper(dispatcher: Dispatcher, types_: tuple) -> subprocess.Popen | None:
    """A helper process compiling ``dispatcher`` for ``types_``, holding its lock (None if the lock
    is held by another process or the helper cannot start)."""
    handle = lock_file(dispatcher)
    if handle is None:
        return None
    with handle:
        if not try_lock(handle):
            return None  # another process is compiling it: compile_once waits for that one
        order = pickle.dumps((os.getpid(), [os.path.abspath(p) for p in sys.path],
                              dispatcher.py_func.__module__, dispatcher.py_func.__qualname__, types_))
        root = str(Path(__file__).resolve().parents[3])  # the folder presag_opt is imported from
        try:
            with interrupts_held():  # a started helper is always known to the finally that kills it
                helper = subprocess.Popen(
                    [sys.executable, "-c", _HELPER_CODE, root], stdin=subprocess.PIPE, stdout=subprocess.DEVNULL,
                    stderr=subprocess.DEVNULL, pass_fds=(handle.fileno(),))
        except OSError:
            return None
    # the helper now holds the only open copy of the locked file: the lock is its until it exits
    try:
        helper.stdin.write(order)
        helper.stdin.close()
    except OSError:
        pass  # the helper is gone already: the lock with it
    return helper


_HELPER_CODE = ("import sys; sys.path.insert(0, sys.argv[1]); "
                "from presag_opt.dynamics.batch.compilation import _helper_main; _helper_main()")
"""What a helper process of :func:`compiling_elsewhere` runs (its order is pickled on standard input)."""


def _helper_main() -> None:
    """The helper of :func:`compiling_elsewhere`: read the order, compile, exit."""
    import importlib

    parent, path, module, name, types_ = pickle.loads(sys.stdin.buffer.read())
    end_with_parent(parent)
    sys.path[:0] = [p for p in path if p not in sys.path]
    dispatcher = getattr(importlib.import_module(module), name)
    dispatcher.compile(types_)
