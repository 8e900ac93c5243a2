"""``presag_opt.dynamics.run_plan``: the route of a run laid out before any form-finding — the analysed
central spans, the start of each pantograph, the simulated time and the window each pantograph spends in
the analysed section — checked against the arithmetic of the ideal 10 × 60 m section."""

from __future__ import annotations

import numpy as np
import pytest

from presag_opt.dynamics.integrator import IntegratorSettings
from presag_opt.dynamics.pantograph import load_pantograph
from presag_opt.dynamics.run_plan import plan_run, recorded_droppers, route
from presag_opt.dynamics.settings import SimulationSettings
from presag_opt.errors import ModelError
from presag_opt.speed import doppler_factor
from presag_opt.system.loader import load_catenary

IDEAL = load_catenary("st_9.8_ideal")  # 10 spans of 60 m
PANTOGRAPH = load_pantograph("case_study_2mass_friction")


@pytest.mark.parametrize(
    ("changes", "message"),
    [
        ({"speed": 350 / 3.6}, r"speed = 350 km/h is outside the valid range \[0, 344.5\d*\) km/h"),
        ({"static_force": 0.0}, r"static_force = 0 N is outside the valid range \(0, 500\] N"),
        ({"static_force": -50.0}, r"static_force = -50 N is outside the valid range"),
        ({"speed": -10.0}, r"speed = -36 km/h is outside the valid range \(0, 600\] km/h"),
        ({"aero_coefficient": -1e-3}, r"aero_coefficient = -\d.*N/\(km/h\)\^2 is outside the valid range"),
        ({"settings": SimulationSettings(integrator=IntegratorSettings(time_step=8e-3))},
         r"time_step = 8 ms is too large for contact stiffness 50 kN/m .* at most 7.54 ms"),
        ({"settings": SimulationSettings(lead_in_spans=5)}, r"the section has 10 spans: too few .* after 5 lead-in"),
        ({"spacings": [400.0]}, r"the rear pantograph would start 280.0 m before the section"),
        ({"settings": SimulationSettings(run_out=10.0)}, r"the leading pantograph would run off the section"),
        ({"pantograph": [load_pantograph("en50318_2mass")] * 2}, r"2 pantograph model\(s\) given for 1 pantograph"),
    ],
)
def test_bad_input_is_a_model_error_before_form_finding(changes, message):
    """Every input error is found by plan_run, i.e. without form-finding the catenary."""
    arguments = {
        "pantograph": load_pantograph("case_study_2mass_friction"),
        "speed": 25.0,
        "static_force": 120.0,
        "aero_coefficient": 0.0,
        **changes,
    }
    with pytest.raises(ModelError, match=message):
        plan_run(load_catenary("st_9.8_ideal"), **arguments)



def test_the_route_of_a_catenary_is_its_mast_stations_and_wire_wave_speed():
    name, wave_speed, masts = route(IDEAL)
    assert name == IDEAL.name
    np.testing.assert_allclose(masts, np.arange(11) * 60.0, rtol=0, atol=1e-12)
    assert wave_speed == pytest.approx(np.sqrt(IDEAL.contact_wire.tension / IDEAL.contact_wire.mass_per_length),
                                       rel=1e-12)  # c = sqrt(T/ρ)


def test_one_pantograph_runs_two_lead_in_spans_then_the_two_central_spans_and_the_run_out():
    """Spans 4 and 5 (240–360 m) of ten; the start 2 spans earlier (120 m); the run ends 0.25 s after
    the analysed section: (360 + 0.25 v − 120)/v of simulated time (the 2 ms steps fit in the line)."""
    speed = 40.0
    plan = plan_run(IDEAL, PANTOGRAPH, speed=speed, static_force=120.0)
    assert plan.analysed_spans == (4, 5) and plan.analysed_section == (240.0, 360.0)
    np.testing.assert_array_equal(plan.starts, [120.0])
    assert plan.duration == pytest.approx((360.0 + 0.25 * speed - 120.0) / speed, rel=1e-12)
    assert plan.step_count(2e-3) == int(np.ceil(plan.duration / 2e-3 - 1e-9))
    start, end = plan.window(0)
    assert (start, end) == pytest.approx((120.0 / speed, 240.0 / speed), rel=1e-12)
    assert plan.speed_ratio == pytest.approx(speed / plan.wave_speed, rel=1e-15)
    assert plan.doppler_factor == pytest.approx(doppler_factor(speed, plan.wave_speed), rel=1e-15)


