"""Operating band, mean contact force and force levels (presag_opt.design.band)."""

from __future__ import annotations

import pytest

from presag_opt.design import CASE_STUDY_BAND, KMH, OperatingBand, force_levels_for_band, mean_contact_force
from presag_opt.errors import ModelError


def test_case_study_band_gives_the_papers_mean_force_band():
    low, high = CASE_STUDY_BAND.mean_force_band()
    # 140 N + 0.00097 N/(km/h)² · (90 km/h)² = 147.857 N, the paper's "70–148 N"; exact arithmetic.
    assert low == pytest.approx(70.0, abs=1e-12)
    assert high == pytest.approx(147.857, abs=1e-9)
    assert float(mean_contact_force(100.0, 50.0 * KMH, 0.001 / KMH**2)) == pytest.approx(102.5, rel=1e-12)


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        (dict(static_force_low=150.0, static_force_high=70.0), r"static_force_low = 150 N is above static_force_high"),
        (dict(speed_low=100 * KMH, speed_high=50 * KMH), r"speed_low = 100 km/h is above speed_high = 50 km/h"),
        (dict(static_force_low=0.0), r"static_force_low = 0 N is outside the valid range \(0, 1000\] N"),
        (dict(aero_coefficient=-1e-3 / KMH**2), r"aero_coefficient = -0.001 N/\(km/h\)\^2 is outside"),
    ],
)
def test_operating_band_rejects_bad_input(kwargs, message):
    full = dict(static_force_low=70.0, static_force_high=140.0, speed_high=90 * KMH, aero_coefficient=0.00097 / KMH**2)
    with pytest.raises(ModelError, match=message):
        OperatingBand(**{**full, **kwargs})


@pytest.mark.parametrize(
    ("band", "levels"),
    [((70.0, 147.857), (50.0, 100.0, 150.0)), ((30.0, 100.0), (30.0, 50.0, 100.0)), ((100.0, 100.0), (100.0,))],
)
def test_force_levels_bracket_the_band(band, levels):
    assert force_levels_for_band(*band) == levels
