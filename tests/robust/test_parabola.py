"""The parabolic design's exact search (presag_opt.robust.parabola): against an LP written here, a brute-force
scan, closed forms of a two-point path, and its refusals."""

from __future__ import annotations

import numpy as np
import pytest

from presag_opt.errors import ModelError
from presag_opt.robust import ForceScenarios, Risk
from presag_opt.robust.parabola import ParabolaObjective


def _lp_minimax(objective: ParabolaObjective, bound: float | None = None, sense: str = "min") -> float:
    """The parabola's minimax optimum (bound None) or an end of its sublevel interval, as an LP written
    independently of the search: epigraph variables over every scenario's and span's max and min. [-]"""
    import cvxpy as cp

    s = cp.Variable(nonneg=True)
    h = objective.offset + cp.reshape(objective.slope, (1, objective.slope.size), order="C") * s
    ends = list(objective.starts) + [objective.slope.size]
    spread = []
    for k in range(objective.offset.shape[0]):
        for a, b in zip(ends[:-1], ends[1:]):
            spread.append(cp.max(h[k, a:b]) - cp.min(h[k, a:b]))
    worst = cp.max(cp.hstack(spread))
    if bound is None:
        problem = cp.Problem(cp.Minimize(worst))
    else:
        problem = cp.Problem(cp.Minimize(s) if sense == "min" else cp.Maximize(s), [worst <= bound])
    problem.solve(solver=cp.CLARABEL)
    assert problem.status == cp.OPTIMAL
    return float(s.value)


@pytest.fixture(scope="module")
def objective(path, scenarios):
    return ParabolaObjective.of(path, scenarios)


def test_the_minimum_equals_an_independent_lp(objective):
    """Clarabel's gap tolerance is 1e-8: S* agrees to 1e-6 relative (0.06 mm on 60 m would be 1e-3)."""
    best, value = objective.minimum()
    lp = _lp_minimax(objective)
    assert best == pytest.approx(lp, rel=1e-6)
    assert value <= objective(lp) + 1e-12  # the search is never beaten by the LP's point


def test_the_tolerance_interval_equals_the_independent_lps(objective):
    best, value = objective.minimum()
    bound = 1.1 * value
    low, high = objective.sublevel_interval(best, bound)
    assert low == pytest.approx(_lp_minimax(objective, bound, "min"), rel=1e-6)
    assert high == pytest.approx(_lp_minimax(objective, bound, "max"), rel=1e-6)
    assert objective(low) <= bound and objective(high) <= bound
    assert objective(high + 1e-9) > bound  # 1e-9 · 60 m = 0.06 µm beyond the end is outside
    assert low == 0.0 or objective(low - 1e-9) > bound


@pytest.mark.parametrize("risk", ["minimax", "mean", "cvar:0.9"])
def test_every_risk_measure_is_minimised(path, risk):
    """A scan at 0.0005 ‰ never beats the search; the search is a minimum (no lower value 1e-7 to
    either side: J is convex)."""
    objective = ParabolaObjective.of(path, ForceScenarios.band(70.0, 150.0), Risk.parse(risk))
    best, value = objective.minimum()
    scan = min(objective(s) for s in np.linspace(0.0, 2.5e-3, 5001))
    assert value <= scan + 1e-12
    assert value <= objective(best + 1e-7) and value <= objective(max(best - 1e-7, 0.0))


def _two_points(a: float, b: float) -> ParabolaObjective:
    """A path of two points in one span under one force: h = (0, a − b·S), so J(S) = |a − b·S|. [m]"""
    return ParabolaObjective(offset=np.array([[0.0, a]]), slope=np.array([0.0, -b]), starts=np.array([0]),
                             weights=np.array([1.0]), risk=Risk())


def test_a_two_point_path_has_its_closed_form():
    """J = |a − b·S|: minimum 0 at S = a/b, interval (a ∓ B)/b; resolution 1e-12 in S."""
    objective = _two_points(0.02, 10.0)
    best, value = objective.minimum()
    assert best == pytest.approx(2e-3, abs=1e-11) and value == pytest.approx(0.0, abs=1e-10)
    low, high = objective.sublevel_interval(best, 0.005)
    assert low == pytest.approx(1.5e-3, abs=1e-11) and high == pytest.approx(2.5e-3, abs=1e-11)


def test_a_waviness_that_only_falls_is_refused():
    """J = |1 − S| falls up to S = 1000 ‰: no physical optimum, said in one line."""
    with pytest.raises(ModelError, match="still falls at S_rel"):
        _two_points(1.0, 1.0).minimum()


def test_an_interval_without_an_upper_end_is_refused():
    flat = _two_points(0.0, 0.0)
    with pytest.raises(ModelError, match="no upper end of the tolerance interval"):
        flat.sublevel_interval(0.0, 0.001)