def test_a_train_starts_its_rear_pantographs_behind_the_leading_one_and_runs_until_the_rear_leaves():
    speed, spacing = 30.0, 50.0
    settings = SimulationSettings(lead_in_spans=3, analysed_spans=2, run_out=0.1)
    plan = plan_run(IDEAL, PANTOGRAPH, speed=speed, static_force=100.0, spacings=[spacing], settings=settings)
    np.testing.assert_array_equal(plan.starts, [60.0, 10.0])  # 3 lead-in spans before 240 m, then 50 m behind
    assert plan.duration == pytest.approx((360.0 + 0.1 * speed - 10.0) / speed, rel=1e-12)
    assert plan.window(1) == pytest.approx(((240.0 - 10.0) / speed, (360.0 - 10.0) / speed), rel=1e-12)
    assert len(plan.pantographs) == 2 and plan.pantographs[0] is plan.pantographs[1]


def test_a_time_step_that_would_carry_the_leading_pantograph_off_the_line_is_cut_to_whole_steps():
    """Spans 3–6 analysed after 3 lead-in spans: the run starts at 0 m and, with a 3 s run-out at 60 m/s,
    must end at the last mast, 600 m: 10 s are 1428.6 steps of 7 ms; rounded up (1429) the pantograph
    would pass the mast by 0.18 m, so the 1428 whole steps that fit (9.996 s) are simulated."""
    settings = SimulationSettings(lead_in_spans=3, analysed_spans=4, run_out=3.0,
                                  integrator=IntegratorSettings(scheme="hht", hht_alpha=-0.005, time_step=7e-3))
    plan = plan_run(IDEAL, PANTOGRAPH, speed=60.0, static_force=100.0, settings=settings)
    assert plan.starts[0] == 0.0 and plan.analysed_section == (180.0, 420.0)
    assert plan.duration == pytest.approx(1428 * 7e-3, rel=1e-12)
    assert plan.window(0)[1] == pytest.approx(420.0 / 60.0, rel=1e-12)  # the window ends inside the run
    longer = plan_run(IDEAL, PANTOGRAPH, speed=60.0, static_force=100.0,
                      settings=SimulationSettings(lead_in_spans=3, analysed_spans=4, run_out=2.0))
    assert longer.duration == pytest.approx(540.0 / 60.0, rel=1e-12)  # room left: the exact time, not cut


class _Droppers:
    def __init__(self, stations):
        self.station = np.asarray(stations)

    def __len__(self):
        return len(self.station)


class _Model:
    def __init__(self, stations):
        self.droppers = _Droppers(stations)


def test_the_droppers_recorded_are_those_in_the_analysed_section_or_all():
    model = _Model([10.0, 240.0, 300.0, 360.0, 361.0])
    np.testing.assert_array_equal(recorded_droppers(model, (240.0, 360.0), SimulationSettings()), [1, 2, 3])
    np.testing.assert_array_equal(recorded_droppers(model, (240.0, 360.0), SimulationSettings(droppers="all")),
                                  [0, 1, 2, 3, 4])


def test_every_entry_of_a_list_of_pantographs_must_be_one():
    with pytest.raises(ModelError, match=r"pantograph: every entry must be a Pantograph \(see load_pantograph\)"):
        plan_run(IDEAL, [PANTOGRAPH, "en50318_2mass"], speed=30.0, static_force=100.0, spacings=[100.0])
