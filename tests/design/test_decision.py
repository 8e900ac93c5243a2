"""The decision procedure (presag_opt.design.decision): each branch on constructed inputs, and the
report case the issue quotes (a headline outside its own tolerance, validity unreadable, uplift over)."""

from __future__ import annotations

import pytest

from presag_opt.design.decision import (
    DELTA_E_RULE,
    DYNAMIC_ROBUST,
    QUASI_STATIC_ROBUST,
    Candidate,
    DecisionInputs,
    decide,
    highest_static_force_static,
)
from presag_opt.errors import ModelError

LIMIT = 0.0835


def qs(s_rel, uplift=0.06, dynamic=True):
    return (Candidate(method=DELTA_E_RULE, presag_rel=s_rel * 1.05, uplift=uplift, uplift_dynamic=dynamic),
            Candidate(method=QUASI_STATIC_ROBUST, presag_rel=s_rel, tolerance=(0.9 * s_rel, 1.1 * s_rel),
                      uplift=uplift, uplift_dynamic=dynamic))


def test_low_beta_and_inside_the_dynamic_tolerance_builds_the_quasi_static_robust_design():
    d = decide(DecisionInputs(candidates=qs(1e-3), beta_max=0.26, dynamic_tolerance=(0.8e-3, 1.2e-3)))
    assert (d.chosen.method, d.status) == (QUASI_STATIC_ROBUST, "decided")
    assert [c.method for c in d.alternatives] == [DELTA_E_RULE]
    assert "0.26" in d.reason and "0.35" in d.reason


def test_outside_the_dynamic_tolerance_falls_back_to_the_delta_e_rule_then_the_dynamic_design():
    candidates = qs(1e-3)
    # the tolerance holds the Δe rule (1.05e-3) but not the robust design (1.0e-3)
    d = decide(DecisionInputs(candidates=candidates, beta_max=0.2, dynamic_tolerance=(1.02e-3, 1.2e-3)))
    assert d.chosen.method == DELTA_E_RULE
    dynamic = Candidate(method=DYNAMIC_ROBUST, presag_rel=0.7e-3, uplift=0.07, uplift_dynamic=True)
    d = decide(DecisionInputs(candidates=(*candidates, dynamic), beta_max=0.2, dynamic_tolerance=(0.6e-3, 0.8e-3)))
    assert (d.chosen.method, d.status) == (DYNAMIC_ROBUST, "decided")
    assert "outside the dynamic tolerance 0.60–0.80 ‰" in d.reason


def test_above_the_validity_limit_the_dynamic_design_decides_or_the_decision_is_provisional():
    dynamic = Candidate(method=DYNAMIC_ROBUST, presag_rel=0.8e-3, uplift=0.07, uplift_dynamic=True)
    d = decide(DecisionInputs(candidates=(*qs(1e-3), dynamic), beta_max=0.45, beta_limit=0.4, beta_limit_uncertainty=0.05))
    assert (d.chosen.method, d.status) == (DYNAMIC_ROBUST, "decided")
    assert "β* = 0.40 ± 0.05" in d.reason
    d = decide(DecisionInputs(candidates=qs(1e-3), beta_max=0.45))
    assert d.status == "provisional" and "was not computed" in d.reason
    # β at the study's limit minus its uncertainty is still trusted; just above it is not
    assert decide(DecisionInputs(candidates=qs(1e-3), beta_max=0.35, beta_limit=0.4, beta_limit_uncertainty=0.05,
                                 dynamic_tolerance=(0.8e-3, 1.2e-3))).status == "decided"
    assert decide(DecisionInputs(candidates=qs(1e-3), beta_max=0.36, beta_limit=0.4,
                                 beta_limit_uncertainty=0.05)).status == "provisional"


