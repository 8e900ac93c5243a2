"""``presag_opt.validation.paper``: the paper's published numbers (doi:10.1108/RS-05-2025-0016) as
transcribed, checked for consistency with each other and with the paper's own formulas, so that a
typing slip in a transcription fails here and not as a puzzling comparison elsewhere."""

from __future__ import annotations

import pytest

from presag_opt.system.loader import builtin_model_names, load_catenary
from presag_opt.validation import paper


@pytest.mark.parametrize(("system", "tension"), [("7.1/7.1", 7.1e3), ("9.8/9.8", 9.8e3)])
def test_table1_e_mid_is_eq1_to_its_printed_digits(system, tension):
    """Eq. (1): e_mid = l/(4(T_CW + T_MW)) at l = 60 m, printed to 1e-3 mm/N (so within 5e-4)."""
    row = paper.PAPER_TABLE1[system]
    e_mid = paper.PAPER_TABLE1_SPAN_LENGTH / (4 * 2 * tension) * 1e3
    assert row["e_mid_mm_per_N"] == pytest.approx(e_mid, abs=5e-4)


@pytest.mark.parametrize("system", ["7.1/7.1", "9.8/9.8"])
def test_table1_relative_presag_is_its_presag_over_60_m_to_the_printed_digits(system):
    """S_rel = S/l: printed to 0.01 ‰ from S printed to 1 mm (so within 0.01 ‰ + 1 mm/60 m/2)."""
    row = paper.PAPER_TABLE1[system]
    for s_mm, s_rel in zip(row["presag_mm"], row["presag_rel_permille"]):
        assert s_rel == pytest.approx(s_mm / paper.PAPER_TABLE1_SPAN_LENGTH, abs=0.005 + 0.5 / 60.0)


@pytest.mark.parametrize(("system", "tension"), [("7.1/7.1", 7.1e3), ("9.8/9.8", 9.8e3)])
def test_table1_presag_spans_0_5_to_0_7_times_the_static_force_elasticity(system, tension):
    """Table 1's empirical rule S = (0.5 … 0.7)·F_stat·e_mid at 140 N, with e_mid of eq. (1) unrounded
    (0.7·140·1.0563 = 103.5 → 104 mm; with the printed 1.056 it would round to 103), rounded to 1 mm."""
    e_mid = paper.PAPER_TABLE1_SPAN_LENGTH / (4 * 2 * tension) * 1e3
    low, high = (f * paper.PAPER_TABLE1_STATIC_FORCE * e_mid for f in (0.5, 0.7))
    assert paper.PAPER_TABLE1[system]["presag_mm"] == (round(low), round(high))


def test_the_case_study_recommendation_is_consistent_in_itself():
    rec = paper.PAPER_RECOMMENDATION
    # S = S_rel × 60 m: 1.12 ‰ × 60 m = 67.2 mm, printed as 67 mm
    assert rec["presag_mm"] == round(rec["presag_rel_permille"] * 60.0)
    # the recommended S_rel lies inside the ranges of both layouts
    for low, high in rec["presag_rel_range_permille"].values():
        assert low < rec["presag_rel_permille"] < high
    assert rec["fm_band_N"][0] < rec["fm_band_N"][1]


def test_table2_keeps_the_papers_orderings():
    """The Δe rule asks more than mid/mast, and the softer 7.1/7.1 system more than the 9.8/9.8 one."""
    t2 = paper.PAPER_TABLE2_MM
    assert all(row["delta-e"] > row["mid-mast"] for row in t2.values())
    assert t2["7.1/7.1"]["delta-e"] > t2["9.8/9.8"]["delta-e"] and t2["7.1/7.1"]["mid-mast"] > t2["9.8/9.8"]["mid-mast"]
    assert paper.PAPER_TABLE2_FORCE == paper.PAPER_TABLE1_STATIC_FORCE


def test_the_models_named_are_built_in_and_of_the_tension_they_say():
    names = builtin_model_names()
    for name, tension in zip(paper.PAPER_TABLE2_MODELS, (7.1e3, 9.8e3)):
        assert name in names
        catenary = load_catenary(name)
        assert (catenary.contact_wire.tension, catenary.messenger_wire.tension) == (tension, tension)
    assert paper.SINGLE_CURVE_MODEL in names
    assert set(paper.PAPER_SINGLE_CURVE_ERROR) == {0.030, 0.070}  # the two geometries of Fig. 5b
