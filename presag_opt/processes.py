"""Worker processes that stop with the work that started them.

Every parallel part of the toolkit (the layouts of a recommendation, the force levels of an
elasticity study, the pre-sags of a dynamic design, the units of a parametric study) runs its
tasks in a :class:`concurrent.futures.ProcessPoolExecutor` opened by :func:`worker_pool`. When the
work ends normally the pool is closed and waited for. When it ends by an error, Ctrl-C or SIGTERM
(the command line turns SIGTERM into the same interrupt as Ctrl-C), the queued tasks are dropped and
the worker processes are killed at once, so that none keeps computing after its parent has
given up. What a parametric study has stored stays stored (see :mod:`presag_opt.studies.store`).
"""

from __future__ import annotations

import multiprocessing
from collections.abc import Iterator
from concurrent.futures import ProcessPoolExecutor
from contextlib import contextmanager


@contextmanager
def worker_pool(workers: int, start_method: str = "spawn") -> Iterator[ProcessPoolExecutor]:
    """A process pool that is stopped, workers and all, if the ``with`` block does not finish.

    Parameters
    ----------
    workers : int
        Worker processes. [-]
    start_method : {"spawn", "fork", "forkserver"}
        How the workers start ("spawn" where the parent runs threads, such as the command line's
        progress display; "fork" only where the platform has it).
    """
    pool = ProcessPoolExecutor(max_workers=workers, mp_context=multiprocessing.get_context(start_method))
    try:
        yield pool
    except BaseException:
        stop(pool)
        raise
    pool.shutdown(wait=True)


def stop(pool: ProcessPoolExecutor) -> None:
    """Drop the pool's queued tasks and kill its worker processes without waiting for them."""
    processes = list((getattr(pool, "_processes", None) or {}).values())
    pool.shutdown(wait=False, cancel_futures=True)
    # SIGKILL, not SIGTERM: a forked worker inherits the command line's SIGTERM handler, which would
    # turn the signal into an exception inside its task instead of ending it.
    for process in processes:
        if process.is_alive():
            process.kill()
