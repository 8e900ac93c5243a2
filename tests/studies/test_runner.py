"""Running a study end to end: results, determinism across workers and schedulers, resume after SIGKILL.

All tests share one uninterrupted run of the 2 x 2 x 2 test study (5-span catenary, coarse numerics,
speeds 140 and 180 km/h: a few seconds of simulation).
"""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

from presag_opt.studies.definition import load_study
from presag_opt.studies.runner import run_study
from presag_opt.studies.store import open_store, units_directory


@pytest.fixture(scope="module")
def small_study(small_study_path):
    return load_study(small_study_path)


@pytest.fixture(scope="module")
def reference_store(small_study, tmp_path_factory) -> Path:
    """The test study run once, uninterrupted, with two local workers."""
    store = tmp_path_factory.mktemp("reference") / "study.nc"
    outcome = run_study(small_study, store, workers=2, progress=None)
    assert outcome.units_computed == outcome.units_total == 4
    return store


def assert_same_store(actual: Path, expected: Path) -> None:
    """Identical datasets (readable diff first), then identical files byte for byte."""
    xr.testing.assert_identical(open_store(actual), open_store(expected))
    assert actual.read_bytes() == expected.read_bytes()


def test_small_study_runs_end_to_end(small_study, reference_store):
    ds = open_store(reference_store)
    assert ds["sigma"].dims == ("presag", "speed", "static_force")
    assert ds["sigma"].shape == (2, 2, 2)
    assert not ds["failed"].any(), ds["failure"].values
    assert ds.attrs["study_hash"] == small_study.digest()
    # The mean contact force equals the mean uplift force F_stat + alpha v^2 up to the friction and
    # the window's incomplete periods: within 3 % here (coarse mesh, one analysed span).
    np.testing.assert_allclose(ds["F_m"], ds["F_m_nominal"].broadcast_like(ds["F_m"]), rtol=0.03)
    # Statistics are derived from F_m and sigma by definition (EN 50367): exact up to rounding.
    np.testing.assert_allclose(ds["stat_max"], ds["F_m"] + 3 * ds["sigma"], rtol=1e-12)
    np.testing.assert_allclose(ds["sigma_over_F_m"], ds["sigma"] / ds["F_m"], rtol=1e-15)
    # beta = v / c with c = sqrt(9.8 kN / 1.07 kg/m) = 95.70 m/s.
    np.testing.assert_allclose(ds["beta"].isel(presag=0), ds["speed"] / np.sqrt(9800 / 1.07), rtol=1e-12)
    # The Delta-e rule grows with F_m (S = F_m * delta_e, delta_e about 0.55-0.6 mm/N on ST 9,8/9,8).
    rule_per_newton = ds["presag_delta_e"] / ds["F_m_nominal"]
    assert float(rule_per_newton.min()) > 0.4e-3 and float(rule_per_newton.max()) < 0.8e-3
    assert np.all(ds["uplift_max"] > 0.0)


def test_rerun_skips_finished_units_and_rewrites_the_same_store(small_study, reference_store, tmp_path):
    store = tmp_path / "study.nc"
    store.write_bytes(reference_store.read_bytes())
    units = units_directory(reference_store)
    copy = units_directory(store)
    copy.mkdir()
    for f in units.iterdir():
        (copy / f.name).write_bytes(f.read_bytes())
    outcome = run_study(small_study, store, workers=1, progress=None)
    assert outcome.units_computed == 0
    assert_same_store(store, reference_store)


@pytest.mark.e2e
def test_sigkill_then_resume_with_another_worker_count_gives_the_uninterrupted_store(small_study_path, small_study, reference_store, tmp_path):
    store = tmp_path / "killed.nc"
    units = units_directory(store)
    script = (
        "import sys\n"
        "from presag_opt.studies.definition import load_study\n"
        "from presag_opt.studies.runner import run_study\n"
        "if __name__ == '__main__':\n"
        "    run_study(load_study(sys.argv[1]), sys.argv[2], workers=1, progress=None)\n"
    )
    # A session of its own, so that the orphaned pool worker can be ended by its group after the kill.
    proc = subprocess.Popen([sys.executable, "-c", script, str(small_study_path), str(store)],
                            start_new_session=True)
    try:
        deadline = time.monotonic() + 120
        while not any(p.name != "study.json" and p.suffix == ".json" for p in units.glob("*.json")):
            assert proc.poll() is None, "the study finished or died before a unit was stored"
            assert time.monotonic() < deadline, "no unit stored within 120 s"
            time.sleep(0.05)
        os.kill(proc.pid, signal.SIGKILL)
        proc.wait(timeout=30)
    finally:
        try:
            os.killpg(proc.pid, signal.SIGKILL)
        except ProcessLookupError:
            pass
    assert proc.returncode == -signal.SIGKILL
    stored = {p.name for p in units.glob("*.json")} - {"study.json"}
    assert 1 <= len(stored) < 4, "the kill should come after the first and before the last unit"
    assert not store.exists()
    # Resumed with one worker: the reference ran with two, so this also shows the worker count does
    # not change a bit.
    outcome = run_study(small_study, store, workers=1, progress=None)
    assert outcome.units_computed == 4 - len(stored)
    assert_same_store(store, reference_store)


@pytest.mark.e2e
def test_dask_local_cluster_gives_the_same_store(small_study, reference_store, tmp_path):
    distributed = pytest.importorskip("distributed")
    store = tmp_path / "dask.nc"
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                  dashboard_address=":0") as cluster:
        run_study(small_study, store, scheduler=cluster.scheduler_address, progress=None)
    assert_same_store(store, reference_store)


@pytest.mark.slow
def test_paper_grid_runs_and_is_analysed(tmp_path):
    """The full 400-run study (tens of minutes with today's engine): every run finishes and the analysis
    gives its verdict at every speed of the grid."""
    from presag_opt.studies.validity_analysis import validity_analysis

    store = tmp_path / "paper.nc"
    outcome = run_study(load_study("paper_grid_st98"), store, workers=2, progress=None)
    assert outcome.runs_total == 400 and outcome.runs_failed == 0
    result = validity_analysis(open_store(store))
    assert len(result.per_beta) == 10 and result.criterion
    assert result.uplift is not None
