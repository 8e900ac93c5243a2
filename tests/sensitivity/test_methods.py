"""The SALib wrapper against the Ishigami function's known indices and a linear function's exact effects."""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest

from presag_opt.errors import ConvergenceError, ModelError
from presag_opt.sensitivity.evaluation import evaluate_rows
from presag_opt.sensitivity.inputs import SensitivityInput
from presag_opt.sensitivity.methods import (
    MORRIS_LEVELS,
    morris_design,
    morris_indices,
    sobol_design,
    sobol_indices,
)
from presag_opt.sensitivity.reference import ishigami, ishigami_indices


def inputs(names, bounds):
    return [SensitivityInput(name=n, value=0.5 * (lo + hi), low=lo, high=hi, unit="-", factor=1.0, reason="test",
                             declared=False) for n, (lo, hi) in zip(names, bounds)]


# x1..x3 of Ishigami and x4, which it does not depend on
ISHIGAMI = inputs(["x1", "x2", "x3", "x4"], [(-math.pi, math.pi)] * 4)


def run(method, n, seed, workers=1):
    design = morris_design if method == "morris" else sobol_design
    analyse = morris_indices if method == "morris" else sobol_indices
    rows = design(ISHIGAMI, n, seed)
    values = evaluate_rows(ishigami, rows, workers=workers).values[:, 0]
    return analyse(ISHIGAMI, rows, values, output="f", unit="-", seed=seed)


def test_sobol_reproduces_the_ishigami_indices():
    # N = 4096 base samples (24 576 evaluations): the bootstrap half-widths are 0.01-0.03; the
    # estimators' error at this N is of that order, so |estimate - exact| < 0.04 (and within 3 half-widths
    # plus 0.01) can fail for a wrong estimator or a mislabelled input while holding for the right one.
    result = run("sobol", 4096, seed=7)
    s1, st = ishigami_indices()
    by_name = {s.name: s for s in result.sobol}
    for name, exact_first, exact_total in zip(("x1", "x2", "x3"), s1, st):
        got = by_name[name]
        assert abs(got.first - exact_first) < min(0.04, 3 * got.first_conf + 0.01), (name, got)
        assert abs(got.total - exact_total) < min(0.04, 3 * got.total_conf + 0.01), (name, got)
    # ranked by ST: x1 (0.558), x2 (0.442), x3 (0.244), x4 (0)
    assert result.ranked_names() == ("x1", "x2", "x3", "x4")


def test_an_input_the_output_does_not_depend_on_gets_zero():
    sobol = {s.name: s for s in run("sobol", 1024, seed=3).sobol}["x4"]
    low, high = sobol.total_interval
    assert low <= 0.0 <= high
    assert abs(sobol.total) < 1e-12 and abs(sobol.first) < 0.05  # ST exactly 0: f(A) = f(A_B^(4))
    morris = {e.name: e for e in run("morris", 20, seed=3).morris}["x4"]
    assert morris.mu_star == 0.0 and morris.sigma == 0.0


def expected_mu_star(i):
    """E|EE_i| of Ishigami on the 4-level Morris grid, by enumeration (an independent computation)."""
    levels = np.linspace(-math.pi, math.pi, MORRIS_LEVELS)
    delta = MORRIS_LEVELS / (2 * (MORRIS_LEVELS - 1))  # in units of the range
    step = delta * 2 * math.pi
    effects = []
    for point in itertools.product(levels, repeat=3):
        x = np.array(point)
        if x[i] + step > math.pi + 1e-12:
            continue
        up = x.copy()
        up[i] += step
        effects.append(abs(ishigami(up)[0] - ishigami(x)[0]) / delta)
    return float(np.mean(effects)), float(np.std(effects))


def test_morris_mu_star_matches_the_enumerated_expectation():
    # r = 400 trajectories: the standard error of mu* is std(|EE|)/sqrt(400) = std/20; allow 4 of them.
    result = {e.name: e for e in run("morris", 400, seed=11).morris}
    for i, name in enumerate(("x1", "x2", "x3")):
        mean, std = expected_mu_star(i)
        assert abs(result[name].mu_star - mean) < 4 * std / 20 + 1e-9, (name, result[name].mu_star, mean)