def test_the_issue_report_case_is_uplift_bound_with_the_highest_static_force():
    """ST 7,1/7,1 at 120 km/h (quick report): Δe rule 85 mm, robust 81 mm in 77–85 mm on 60 m, validity not
    readable, dynamic uplift 93.7 mm at every swept pre-sag: no S keeps 83.5 mm; the sweep kept it at 70 N."""
    on60 = 1 / 60.0
    candidates = (Candidate(method=DELTA_E_RULE, presag_rel=0.085 * on60, uplift=0.0937, uplift_dynamic=True),
                  Candidate(method=QUASI_STATIC_ROBUST, presag_rel=0.081 * on60, tolerance=(0.077 * on60, 0.085 * on60),
                            uplift=0.0937, uplift_dynamic=True))
    d = decide(DecisionInputs(candidates=candidates, beta_max=0.41, highest_static_force=70.0))
    assert d.status == "uplift-bound"
    assert d.headline(60.0).startswith("No pre-sag keeps the steady-arm uplift limit")
    assert "93.7 mm" in d.reason and "83.5 mm" in d.reason and "70 N" in d.reason
    # ... unless a pre-sag outside the answers kept it in the sweep: then the dynamic design decides (not run)
    d = decide(DecisionInputs(candidates=candidates, beta_max=0.41, highest_static_force=140.0,
                              some_presag_keeps_uplift=True))
    assert d.status == "provisional" and "uplift 93.7 mm over the limit 83.5 mm" in d.reason


def test_static_uplift_bound_and_its_highest_static_force():
    # F_m·e = limit: e = 0.6 mm/N -> F_m 139.2 N; α v² = 0.00097·90² = 7.857 N -> F_stat 131.3 N
    force = highest_static_force_static(0.6e-3, LIMIT, 0.00097 * 3.6**2, 90 / 3.6)
    assert force == pytest.approx(LIMIT / 0.6e-3 - 0.00097 * 90**2, rel=1e-12)
    c = Candidate(method=DELTA_E_RULE, presag_rel=1e-3, uplift=0.6e-3 * 147.9)
    d = decide(DecisionInputs(candidates=(c,), beta_max=0.26, highest_static_force=force))
    assert d.status == "uplift-bound" and "static estimate" in d.reason and "131 N" in d.reason


def test_bad_inputs():
    with pytest.raises(ModelError, match="at least one candidate"):
        DecisionInputs(candidates=(), beta_max=0.2)
    with pytest.raises(ModelError, match="beta_max = 1.2 is outside the valid range"):
        DecisionInputs(candidates=qs(1e-3), beta_max=1.2)
    with pytest.raises(ModelError, match="presag_rel = 7 ‰ is outside the valid range"):
        Candidate(method=DELTA_E_RULE, presag_rel=7e-3)
    with pytest.raises(ModelError, match="is not one of"):
        Candidate(method="guess", presag_rel=1e-3)


def test_a_dynamic_robust_design_enters_as_a_candidate():
    from types import SimpleNamespace

    from presag_opt.design.decision import dynamic_candidate

    design = SimpleNamespace(presag_rel=0.75e-3, uplift_max=0.062)
    tolerance = SimpleNamespace(low=0.65e-3, high=0.9e-3)
    c = dynamic_candidate(design, tolerance)
    assert (c.method, c.presag_rel, c.tolerance, c.uplift, c.uplift_dynamic) == (
        DYNAMIC_ROBUST, 0.75e-3, (0.65e-3, 0.9e-3), 0.062, True)
    # the case study's shape: β well inside, the quasi-static robust S inside the dynamic tolerance -> it is built
    d = decide(DecisionInputs(candidates=(*qs(0.93e-3, uplift=0.055), c), beta_max=0.26, beta_limit=0.55,
                              beta_limit_uncertainty=0.06, dynamic_tolerance=(0.65e-3, 0.95e-3)))
    assert (d.chosen.method, d.status) == (QUASI_STATIC_ROBUST, "decided")
    assert [a.method for a in d.alternatives] == [DELTA_E_RULE, DYNAMIC_ROBUST]
