"""The headline numbers pinned: the case-study recommendation, the robust design and its tolerance
band, and Table 2 tied to independent estimates.

Each value is a regression value computed once with this code on the built-in models, with the
paper's number (``presag_opt.validation.paper``) and the difference beside it. Tolerances: the
form-finding result is identical to all printed digits when its force and geometry tolerances are
tightened 100 × and 50 × (measured), so the pins use 1e-4 relative, room for floating-point
differences between platforms (BLAS, IPOPT iterates), far below any change of the model: the
smallest documented difference from the paper is 2 %.
"""

from __future__ import annotations

import numpy as np
import pytest

from presag_opt.design import CASE_STUDY_BAND, layout_recommendation, section_elasticity
from presag_opt.elasticity import linear_elasticity
from presag_opt.robust import build_path_model, robust_study
from presag_opt.static.form_finding import form_find
from presag_opt.system.loader import load_catenary
from presag_opt.validation import PAPER_RECOMMENDATION, PAPER_TABLE1, PAPER_TABLE2_MM, table2_row

PIN = 1e-4
"""Relative tolerance of a regression pin (see the module docstring)."""

# S_rel range ends [‰] of the case-study band (F_m 70–147.9 N, Δe rule, active-set elasticity at
# 50/100/150 N). Paper: ideal 0.68–1.35 (ours +3.6 %, −2.1 %); mixed 0.82–1.62 (ours −24 %, −33 %: the
# paper's 31 span lengths are not published, ours are a stand-in list, models/README.md).
IDEAL_RANGE = (0.7043610, 1.3212899)
MIXED_RANGE = (0.6199784, 1.0860220)
# Recommended S_rel [‰] = mean of the four range ends. Paper 1.12 ‰ (ours −17 %, from the mixed range).
RECOMMENDED = 0.9329128
# Robust minimax parabola over F_m 70–148 N on ST 9,8/9,8 ideal spans [mm]: the paper has no robust
# design; its nearest number is the recommended 67 mm (ours 55.8 mm, −17 %). The nominal design is the
# Δe rule over the band as the recommendation defines it, the mean of the S_rel range ends on the model's
# own geometry (60.81 mm; until this version the rule at the band centre on the robust geometry, 61.38 mm,
# a second number for one rule).
ROBUST = {
    "presag": 55.80729,
    "worst": 24.39085,
    "nominal_presag": 60.80786,
    "nominal_worst": 29.22630,
    "tolerance": (50.93509, 58.33091),
    "centre_tolerance": (50.32047, 57.99680),
}


@pytest.fixture(scope="module")
def mixed_layout(st98_mixed):
    """The mixed layout of the case study (31-span section, the same form-finding as ``recommend``)."""
    low, high = CASE_STUDY_BAND.mean_force_band()
    section = section_elasticity(st98_mixed, force_levels=(50.0, 100.0, 150.0), elasticity_method="active-set")
    return layout_recommendation(section, CASE_STUDY_BAND)


@pytest.fixture(scope="module")
def study():
    return robust_study(load_catenary("st_9.8_ideal"), (70.0, 148.0))


def test_case_study_recommendation(short_recommendation, mixed_layout):
    # The ideal layout of ``short_recommendation`` is the case study's ideal layout (same model).
    ideal = short_recommendation.layouts[0]
    assert ideal.layout_kind == "ideal"
    assert np.array(ideal.presag_rel_range) * 1e3 == pytest.approx(IDEAL_RANGE, rel=PIN)
    assert np.array(mixed_layout.presag_rel_range) * 1e3 == pytest.approx(MIXED_RANGE, rel=PIN)
    ends = [*ideal.presag_rel_range, *mixed_layout.presag_rel_range]
    assert np.mean(ends) * 1e3 == pytest.approx(RECOMMENDED, rel=PIN)
    # Beside the paper: ideal ends within 4 % of the paper's (the model's assumed parameters), the
    # recommendation below the paper's by the documented 17 % (± 1 %, printed digits of 1.12).
    paper = PAPER_RECOMMENDATION["presag_rel_range_permille"]
    assert np.array(IDEAL_RANGE) == pytest.approx(paper["ideal"], rel=0.04)
    assert RECOMMENDED / PAPER_RECOMMENDATION["presag_rel_permille"] - 1.0 == pytest.approx(-0.167, abs=0.01)
    # β at 90 km/h: 0.2612 against the paper's 0.26 (two printed digits: ± 0.005).
    assert mixed_layout.speed.beta_max == pytest.approx(PAPER_RECOMMENDATION["beta_max"], abs=0.005)
    assert mixed_layout.speed.beta_max == pytest.approx(0.2612275, rel=PIN)


def test_the_ideal_layouts_static_uplift_stays_below_the_limit(short_recommendation):
    uplift = short_recommendation.layouts[0].steady_arm_uplift
    assert uplift.uplift * 1e3 == pytest.approx(53.85102, rel=PIN)  # limit 83.5 mm
    assert uplift.within_limit and not short_recommendation.warnings


