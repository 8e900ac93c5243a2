"""The runtime (:mod:`presag_opt.runtime`): scoped to its ``with`` block, handed to worker processes
whatever their start method, and a command run in-process leaves nothing of its own behind."""

from __future__ import annotations

import pickle
import signal
import threading

import pytest

from presag_opt import runtime
from presag_opt.processes import WorkerMemo, WorkerPolicy, run_job, worker_pool
from presag_opt.runtime import Runtime


def test_a_runtime_is_in_force_inside_its_block_only(tmp_path, test_runtime):
    assert runtime.current() == test_runtime
    inner = test_runtime.replace(state_cache=tmp_path, compile=False)
    with inner:
        assert runtime.current() == inner
        with inner.replace(state_cache=None) as innermost:
            assert runtime.current() is innermost
        assert runtime.current() == inner
    assert runtime.current() == test_runtime


def test_another_thread_starts_from_the_environment(tmp_path, test_runtime):
    seen = []
    with test_runtime.replace(state_cache=tmp_path):
        thread = threading.Thread(target=lambda: seen.append(runtime.current()))
        thread.start()
        thread.join()
    assert seen[0].state_cache is None  # a new thread's context holds no runtime: the library's default


def test_a_runtime_is_frozen_and_pickles(tmp_path):
    settings = Runtime(state_cache=tmp_path, compile=False, library_folder=tmp_path / "lib", debug=True)
    assert pickle.loads(pickle.dumps(settings)) == settings
    with pytest.raises(AttributeError):
        settings.compile = True  # frozen


@pytest.mark.parametrize("policy", [WorkerPolicy.PICKLED, WorkerPolicy.FAST_START], ids=["spawn", "fork"])
def test_workers_run_in_the_runtime_of_the_pool_that_started_them(policy, tmp_path, test_runtime):
    """Spawned (pickled) or forked (inherited), a worker caches and compiles as its parent does."""
    settings = test_runtime.replace(state_cache=tmp_path / "states", compile=False)
    with settings, worker_pool(2, policy) as pool:
        seen = [f.result() for f in [pool.submit(runtime.current) for _ in range(4)]]
    assert seen == [settings] * 4


class _Counter:
    """A job that counts its calls in its own memo (one per worker)."""

    def __init__(self):
        self.memo = WorkerMemo(1)

    def __call__(self, value):
        calls = self.memo.get("calls", lambda: [])
        calls.append(value)
        return len(calls)


def test_a_jobs_memo_lives_as_long_as_its_worker(test_runtime):
    with worker_pool(1, WorkerPolicy.PICKLED, job=_Counter()) as pool:
        counts = [pool.submit(run_job, i).result() for i in range(3)]
    assert counts == [1, 2, 3]  # one worker: its job kept the memo from task to task
    job = _Counter()
    assert [job(i) for i in range(2)] == [1, 2]
    assert len(pickle.loads(pickle.dumps(job.memo))) == 0  # the memo travels empty


def test_the_memo_keeps_the_most_recent_entries():
    memo = WorkerMemo(2)
    computed = []
    for key in ("a", "b", "a", "c", "b"):
        memo.get(key, lambda k=key: computed.append(k) or k.upper())
    assert computed == ["a", "b", "c", "b"]  # "a" was recent when "c" came; "b" was not


def test_a_command_in_process_leaves_nothing_behind(presag, tmp_path, test_runtime):
    handler = signal.getsignal(signal.SIGTERM)
    ideal = ("--models", "st_9.8_ideal", "--max-speed", "260", "--allow-supercritical", "--json")
    ran = presag("recommend", *ideal, "--no-cache", cwd=tmp_path)
    assert ran.returncode == 0, ran.stderr
    assert ran.stderr.count("presag: warning: speed ratio β = 0.75 exceeds 0.7") == 1
    assert signal.getsignal(signal.SIGTERM) is handler  # the command's SIGTERM handler is gone
    assert runtime.current() == test_runtime  # and so is its runtime (--no-cache)
    again = presag("recommend", *ideal, cwd=tmp_path)
    assert again.stderr == ran.stderr  # each warning shown once per command, not once per process
