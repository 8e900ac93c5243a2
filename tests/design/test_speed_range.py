"""Speed context (presag_opt.design.speed_range): β = 0.26 at 90 km/h on ST 9,8/9,8 (section 5.2)."""

from __future__ import annotations

import pytest

from presag_opt.design import KMH, speed_context
from presag_opt.errors import ModelError
from presag_opt.system.loader import load_catenary


def test_beta_at_90_kmh_on_st98_is_026():
    speed = speed_context(load_catenary("st_9.8_ideal").contact_wire, 0.0, 90 * KMH)
    assert speed.beta_max == pytest.approx(0.26, abs=0.01)  # the paper's value, printed to 0.01
    assert speed.doppler_factor_min == pytest.approx((1 - speed.beta_max) / (1 + speed.beta_max), rel=1e-12)
    assert speed.quasi_static_valid and not speed.warnings


def test_speed_band_crossing_the_limit_warns():
    wire = load_catenary("st_9.8_ideal").contact_wire
    crossing = speed_context(wire, 50 * KMH, 160 * KMH)
    assert not crossing.quasi_static_valid
    assert "crosses β = 0.4 at 138 km/h" in crossing.warnings[0]
    above = speed_context(wire, 150 * KMH, 200 * KMH)
    assert "lies above β = 0.4" in above.warnings[0]


def test_speed_at_the_wave_speed_is_an_error():
    wire = load_catenary("st_9.8_ideal").contact_wire
    with pytest.raises(ModelError, match=r"speed = .* km/h is outside the valid range"):
        speed_context(wire, 0.0, wire.wave_speed)
