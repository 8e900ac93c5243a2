"""robust/band_evaluation.py: the band statistics of a pre-sag, checked against the simulator's own
run statistics, the evaluator's cache, and a pre-sag split over the workers against the same pre-sag
in one batch (small fast band of ``test_dynamic_search.py``)."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from presag_opt.dynamics.batch import simulate_many
from presag_opt.errors import ModelError
from presag_opt.processes import worker_pool
from presag_opt.robust import band_evaluation
from presag_opt.robust.band_evaluation import BandEvaluation, BandEvaluator, BandStatistics, join_parts, split_grid
from presag_opt.robust.operating_grid import OperatingGrid
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


def test_split_grids_join_back_in_the_grid_order_with_every_pantograph():
    grid = OperatingGrid(static_forces=(80.0, 100.0, 120.0), speeds=(30.0, 40.0), aero_coefficient=0.0)
    parts = split_grid(grid, 2)
    assert [p.static_forces for p in parts] == [(80.0, 120.0), (100.0,)]
    assert split_grid(grid, 5) == tuple(replace(grid, static_forces=(f,)) for f in grid.static_forces)
    assert split_grid(grid, 1) == (grid,)

    def code(point, pantograph):  # a number that names the point and the pantograph of a run
        return point.speed * 1e3 + point.static_force + 0.1 * pantograph

    def evaluation(part):
        values = np.array([code(p, k) for p in part.points() for k in range(2)])  # two pantographs per run
        return BandEvaluation(statistics=BandStatistics(presag_rel=1e-3, mean_force=values, sigma=-values,
                                                        uplift_max=values + 1.0),
                              histories=tuple(np.array([v]) for v in values), loss_of_contact=2.0 * values,
                              wall_time=float(len(values)), warnings=(f"part {len(values)}",))

    joined = join_parts(grid, parts, [evaluation(p) for p in parts])
    expected = np.array([code(p, k) for p in grid.points() for k in range(2)])
    assert joined.statistics.mean_force.tolist() == expected.tolist()
    assert joined.statistics.sigma.tolist() == (-expected).tolist()
    assert joined.statistics.uplift_max.tolist() == (expected + 1.0).tolist()
    assert [h[0] for h in joined.histories] == expected.tolist()
    assert joined.loss_of_contact.tolist() == (2.0 * expected).tolist()
    assert joined.wall_time == 8.0  # the parts ran side by side: the longest
    assert joined.warnings == ("part 8", "part 4")


def test_a_lone_presag_split_over_the_workers_is_the_same_to_the_last_bit(monkeypatch):
    started = []

    def counted_pool(*args, **kwargs):
        started.append(args)
        return worker_pool(*args, **kwargs)

    monkeypatch.setattr(band_evaluation, "worker_pool", counted_pool)
    alone = BandEvaluator(CATENARY, PANTOGRAPH, GRID, settings=SETTINGS)(PRESAG_REL)
    messages = []
    with BandEvaluator(CATENARY, PANTOGRAPH, GRID, settings=SETTINGS, workers=2, progress=messages.append) as evaluator:
        split = evaluator(PRESAG_REL)
        pair = evaluator.evaluate_many([PRESAG_REL, 0.015 / SPAN, 0.018 / SPAN])
        pool = evaluator._pool
        workers = list(pool._processes.values())
    assert len(started) == 1  # one set of workers for the evaluator's block
    assert not any(w.is_alive() for w in workers)  # stopped with the block
    assert pair[0] is split and evaluator.runs_used == 3 * len(GRID.points())
    assert messages == ["S = 12.0 mm in 2 processes, each pre-sag's 4 runs in 2 parts", "S = 15.0, 18.0 mm in 2 processes"]
    for name in ("mean_force", "sigma", "uplift_max"):
        assert np.array_equal(getattr(split.statistics, name), getattr(alone.statistics, name)), name
    assert all(np.array_equal(a, b) for a, b in zip(split.histories, alone.histories, strict=True))
    assert np.array_equal(split.loss_of_contact, alone.loss_of_contact)


def test_the_evaluators_workers_stop_when_its_block_is_interrupted():
    with pytest.raises(KeyboardInterrupt):
        with BandEvaluator(CATENARY, PANTOGRAPH, GRID, settings=SETTINGS, workers=2) as evaluator:
            evaluator(PRESAG_REL)
            workers = list(evaluator._pool._processes.values())
            raise KeyboardInterrupt
    for worker in workers:
        worker.join(timeout=30.0)  # stop() kills them; bounded against a hang only
    assert not any(w.is_alive() for w in workers)
    assert evaluator._pool is None
