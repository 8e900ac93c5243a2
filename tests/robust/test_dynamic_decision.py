"""The dynamic robust design in the decision (presag_opt.robust.dynamic_decision): a provisional decision
becomes final where the dynamic design decides, with the method and its reason stated."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest

from presag_opt.design import CASE_STUDY_BAND
from presag_opt.design.band import KMH
from presag_opt.design.decision import (
    DELTA_E_RULE,
    DYNAMIC_ROBUST,
    QUASI_STATIC_ROBUST,
    Candidate,
    DecisionInputs,
    decide,
)
from presag_opt.robust.dynamic_decision import decision_with_dynamic, simulated_band
from presag_opt.robust.dynamic_study import QUASI_STATIC

# The case study's numbers (presag robust --dynamic, measured this session): Δe rule 56 mm (recommend's S_rel),
# quasi-static robust 56.7 mm with a simulated uplift of 50.9 mm, dynamic robust 45.1 mm, tolerance 28.0–56.1 mm,
# uplift 52.9 mm; β_max = 0.26.
L = 60.0


def study(dynamic_mm=45.09, tolerance_mm=(28.0, 56.125), uplift_mm=52.9, quasi_mm=56.71, quasi_uplift_mm=50.9):
    """A stand-in of DynamicRobustStudy with the attributes the decision reads."""
    grid = SimpleNamespace(static_forces=(70.0, 93.3, 116.7, 140.0), speeds=(50 * KMH, 70 * KMH, 90 * KMH))
    quasi = SimpleNamespace(presag_rel=quasi_mm / L / 1e3, uplift_max=quasi_uplift_mm / 1e3)
    return SimpleNamespace(
        design=SimpleNamespace(presag_rel=dynamic_mm / L / 1e3, uplift_max=uplift_mm / 1e3, grid=grid),
        tolerance=SimpleNamespace(low=tolerance_mm[0] / L / 1e3, high=tolerance_mm[1] / L / 1e3),
        method=lambda name: {QUASI_STATIC: quasi}[name],
    )


def quick(delta_e_mm=56.0, beta_max=0.26, uplift_mm=53.9):
    return decide(DecisionInputs(
        candidates=(Candidate(method=DELTA_E_RULE, presag_rel=delta_e_mm / L / 1e3, uplift=uplift_mm / 1e3),),
        beta_max=beta_max,
        not_checked=("the quasi-static robust design and its tolerance (presag robust)",
                     "the dynamic robust design and its tolerance (this command with --dynamic-robust, or presag robust --dynamic)")))


def test_the_case_study_decision_becomes_final_with_the_dynamic_design():
    before = quick()
    assert before.status == "provisional"
    after = decision_with_dynamic(before, study(), "the case study's ideal section")
    # β_max 0.26 is trusted; the study's robust design, 56.7 mm, lies outside the dynamic tolerance 28.0-56.1 mm,
    # the Δe rule, 56.0 mm, inside it (by 0.1 mm): the Δe rule is built and the decision is final.
    assert after.status == "decided"
    assert after.chosen.method == DELTA_E_RULE
    assert "inside the dynamic tolerance" in after.reason
    assert {c.method for c in after.alternatives} == {QUASI_STATIC_ROBUST, DYNAMIC_ROBUST}
    assert not any("dynamic robust design and its tolerance" in n for n in after.inputs.not_checked)
    assert any("the case study's ideal section" in n for n in after.inputs.not_checked)
    assert after.inputs.dynamic_tolerance == pytest.approx((28.0 / L / 1e3, 56.125 / L / 1e3), rel=1e-12)


def test_the_dynamic_design_decides_where_no_quasi_static_answer_is_inside_its_tolerance():
    after = decision_with_dynamic(quick(delta_e_mm=61.4), study(), "x")
    assert after.status == "decided" and after.chosen.method == DYNAMIC_ROBUST
    assert after.chosen.presag_rel * L * 1e3 == pytest.approx(45.09, rel=1e-12)
    assert "the dynamic robust design decides" in after.reason
    assert "outside the dynamic tolerance" in after.reason
    assert [c.method for c in after.alternatives] == [QUASI_STATIC_ROBUST, DELTA_E_RULE]
    lines = after.lines(L)
    assert lines[0] == "Pre-sag to build: 0.75 ‰ = 45 mm on 60 m (dynamic robust design)"
    assert any(line.startswith("  alternative: quasi-static Δe rule") for line in lines)


def test_above_the_validity_limit_the_dynamic_design_decides_even_inside_its_tolerance():
    after = decision_with_dynamic(quick(beta_max=0.45), study(), "x")
    assert after.chosen.method == DYNAMIC_ROBUST and after.status == "decided"
    assert "β_max = 0.45 is above" in after.reason


def test_a_dynamic_design_over_the_uplift_limit_is_uplift_bound():
    after = decision_with_dynamic(quick(beta_max=0.45), study(uplift_mm=90.0, quasi_uplift_mm=95.0), "x")
    assert after.status == "uplift-bound"


def test_a_decision_that_has_a_robust_design_keeps_it():
    inputs = quick().inputs
    robust = Candidate(method=QUASI_STATIC_ROBUST, presag_rel=55.8 / L / 1e3, tolerance=(51 / L / 1e3, 58 / L / 1e3))
    before = decide(DecisionInputs(candidates=inputs.candidates + (robust,), beta_max=0.26))
    after = decision_with_dynamic(before, study(), "x")
    kept = next(c for c in (after.chosen, *after.alternatives) if c.method == QUASI_STATIC_ROBUST)
    assert kept is robust
    assert after.chosen is robust and after.status == "decided"  # 55.8 mm inside 28.0-56.1 mm, robust preferred


def test_the_simulated_band_starts_at_50_kmh():
    band = simulated_band(CASE_STUDY_BAND)
    assert band.speed_low == pytest.approx(50 * KMH, rel=1e-12) and band.speed_high == CASE_STUDY_BAND.speed_high
    slow = simulated_band(CASE_STUDY_BAND.__class__(static_force_low=70.0, static_force_high=140.0, speed_low=0.0,
                                                    speed_high=40 * KMH, aero_coefficient=0.0))
    assert slow.speed_low == pytest.approx(20 * KMH, rel=1e-12)
    assert np.isclose(simulated_band(CASE_STUDY_BAND.__class__(
        static_force_low=70.0, static_force_high=140.0, speed_low=60 * KMH, speed_high=90 * KMH,
        aero_coefficient=0.0)).speed_low, 60 * KMH)
