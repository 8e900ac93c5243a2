"""Work on a Dask distributed cluster: the client, and tasks that survive the loss of a worker.

:func:`results_on_dask` sends tasks to a scheduler and yields their results as they finish. What a
task needs travels with the task itself, so that the scheduler can run it again on any worker when
the one it ran on dies. The one thing kept per worker is the *job* (the object that does the work
and keeps a memo from task to task, e.g. a study's
:class:`~presag_opt.studies.work.UnitRunner`): it is held by a worker plugin, which the scheduler
installs on every worker, including one that joins or restarts after the tasks were sent.

Data scattered to the workers is not used. The scheduler cannot recompute scattered data, and its
memory manager keeps one copy of a key that no waiting task needs, so a worker killed mid-study
could take the only copy with it and cancel every task that depends on it.
"""

from __future__ import annotations

import uuid
from collections.abc import Callable, Iterable, Iterator
from typing import Any

from presag_opt import runtime
from presag_opt.errors import ModelError

_CONNECT_TIMEOUT = "20s"
"""How long a client waits for the scheduler before it gives up. [s]"""


def dask_client(address: str):
    """A Dask distributed client of the scheduler at ``address`` (one clear line if it cannot connect).

    Parameters
    ----------
    address : str
        Scheduler address, e.g. ``tcp://host:8786``.

    Raises
    ------
    ModelError
        Dask distributed is not installed, or the scheduler does not answer within 20 s.
    """
    try:
        from distributed import Client
    except ImportError:
        raise ModelError("--scheduler needs Dask distributed: pip install 'presag-opt[cluster]'") from None
    try:
        return Client(str(address), timeout=_CONNECT_TIMEOUT)
    except (OSError, TimeoutError) as exc:
        raise ModelError(f"scheduler {address}: cannot connect ({str(exc).splitlines()[0]})") from None


def results_on_dask(tasks: Iterable[tuple[Any, tuple]], address: str, job: Any,
                    run: Callable[..., Any]) -> Iterator[tuple[Any, Any]]:
    """Run tasks on a Dask distributed cluster; yield ``(label, result)`` in the order they finish.

    Each task runs ``run(job, *work)`` on a worker, inside the runtime in force here
    (:func:`presag_opt.runtime.current`: a Dask worker is not started by this process, so the
    runtime travels with each task). ``job`` reaches every worker once, through a worker plugin, so
    whatever it keeps serves all the tasks there; a worker that restarts gets it afresh (pickled, as
    the job's memo travels: empty). A task whose worker dies is run again by the scheduler.

    Parameters
    ----------
    tasks : iterable of (label, work)
        The tasks: ``work`` is a tuple of picklable arguments, sent with the task; labels may repeat.
    address : str
        Scheduler address.
    job : object
        Picklable; handed to ``run`` on the worker.
    run : callable
        ``run(job, *work)``, importable on the workers (``operator.call`` calls the job itself).

    Yields
    ------
    (label, result)
        As each task finishes. Closing the generator early cancels the tasks not yet finished.

    Raises
    ------
    ModelError
        No Dask distributed, or the scheduler does not answer.
    """
    tasks = list(tasks)
    if not tasks:
        return
    name = f"presag-job-{uuid.uuid4().hex}"
    with dask_client(address) as client:
        from distributed import as_completed as dask_completed

        client.register_plugin(JobPlugin(job), name=name)
        settings = runtime.current()
        futures = {client.submit(run_with_job, name, run, settings, *work, pure=False): label
                   for label, work in tasks}
        try:
            for future in dask_completed(list(futures)):
                yield futures[future], future.result()
        finally:
            client.cancel(list(futures))
            try:
                client.unregister_worker_plugin(name)
            except Exception:  # noqa: BLE001 - a cluster going down takes the plugin with it
                pass


def run_with_job(name: str, run: Callable[..., Any], settings: runtime.Runtime, *work: Any) -> Any:
    """A Dask task: ``run(job, *work)`` in the runtime ``settings`` of the process that submitted it,
    with the job that the plugin ``name`` holds on this worker."""
    from distributed import get_worker

    plugin = get_worker().plugins.get(name)
    if plugin is None:
        raise ModelError(f"Dask worker has no job {name!r}: it was not registered with the scheduler")
    with settings:
        return run(plugin.job, *work)


def _worker_plugin_base() -> type:
    try:
        from distributed.diagnostics.plugin import WorkerPlugin
    except ImportError:  # without distributed no cluster runs; the class is still importable
        return object
    return WorkerPlugin


class JobPlugin(_worker_plugin_base()):
    """A Dask worker plugin that holds a job on each worker: installed on every worker the scheduler
    has or gets while it is registered.

    Parameters
    ----------
    job : object
        Picklable; each worker holds its own copy.
    """

    def __init__(self, job: Any):
        self.job = job


__all__ = ["JobPlugin", "dask_client", "results_on_dask", "run_with_job"]
