"""Tasks on a Dask cluster (``presag_opt.cluster``): results by label, one job per worker held by a
plugin, nothing scattered, the plugin gone after the run, tasks cancelled when the caller stops.

A threaded in-process cluster runs them here; a worker process killed mid-study (one, or all of them)
is the e2e test in ``tests/studies/test_faults_in_studies.py``.
"""

from __future__ import annotations

import sys
import threading
import time

import pytest

from presag_opt import runtime
from presag_opt.cluster import JobPlugin, results_on_dask, run_with_job
from presag_opt.errors import ModelError

distributed = pytest.importorskip("distributed")


class CountingJob:
    """A job that counts the tasks it served (its count travels with it when pickled: the plugin
    pickles the job once, so each worker starts from the count it had here)."""

    def __init__(self) -> None:
        self.calls = 0
        self.lock = threading.Lock()

    def __getstate__(self) -> dict:
        return {"calls": self.calls}

    def __setstate__(self, state: dict) -> None:
        self.calls = state["calls"]
        self.lock = threading.Lock()

    def __call__(self, value: float) -> tuple[int, float]:
        with self.lock:
            self.calls += 1
            return id(self), self.calls, 2.0 * value


def run_counting(job: CountingJob, value: float) -> tuple[int, int, float]:
    return job(value)


def scheduler_tasks(address: str) -> int:
    """Tasks the scheduler holds, once it has none or after 30 s (it forgets released keys a moment
    after the client that held them says so)."""
    with distributed.Client(address) as client:
        deadline = time.monotonic() + 30
        while (count := client.run_on_scheduler(lambda dask_scheduler: len(dask_scheduler.tasks))) and \
                time.monotonic() < deadline:
            time.sleep(0.05)
    return count


@pytest.fixture(scope="module")
def cluster():
    with distributed.LocalCluster(n_workers=1, threads_per_worker=1, processes=False,
                                  dashboard_address=":0") as local:
        yield local


def test_every_task_comes_back_with_its_label_and_one_job_serves_the_worker(cluster):
    tasks = [("a", (1.0,)), ("b", (2.0,)), ("a", (3.0,))]  # labels may repeat
    results = list(results_on_dask(tasks, cluster.scheduler_address, CountingJob(), run_counting))
    assert sorted((label, value) for label, (_, _, value) in results) == [("a", 2.0), ("a", 6.0), ("b", 4.0)]
    jobs = {job for _, (job, _, _) in results}
    assert len(jobs) == 1  # one worker: every task called the same job object
    assert sorted(calls for _, (_, calls, _) in results) == [1, 2, 3]  # its count carried from task to task


def test_nothing_is_scattered_and_the_plugin_is_gone_after_the_run(cluster):
    list(results_on_dask([(0, (1.0,))], cluster.scheduler_address, CountingJob(), run_counting))
    assert scheduler_tasks(cluster.scheduler_address) == 0
    with distributed.Client(cluster.scheduler_address) as client:
        plugins = client.run(lambda dask_worker: [n for n in dask_worker.plugins if n.startswith("presag-job-")])
    assert all(names == [] for names in plugins.values()), plugins


def wait_for_gate(job: CountingJob, value: int) -> int:
    """A task that returns once the cluster-wide event ``gate-<value>`` is set (or after 60 s)."""
    distributed.Event(f"gate-{value}").wait(60)
    return value


def test_stopping_early_cancels_the_tasks_not_yet_finished():
    """Four tasks run at once, each waiting for its own gate: the first gate opened gives the first
    result; closing the results then cancels the three still running (the scheduler forgets them)."""
    with distributed.LocalCluster(n_workers=1, threads_per_worker=4, processes=False,
                                  dashboard_address=":0") as local, distributed.Client(local) as client:
        try:
            results = results_on_dask([(i, (i,)) for i in range(4)], local.scheduler_address, CountingJob(),
                                      wait_for_gate)
            distributed.Event("gate-2", client=client).set()
            assert next(results) == (2, 2)
            results.close()
            assert scheduler_tasks(local.scheduler_address) == 0
        finally:
            for i in range(4):
                distributed.Event(f"gate-{i}", client=client).set()


def test_no_tasks_need_no_cluster():
    assert list(results_on_dask([], "tcp://127.0.0.1:1", CountingJob(), run_counting)) == []


def test_a_task_on_a_worker_without_the_job_says_so(cluster):
    with distributed.Client(cluster.scheduler_address) as client:
        future = client.submit(run_with_job, "presag-job-none", run_counting, runtime.current(), 1.0, pure=False)
        with pytest.raises(ModelError, match="has no job 'presag-job-none'"):
            future.result()


def test_the_plugin_holds_its_job():
    job = CountingJob()
    assert JobPlugin(job).job is job
    assert isinstance(JobPlugin(job), distributed.diagnostics.plugin.WorkerPlugin)


def test_without_distributed_the_run_says_what_to_install(monkeypatch):
    monkeypatch.setitem(sys.modules, "distributed", None)  # import distributed raises ImportError
    with pytest.raises(ModelError, match=r"needs Dask distributed: pip install 'presag-opt\[cluster\]'"):
        list(results_on_dask([(0, (1.0,))], "tcp://127.0.0.1:1", CountingJob(), run_counting))
