"""The fleet design: the pantograph axis of the operating grid, its weights and risk measures, and the
search over the fleet checked against known optima.

The search is exercised on pantograph types whose contact force is an exact affine function of the
pre-sag, F(t; S) = F_m + B b(t) + (S − S₀)·A a(t) with orthogonal zero-mean a and b, so that
σ²(S) = (B² + (S − S₀)² A²)/2 and σ/F_m has its minimum at the type's own S₀: the surrogate through
simulated pre-sags is then exact, and the optima are known in closed form.
"""

from __future__ import annotations

import cvxpy as cp
import numpy as np
import pytest

from presag_opt.errors import ModelError
from presag_opt.robust import BandEvaluation, BandStatistics, DynamicObjective, OperatingGrid, Risk, SearchSettings
from presag_opt.robust.fleet import FleetEvaluator, FleetGrid, fleet_robust_presag
from presag_opt.robust.lp import _risk_objective

SPAN = 60.0
TIME = np.linspace(0.0, 1.0, 2000, endpoint=False)


class AffineType:
    """A stand-in for one type's :class:`BandEvaluator`: one operating point, exact affine force in S."""

    def __init__(self, optimum_mm: float, slope: float, mean_force: float = 100.0, floor: float = 6.0):
        self.optimum = optimum_mm * 1e-3 / SPAN
        self.slope, self.mean_force, self.floor = slope, mean_force, floor
        self.grid = OperatingGrid(static_forces=(100.0,), speeds=(20.0,), aero_coefficient=0.0)
        self.evaluations: dict[float, BandEvaluation] = {}
        self.reference_span = SPAN
        self.spacings = None
        self.runs_used = 0

    def sigma(self, presag_rel: float) -> float:
        return float(np.sqrt(0.5 * (self.floor**2 + ((presag_rel - self.optimum) * SPAN * 1e3 * self.slope) ** 2)))

    def __call__(self, presag_rel):
        return self.evaluate_many([presag_rel])[0]

    def evaluate_many(self, presags):
        for s in presags:
            if s not in self.evaluations:
                force = (self.mean_force + self.floor * np.cos(2 * np.pi * 5 * TIME)
                         + (s - self.optimum) * SPAN * 1e3 * self.slope * np.sin(2 * np.pi * 3 * TIME))
                self.evaluations[s] = BandEvaluation(
                    statistics=BandStatistics(presag_rel=s, mean_force=np.array([force.mean()]),
                                              sigma=np.array([force.std()]), uplift_max=np.array([0.04])),
                    histories=(force,), loss_of_contact=np.zeros(1), wall_time=0.0)
                self.runs_used += 1
        return [self.evaluations[s] for s in presags]


def fleet_of(types, shares):
    fleet = object.__new__(FleetEvaluator)  # the real joining and bookkeeping, stand-in members
    fleet.grid = FleetGrid(grid=types[0].grid, names=tuple(f"type {k}" for k in range(len(types))),
                           shares=tuple(shares))
    fleet.members = list(types)
    fleet.evaluations = {}
    fleet.workers, fleet.progress = 1, None
    return fleet


def test_fleet_weights_carry_the_shares_and_split_a_train():
    grid = OperatingGrid(static_forces=(70.0, 140.0), speeds=(14.0, 20.0, 25.0), aero_coefficient=0.0)
    fleet = FleetGrid(grid=grid, names=("a", "b"), shares=(0.7, 0.3), pantographs_per_train=2)
    w = fleet.weights
    assert len(w) == 2 * 6 * 2
    assert w.sum() == pytest.approx(1.0, abs=1e-15)
    assert fleet.of_type(w, 0).sum() == pytest.approx(0.7, abs=1e-15)
    # both pantographs of a train carry half its point's weight
    assert np.array_equal(fleet.of_type(w, 1)[0::2], fleet.of_type(w, 1)[1::2])
    with pytest.raises(ModelError, match="must be non-negative and sum to 1"):
        FleetGrid(grid=grid, names=("a", "b"), shares=(0.7, 0.7))


def test_cvar_over_the_fleet_is_the_linear_program_and_a_known_value():
    grid = OperatingGrid(static_forces=(70.0, 105.0, 140.0), speeds=(14.0, 25.0), aero_coefficient=0.0)
    fleet = FleetGrid(grid=grid, names=("a", "b", "c"), shares=(0.5, 0.3, 0.2))
    rng = np.random.default_rng(3)
    losses = rng.uniform(0.05, 0.2, len(fleet.weights))
    risk = Risk(measure="cvar", level=0.9)
    loss = cp.Parameter(len(losses))
    weights = cp.Parameter(len(losses), nonneg=True)
    objective, constraints = _risk_objective(loss, weights, risk)
    loss.value, weights.value = losses, fleet.weights
    problem = cp.Problem(cp.Minimize(objective), constraints)
    problem.solve(solver=cp.CLARABEL)
    assert problem.status == cp.OPTIMAL
    # optimality: the LP (Rockafellar–Uryasev) value is the exact CVaR of the discrete distribution
    assert problem.value == pytest.approx(risk.value(losses, fleet.weights), abs=1e-7)
    # known value: a type holding more than the worst 10 % of the weight at one loss level is the CVaR
    stepped = np.concatenate([np.full(6, 0.10), np.full(6, 0.12), np.full(6, 0.30)])
    assert risk.value(stepped, fleet.weights) == pytest.approx(0.30, abs=1e-12)
    assert Risk(measure="mean").value(stepped, fleet.weights) == pytest.approx(0.5 * 0.10 + 0.3 * 0.12 + 0.2 * 0.30)


