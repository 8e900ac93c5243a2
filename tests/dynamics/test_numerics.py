"""Automatic numerics: the rule's values against the convergence figures it is built on, and the
warnings for explicit settings that under-resolve a run."""

from __future__ import annotations

import pytest

from presag_opt.dynamics.numerics import (
    ELEMENTS_PER_WAVELENGTH,
    STEPS_PER_PERIOD,
    numerics_for_speed,
    resolution_warnings,
)
from presag_opt.dynamics.settings import SimulationSettings

ST98 = 95.70  # contact-wire wave speed of ST 9,8/9,8, sqrt(9800 N / 1.07 kg/m) [m/s]
EN = 121.72  # EN 50318-style wire, sqrt(20000 N / 1.35 kg/m) [m/s]


def test_low_speeds_keep_the_papers_numerics():
    """On ST 9,8/9,8 the rule gives the paper's 0.5 m up to 56 km/h (a 4 m wave) and its 2 ms up to
    124 km/h (31 Hz), and refines beyond."""
    assert numerics_for_speed(50 / 3.6, ST98, 20.0).element_length == 0.5
    assert numerics_for_speed(60 / 3.6, ST98, 20.0).element_length == 0.49
    assert numerics_for_speed(120 / 3.6, ST98, 20.0).time_step == 2e-3
    assert numerics_for_speed(130 / 3.6, ST98, 20.0).time_step == pytest.approx(1.9e-3, rel=1e-12)


def test_the_rule_resolves_the_shortest_wave_as_documented():
    """(c − v)/f_c with at least 8 elements, f_c/(1 − β) with at least 16 steps; EN 50318 at
    300 km/h lands at or below the 0.25 m / 1 ms that the convergence study found sufficient."""
    for c, kmh in ((ST98, 180), (EN, 250), (EN, 300)):
        chosen = numerics_for_speed(kmh / 3.6, c, 20.0)
        assert chosen.shortest_wavelength == pytest.approx((c - kmh / 3.6) / 20.0, rel=1e-12)
        assert chosen.elements_per_wavelength >= ELEMENTS_PER_WAVELENGTH
        assert chosen.steps_per_period >= STEPS_PER_PERIOD
    fast = numerics_for_speed(300 / 3.6, EN, 20.0)
    assert fast.element_length <= 0.25 and fast.time_step <= 1e-3


def test_finer_numerics_as_the_speed_rises():
    chosen = [numerics_for_speed(kmh / 3.6, ST98, 20.0) for kmh in range(50, 320, 10)]
    assert all(a.element_length >= b.element_length and a.time_step >= b.time_step
               for a, b in zip(chosen, chosen[1:]))


def test_auto_settings_follow_the_speed_and_fixed_ones_do_not():
    auto = SimulationSettings(numerics="auto").for_speed(180 / 3.6, ST98)
    assert (auto.static.element_length, auto.integrator.time_step) == (0.28, pytest.approx(1.4e-3, rel=1e-12))
    fixed = SimulationSettings()
    assert fixed.for_speed(180 / 3.6, ST98) is fixed


def test_under_resolved_settings_are_named_in_one_line_each():
    """The paper's 0.5 m / 2 ms pass at 90 km/h (7.1 elements per wave, 18 steps per period) and are
    flagged at 180 km/h on ST 9,8/9,8 (element length) and 300 km/h on EN 50318 (both)."""
    assert resolution_warnings(90 / 3.6, ST98, 20.0, element_length=0.5, time_step=2e-3) == ()
    (line,) = resolution_warnings(180 / 3.6, ST98, 20.0, element_length=0.5, time_step=2e-3)
    assert line.startswith("element_length = 0.5 m under-resolves 180 km/h (β = 0.52)")
    both = resolution_warnings(300 / 3.6, EN, 20.0, element_length=0.5, time_step=2e-3)
    assert [w.split(" = ")[0] for w in both] == ["element_length", "time_step"]
