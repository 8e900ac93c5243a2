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
    assert speed.validity.verdict == "holds"


def test_the_speed_context_states_the_one_validity_statement():
    """No warning of its own: the band's validity is the statement every command prints
    (presag_opt.design.validity_limit), here against the paper's limit 0.35–0.40."""
    wire = load_catenary("st_9.8_ideal").contact_wire
    crossing = speed_context(wire, 50 * KMH, 160 * KMH)
    assert crossing.validity.verdict == "beyond" and crossing.validity.beta_max == pytest.approx(crossing.beta_max)
    assert "121–138 km/h" in crossing.validity.sentence()
    at = speed_context(wire, 0.0, 130 * KMH)
    assert at.validity.verdict == "at the limit"
    assert speed_context(wire, 0.0, 90 * KMH).to_dict()["validity"]["verdict"] == "holds"


def test_speed_at_the_wave_speed_is_an_error():
    wire = load_catenary("st_9.8_ideal").contact_wire
    with pytest.raises(ModelError, match=r"speed = .* km/h is outside the valid range"):
        speed_context(wire, 0.0, wire.wave_speed)
