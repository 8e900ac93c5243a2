"""``presag_opt.dynamics.results``: the named results of a run and of a batch, and the one ``--json``
summary both give (user units in the key names: km/h, mm, ms, %; spans counted from 1)."""

from __future__ import annotations

import numpy as np
import pytest

from presag_opt.dynamics.results import BatchResult, RunOutcome
from presag_opt.dynamics.settings import OperatingPoint, SimulationSettings
from presag_opt.dynamics.statistics import contact_force_statistics
from presag_opt.units import KMH

TIME = np.arange(0.0, 4.0, 1e-3)
POINT = OperatingPoint(speed=180 * KMH, static_force=120.0, aero_coefficient=0.00097 / KMH**2)


def _statistics(mean: float, amplitude: float):
    """A 2 Hz sine about ``mean``: σ = amplitude/√2 (well below the 20 Hz cut-off, over whole periods)."""
    return contact_force_statistics(TIME, mean + amplitude * np.sin(2 * np.pi * 2.0 * TIME), window_start=1.0,
                                    window_end=3.0)


def _outcome(**changes) -> RunOutcome:
    fields = dict(point=POINT, statistics=(_statistics(151.4, 30.0),), uplift_max=0.0421, slack_droppers_max=3,
                  speed_ratio=0.52, doppler_factor=0.316, wave_speed=345 * KMH, analysed_spans=(4, 5),
                  analysed_section=(240.0, 360.0), newton_iterations=7, wall_time=1.25, time_step=2e-3,
                  warnings=("coarse",))
    fields.update(changes)
    return RunOutcome(**fields)


def test_a_run_summary_is_in_user_units_with_spans_counted_from_one():
    out = _outcome().to_dict(catenary="ST 9,8/9,8", pantograph="2-mass")
    assert out["speed_kmh"] == pytest.approx(180.0, rel=1e-12)
    assert out["aero_force_N"] == pytest.approx(0.00097 * 180.0**2, rel=1e-12)
    assert out["uplift_max_mm"] == pytest.approx(42.1, rel=1e-12)
    assert out["wave_speed_kmh"] == pytest.approx(345.0, rel=1e-12)
    assert out["time_step_ms"] == pytest.approx(2.0, rel=1e-12)
    assert out["analysed_spans"] == [5, 6] and out["analysed_section_m"] == [240.0, 360.0]
    assert out["Fm_N"] == pytest.approx(151.4, rel=1e-9)
    assert out["sigma_N"] == pytest.approx(30.0 / np.sqrt(2.0), rel=1e-3)  # a sampled sine: σ to 0.1 %
    assert (out["slack_droppers_max"], out["warnings"], out["pantograph"]) == (3, ["coarse"], "2-mass")
    assert "error" not in out and "pantographs" not in out


def test_a_failed_run_keeps_its_point_and_reason_but_no_statistics():
    failed = _outcome(statistics=(), uplift_max=float("nan"), error="Newton did not converge at t = 1.2 s")
    assert not failed.ok and _outcome().ok
    out = failed.to_dict(catenary="c", pantograph="p")
    assert out["error"] == "Newton did not converge at t = 1.2 s"
    assert not {"Fm_N", "sigma_N", "uplift_max_mm", "slack_droppers_max"} & set(out)
    assert out["speed_kmh"] == pytest.approx(180.0, rel=1e-12)


def test_a_train_lists_each_pantograph_with_its_offset_and_its_own_statistics():
    two = _outcome(statistics=(_statistics(151.4, 30.0), _statistics(140.0, 10.0)), offsets=(0.0, 200.0))
    out = two.to_dict(catenary="c", pantograph=("front", "rear"))
    assert out["pantograph"] == "front" and out["Fm_N"] == pytest.approx(151.4, rel=1e-9)  # the leading one
    assert [(p["name"], p["offset_m"]) for p in out["pantographs"]] == [("front", 0.0), ("rear", 200.0)]
    assert out["pantographs"][1]["sigma_N"] == pytest.approx(10.0 / np.sqrt(2.0), rel=1e-3)
    assert [p["name"] for p in two.to_dict(catenary="c", pantograph="same")["pantographs"]] == ["same", "same"]


def test_a_batch_counts_its_failed_runs_and_lists_every_run_in_order():
    runs = (_outcome(), _outcome(statistics=(), error="failed"), _outcome(point=OperatingPoint(speed=20.0,
                                                                                                static_force=90.0)))
    batch = BatchResult(catenary_name="c", pantograph_names=("p",), runs=runs, wall_time=3.0,
                        settings=SimulationSettings())
    assert batch.failed == (runs[1],)
    out = batch.to_dict()
    assert (out["failed_runs"], out["wall_time_s"], out["pantographs"]) == (1, 3.0, ["p"])
    assert [r["speed_kmh"] for r in out["runs"]] == pytest.approx([180.0, 180.0, 72.0], rel=1e-12)
    assert out["runs"][1]["error"] == "failed"