def test_linear_function_has_exact_effects_scaled_by_the_range():
    lin = inputs(["a", "b", "c"], [(0.0, 2.0), (5.0, 6.0), (-1.0, 1.0)])
    rows = morris_design(lin, 10, seed=1)
    values = 3.0 * rows[:, 0] - 2.0 * rows[:, 2]
    table = morris_indices(lin, rows, values, output="y", unit="-", seed=1)
    got = {e.name: e for e in table.morris}
    assert got["a"].mu_star == pytest.approx(6.0, rel=1e-12)  # |3| * (2 - 0)
    assert got["c"].mu_star == pytest.approx(4.0, rel=1e-12)  # |-2| * (1 - (-1))
    assert got["b"].mu_star == 0.0
    assert got["c"].relative == pytest.approx(4.0 / 6.0, rel=1e-12)
    assert max(e.sigma for e in table.morris) < 1e-12  # linear: every elementary effect the same


@pytest.mark.parametrize("method,n", [("morris", 6), ("sobol", 64)])
def test_reproducible_with_a_seed_and_independent_of_worker_count(method, n):
    one = run(method, n, seed=5, workers=1)
    assert run(method, n, seed=5, workers=1) == one
    assert run(method, n, seed=5, workers=2) == one
    assert run(method, n, seed=6, workers=1) != one


def test_bad_sample_sizes_are_refused_in_one_line():
    with pytest.raises(ModelError, match="samples = 1 trajectories is outside the valid range"):
        morris_design(ISHIGAMI, 1, 0)
    with pytest.raises(ModelError, match="samples = 100 is not a valid Sobol base sample: a power of two"):
        sobol_design(ISHIGAMI, 100, 0)


def test_spread_design_fills_the_box_reproducibly():
    from presag_opt.sensitivity.methods import spread_design

    box = inputs(["a", "b"], [(0.0, 2.0), (5.0, 6.0)])
    rows = spread_design(box, 64, seed=2)
    assert rows.shape == (64, 2)
    assert np.all(rows[:, 0] >= 0.0) and np.all(rows[:, 0] <= 2.0) and np.all(rows[:, 1] >= 5.0)
    # a scrambled Sobol sample of 64 points has its mean within 0.05 of the box centre (uniform: ±0.58/8 = 0.07 sd)
    assert abs(rows[:, 0].mean() - 1.0) < 0.05
    assert np.array_equal(spread_design(box, 64, seed=2), rows)
    with pytest.raises(ModelError, match="a power of two"):
        spread_design(box, 10, seed=2)


def test_morris_drops_a_trajectory_with_a_failed_point_and_counts_it():
    k = len(ISHIGAMI)
    rows = morris_design(ISHIGAMI, 12, seed=4)
    values = np.array([ishigami(r)[0] for r in rows])
    broken = values.copy()
    broken[3 * (k + 1) + 2] = np.nan  # a point inside trajectory 3
    table = morris_indices(ISHIGAMI, rows, broken, output="f", unit="-", seed=4)
    assert (table.samples, table.dropped) == (11, 1)
    # the indices are those of the design without that trajectory, to the last bit
    keep = np.ones(len(rows), dtype=bool)
    keep[3 * (k + 1) : 4 * (k + 1)] = False
    alone = morris_indices(ISHIGAMI, rows[keep], values[keep], output="f", unit="-", seed=4)
    assert table.morris == alone.morris
    with pytest.raises(ConvergenceError, match="11 of 12 trajectories hold a failed evaluation; fewer than 2"):
        morris_indices(ISHIGAMI, rows, np.where(np.arange(len(rows)) < 11 * (k + 1), np.nan, values), output="f",
                       unit="-", seed=4)


def test_sobol_drops_a_base_sample_with_a_failed_point_and_reports_the_effective_sample_size():
    k = len(ISHIGAMI)
    rows = sobol_design(ISHIGAMI, 256, seed=5)
    values = np.array([ishigami(r)[0] for r in rows])
    broken = values.copy()
    broken[[7, 5 * (k + 2), 5 * (k + 2) + 1, 200 * (k + 2) + k + 1]] = np.nan  # base samples 1, 5 and 200
    table = sobol_indices(ISHIGAMI, rows, broken, output="f", unit="-", seed=5)
    assert (table.samples, table.dropped) == (253, 3)
    keep = np.repeat(~np.isin(np.arange(256), [1, 5, 200]), k + 2)
    alone = sobol_indices(ISHIGAMI, rows[keep], values[keep], output="f", unit="-", seed=5)
    assert table.sobol == alone.sobol and table.mean == alone.mean