def test_robust_study_headline(study):
    pinned = {
        "presag": study.robust.presag_rel * study.reference_span * 1e3,
        "worst": study.robust.worst_case_waviness * 1e3,
        "nominal_presag": study.nominal.presag_rel * study.reference_span * 1e3,
        "nominal_worst": study.nominal.worst_case_waviness * 1e3,
        "tolerance": np.array([study.tolerance.low, study.tolerance.high]) * study.reference_span * 1e3,
        "centre_tolerance": np.array([study.centre_tolerance.low, study.centre_tolerance.high])
        * study.reference_span
        * 1e3,
    }
    for key, value in ROBUST.items():
        assert pinned[key] == pytest.approx(value, rel=PIN), key


def test_robust_waviness_holds_on_the_re_form_found_geometry(study):
    """The LP's waviness comes from the path model, affine in the dropper depths about the geometry
    it was linearised on. Form-finding again at the design's own pre-sag and recomputing the
    elasticity gives the exact quasi-static waviness, independent of that linearisation.

    Measured: 0.04 % apart (the path was linearised 0.1 mm from the design's own pre-sag; for the
    nominal Δe design, 5.6 mm away, it is 1.1 %: the affine model's error grows with the distance).
    Tolerance 0.2 %, about five times the measured error, far below the 18 % gap between the robust
    and the nominal design.
    """
    design = study.robust
    state = form_find(load_catenary("st_9.8_ideal").with_presag(design.presag_rel))
    section = section_elasticity(state, force_levels=study.path.section.force_levels, elasticity_method="active-set")
    fresh = build_path_model(state, section)
    exact = fresh.waviness(fresh.reference_depth, study.scenarios.forces).max()
    assert exact == pytest.approx(design.worst_case_waviness, rel=2e-3)


def test_table2_against_the_linear_elasticity_and_the_paper(ideal71, ideal98, st71, st98):
    """Table 2's S = F_m·(e_mid − e_mast) at 140 N, tied to an independent computation.

    No dropper slackens at mid-span or at the masts at 140 N, so the re-solved curves Table 2 uses
    (active-set, interpolated between 100 and 150 N) equal the tangent-stiffness (linear) ones there:
    a different code path (one banded Cholesky factorisation, no re-solve). Tolerance 0.1 %, the
    active-set method's measured distance from Newton in e_mid is 0.06–0.09 %. The linear e_mid is
    itself tied to the two-string closed form in ``test_elasticity``.
    """
    for section, state in ((ideal71, st71), (ideal98, st98)):
        linear = linear_elasticity(state)
        row = table2_row(section, 140.0)
        assert row.presag_mid_mast == pytest.approx(140.0 * (linear.e_mid - linear.e_mast), rel=1e-3)
        # Beside the paper's Table 2 (S mid-mast): 7.1/7.1 86.3 vs 96 mm (−10.1 %), 9.8/9.8 62.0 vs
        # 58 mm (+6.9 %), ± 0.5 points for the paper's printed whole millimetres; Table 1's empirical
        # range (e_mast = 0.5…0.3 e_mid) holds ours.
        paper = PAPER_TABLE2_MM[row.tension_label]["mid-mast"]
        assert row.presag_mid_mast * 1e3 / paper - 1.0 == pytest.approx(
            {"7.1/7.1": -0.101, "9.8/9.8": 0.069}[row.tension_label], abs=0.005
        )
        low, high = PAPER_TABLE1[row.tension_label]["presag_mm"]
        assert low <= row.presag_mid_mast * 1e3 <= high


def test_case_study_decision():
    """``presag recommend`` of the case study, as pinned: the quasi-static robust design over the band's F_m
    70–147.9 N (55.77 mm; 55.81 mm over the rounded 70–148 N of ``ROBUST``), the Δe rule's number (the paper's
    mean of range ends) beside it; it keeps 2.5 mm to its tolerance's upper end, at least the assumed
    crew's ±2.5 mm; provisional until the dynamic tolerance is computed (``--dynamic-robust``)."""
    from presag_opt.design.decision import DELTA_E_RULE, QUASI_STATIC_ROBUST
    from presag_opt.pipeline.band import answer_band

    decision = answer_band().decision
    assert (decision.status, decision.basis) == ("provisional", QUASI_STATIC_ROBUST)
    assert decision.mm(decision.presag_rel) == pytest.approx(55.77360, rel=PIN)
    assert decision.mm(decision.answer(DELTA_E_RULE).presag_rel) == pytest.approx(RECOMMENDED * 60.0, rel=PIN)
    assert decision.mm(decision.margin()) >= 2.5  # the assumed crew's
    assert decision.validity.verdict == "holds" and decision.validity.beta_max == pytest.approx(0.2612275, rel=PIN)
