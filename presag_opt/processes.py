"""Worker processes that stop with the work that started them.

Every parallel part of the toolkit (the layouts of a recommendation, the force levels of an
elasticity study, the pre-sags of a dynamic design, the units of a parametric study) runs its
tasks in a :class:`concurrent.futures.ProcessPoolExecutor` opened by :func:`worker_pool`. The call
site says what its work needs (a :class:`WorkerPolicy`); this module alone decides how the workers
start (:func:`start_method`).

Every worker runs in its parent's :class:`~presag_opt.runtime.Runtime` (handed over when it starts:
pickled under spawn, inherited under fork), so it caches and compiles as the parent does. Work that
keeps something from one task to the next (a form-found state, a memo of the states of a study)
gives the pool a *job*: an object handed to each worker once, which the tasks then call through
:func:`run_job`; its memos (:class:`WorkerMemo`) live as long as the worker and never in the parent.

When the work ends normally the pool is closed and waited for. When it ends by an error, Ctrl-C or
SIGTERM (the command line turns SIGTERM into the same interrupt as Ctrl-C), the queued tasks are
dropped and the worker processes are killed at once, so that none keeps computing after its parent
has given up; a worker is started with both interrupts held back (:class:`_StoppablePool`), so that
none is left half-started, reading its start-up data from a closed pipe. When the parent itself is killed (SIGKILL, out of memory), each worker exits within
:data:`PARENT_POLL` seconds: on Linux the kernel kills it with the parent (``PR_SET_PDEATHSIG``),
and everywhere a thread in the worker ends it once it has been re-parented. What a parametric study
has stored stays stored (see :mod:`presag_opt.studies.store`).
"""

from __future__ import annotations

import contextvars
import ctypes
import enum
import multiprocessing
import os
import signal
import sys
import threading
import time
import warnings
from collections import OrderedDict
from collections.abc import Callable, Hashable, Iterator
from concurrent.futures import ProcessPoolExecutor
from contextlib import contextmanager
from typing import Any

from presag_opt import runtime
from presag_opt.errors import ModelError

PARENT_POLL = 1.0
"""Seconds between a worker's checks that its parent still runs. [s]"""

_PR_SET_PDEATHSIG = 1
"""``prctl`` option: the signal a process receives when its parent dies (Linux)."""


class WorkerPolicy(enum.Enum):
    """What the work of a pool needs from its worker processes.

    PICKLED
        Tasks and their arguments are pickled, and the parent may run threads (the command line's
        progress display, a Dask client): the workers are spawned (a fork of a process with threads
        can deadlock on a lock one of them held).
    FAST_START
        Tasks are pickled and short enough that re-importing the package in each worker would
        dominate: forked where the platform has ``fork``, else spawned.
    INHERITED
        Tasks use state of the parent that cannot be pickled (compiled CasADi functions, in the
        pool's job): forked; only where :func:`pool_available` says so.
    """

    PICKLED = "pickled"
    FAST_START = "fast-start"
    INHERITED = "inherited"


def pool_available(policy: WorkerPolicy) -> bool:
    """Whether this platform can open a pool of the given policy (``INHERITED`` needs ``fork``)."""
    return policy is not WorkerPolicy.INHERITED or "fork" in multiprocessing.get_all_start_methods()


def start_method(policy: WorkerPolicy) -> str:
    """The start method of a pool of the given policy on this platform: ``"spawn"`` or ``"fork"``.

    Raises
    ------
    ModelError
        ``INHERITED`` on a platform without ``fork``.
    """
    forking = "fork" in multiprocessing.get_all_start_methods()
    if policy is WorkerPolicy.INHERITED:
        if not forking:
            raise ModelError("this work needs worker processes started with fork, which this platform lacks; "
                             "run it with one worker")
        return "fork"
    if policy is WorkerPolicy.FAST_START and forking:
        return "fork"
    return "spawn"


