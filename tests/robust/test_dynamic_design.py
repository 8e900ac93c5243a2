"""The dynamic robust search against brute force, on band evaluations whose answer is known exactly.

A synthetic evaluator stands in for the simulator: at grid point k the "filtered contact force" is
F_m,k + A_k(S)·√2 sin(ω t) + B_k·√2 sin(3ω t) over whole periods, so σ_k(S)² = A_k(S)² + B_k², with
A_k cubic in S (the history surrogate, exact only for affine A_k, has to earn its answer) and a
steady-arm uplift falling linearly with S. The slopes put the worst case's rise at about 1 %/mm on
either side of its minimum, as on the case study (0.5–1.4 %/mm between 30, 45 and 60 mm). Brute force
evaluates the same functions on a 0.05 mm grid.
The search against the real simulator is tested in ``test_dynamic_search.py``.
"""

from __future__ import annotations

import numpy as np
import pytest

from presag_opt.design.band import KMH, OperatingBand
from presag_opt.errors import ConvergenceError, ModelError
from presag_opt.robust.band_evaluation import BandEvaluation, BandStatistics
from presag_opt.robust.dynamic_design import (
    DynamicObjective,
    SearchSettings,
    dynamic_robust_presag,
    dynamic_tolerance,
)
from presag_opt.robust.operating_grid import OperatingGrid
from presag_opt.robust.scenarios import Risk
from presag_opt.robust.surrogate import HistorySurrogate

SPAN = 60.0
GRID = OperatingGrid.from_band(
    OperatingBand(static_force_low=70.0, static_force_high=140.0, speed_low=50 * KMH, speed_high=90 * KMH,
                  aero_coefficient=0.0),
    static_points=3, speed_points=2,
)
MEAN = np.array([70.0, 105.0, 140.0, 70.0, 105.0, 140.0])  # F_m of each point [N]
CENTRE = np.array([38.0, 55.0, 70.0, 45.0, 62.0, 78.0]) * 1e-3  # pre-sag where A_k = 0 [m]
SLOPE = np.array([0.30, 0.22, 0.18, 0.40, 0.28, 0.24]) * 0.4e3  # ∂A_k/∂S [N/m]
CUBIC = 1.5e5  # [N/m³]
FLOOR = np.array([4.0, 4.5, 5.0, 5.5, 6.0, 7.0])  # B_k [N]
UPLIFT = (0.080, 0.4)  # uplift at S = 0 [m] and its fall per metre of pre-sag [-]
TIME = np.linspace(0.0, 2.0, 4001)[:-1]  # 20 whole periods of 10 Hz


def amplitude(presag):
    d = presag - CENTRE
    return SLOPE * d + CUBIC * d**3


def exact(presag, floor=FLOOR):
    """Exact statistics at a pre-sag on the reference span. [m]"""
    a = amplitude(presag)
    return BandStatistics(presag_rel=presag / SPAN, mean_force=MEAN.copy(), sigma=np.sqrt(a**2 + floor**2),
                          uplift_max=np.full(len(MEAN), UPLIFT[0] - UPLIFT[1] * presag))


class SyntheticEvaluator:
    """The interface of BandEvaluator, with the band statistics above instead of simulations."""

    def __init__(self, floor=FLOOR):
        self.floor = floor
        self.grid = GRID
        self.reference_span = SPAN
        self.evaluations = {}
        self.runs_used = 0

    def __call__(self, presag_rel):
        presag_rel = float(presag_rel)
        if presag_rel not in self.evaluations:
            a = amplitude(presag_rel * SPAN)
            u, w = np.sqrt(2) * np.sin(2 * np.pi * 10 * TIME), np.sqrt(2) * np.sin(2 * np.pi * 30 * TIME)
            histories = tuple(m + ak * u + b * w for m, ak, b in zip(MEAN, a, self.floor))
            stats = exact(presag_rel * SPAN, self.floor)
            stats = BandStatistics(presag_rel=presag_rel, mean_force=np.array([np.mean(h) for h in histories]),
                                   sigma=np.array([np.std(h) for h in histories]), uplift_max=stats.uplift_max)
            self.evaluations[presag_rel] = BandEvaluation(statistics=stats, histories=histories,
                                                          loss_of_contact=np.zeros(len(MEAN)), wall_time=0.0)
            self.runs_used += len(MEAN)
        return self.evaluations[presag_rel]

    def evaluate_many(self, presags):
        return [self(s) for s in presags]


def brute_force(objective, low=0.0, high=0.150):
    """Best pre-sag [m] and objective on a 0.05 mm grid, limits kept."""
    presags = np.arange(low, high + 1e-9, 5e-5)
    values = np.array([objective.value(exact(s), GRID.weights) if objective.feasible(exact(s)) else np.inf
                       for s in presags])
    return presags[int(np.argmin(values))], float(values.min())


@pytest.mark.parametrize("risk", ["minimax", "mean", "cvar:0.7"])
def test_search_finds_the_brute_force_optimum(risk):
    objective = DynamicObjective(risk=Risk.parse(risk), uplift_limit=0.1)
    best, value = brute_force(objective)
    evaluator = SyntheticEvaluator()
    design = dynamic_robust_presag(evaluator, objective, starts=(0.0558 / SPAN, 0.0614 / SPAN))
    assert abs(design.presag - best) <= 1e-3  # 1 mm (issue)
    assert design.objective == pytest.approx(value, rel=0.01)  # 1 % (issue)
    assert design.statistics.simulated  # the answer is a simulated pre-sag, not the surrogate's
    assert design.runs_used == len(evaluator.evaluations) * len(MEAN)
    assert len(design.evaluated) <= 8


