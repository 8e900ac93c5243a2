"""The empirical rule (presag_opt.design.empirical): eq. 1–3 and the paper's Table 1 to the printed digits."""

from __future__ import annotations

import pytest

from presag_opt.design import EmpiricalPresag
from presag_opt.errors import ModelError
from presag_opt.validation import PAPER_TABLE1


@pytest.mark.parametrize("label", ["7.1/7.1", "9.8/9.8"])
def test_table1_is_reproduced_to_the_printed_digits(label):
    tension = float(label.split("/")[0]) * 1e3
    rule = EmpiricalPresag(span_length=60.0, contact_wire_tension=tension, messenger_wire_tension=tension, static_force=140.0)
    printed = rule.printed()
    paper = PAPER_TABLE1[label]
    # Exact equality: printed() rounds to the paper's digits, so any other value is a mismatch.
    assert printed["e_mid_mm_per_N"] == paper["e_mid_mm_per_N"]
    assert printed["presag_mm"] == paper["presag_mm"]
    assert printed["presag_rel_permille"] == paper["presag_rel_permille"]


def test_table1_rounds_presag_to_mm_before_dividing():
    rule = EmpiricalPresag(span_length=60.0, contact_wire_tension=9.8e3, messenger_wire_tension=9.8e3, static_force=140.0)
    # Unrounded: 53.57 mm / 60 m = 0.893 ‰ prints as 0.89; the paper's 0.90 ‰ is 54 mm / 60 m.
    assert round(rule.presag_rel[0] * 1e3, 2) == 0.89
    assert rule.printed()["presag_rel_permille"][0] == 0.90


def test_empirical_rule_follows_equations_1_to_3():
    rule = EmpiricalPresag(
        span_length=50.0, contact_wire_tension=10e3, messenger_wire_tension=15e3, static_force=100.0, k=5.0,
        e_mast_ratios=(0.4,),
    )
    e_mid = 50.0 / (5.0 * 25e3)
    # Closed-form arithmetic: only floating-point rounding separates the two sides.
    assert rule.e_mid == pytest.approx(e_mid, rel=1e-14)
    assert rule.presag[0] == pytest.approx(100.0 * 0.6 * e_mid, rel=1e-14)
    assert rule.presag_rel[0] == pytest.approx(100.0 * 0.6 * e_mid / 50.0, rel=1e-14)


@pytest.mark.parametrize(
    ("field", "value"), [("static_force", 0.0), ("static_force", -10.0), ("contact_wire_tension", -9.8e3), ("span_length", 0.0)]
)
def test_empirical_rule_rejects_bad_input(field, value):
    kwargs = dict(span_length=60.0, contact_wire_tension=9.8e3, messenger_wire_tension=9.8e3, static_force=140.0)
    kwargs[field] = value
    with pytest.raises(ModelError, match=rf"^{field} = .* is outside the valid range"):
        EmpiricalPresag(**kwargs)


def test_to_dict_reports_every_number_in_its_edge_unit():
    rule = EmpiricalPresag(span_length=60.0, contact_wire_tension=9.8e3, messenger_wire_tension=7.1e3,
                           static_force=140.0, e_mast_ratios=[0.5, 0.3])
    assert rule.e_mast_ratios == (0.5, 0.3) and isinstance(rule.e_mast_ratios, tuple)  # a list is stored as a tuple
    out = rule.to_dict()
    # Unit conversions only (× or ÷ 1e3): equal to round-off, 1e-12.
    assert out["span_length_m"] == 60.0 and out["static_force_N"] == 140.0 and out["k"] == 4.0
    assert out["tension_kN"] == pytest.approx([9.8, 7.1], rel=1e-12)
    assert out["e_mast_ratios"] == [0.5, 0.3]
    assert out["e_mid_mm_per_N"] == pytest.approx(rule.e_mid * 1e3, rel=1e-12)
    assert out["e_mast_mm_per_N"] == pytest.approx([e * 1e3 for e in rule.e_mast], rel=1e-12)
    assert out["presag_mm"] == pytest.approx([s * 1e3 for s in rule.presag], rel=1e-12)
    assert out["presag_rel_permille"] == pytest.approx([s * 1e3 for s in rule.presag_rel], rel=1e-12)
    assert out["printed_as_table1"] == rule.printed()


def test_printed_digits_round_half_up_as_the_paper_does():
    from presag_opt.design.empirical import _round_half_up

    # Half-up, not Python's round-half-to-even: 0.125 → 0.13 and 2.5 → 3 (round() gives 0.12 and 2).
    assert _round_half_up(0.125, 2) == 0.13 and _round_half_up(2.5, 0) == 3.0