@contextmanager
def worker_pool(workers: int, policy: WorkerPolicy = WorkerPolicy.PICKLED,
                job: Callable[..., Any] | None = None) -> Iterator[ProcessPoolExecutor]:
    """A process pool that is stopped, workers and all, if the ``with`` block does not finish.

    Each worker runs in the runtime in force here (:func:`presag_opt.runtime.current`).

    Parameters
    ----------
    workers : int
        Worker processes. [-]
    policy : WorkerPolicy
        What the work needs (see :class:`WorkerPolicy`); the start method follows from it.
    job : callable, optional
        Handed to each worker once (pickled under spawn, inherited under fork); tasks submitted as
        ``pool.submit(run_job, *args)`` call it with ``args`` in the worker. Whatever it keeps between
        calls is the worker's.
    """
    if not isinstance(policy, WorkerPolicy):
        raise ModelError(f"policy = {policy!r} is not one of {', '.join(p.name for p in WorkerPolicy)}")
    pool = _StoppablePool(max_workers=workers, mp_context=multiprocessing.get_context(start_method(policy)),
                          initializer=_start_worker, initargs=(os.getpid(), runtime.current(), job))
    try:
        yield pool
    except BaseException:
        stop(pool)
        raise
    pool.shutdown(wait=True)


class _StoppablePool(ProcessPoolExecutor):
    """A process pool that starts each worker with Ctrl-C and SIGTERM held back until it is started and
    registered: an interrupt in the middle of handing a spawned worker its start-up data closed the
    pipe under it, and the worker printed an ``EOFError`` traceback after the command's last line
    (seen once in CI, on a sweep stopped as its workers started). Held, the interrupt is raised right
    after, and :func:`stop` kills the registered worker, which prints nothing."""

    def _spawn_process(self) -> None:
        with interrupts_held():
            super()._spawn_process()


