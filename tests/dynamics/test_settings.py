"""``presag_opt.dynamics.settings``: the validated operating point, the operation with its train, and the
numerical settings of a run (fixed or chosen from the speed)."""

from __future__ import annotations

import numpy as np
import pytest

from presag_opt.dynamics.numerics import numerics_for_speed
from presag_opt.dynamics.settings import OperatingPoint, Operation, SimulationSettings
from presag_opt.errors import ModelError
from presag_opt.units import KMH


def test_simulation_settings_are_validated():
    with pytest.raises(ModelError, match=r"analysed_spans = 0 - is outside the valid range \[1, 200\]"):
        SimulationSettings(analysed_spans=0)
    with pytest.raises(ModelError, match=r"lead_in_spans = 1.5 is not a whole number"):
        SimulationSettings(lead_in_spans=1.5)
    with pytest.raises(ModelError, match=r"droppers = 'some' is not one of 'analysed', 'all'"):
        SimulationSettings(droppers="some")


def test_bad_operating_points_name_value_unit_and_range():
    with pytest.raises(ModelError, match=r"static_force = -5 N is outside the valid range \(0, 500\] N"):
        OperatingPoint(speed=20.0, static_force=-5.0)
    with pytest.raises(ModelError, match=r"speed = 0 km/h is outside the valid range"):
        OperatingPoint(speed=0.0, static_force=100.0)



def test_the_uplift_force_is_the_static_force_plus_alpha_v_squared():
    """Eq. (4) of doi:10.1108/RS-05-2025-0016 with the case study's α_ae = 0.00097 N/(km/h)² at 180 km/h:
    120 + 0.00097·180² = 151.428 N (exact arithmetic, so 1e-12)."""
    point = OperatingPoint(speed=180 * KMH, static_force=120.0, aero_coefficient=0.00097 / KMH**2)
    assert point.uplift_force == pytest.approx(151.428, rel=1e-12)
    assert point.aero_force == pytest.approx(31.428, rel=1e-12)
    assert OperatingPoint(speed=50.0, static_force=90.0).uplift_force == 90.0  # α_ae defaults to 0


def test_the_offsets_of_a_train_are_the_running_sum_of_its_spacings():
    np.testing.assert_array_equal(Operation(speed=50.0, static_force=90.0, spacings=[200, 35.5]).offsets,
                                  [0.0, 200.0, 235.5])
    np.testing.assert_array_equal(Operation(speed=50.0, static_force=90.0).offsets, [0.0])
    assert Operation(speed=50.0, static_force=90.0, spacings=[]).spacings is None  # an empty train is one pantograph
    with pytest.raises(ModelError, match=r"spacings\[1\] = 0.5 m is outside the valid range \[1, 2000\] m"):
        Operation(speed=50.0, static_force=90.0, spacings=[200, 0.5])


def test_fixed_numerics_are_kept_and_auto_numerics_follow_the_speed():
    fixed = SimulationSettings()
    assert fixed.for_speed(50.0, 100.0) is fixed
    auto = SimulationSettings(numerics="auto")
    chosen = numerics_for_speed(50.0, 100.0, auto.cutoff_frequency)
    run = auto.for_speed(50.0, 100.0)
    assert (run.static.element_length, run.integrator.time_step) == (chosen.element_length, chosen.time_step)
    assert run.analysed_spans == auto.analysed_spans and run.numerics == "auto"
    back = run.with_fixed_numerics()
    assert (back.numerics, back.static.element_length, back.integrator.time_step) == ("fixed", 0.5, 2e-3)
    assert SimulationSettings().with_fixed_numerics(element_length=0.25, time_step=1e-3).static.element_length == 0.25


def test_the_default_window_is_the_papers():
    """Two analysed central spans after two lead-in spans, 20 Hz cut-off (EN 50318), HHT-α = −0.005."""
    s = SimulationSettings()
    assert (s.analysed_spans, s.lead_in_spans, s.cutoff_frequency, s.run_out) == (2, 2, 20.0, 0.25)
    assert (s.integrator.scheme, s.integrator.hht_alpha) == ("hht", -0.005)
    with pytest.raises(ModelError, match=r"numerics = 'fast' is not one of 'fixed', 'auto'"):
        SimulationSettings(numerics="fast")
