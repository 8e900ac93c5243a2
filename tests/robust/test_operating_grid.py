"""The operating grid of a dynamic design: points, weights, and the checks made before any work."""

from __future__ import annotations

import numpy as np
import pytest

from presag_opt.design.band import KMH, OperatingBand
from presag_opt.dynamics.cost import BATCH_SECONDS_PER_NODE_STEP
from presag_opt.dynamics.pantograph import load_pantograph
from presag_opt.dynamics.run_plan import plan_run
from presag_opt.dynamics.settings import SimulationSettings
from presag_opt.errors import ModelError
from presag_opt.robust.operating_grid import OperatingGrid, band_static_settings, band_work
from presag_opt.static.run_time import form_find_estimate
from presag_opt.system.loader import load_catenary

CATENARY = load_catenary("st_9.8_ideal")
PANTOGRAPH = load_pantograph("case_study_2mass_friction")


def band(forces=(70.0, 140.0), speeds_kmh=(50.0, 90.0)):
    return OperatingBand(static_force_low=forces[0], static_force_high=forces[1], speed_low=speeds_kmh[0] * KMH,
                         speed_high=speeds_kmh[1] * KMH, aero_coefficient=0.00097 / KMH**2)


def test_points_cover_the_band_ends_speed_by_speed():
    grid = OperatingGrid.from_band(band(), static_points=4, speed_points=3)
    assert grid.static_forces == pytest.approx((70.0, 70 + 70 / 3, 70 + 140 / 3, 140.0), rel=1e-12)
    assert np.array(grid.speeds) / KMH == pytest.approx([50.0, 70.0, 90.0], rel=1e-12)
    points = grid.points()
    np.testing.assert_allclose([(p.speed / KMH, p.static_force) for p in points[:5]],
                               [(50.0, 70.0), (50.0, 70 + 70 / 3), (50.0, 70 + 140 / 3), (50.0, 140.0), (70.0, 70.0)],
                               rtol=1e-12)
    assert grid.mean_force_band == pytest.approx((70.0 + 0.00097 * 50**2, 140.0 + 0.00097 * 90**2), rel=1e-12)


def test_weights_are_the_trapezoidal_rule_of_a_uniform_band():
    grid = OperatingGrid.from_band(band(), static_points=4, speed_points=3)
    weights = grid.weights.reshape(3, 4)
    assert grid.weights.sum() == pytest.approx(1.0, rel=1e-15)
    # an affine function of F_stat and v: the weighted mean is its value at the band centre
    values = np.array([[2.0 * f + 3.0 * v for f in grid.static_forces] for v in grid.speeds])
    assert float((weights * values).sum()) == pytest.approx(2.0 * 105.0 + 3.0 * 70.0 * KMH, rel=1e-12)
    assert weights[0, 0] == pytest.approx(weights[1, 1] / 4.0, rel=1e-12)  # a corner has a quarter cell


@pytest.mark.parametrize("forces,speeds,words", [
    ((70.0, 70.0), (50.0, 90.0), "static force band 70:70 N is empty"),
    ((70.0, 140.0), (90.0, 90.0), "speed band 90:90 km/h is empty"),
    ((70.0, 140.0), (0.0, 90.0), "speed band starts at 0 km/h"),
])
def test_empty_bands_are_refused(forces, speeds, words):
    with pytest.raises(ModelError, match=words):
        OperatingGrid.from_band(band(forces, speeds))


def test_an_inverted_band_is_refused():
    with pytest.raises(ModelError, match="static_force_low = 140 N is above static_force_high = 70 N"):
        band((140.0, 70.0))
    with pytest.raises(ModelError, match="speed_low = 90 km/h is above speed_high = 50 km/h"):
        band(speeds_kmh=(90.0, 50.0))


def test_a_speed_at_the_wave_speed_is_refused_before_any_work():
    wave = CATENARY.contact_wire.wave_speed / KMH
    grid = OperatingGrid.from_band(band(speeds_kmh=(100.0, wave)))
    with pytest.raises(ModelError, match=r"speed = 344.5\d* km/h is at or above the contact-wire wave speed 344.5 km/h"):
        grid.check(CATENARY, PANTOGRAPH, SimulationSettings(numerics="auto"))


def test_a_point_the_simulator_refuses_is_named():
    grid = OperatingGrid.from_band(band())
    short = SimulationSettings(analysed_spans=8, lead_in_spans=2)
    with pytest.raises(ModelError, match=r"operating point 50 km/h, 70 N: the section has 10 spans"):
        grid.check(CATENARY, PANTOGRAPH, short)


def test_one_discretisation_fine_enough_for_the_fastest_speed():
    auto = SimulationSettings(numerics="auto")
    assert band_static_settings(CATENARY, (50 * KMH, 90 * KMH), auto).element_length == 0.44
    assert band_static_settings(CATENARY, (50 * KMH,), auto).element_length == 0.5
    assert band_static_settings(CATENARY, (50 * KMH, 180 * KMH), auto).element_length == 0.28
    fixed = SimulationSettings().with_fixed_numerics(element_length=0.3)
    assert band_static_settings(CATENARY, (50 * KMH, 180 * KMH), fixed).element_length == 0.3


def test_the_announced_cost_puts_every_run_on_the_one_shared_discretisation():
    grid = OperatingGrid.from_band(band(), static_points=4, speed_points=3)
    auto = SimulationSettings(numerics="auto")
    static = band_static_settings(CATENARY, grid.speeds, auto)
    nodes, form_seconds = form_find_estimate(CATENARY, static)
    steps = 0
    for p in grid.points():
        plan = plan_run(CATENARY, PANTOGRAPH, speed=p.speed, static_force=p.static_force,
                        aero_coefficient=p.aero_coefficient, settings=auto)
        steps += plan.step_count(plan.settings.integrator.time_step)  # each speed keeps its own time step
    one = band_work(CATENARY, PANTOGRAPH, grid, evaluations=1, workers=1)
    # one form-finding at the fastest speed's 0.44 m, not one per speed (0.5, 0.47 and 0.44 m)
    assert one.nodes == (nodes,)
    assert one.form_finding_seconds == pytest.approx(form_seconds, rel=1e-12)
    assert one.run_seconds == pytest.approx(BATCH_SECONDS_PER_NODE_STEP * nodes * steps, rel=1e-12)
    seven = band_work(CATENARY, PANTOGRAPH, grid, evaluations=7, workers=2)
    assert seven.runs == 7 * 12
    assert seven.run_seconds == pytest.approx(3.5 * one.run_seconds, rel=1e-12)
    assert seven.form_finding_seconds == pytest.approx(3.5 * one.form_finding_seconds, rel=1e-12)
    assert seven.memory == pytest.approx(2 * one.memory, rel=1e-12)
