"""The simulation job (presag_opt.jobs.simulation): a case built from a model or replaced from a case file, one
point run in full, a grid run as batches that agree with the single runs, refusals before any work."""

from __future__ import annotations

import time

import pytest

from presag_opt import load_catenary, simulate
from presag_opt.dynamics.settings import SimulationSettings
from presag_opt.errors import ModelError
from presag_opt.jobs.simulation import simulation_case
from presag_opt.system.catenary import SpanLayout
from presag_opt.units import KMH

PANTOGRAPH = "case_study_2mass_friction"


@pytest.fixture(scope="module")
def five():
    return load_catenary("st_9.8_ideal").with_layout(SpanLayout(span_lengths=(60.0,) * 5))


@pytest.fixture(scope="module")
def quick():
    """Coarse fixed numerics and one analysed span: the engines' agreement, not the physics, is tested here."""
    return SimulationSettings(analysed_spans=1, lead_in_spans=1).with_fixed_numerics(element_length=1.0, time_step=4e-3)


def test_a_case_takes_the_designer_s_units_and_replaces_only_what_is_given():
    case = simulation_case(case="case_study_st98", static_force=(110.0, 120.0), aero_coefficient_kmh=0.002,
                           presag_mm=45.0)
    original = simulation_case(case="case_study_st98")
    assert case.operation.static_force == 110.0 and case.speeds == original.speeds
    assert case.operation.aero_coefficient == pytest.approx(0.002 / KMH**2, rel=1e-12)
    assert case.catenary.presag_rel * max(case.catenary.layout.span_lengths) == pytest.approx(0.045, rel=1e-12)
    assert original.catenary.presag_rel != case.catenary.presag_rel
    built = simulation_case("st_9.8_ideal", PANTOGRAPH, speed_kmh=(80.0, 90.0), static_force=100.0)
    assert built.speeds == pytest.approx((80 * KMH, 90 * KMH), rel=1e-12) and built.operation.speed == built.speeds[0]


@pytest.mark.parametrize(("keywords", "message"), [
    ({}, "give a catenary model"),
    ({"model": "st_9.8_ideal", "case": "case_study_st98"}, "not both"),
    ({"model": "st_9.8_ideal", "speed_kmh": 80.0}, "pantograph, static_force required with a catenary model"),
    ({"case": "case_study_st98", "speed_kmh": 300.0}, "speed = 300 km/h is β = "),
    ({"case": "case_study_st98", "scheme": "euler"}, "scheme = 'euler': give one of hht, newmark"),
])
def test_bad_input_is_refused_before_any_work(keywords, message):
    started = time.monotonic()
    with pytest.raises(ModelError, match=message):
        simulate(**keywords)
    assert time.monotonic() - started < 5  # no form-finding, no run


def test_a_grid_runs_as_batches_that_agree_with_the_single_runs(five, quick):
    grid = simulate(five, PANTOGRAPH, speed_kmh=90.0, static_force=(70.0, 100.0), aero_coefficient_kmh=0.00097,
                    settings=quick)
    assert grid.run is None and len(grid.grid.runs) == 2
    rows = grid.table()
    assert [r["F_stat [N]"] for r in rows] == [70.0, 100.0]
    for row in rows:  # the mean force is the static force plus the aerodynamic uplift, F_m = F_stat + α_ae v²
        assert row["F_m [N]"] == pytest.approx(row["F_stat [N]"] + 0.00097 * 90.0**2, rel=0.01)
    single = simulate(five, PANTOGRAPH, speed_kmh=90.0, static_force=100.0, aero_coefficient_kmh=0.00097,
                      settings=quick)
    assert single.grid is None and single.run is not None
    # the batch engine against the single-run engine: the documented agreement of 1e-3
    assert single.run.to_dict()["sigma_N"] == pytest.approx(rows[1]["σ [N]"], rel=1e-3)
    assert "2 runs" in grid._repr_html_() and list(grid.to_frame().columns) == list(rows[0])
    assert grid.to_dict()["case"] == five.name and single.to_dict() == single.run.to_dict()