def test_fleet_minimax_lies_where_the_two_types_cross():
    a, b = AffineType(optimum_mm=40.0, slope=0.4), AffineType(optimum_mm=60.0, slope=0.4)
    fleet = fleet_of([a, b], (0.5, 0.5))
    search = SearchSettings(presag_tolerance=0.5e-3)
    design = fleet_robust_presag(fleet, DynamicObjective(), starts=(45e-3 / SPAN, 55e-3 / SPAN), search=search)
    # equal slopes and floors: the curves cross half-way, at 50 mm, σ/F_m = √((6² + (10·0.4)²)/2)/100
    known = np.sqrt(0.5 * (6.0**2 + 4.0**2)) / 100.0
    assert design.fleet.presag * 1e3 == pytest.approx(50.0, abs=0.5)
    assert design.fleet.worst_case_objective == pytest.approx(known, rel=1e-3)
    own = {t.name: t for t in design.per_type}
    assert own["type 0"].design.presag * 1e3 == pytest.approx(40.0, abs=0.5)
    assert own["type 1"].design.presag * 1e3 == pytest.approx(60.0, abs=0.5)
    # each type's own optimum serves the fleet worse than the fleet design (the other type at 20 mm off)
    worst_at_own = np.sqrt(0.5 * (6.0**2 + 8.0**2)) / 100.0
    for t in design.per_type:
        assert t.fleet_worst_case == pytest.approx(worst_at_own, rel=2e-3)
        assert t.fleet_worst_case > design.fleet.worst_case_objective
    low, high = design.to_dict()["tolerance_mm"]
    assert low < 50.0 < high


def test_share_weighted_mean_follows_the_larger_share():
    a, b = AffineType(optimum_mm=40.0, slope=0.4), AffineType(optimum_mm=60.0, slope=0.4)
    fleet = fleet_of([a, b], (0.8, 0.2))
    objective = DynamicObjective(risk=Risk(measure="mean"))
    design = fleet_robust_presag(fleet, objective, starts=(45e-3 / SPAN, 55e-3 / SPAN),
                                 search=SearchSettings(presag_tolerance=0.5e-3))
    # brute force of 0.8 σ_a + 0.2 σ_b over S on a 0.01 mm grid
    grid = np.arange(30.0, 70.0, 0.01) * 1e-3 / SPAN
    values = np.array([0.8 * a.sigma(s) + 0.2 * b.sigma(s) for s in grid]) / 100.0
    best = grid[int(np.argmin(values))] * SPAN * 1e3
    assert design.fleet.presag * 1e3 == pytest.approx(best, abs=0.6)
    assert design.fleet.objective == pytest.approx(values.min(), rel=2e-3)
    assert abs(design.fleet.presag * 1e3 - 40.0) < abs(design.fleet.presag * 1e3 - 60.0)


def test_one_type_fleet_is_the_band_evaluation_and_a_train_has_a_point_per_pantograph():
    from presag_opt.robust import BandEvaluator
    from tests.robust.test_dynamic_search import CATENARY, GRID, PANTOGRAPH, SETTINGS
    from tests.robust.test_dynamic_search import SPAN as SHORT

    design = 0.012 / SHORT
    alone = BandEvaluator(CATENARY, PANTOGRAPH, GRID, settings=SETTINGS)(design).statistics
    fleet = FleetEvaluator(CATENARY, [PANTOGRAPH], (1.0,), GRID, settings=SETTINGS)(design).statistics
    for field in ("mean_force", "sigma", "uplift_max"):
        assert np.array_equal(getattr(alone, field), getattr(fleet, field))
    train = FleetEvaluator(CATENARY, [PANTOGRAPH], (1.0,), GRID, spacing=10.0, settings=SETTINGS)(design).statistics
    assert len(train.sigma) == 2 * len(alone.sigma)
    assert np.array_equal(train.uplift_max[0::2], train.uplift_max[1::2])  # one uplift per run
    # the trailing pantograph runs on a wire its leader has set swinging: its σ differs
    assert np.abs(train.sigma[1::2] / train.sigma[0::2] - 1.0).max() > 0.01
