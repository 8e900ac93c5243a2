"""Tolerance bands (presag_opt.robust.tolerance)."""

from __future__ import annotations

import pytest

from presag_opt.robust import tolerance_band


def test_tolerance_band_contains_the_optimum_and_its_ends_are_on_the_bound(path, scenarios):
    tol = tolerance_band(path, scenarios, within=0.10)
    assert tol.low < tol.best < tol.high
    for end in (tol.low, tol.high):
        worst = path.waviness(path.parabola_depths(end), scenarios.forces).max()
        assert worst == pytest.approx(1.10 * tol.best_objective, rel=1e-4)
    outside = path.waviness(path.parabola_depths(tol.high + 2e-5), scenarios.forces).max()
    assert outside > 1.10 * tol.best_objective
