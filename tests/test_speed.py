"""``presag_opt.speed``: the wave speed c = sqrt(T/ρ), the speed ratio β = v/c with its EN 50119 limit
0.7 (a warning in the API, a refusal on design commands unless accepted) and the Doppler factor."""

from __future__ import annotations

import warnings

import pytest

from presag_opt.errors import ModelError
from presag_opt.speed import SPEED_RATIO_LIMIT, check_speed_limit, doppler_factor, speed_ratio, wave_speed
from presag_opt.units import KMH

TENSION = 20e3  # N, EN 50318-style contact wire
MASS_PER_LENGTH = 1.35  # kg/m


def test_wave_speed_of_en50318_contact_wire():
    """sqrt(20 000 / 1.35) = 121.716 m/s (to the printed digits)."""
    assert wave_speed(TENSION, MASS_PER_LENGTH) == pytest.approx(121.716, abs=5e-4)



def test_speed_at_wave_speed_is_an_error():
    c = wave_speed(TENSION, MASS_PER_LENGTH)
    with pytest.raises(ModelError, match="below the contact-wire wave speed"):
        speed_ratio(c, c)



def test_speed_ratio_above_0_7_warns_and_below_does_not():
    c = 100.0
    with pytest.warns(UserWarning, match="0.75"):
        assert speed_ratio(75.0, c) == pytest.approx(0.75, rel=1e-12)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert speed_ratio(50.0, c) == pytest.approx(0.5, rel=1e-12)



def test_doppler_factor_at_a_third_of_the_wave_speed_is_one_half():
    """(c - c/3)/(c + c/3) = 1/2 exactly; round-off only."""
    assert doppler_factor(40.0, 120.0) == pytest.approx(0.5, rel=1e-12)



def test_the_case_study_contact_wire_runs_waves_at_345_km_h():
    """ST 9,8/9,8: AC-120 contact wire, 1.07 kg/m at 9.8 kN: sqrt(9800/1.07) = 95.70 m/s = 344.5 km/h (the
    limit the command line quotes as "[0, 344.5) km/h")."""
    assert wave_speed(9800.0, 1.07) / KMH == pytest.approx(344.5, abs=0.05)


@pytest.mark.parametrize(("tension", "mass", "message"), [
    (0.0, 1.0, r"^tension = 0\.0 N is outside the valid range \(0, ∞\) N$"),
    (-1.0, 1.0, r"^tension = -1\.0 N is outside"),
    (1.0, 0.0, r"^mass_per_length = 0\.0 kg/m is outside the valid range \(0, ∞\) kg/m$"),
    (float("nan"), 1.0, r"^tension = nan N is outside"),
    (1.0, float("inf"), r"^mass_per_length = inf kg/m is outside"),
])
def test_a_wave_speed_needs_a_positive_tension_and_mass(tension, mass, message):
    with pytest.raises(ModelError, match=message):
        wave_speed(tension, mass)


@pytest.mark.parametrize(("speed", "wave", "message"), [
    (-1.0, 100.0, r"^speed = -3\.6 km/h is outside the valid range \[0, 360\) km/h \(below the contact-wire wave "
                  r"speed 100 m/s\)$"),
    (100.0, 100.0, r"^speed = 360 km/h is outside the valid range \[0, 360\) km/h"),
    (10.0, 0.0, r"^wave_speed = 0\.0 m/s must be positive$"),
])
def test_speeds_outside_zero_to_the_wave_speed_are_refused(speed, wave, message):
    with pytest.raises(ModelError, match=message):
        speed_ratio(speed, wave)
    with pytest.raises(ModelError, match=message):
        check_speed_limit(speed, wave)


def test_the_en50119_limit_is_refused_at_and_above_0_7_naming_the_accepting_setting():
    """At β = 0.7 exactly the speed is refused (the limit is β < 0.7); just below it is accepted."""
    assert SPEED_RATIO_LIMIT == 0.7
    c = 100.0
    check_speed_limit(69.999, c)
    with pytest.raises(ModelError) as caught:
        check_speed_limit(70.0, c, accept="--allow-supercritical")
    assert str(caught.value) == ("speed = 252 km/h is β = 0.70 of the contact-wire wave speed 360 km/h, at or above the "
                                 "EN 50119 limit β < 0.7 (speeds below 252 km/h); give --allow-supercritical to run it "
                                 "anyway")
    with pytest.raises(ModelError, match="give allow_supercritical=True to run it anyway"):
        check_speed_limit(90.0, c)


def test_the_doppler_factor_is_one_at_rest_and_falls_towards_zero_at_the_wave_speed():
    assert doppler_factor(0.0, 100.0) == 1.0
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        assert doppler_factor(99.0, 100.0) == pytest.approx(1.0 / 199.0, rel=1e-12)  # (1 − 0.99)/(1 + 0.99)
