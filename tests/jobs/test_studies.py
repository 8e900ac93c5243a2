"""The study jobs (presag_opt.jobs.studies): the Monte Carlo in mm, refusals in the designer's units before any
work, the Monte Carlo summary in a notebook."""

from __future__ import annotations

import time

import pytest

from presag_opt import OperatingBand, simulate, tolerance, validity
from presag_opt.errors import ModelError


def test_the_monte_carlo_shows_its_percentiles_in_mm():
    result = tolerance(dropper_error_mm=2.0, samples=400, seed=3)
    assert result.errors.dropper_length == pytest.approx(2e-3, rel=1e-12) and result.samples == 400
    rows = result.table()
    assert [r[""] for r in rows] == ["error-free", "P50", "P90", "P95", "P99"]
    assert rows[3]["value [mm]"] == pytest.approx(result.percentiles[95].value * 1e3, rel=1e-12)
    assert rows[0]["value [mm]"] <= rows[1]["value [mm]"] <= rows[3]["value [mm]"]  # errors only add waviness
    assert "P95" in result._repr_html_() and list(result.to_frame().columns) == list(rows[0])


def test_a_supercritical_speed_is_refused_before_any_work():
    band = OperatingBand.from_kmh(static_force=(70, 140), speed_kmh=300, aero_coefficient_kmh=0.00097)
    started = time.monotonic()
    with pytest.raises(ModelError, match="allow_supercritical=True"):
        tolerance(band=band, dropper_error_mm=2.0)
    with pytest.raises(ModelError, match="speed = 300 km/h is β = "):
        simulate("st_9.8_ideal", "case_study_2mass_friction", speed_kmh=300, static_force=100)
    assert time.monotonic() - started < 5  # no form-finding


def test_a_missing_study_store_is_one_line(tmp_path):
    with pytest.raises(ModelError) as caught:
        validity(tmp_path / "missing.nc")
    assert "missing.nc" in str(caught.value) and "\n" not in str(caught.value)
