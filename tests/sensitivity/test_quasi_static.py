"""Quasi-static outputs: the recommendation evaluator, what it reuses between samples, and the robust one."""

from __future__ import annotations

import pickle
from pathlib import Path

import numpy as np
import pytest

from presag_opt.design.band import CASE_STUDY_BAND
from presag_opt.sensitivity.evaluation import evaluate_rows
from presag_opt.sensitivity.quasi_static import RecommendationEvaluator, RobustEvaluator, _band_with
from presag_opt.system.loader import load_catenary

TINY = Path(__file__).parents[1] / "cli" / "models" / "tiny_catenary.toml"
NAMES = ("operation.aero_coefficient", "catenary.system_height")


@pytest.fixture(scope="module")
def tiny():
    return load_catenary(TINY)


def trajectory(tiny) -> np.ndarray:
    """Three points as in a Morris trajectory: a step in the system height, then one in α_ae only."""
    h = tiny.system_height
    return np.array([[0.00097 * 3.6**2, h], [0.00097 * 3.6**2, h + 0.1], [0.0012 * 3.6**2, h + 0.1]])


def test_the_band_takes_the_samples_aero_coefficient_only():
    band = _band_with(CASE_STUDY_BAND, NAMES, np.array([1e-4, 1.3]))
    assert band.aero_coefficient == 1e-4
    assert (band.static_force_low, band.speed_high) == (CASE_STUDY_BAND.static_force_low, CASE_STUDY_BAND.speed_high)


def test_reused_form_findings_give_the_very_same_values(tiny):
    evaluator = RecommendationEvaluator(ideal=tiny, mixed=tiny, names=NAMES)
    rows = trajectory(tiny)
    shared = evaluate_rows(evaluator, rows, chunk=3).values  # one task: the rows in order, in this process
    # ideal and mixed are the same model here: each row computes its layout once and reuses it for the
    # other; the α_ae step (row 2) changes no catenary, so its form-finding is row 1's (one hit)
    assert (evaluator.reuse.misses, evaluator.reuse.hits) == (2, 1)
    fresh = [RecommendationEvaluator(ideal=tiny, mixed=tiny, names=NAMES)(row) for row in rows]
    np.testing.assert_array_equal(shared, np.array(fresh))  # bit for bit: the reused object is the one computed
    # α_ae raises the band's top F_m: the recommended S_rel must move with it (the state alone is reused)
    assert abs(shared[2, 2] - shared[1, 2]) > 1e-4


def test_the_memo_is_the_evaluators_own_and_travels_empty(tiny):
    first = RecommendationEvaluator(ideal=tiny, mixed=tiny, names=NAMES)
    first(trajectory(tiny)[0])
    other = RecommendationEvaluator(ideal=tiny, mixed=tiny, names=NAMES)
    assert first.reuse.misses == 1 and other.reuse.misses == 0 and not other.reuse.states
    sent = pickle.loads(pickle.dumps(first))  # as to a worker process
    assert not sent.reuse.states and sent.reuse.hits == sent.reuse.misses == 0 and sent.reuse.size == first.reuse.size
    assert sent == first  # the memo takes no part in what the evaluator is


def test_recommendation_values_are_consistent(tiny):
    values = RecommendationEvaluator(ideal=tiny, mixed=tiny, names=NAMES)(trajectory(tiny)[0])
    ideal, mixed, recommended, ratio = values
    # the same model as both layouts: equal S_rel, ratio 1, the recommendation their common mean
    assert ideal == pytest.approx(mixed, rel=1e-12) and ratio == pytest.approx(1.0, rel=1e-12)
    assert recommended == pytest.approx(ideal, rel=1e-12)
    assert 0.1 < ideal < 5.0  # ‰: inside the model's pre-sag range, not a unit slip of 1e3


def test_the_reuse_keeps_a_bounded_number_of_entries(tiny):
    evaluator = RecommendationEvaluator(ideal=tiny, mixed=tiny, names=NAMES)
    reuse = evaluator.reuse
    for dh in (0.0, 0.05, 0.1, 0.15, 0.2, 0.25):
        evaluator(np.array([0.00097 * 3.6**2, tiny.system_height + dh]))
    assert len(reuse.states) == reuse.size and len(reuse.layouts) <= reuse.size
    reuse.clear()
    assert not reuse.states and reuse.hits == reuse.misses == 0


def test_robust_values_hold_the_design_inside_its_tolerance(tiny):
    s, low, high, width = RobustEvaluator(catenary=tiny, names=NAMES)(trajectory(tiny)[0])
    assert low <= s <= high and width == pytest.approx(high - low, abs=1e-12)
