"""robust/monte_carlo.py: the quasi-static Monte Carlo of the worst-case waviness, percentile intervals and the
largest dropper tolerance (ST 9,8/9,8, case-study F_m band)."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from presag_opt.robust import Risk, evaluate_design
from presag_opt.robust.installation import InstallationErrors
from presag_opt.robust.monte_carlo import (
    QuasiStaticMonteCarlo,
    largest_dropper_tolerance,
    percentile_summary,
)


def test_order_statistic_interval_of_the_median_has_the_tabulated_ranks():
    # For n = 100 the distribution-free 95 % interval of the median is [x_(40), x_(61)] (Conover, table A3)
    values = np.arange(1.0, 101.0)
    median = percentile_summary(values, levels=(50,))[50]
    assert (median.low, median.high) == (40.0, 61.0)
    assert median.value == 50.5


def test_error_free_monte_carlo_is_the_nominal_design_exactly(monte_carlo, path, design, scenarios):
    result = monte_carlo.run(InstallationErrors(), samples=200, seed=3)
    nominal = evaluate_design(path, design.depths, scenarios, shape="parabola", risk=Risk()).worst_case_waviness
    assert monte_carlo.nominal_worst_case == nominal
    assert np.all(result.worst_case == nominal)
    assert all(p.value == p.low == p.high == nominal for p in result.percentiles.values())


def test_p95_rises_with_the_dropper_tolerance(monte_carlo):
    p95 = [monte_carlo.run(InstallationErrors(dropper_length=t), samples=4000, seed=11).percentiles[95]
           for t in (5e-3, 10e-3, 20e-3)]
    # The minimax design sits on its worst case: any error raises it. Measured 31.9, 40.9, 59.7 mm on
    # this 30 mm reference path, each CI about ±0.3 mm wide: each step is many CI widths.
    assert monte_carlo.nominal_worst_case < p95[0].low
    assert p95[0].high < p95[1].low and p95[1].high < p95[2].low


def test_largest_dropper_tolerance_is_the_edge_of_the_loss(monte_carlo):
    found = largest_dropper_tolerance(monte_carlo, InstallationErrors(), within=0.10, samples=2000, seed=5)
    bound = 1.10 * monte_carlo.nominal_worst_case
    assert 0.0 < found.tolerance < 5e-3
    assert found.at_tolerance.percentiles[95].value <= bound
    beyond = monte_carlo.run(InstallationErrors(dropper_length=found.tolerance + found.resolution), samples=2000, seed=5)
    assert beyond.percentiles[95].value > bound


def test_monte_carlo_is_reproducible_with_a_seed(monte_carlo):
    errors = InstallationErrors(dropper_length=4e-3, contact_wire_height=2e-3, distribution="uniform")
    a = monte_carlo.run(errors, samples=300, seed=21)
    fresh = QuasiStaticMonteCarlo(monte_carlo.path, monte_carlo.depths, monte_carlo.scenarios, monte_carlo.response)
    b = fresh.run(dataclasses.replace(errors), samples=300, seed=21)
    assert np.array_equal(a.worst_case, b.worst_case)
    assert not np.array_equal(a.worst_case, monte_carlo.run(errors, samples=300, seed=22).worst_case)


def test_the_crew_tolerance_of_the_mid_span_pre_sag_matches_re_solved_installed_lines(monte_carlo):
    """presag_errors is linear in the errors (common random numbers: twice the error, twice δS) and matches
    the re-solved installed line of each realisation: δS read off installed_state's node heights, to 2 % of
    the largest δS (the linearisation is good to about 1 % of the heights, docs/robust.md)."""
    from presag_opt.robust.monte_carlo import installation_tolerance, presag_errors
    from presag_opt.robust.realisation import installed_state

    errors = InstallationErrors(dropper_length=5e-3)
    draws = monte_carlo.draws(4, "normal", 17)
    linear = presag_errors(monte_carlo, errors, draws)
    assert np.allclose(presag_errors(monte_carlo, InstallationErrors(dropper_length=10e-3), draws), 2 * linear,
                       rtol=1e-12, atol=1e-15)
    path = monte_carlo.path
    sample = draws.scaled(errors)
    for i in range(2):
        built = installed_state(path.state, sample, i)
        move = built.positions[path.nodes, 2] - path.state.positions[path.nodes, 2]
        for k, span in enumerate(path.spans):
            points = np.flatnonzero(path.node_span == span)
            x = path.node_position[points]
            ends, middle = points[[np.argmin(x), np.argmax(x)]], points[np.argmin(np.abs(x - 0.5 * x.max()))]
            resolved = 0.5 * (move[ends[0]] + move[ends[1]]) - move[middle]
            assert resolved == pytest.approx(linear[i, k], abs=0.02 * np.abs(linear).max())
    tolerance = installation_tolerance(monte_carlo, errors, samples=2000, seed=5)
    assert tolerance.kind == "monte-carlo" and "P95" in tolerance.source and "dropper 5 mm" in tolerance.source
    worst = np.abs(presag_errors(monte_carlo, errors, monte_carlo.draws(2000, "normal", 5))).max(axis=1)
    assert tolerance.half_width == pytest.approx(np.percentile(worst, 95), rel=1e-12)
    assert installation_tolerance(monte_carlo, InstallationErrors(), samples=100).half_width == 0.0
