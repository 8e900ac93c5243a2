"""Worker processes stop with their parent: an error or an interrupt inside :func:`worker_pool`
kills the workers at once, and SIGTERM to the ``presag`` command stops it as Ctrl-C does, workers
and all."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from presag_opt.processes import WorkerPolicy, worker_pool

SCRIPT = Path(sys.executable).parent / "presag"
SMALL_STUDY = Path(__file__).parent / "studies" / "models" / "small_grid.toml"


def _stat(pid: int) -> list[str]:
    """The fields of ``/proc/PID/stat`` after the command name (state first); empty once it is gone."""
    try:
        return Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()
    except (FileNotFoundError, ProcessLookupError, IndexError):
        return []


def _alive(pid: int) -> bool:
    """Whether ``pid`` runs (a zombie counts as gone)."""
    fields = _stat(pid)
    return bool(fields) and fields[0] != "Z"


def _children(pid: int) -> list[int]:
    return [int(entry.name) for entry in Path("/proc").iterdir()
            if entry.name.isdigit() and (fields := _stat(int(entry.name))) and int(fields[1]) == pid]


def _kill(pids: list[int]) -> None:
    """SIGKILL each of ``pids`` that still runs (a test's processes, whatever happened)."""
    for pid in pids:
        try:
            os.kill(pid, signal.SIGKILL)
        except ProcessLookupError:
            pass


WORKING = 1.5
"""Processor time a worker (or the compile helper) has spent when the test stops its command: past its
start (imports, about 1 s) and inside a task. [s]"""


def _processor_seconds(pid: int) -> float:
    """User and system time ``pid`` has spent, 0 once it is gone. [s]"""
    fields = _stat(pid)
    return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK") if fields else 0.0


def _wait_until(condition, seconds: float) -> bool:
    deadline = time.monotonic() + seconds
    while time.monotonic() < deadline:
        if condition():
            return True
        time.sleep(0.05)
    return condition()


@pytest.mark.skipif(not Path("/proc").is_dir(), reason="reads the process table from /proc")
def test_an_error_inside_the_pool_kills_the_busy_workers():
    with pytest.raises(RuntimeError, match="given up"):
        with worker_pool(2, WorkerPolicy.PICKLED) as pool:
            futures = [pool.submit(time.sleep, 60) for _ in range(2)]
            assert _wait_until(lambda: all(f.running() for f in futures), 30), "the workers did not start"
            workers = [p.pid for p in pool._processes.values()]
            raise RuntimeError("given up")
    assert len(workers) == 2
    assert _wait_until(lambda: not any(_alive(pid) for pid in workers), 5), "a worker outlived its pool"


@pytest.mark.e2e
@pytest.mark.skipif(not Path("/proc").is_dir(), reason="reads the process table from /proc")
def test_sigterm_stops_a_sweep_and_its_workers(tmp_path):
    process = subprocess.Popen([str(SCRIPT), "sweep", str(SMALL_STUDY), "--out", str(tmp_path / "s.nc"),
                                "--workers", "2", "--quiet"], cwd=tmp_path, stdout=subprocess.PIPE,
                               stderr=subprocess.PIPE, text=True, start_new_session=True)
    try:
        # The pool's two spawned workers (and its resource tracker) are children of the command.
        assert _wait_until(lambda: len(_children(process.pid)) >= 3, 60), "the workers did not start"
        workers = _children(process.pid)  # stopped as they start: the pool lives about 3 s (see POOL_COMMANDS)
        process.send_signal(signal.SIGTERM)
        out, err = process.communicate(timeout=300)  # seconds normally; the bound is against a hang
        assert process.returncode == 130
        assert err.strip().splitlines()[-1] == "presag: interrupted", err
        assert _wait_until(lambda: not any(_alive(pid) for pid in workers), 10), "a worker outlived the command"
    finally:
        try:
            os.killpg(process.pid, signal.SIGKILL)
        except ProcessLookupError:
            pass


def _helpers(pid: int) -> list[int]:
    """The kernel compile helpers among the children of ``pid`` (not the C compiler's processes)."""
    found = []
    for child in _children(pid):
        try:
            if b"_helper_main" in Path(f"/proc/{child}/cmdline").read_bytes():
                found.append(child)
        except (FileNotFoundError, ProcessLookupError):
            pass
    return found


FIRST_SIMULATE = ["simulate", "--case", "case_study_st98", "--speed", "80", "--static-force", "100,120"]


@pytest.mark.e2e
@pytest.mark.skipif(not Path("/proc").is_dir() or (os.cpu_count() or 1) < 2,
                    reason="reads the process table from /proc; the helper needs two cores")
@pytest.mark.parametrize("stop", ["SIGTERM", "SIGKILL"])
def test_the_kernel_compile_helper_stops_with_its_command(stop, tmp_path):
    """The first dynamic command with an empty numba cache starts a helper that compiles half of the
    kernel (presag_opt.dynamics.batch.compilation). SIGTERM to the command: exit 130, one line, the
    helper gone and its compile lock free; SIGKILL: the helper exits alone within seconds."""
    import fcntl

    env = {**os.environ, "NUMBA_CACHE_DIR": str(tmp_path / "numba"), "XDG_CACHE_HOME": str(tmp_path / "xdg")}
    env.pop("PRESAG_NO_COMPILE", None)
    process = subprocess.Popen([str(SCRIPT), *FIRST_SIMULATE], cwd=tmp_path, env=env, stdout=subprocess.DEVNULL,
                               stderr=subprocess.PIPE, text=True, start_new_session=True)
    helpers: list[int] = []
    try:
        assert _wait_until(lambda: _helpers(process.pid), 120), "the helper did not start"
        helpers = _helpers(process.pid)
        assert _wait_until(lambda: max(_processor_seconds(pid) for pid in helpers) >= WORKING, 120), (
            "the helper did not compile")
        if stop == "SIGTERM":
            process.send_signal(signal.SIGTERM)
            _, err = process.communicate(timeout=120)
            assert process.returncode == 130
            assert err.strip().splitlines()[-1] == "presag: interrupted" and "Traceback" not in err, err
            assert not any(_alive(pid) for pid in helpers), "the helper outlived the command"
            for lock in (tmp_path / "numba").rglob("presag-kernel-*.lock"):
                with open(lock) as handle:
                    fcntl.flock(handle, fcntl.LOCK_EX | fcntl.LOCK_NB)  # raises if still held
        else:
            process.kill()
            process.wait(timeout=30)
            assert _wait_until(lambda: not any(_alive(pid) for pid in helpers), 5.0), "the helper outlived a SIGKILL"
    finally:
        _kill([process.pid, *helpers])


ROBUST_MODEL = Path(__file__).parent / "robust" / "models" / "st_9.8_six_short_spans.toml"

POOL_COMMANDS = {
    "sweep": (["sweep", str(SMALL_STUDY), "--out", "{tmp}/s.nc", "--workers", "2"], False),
    "recommend": (["recommend", "--models", "st_9.8_ideal,st_9.8_mixed", "--no-cache", "--elasticity-method",
                   "newton"], True),
    "elasticity": (["elasticity", "st_9.8_mixed", "--forces", "40,60,80,100,120,140,160,180,200,220,240,260"], True),
    "robust --dynamic": (["robust", str(ROBUST_MODEL), "--dynamic", "--grid-points", "2,2", "--workers", "2"], False),
}
"""Every command with a worker pool, with arguments that open one within seconds, and whether the test
kills the command only once a worker is inside a task (:data:`WORKING`) or as soon as the workers
start. Measured on an idle 2-core machine, each worker spends about 6 s of processor time in
``elasticity`` and minutes in ``recommend`` (the re-solved elasticity of the mixed section, without the
form-finding cache): far more than ``WORKING``. The small ``sweep`` (its form-findings cached) keeps its
pool for about 3 s, ``robust --dynamic`` for about 5 s, and ``recommend`` without the re-solved
elasticity kept it for 1.5 s; with a fixed two-second wait before the kill the test found such a pool
gone now and then. Killed as
their workers start, they check the start-up: a worker whose parent dies before it arms
``PR_SET_PDEATHSIG`` sees that it was re-parented and exits."""


@pytest.mark.e2e
@pytest.mark.skipif(not Path("/proc").is_dir(), reason="reads the process table from /proc")
@pytest.mark.parametrize("command", list(POOL_COMMANDS))
def test_workers_exit_within_seconds_of_a_sigkill_of_their_command(command, tmp_path):
    """SIGKILL cannot be caught, so the command cannot stop its pool: each worker must notice alone
    (PR_SET_PDEATHSIG on Linux, else its parent-watch thread within PARENT_POLL = 1 s)."""
    arguments, inside_a_task = POOL_COMMANDS[command]
    args = [a.format(tmp=tmp_path) for a in arguments]
    process = subprocess.Popen([str(SCRIPT), *args, "--quiet"], cwd=tmp_path, stdout=subprocess.DEVNULL,
                               stderr=subprocess.PIPE, start_new_session=True)
    workers: list[int] = []
    try:
        assert _wait_until(lambda: len(_children(process.pid)) >= 2, 120), "the workers did not start"
        workers = _children(process.pid)
        if inside_a_task:
            assert _wait_until(lambda: not all(_alive(pid) for pid in workers)
                               or max(_processor_seconds(pid) for pid in workers) >= WORKING, 120), "no worker worked"
        assert all(_alive(pid) for pid in workers), f"{command}: the pool ended before the kill; give it more work"
        process.kill()
        process.wait(timeout=30)
        assert _wait_until(lambda: not any(_alive(pid) for pid in workers), 5.0), (
            f"{command}: {sum(_alive(pid) for pid in workers)} of {len(workers)} workers outlived a SIGKILL by 5 s")
    finally:
        _kill([process.pid, *workers])


def test_the_policy_alone_chooses_the_start_method(monkeypatch):
    import multiprocessing

    from presag_opt.errors import ModelError
    from presag_opt.processes import WorkerPolicy, pool_available, start_method

    monkeypatch.setattr(multiprocessing, "get_all_start_methods", lambda: ["fork", "spawn", "forkserver"])
    assert [start_method(p) for p in WorkerPolicy] == ["spawn", "fork", "fork"]
    assert pool_available(WorkerPolicy.INHERITED)
    monkeypatch.setattr(multiprocessing, "get_all_start_methods", lambda: ["spawn"])  # as on Windows
    assert start_method(WorkerPolicy.PICKLED) == start_method(WorkerPolicy.FAST_START) == "spawn"
    assert not pool_available(WorkerPolicy.INHERITED)
    with pytest.raises(ModelError, match="needs worker processes started with fork"):
        start_method(WorkerPolicy.INHERITED)


def test_no_call_site_outside_processes_chooses_a_start_method():
    package = Path(__file__).resolve().parents[1] / "presag_opt"
    offenders = [str(path.relative_to(package)) for path in package.rglob("*.py") if path.name != "processes.py"
                 and any(word in path.read_text() for word in ("get_context(", "get_all_start_methods", "mp_context"))]
    assert offenders == []


def _blas_threads() -> list[int]:
    import numpy  # noqa: F401 (loads numpy's BLAS)
    import scipy.sparse.linalg  # noqa: F401 (and scipy's)
    from threadpoolctl import threadpool_info

    return [pool["num_threads"] for pool in threadpool_info() if pool["user_api"] == "blas"]


@pytest.mark.parametrize("policy", [WorkerPolicy.FAST_START, WorkerPolicy.PICKLED])
def test_a_worker_runs_its_linear_algebra_on_one_thread(policy):
    """Each worker's BLAS libraries (numpy's and scipy's) are limited to one thread, forked or spawned."""
    with worker_pool(2, policy) as pool:
        threads = pool.submit(_blas_threads).result()
    assert len(threads) >= 1 and set(threads) == {1}


@pytest.fixture
def ctrl_c_raises():
    """Ctrl-C raises KeyboardInterrupt here, as in a terminal: a test run started in the background by a
    non-interactive shell inherits SIGINT ignored."""
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    yield
    signal.signal(signal.SIGINT, previous)


def test_held_interrupts_arrive_when_the_block_ends(ctrl_c_raises):
    from presag_opt.processes import interrupts_held

    reached = []
    with pytest.raises(KeyboardInterrupt), interrupts_held():
        signal.raise_signal(signal.SIGINT)
        reached.append("after the signal")  # the block runs to its end
    assert reached == ["after the signal"]
    assert signal.getsignal(signal.SIGINT) is signal.default_int_handler  # the handler is back
    with interrupts_held():  # nothing arrives: nothing is raised
        pass
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    with interrupts_held():  # an ignored signal stays ignored
        signal.raise_signal(signal.SIGINT)
    assert signal.getsignal(signal.SIGINT) is signal.SIG_IGN


def test_an_interrupt_while_a_worker_starts_leaves_no_half_started_worker(monkeypatch, ctrl_c_raises):
    """The interrupt arrives as a spawned worker starts (here: just before, raised in the main thread).
    Held back, it is raised once the worker is started and registered, and the worker is killed (exit by
    SIGKILL). Delivered at once, it broke the hand-over of the worker's start-up data, and the worker died
    on the closed pipe printing a traceback."""
    import multiprocessing.process

    started = []
    original = multiprocessing.process.BaseProcess.start

    def start_interrupted(process):
        started.append(process)
        signal.raise_signal(signal.SIGINT)
        original(process)

    monkeypatch.setattr(multiprocessing.process.BaseProcess, "start", start_interrupted)
    with pytest.raises(KeyboardInterrupt), worker_pool(1, WorkerPolicy.PICKLED) as pool:
        pool.submit(os.getpid)
    monkeypatch.undo()
    (worker,) = started
    worker.join(30)  # an event: the worker's exit
    assert worker.exitcode == -signal.SIGKILL
