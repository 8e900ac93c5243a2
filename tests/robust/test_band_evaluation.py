"""robust/band_evaluation.py: the band statistics of a pre-sag, checked against the simulator's own
run statistics, and the evaluator's cache (small fast band of ``test_dynamic_search.py``)."""

from __future__ import annotations

import numpy as np
import pytest

from presag_opt.dynamics.batch import simulate_many
from presag_opt.errors import ModelError
from presag_opt.robust.band_evaluation import BandEvaluator, BandStatistics
from presag_opt.static.form_finding import form_find
from tests.robust.test_dynamic_search import CATENARY, GRID, PANTOGRAPH, SETTINGS, SPAN

PRESAG_REL = 0.012 / SPAN


def test_losses_and_the_statistical_minimum():
    stats = BandStatistics(presag_rel=1e-3, mean_force=np.array([100.0, 120.0]), sigma=np.array([10.0, 30.0]),
                           uplift_max=np.array([0.05, 0.06]))
    assert stats.losses("sigma-over-fm").tolist() == [0.1, 0.25]
    assert stats.losses("sigma").tolist() == [10.0, 30.0]
    assert stats.statistical_min.tolist() == [70.0, 30.0]
    with pytest.raises(ModelError, match="objective = 'sigma2' is not one of sigma-over-fm, sigma"):
        stats.losses("sigma2")
    with pytest.raises(ModelError, match=r"workers = 0 is outside the valid range \[1, 64\]"):
        BandEvaluator(CATENARY, PANTOGRAPH, GRID, settings=SETTINGS, workers=0)


def test_band_statistics_are_the_simulators_statistics_and_are_cached():
    evaluator = BandEvaluator(CATENARY, PANTOGRAPH, GRID, settings=SETTINGS)
    evaluation = evaluator(PRESAG_REL)
    assert evaluator(PRESAG_REL) is evaluation  # simulated once
    assert evaluator.runs_used == len(GRID.points())
    # a second method: the batch's own statistics of the same runs on the same form-found state
    state = form_find(CATENARY.with_presag(PRESAG_REL), evaluator.static_settings)
    runs = simulate_many(state, PANTOGRAPH, GRID.points(), settings=SETTINGS).runs
    mean = np.array([r.statistics[0].mean_force for r in runs])
    sigma = np.array([r.statistics[0].std_force for r in runs])
    # the same filtered window, averaged in another order: equal to round-off (1e-9 of the value)
    assert evaluation.statistics.mean_force == pytest.approx(mean, rel=1e-9)
    assert evaluation.statistics.sigma == pytest.approx(sigma, rel=1e-9)
    assert evaluation.statistics.uplift_max == pytest.approx([r.uplift_max for r in runs], rel=1e-12)
    assert evaluation.loss_of_contact.tolist() == [r.statistics[0].loss_of_contact for r in runs]
