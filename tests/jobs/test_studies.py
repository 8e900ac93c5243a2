"""The study jobs (presag_opt.jobs.studies) and the refusals the jobs share: a supercritical speed refused in the
designer's units before any work, a missing study store in one line."""

from __future__ import annotations

import time

import pytest

from presag_opt import OperatingBand, simulate, tolerance, validity
from presag_opt.errors import ModelError


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
