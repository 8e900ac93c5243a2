"""The dynamic robust search with the real simulator, against brute force on the same band and grid.

A small fast band: three 30 m spans of ST 9,8/9,8, the central one analysed without lead-in, the
case-study pantograph at 140–150 km/h and F_stat 80–140 N (2 × 2 points), 0.33 m elements and
1.6 ms (the automatic numerics of 150 km/h, fixed so that all runs share one batch): about 1 s per
simulated pre-sag. The default test scans 1 mm steps around the search's answer (the synthetic
tests in ``test_dynamic_design.py`` cover the whole range exactly); the slow one scans the whole
range. The case study's comparison is ``benchmarks/bench_robust_dynamic.py``.
"""

from __future__ import annotations

import numpy as np
import pytest

from presag_opt.design.band import KMH, OperatingBand
from presag_opt.dynamics.batch import simulate_many
from presag_opt.dynamics.integrator import IntegratorSettings
from presag_opt.dynamics.pantograph import load_pantograph
from presag_opt.dynamics.settings import SimulationSettings
from presag_opt.errors import ConvergenceError
from presag_opt.robust.band_evaluation import BandEvaluator
from presag_opt.robust.dynamic_design import DynamicObjective, SearchSettings, dynamic_robust_presag
from presag_opt.robust.operating_grid import OperatingGrid
from presag_opt.static.discretisation import StaticSettings
from presag_opt.static.form_finding import form_find
from presag_opt.system.catenary import SpanLayout
from presag_opt.system.loader import load_catenary

SPAN = 30.0
CATENARY = load_catenary("st_9.8_ideal").with_layout(SpanLayout(span_lengths=(SPAN,) * 3))
PANTOGRAPH = load_pantograph("case_study_2mass_friction")
SETTINGS = SimulationSettings(analysed_spans=1, lead_in_spans=0, static=StaticSettings(element_length=0.33),
                              integrator=IntegratorSettings(scheme="hht", hht_alpha=-0.005, time_step=1.6e-3))
GRID = OperatingGrid.from_band(
    OperatingBand(static_force_low=80.0, static_force_high=140.0, speed_low=140 * KMH, speed_high=150 * KMH,
                  aero_coefficient=0.00097 / KMH**2),
    static_points=2, speed_points=2,
)
SEARCH = SearchSettings(presag_high=0.030)
STARTS = (0.010 / SPAN, 0.015 / SPAN)


@pytest.fixture(scope="module")
def searched():
    evaluator = BandEvaluator(CATENARY, PANTOGRAPH, GRID, settings=SETTINGS)
    return evaluator, dynamic_robust_presag(evaluator, DynamicObjective(), starts=STARTS, search=SEARCH)


def _scan(evaluator, presags_mm):
    objective = DynamicObjective()
    return np.array([objective.value(e.statistics, GRID.weights)
                     for e in evaluator.evaluate_many([s * 1e-3 / SPAN for s in presags_mm])])


def test_search_agrees_with_brute_force_around_its_answer(searched):
    evaluator, design = searched
    assert len(design.evaluated) <= 5
    presags = np.round(design.presag * 1e3) + np.arange(-2.0, 2.5, 1.0)  # 1 mm steps, ±2 mm
    values = _scan(evaluator, presags)
    best = int(np.argmin(values))
    assert 0 < best < len(presags) - 1  # a minimum inside the scanned window
    assert abs(design.presag * 1e3 - presags[best]) <= 1.0  # 1 mm (issue)
    assert design.objective == pytest.approx(values[best], rel=0.01)  # 1 % (issue)


def test_the_answer_is_a_simulation_of_the_chosen_presag(searched):
    _, design = searched
    state = form_find(CATENARY.with_presag(design.presag_rel), SETTINGS.static)
    batch = simulate_many(state, PANTOGRAPH, GRID.points(), settings=SETTINGS)
    ratio = np.array([run.statistics[0].sigma_over_mean for run in batch.runs])
    np.testing.assert_allclose(design.statistics.losses("sigma-over-fm"), ratio, rtol=1e-12)
    assert design.worst_case_objective == pytest.approx(ratio.max(), rel=1e-12)
    assert design.uplift_max == max(run.uplift_max for run in batch.runs)
    assert design.runs_used == len(design.evaluated) * 4


def test_a_failed_run_stops_the_search_with_its_reason():
    strict = SimulationSettings(analysed_spans=1, lead_in_spans=0, static=SETTINGS.static,
                                integrator=IntegratorSettings(scheme="hht", hht_alpha=-0.005, time_step=1.6e-3,
                                                              tolerance=1e-14, max_iterations=1))
    evaluator = BandEvaluator(CATENARY, PANTOGRAPH, GRID, settings=strict)
    with pytest.raises(ConvergenceError) as error:
        dynamic_robust_presag(evaluator, DynamicObjective(), starts=STARTS, search=SEARCH)
    message = str(error.value)
    assert message.startswith("dynamic robust pre-sag: the run at S = 10.0 mm, 140 km/h, F_stat 80 N failed: Newton")
    assert "\n" not in message


@pytest.mark.slow
def test_search_agrees_with_a_brute_force_scan_of_the_whole_range(searched):
    evaluator, design = searched
    presags = np.arange(0.0, 30.5, 1.0)
    values = _scan(evaluator, presags)
    best = int(np.argmin(values))
    assert abs(design.presag * 1e3 - presags[best]) <= 1.0
    assert design.objective == pytest.approx(values[best], rel=0.01)