def test_the_uplift_limit_moves_the_optimum_to_its_boundary():
    free = brute_force(DynamicObjective(uplift_limit=0.1))[0]
    limit = UPLIFT[0] - UPLIFT[1] * (free + 0.010)  # met only 10 mm above the free optimum
    objective = DynamicObjective(uplift_limit=limit)
    best, value = brute_force(objective)
    assert best == pytest.approx(free + 0.010, abs=6e-5)
    design = dynamic_robust_presag(SyntheticEvaluator(), objective, starts=(0.0558 / SPAN, 0.0614 / SPAN))
    assert abs(design.presag - best) <= 1e-3
    assert design.objective == pytest.approx(value, rel=0.01)
    assert design.uplift_max <= limit


def test_tolerance_interval_matches_brute_force():
    objective = DynamicObjective(uplift_limit=0.1)
    evaluator = SyntheticEvaluator()
    design = dynamic_robust_presag(evaluator, objective, starts=(0.0558 / SPAN, 0.0614 / SPAN))
    searched = len(evaluator.evaluations)
    tolerance = dynamic_tolerance(evaluator, objective, within=0.10)
    presags = np.arange(0.0, 0.150, 5e-5)
    worst = np.array([objective.worst_case(exact(s)) for s in presags])
    inside = presags[worst <= 1.10 * worst.min()]
    assert np.all(np.diff(inside) < 7.5e-5)  # one interval
    low, high = tolerance.low * SPAN, tolerance.high * SPAN
    assert low == pytest.approx(inside[0], abs=1e-3) and high == pytest.approx(inside[-1], abs=1e-3)
    assert low < design.presag < high
    assert tolerance.worst_case_min == pytest.approx(worst.min(), rel=0.01)
    # each end simulated once (neither lay within 2.5 mm, a quarter of the first step, of a simulated pre-sag)
    assert len(evaluator.evaluations) == searched + 2 and tolerance.runs_used == 2 * len(MEAN)


def test_an_uplift_limit_no_presag_meets_names_the_smallest_uplift():
    objective = DynamicObjective(uplift_limit=0.010)  # below the 20 mm reached at S = 150 mm
    with pytest.raises(ModelError) as error:
        dynamic_robust_presag(SyntheticEvaluator(), objective, starts=(0.0558 / SPAN, 0.0614 / SPAN))
    message = str(error.value)
    assert "no pre-sag in 0–150 mm keeps the steady-arm uplift within the limit 10 mm" in message
    assert "the smallest uplift reached is 20.0 mm (at S = 150.0 mm)" in message


def test_a_band_without_contact_is_refused():
    evaluator = SyntheticEvaluator(floor=FLOOR * 10.0)  # σ ≥ 55 N at 70 N: F_m − 3σ ≤ −95 N for every S
    words = r"keeps contact \(F_m - 3 sigma > 0\).*largest F_m - 3 sigma reached is -95\.0 N \(at S = 4[56]\.\d mm\)"
    with pytest.raises(ModelError, match=words):
        dynamic_robust_presag(evaluator, DynamicObjective(uplift_limit=0.1), starts=(0.0558 / SPAN, 0.0614 / SPAN))


def test_a_search_that_does_not_settle_stops_with_its_reason():
    with pytest.raises(ConvergenceError, match="did not settle within 3 simulated pre-sags"):
        dynamic_robust_presag(SyntheticEvaluator(), DynamicObjective(uplift_limit=0.1),
                              starts=(0.120 / SPAN,), search=SearchSettings(max_evaluations=3))


def test_the_surrogate_is_exact_for_an_affine_history_and_at_simulated_presags():
    evaluator = SyntheticEvaluator()
    for s in (0.040, 0.050):
        evaluator(s / SPAN)
    surrogate = HistorySurrogate(list(evaluator.evaluations.values()))
    # between two simulated pre-sags A_k is affine up to the cubic term: at the midpoint the
    # interpolated σ differs from the exact one only by that term
    middle = surrogate.at(0.045 / SPAN)
    assert not middle.simulated
    cubic_free = np.sqrt((SLOPE * (0.045 - CENTRE) + CUBIC * ((0.040 - CENTRE) ** 3 + (0.050 - CENTRE) ** 3) / 2) ** 2
                         + FLOOR**2)
    np.testing.assert_allclose(middle.sigma, cubic_free, rtol=1e-9)
    assert surrogate.at(0.050 / SPAN) is evaluator.evaluations[0.050 / SPAN].statistics


def test_a_start_at_the_optimum_is_confirmed_by_a_third_presag():
    objective = DynamicObjective(uplift_limit=0.1)
    best, value = brute_force(objective)
    evaluator = SyntheticEvaluator()
    design = dynamic_robust_presag(evaluator, objective, starts=(best / SPAN, (best + 0.006) / SPAN))
    simulated = sorted(s * SPAN for s in evaluator.evaluations)
    assert len(simulated) >= 3 and simulated[0] < best  # the other start mirrored about the optimum
    assert abs(design.presag - best) <= 1e-3
    assert design.objective == pytest.approx(value, rel=0.01)
