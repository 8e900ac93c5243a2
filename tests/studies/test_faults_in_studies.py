"""Faults inside a running study: a Dask worker process killed mid-study, a unit that raises
``MemoryError`` in its worker, and two commands on one store at once.

Every finished store is compared byte for byte with an undisturbed run of the same small study.
"""

from __future__ import annotations

import os
import signal
import socket
import subprocess
import sys
import threading
import time
from pathlib import Path

import numpy as np
import pytest

from presag_opt.errors import ModelError
from presag_opt.studies import work
from presag_opt.studies.definition import load_study
from presag_opt.studies.runner import run_study
from presag_opt.studies.store import LOCK, hold_store, open_store, units_directory

SCRIPT = Path(sys.executable).parent / "presag"
STUDY = Path(__file__).parent / "models" / "small_grid.toml"


@pytest.fixture(scope="module")
def study():
    return load_study(STUDY)


@pytest.fixture(scope="module")
def reference(study, tmp_path_factory) -> bytes:
    """The bytes of the small study's store, undisturbed."""
    path = tmp_path_factory.mktemp("reference") / "study.nc"
    run_study(study, path, workers=1)
    return path.read_bytes()


@pytest.mark.e2e
@pytest.mark.parametrize("killed", ["one worker", "every worker"])
def test_a_dask_worker_killed_mid_study_changes_no_byte(study, reference, tmp_path, killed):
    """SIGKILL of the busy worker, or of both, 0.5 s into a unit: the nannies restart them and the
    scheduler runs the lost units again. With every worker killed, anything that lived only on the
    workers (data scattered to them) is gone for certain; the tasks must not depend on it."""
    distributed = pytest.importorskip("distributed")
    store = tmp_path / "dask.nc"
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                  dashboard_address=":0") as cluster, distributed.Client(cluster) as client:
        pids = client.run(os.getpid)  # worker address -> pid of the worker process (its nanny restarts it)
        errors: list[BaseException] = []

        def run() -> None:
            try:
                run_study(study, store, scheduler=cluster.scheduler_address)
            except BaseException as exc:  # noqa: BLE001 - reported by the assertion below
                errors.append(exc)

        thread = threading.Thread(target=run)
        thread.start()
        deadline = time.monotonic() + 120
        busy = []
        while not busy and time.monotonic() < deadline:
            busy = [address for address, keys in client.processing().items() if keys]
            time.sleep(0.05)
        assert busy, "no Dask worker picked up a unit within 120 s"
        time.sleep(0.5)  # inside the unit, not at its start
        victims = [pids[busy[0]]] if killed == "one worker" else list(pids.values())
        for pid in victims:
            os.kill(pid, signal.SIGKILL)
        thread.join(timeout=300)
        assert not thread.is_alive(), "the study did not finish after the worker was killed"
        assert not set(victims) & set(client.run(os.getpid).values()), "a killed worker process still runs"
    assert not errors, errors
    assert not units_directory(store).joinpath(LOCK).exists()
    assert store.read_bytes() == reference


def test_a_memory_error_inside_a_worker_fails_its_runs_and_the_study_goes_on(study, tmp_path, monkeypatch):
    """A threaded in-process Dask cluster runs the real runner, so that the patched batch is the one the
    worker calls: the first batch raises MemoryError as an allocation too large for the machine would."""
    distributed = pytest.importorskip("distributed")
    real = work.simulate_many
    calls = []
    lock = threading.Lock()

    def simulate_many(*args, **kwargs):
        with lock:
            calls.append(1)
            first = len(calls) == 1
        if first:
            raise MemoryError("Unable to allocate 48.0 GiB for an array with shape (6, 1000000000)")
        return real(*args, **kwargs)

    monkeypatch.setattr(work, "simulate_many", simulate_many)
    store = tmp_path / "memory.nc"
    with distributed.LocalCluster(n_workers=1, threads_per_worker=1, processes=False,
                                  dashboard_address=":0") as cluster:
        outcome = run_study(study, store, scheduler=cluster.scheduler_address)
    ds = open_store(store)
    # One task (one pre-sag, both speeds, both forces) failed; the other pre-sag's four runs finished.
    assert outcome.units_computed == 4 and outcome.runs_failed == 4
    failed = ds["failed"].values
    assert failed.sum() == 4 and (failed.all(axis=(1, 2)) | ~failed.any(axis=(1, 2))).all()
    reasons = set(ds["failure"].values[failed])
    assert reasons == {"simulation: MemoryError: Unable to allocate 48.0 GiB for an array with shape (6, 1000000000)"}
    assert np.isnan(ds["sigma"].values[failed]).all() and np.isfinite(ds["sigma"].values[~failed]).all()


@pytest.mark.e2e
def test_two_sweeps_on_one_store_one_refuses_and_neither_corrupts_it(reference, tmp_path):
    out = tmp_path / "study.nc"
    command = [str(SCRIPT), "sweep", str(STUDY), "--out", str(out), "--workers", "1", "--quiet"]
    first = subprocess.Popen(command, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        lock = units_directory(out) / LOCK
        deadline = time.monotonic() + 60
        while not lock.exists():
            assert first.poll() is None and time.monotonic() < deadline, "the first sweep took no lock"
            time.sleep(0.02)
        second = subprocess.run(command, capture_output=True, text=True, timeout=120, check=False)
        _, err_first = first.communicate(timeout=300)
    finally:
        first.kill()
    assert second.returncode == 2
    assert second.stderr.strip() == (
        f"presag: error: {out}: another presag sweep (pid {first.pid}) is running this study; wait for it to "
        f"finish (or stop it) and run again — finished units are kept (lock {lock})")
    assert first.returncode == 0, err_first
    assert out.read_bytes() == reference
    assert not lock.exists()


def test_a_lock_left_by_a_killed_command_is_taken_over(tmp_path):
    store = tmp_path / "study.nc"
    units_directory(store).mkdir()
    dead = subprocess.Popen([sys.executable, "-c", "pass"])
    dead.wait()
    (units_directory(store) / LOCK).write_text(f"{dead.pid}@{socket.gethostname()}")
    with hold_store(store):
        assert (units_directory(store) / LOCK).read_text().startswith(f"{os.getpid()}@")
        with pytest.raises(ModelError, match=rf"another presag sweep \(pid {os.getpid()}\) is running this study"):
            with hold_store(store):
                pass
    assert not (units_directory(store) / LOCK).exists()
