"""The tolerance job (presag_opt.jobs.installation_tolerance): the interval, the quasi-static Monte Carlo and the
dropper-tolerance search from one robust study, in mm; refusals in the job's keywords before any work."""

from __future__ import annotations

import time

import pytest

from presag_opt import tolerance
from presag_opt.errors import ModelError


def test_the_monte_carlo_shows_its_percentiles_in_mm():
    answer = tolerance(dropper_error_mm=2.0, samples=400, seed=3)
    result = answer.monte_carlo
    assert result.errors.dropper_length == pytest.approx(2e-3, rel=1e-12) and result.samples == 400
    rows = answer.table()
    assert [r[""] for r in rows] == ["error-free", "P50", "P90", "P95", "P99"]
    assert rows[3]["value [mm]"] == pytest.approx(result.percentiles[95].value * 1e3, rel=1e-12)
    assert rows[0]["value [mm]"] <= rows[1]["value [mm]"] <= rows[3]["value [mm]"]  # errors only add waviness
    assert "P95" in answer._repr_html_() and list(answer.to_frame().columns) == list(rows[0])
    # the design examined is the robust parabola of the band, and the interval is the study's
    assert answer.presag_rel == answer.study.robust_parabola.presag_rel
    assert answer.to_dict()["s_interval_mm"][0] == pytest.approx(
        answer.study.tolerance.low * answer.study.reference_span * 1e3, rel=1e-12)


def test_without_errors_the_answer_is_the_interval_and_the_same_study_serves_the_monte_carlo():
    interval = tolerance(within_percent=5.0)
    assert interval.monte_carlo is None and interval.study.tolerance.within == pytest.approx(0.05)
    assert interval.to_dict()["tolerance_mm"][0] < interval.presag_mm < interval.to_dict()["tolerance_mm"][1]
    assert "interval within 5 %" in interval._repr_html_()
    with pytest.raises(ModelError, match="no Monte Carlo"):
        interval.worst_cases()
    found = tolerance(find_dropper_tolerance=True, samples=400, within_percent=5.0)
    assert found.dropper_tolerance is not None and found.monte_carlo is found.dropper_tolerance.at_tolerance
    assert found.study.tolerance.low == pytest.approx(interval.study.tolerance.low, rel=1e-9)


@pytest.mark.parametrize(("keywords", "message"), [
    ({"dropper_error_mm": 101.0}, r"dropper_error_mm = 101 mm is outside the valid range \[0, 100\] mm"),
    ({"dropper_error_mm": 2.0, "samples": 0}, r"samples = 0 is outside the valid range \[1, 1e\+06\]"),
    ({"dropper_error_mm": 2.0, "samples": 2.5}, "samples = 2.5 is not a whole number"),
    ({"find_dropper_tolerance": True, "dynamic": True}, "find_dropper_tolerance is quasi-static"),
    ({"find_dropper_tolerance": True, "dropper_error_mm": 2.0}, "searches the dropper error"),
    ({"dynamic": True}, "needs dropper_error_mm"),
])
def test_the_tolerance_job_refuses_bad_keywords_before_any_work(keywords, message):
    started = time.monotonic()
    with pytest.raises(ModelError, match=message):
        tolerance(**keywords)
    assert time.monotonic() - started < 5  # no form-finding


def test_the_height_error_is_read_in_mm_for_both_wires():
    """A unit slip here (cm read as mm) passed every tier once (planted-fault runs): the sizes are pinned
    in metres, and a mast height error alone makes the design wavier than error-free."""
    answer = tolerance(dropper_error_mm=0.0, height_error_mm=2.0, samples=400, seed=1)
    errors = answer.monte_carlo.errors
    assert errors.contact_wire_height == pytest.approx(2e-3, rel=1e-12)
    assert errors.messenger_height == pytest.approx(2e-3, rel=1e-12) and errors.dropper_length == 0.0
    assert answer.to_dict()["height_error_mm"] == pytest.approx(2.0, rel=1e-12)
    assert answer.monte_carlo.percentiles[50].value > answer.monte_carlo.nominal_worst_case