@contextmanager
def interrupts_held() -> Iterator[None]:
    """Hold back Ctrl-C and SIGTERM for the length of the block, then deliver the first one that arrived
    to the handler in force (the command line's raises :class:`KeyboardInterrupt`). Outside the main
    thread, where no handler can be set, the block changes nothing."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    received: list[int] = []
    previous = {number: signal.getsignal(number) for number in (signal.SIGINT, signal.SIGTERM)}
    try:
        for number, handler in previous.items():
            if handler not in (signal.SIG_IGN, None):
                signal.signal(number, lambda number, frame: received.append(number))
        yield
    finally:
        for number, handler in previous.items():
            if handler is not None:
                signal.signal(number, handler)
    if received:
        signal.raise_signal(received[0])


STOP_WAIT = 60.0
"""Longest wait for a stopped pool's manager thread to notice its killed workers: it normally takes
milliseconds; the bound only keeps a stuck thread from holding the exit forever (on a loaded machine
a few seconds were seen, and an exit before the thread is done prints a closed-pipe traceback). [s]"""


def stop(pool: ProcessPoolExecutor) -> None:
    """Drop the pool's queued tasks and kill its worker processes without waiting for their tasks.

    The pool's manager thread (in this process) is then given up to :data:`STOP_WAIT` seconds to
    see the workers gone and close its pipes, so that the interpreter does not exit under it (it
    would report a closed pipe as a raw traceback on stderr after the command's last line).
    """
    processes = list((getattr(pool, "_processes", None) or {}).values())
    manager = getattr(pool, "_executor_manager_thread", None)
    pool.shutdown(wait=False, cancel_futures=True)
    # SIGKILL, not SIGTERM: it cannot be caught, so a task cannot turn it into an exception
    for process in processes:
        if process.is_alive():
            process.kill()
    if manager is not None and manager is not threading.current_thread():
        manager.join(STOP_WAIT)


_JOB: contextvars.ContextVar[Callable[..., Any]] = contextvars.ContextVar("presag_worker_job")
"""The job of this worker's pool, set once by :func:`_start_worker` in a worker process (never in
the process that opened the pool)."""


def run_job(*args: Any) -> Any:
    """Call the job of this worker's pool (:func:`worker_pool`'s ``job``) with ``args``: submit it as
    ``pool.submit(run_job, *args)``."""
    return _JOB.get()(*args)


class WorkerMemo:
    """Results a job keeps from one task to the next, the ``size`` most recently used, by key.

    It belongs to the object that holds it (a pool's job, or a computation in the parent) and lives
    as long as that object; pickled (to a spawned worker, a Dask worker) it travels empty. Safe to use
    from several threads (a Dask worker runs tasks in threads).

    Parameters
    ----------
    size : int
        Entries kept. [-]
    """

    def __init__(self, size: int):
        self.size = int(size)
        self._entries: OrderedDict[Hashable, Any] = OrderedDict()
        self._lock = threading.Lock()

    def get(self, key: Hashable, compute: Callable[[], Any]) -> Any:
        """The value kept for ``key``, else ``compute()`` kept under it (computed outside the lock:
        two threads may both compute a missing value; both get an equal one)."""
        with self._lock:
            if key in self._entries:
                self._entries.move_to_end(key)
                return self._entries[key]
        value = compute()
        with self._lock:
            self._entries[key] = value
            while len(self._entries) > self.size:
                self._entries.popitem(last=False)
        return value

    def __len__(self) -> int:
        return len(self._entries)

    def __reduce__(self) -> tuple:
        return WorkerMemo, (self.size,)


_BLAS_THREADS = ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS")
"""Environment variables that set the thread count of a BLAS library when it loads."""


def _start_worker(parent: int, settings: runtime.Runtime, job: Callable[..., Any] | None) -> None:
    """Initializer of every worker: the parent's runtime and job, die with the parent, leave
    interrupts to the parent.

    Ctrl-C reaches the whole process group; the parent stops the pool, so a worker ignores SIGINT
    (no traceback of an interrupted task) and takes SIGTERM's default action (a forked worker would
    otherwise inherit the command line's handler). A worker shows no Python warnings: they would
    reach the terminal raw, once per worker, beside the parent's; the parent raises the same input
    warnings when it checks the work, and results carry their own.

    A worker's linear algebra (BLAS) runs on one thread: the pool already gives each core a worker,
    and BLAS threads of their own would compete with the other workers for the same cores (the
    sparse solves with many right-hand sides of a path model stalled for seconds that way on a
    loaded machine).
    """
    from threadpoolctl import threadpool_limits  # only workers need it

    os.environ.update(dict.fromkeys(_BLAS_THREADS, "1"))  # libraries this worker loads later
    threadpool_limits(1, user_api="blas")  # those loaded already (inherited under fork)
    settings.activate()
    if job is not None:
        _JOB.set(job)
    warnings.simplefilter("ignore")
    end_with_parent(parent)


def end_with_parent(parent: int) -> None:
    """Leave interrupts to the parent process ``parent`` and end when it ends: ignore SIGINT (Ctrl-C
    reaches the whole process group; the parent stops this process), take SIGTERM's default action,
    and exit at once when the parent is gone (``PR_SET_PDEATHSIG`` on Linux, and a thread that
    checks every :data:`PARENT_POLL` seconds everywhere).

    Parameters
    ----------
    parent : int
        Process id of the parent. [-]
    """
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    signal.signal(signal.SIGTERM, signal.SIG_DFL)
    if sys.platform.startswith("linux"):
        try:
            ctypes.CDLL(None, use_errno=True).prctl(_PR_SET_PDEATHSIG, int(signal.SIGKILL), 0, 0, 0)
        except (OSError, AttributeError):
            pass  # no prctl: the watch thread below still ends the worker
    if os.getppid() != parent:  # the parent died before the signal was armed
        os._exit(1)
    threading.Thread(target=_watch_parent, args=(parent,), name="presag-parent-watch", daemon=True).start()


def _watch_parent(parent: int) -> None:
    """End this worker at once when it has been re-parented (its parent is gone)."""
    while True:
        time.sleep(PARENT_POLL)
        if os.getppid() != parent:
            os._exit(1)
