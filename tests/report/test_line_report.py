"""Line report tables (presag_opt.report.line_report): units and rounding of the rows, and the tolerance
columns that only the robust rule adds."""

from __future__ import annotations

from types import SimpleNamespace

from presag_opt.report.line_report import (
    DROPPER_COLUMNS,
    SPAN_COLUMNS,
    STITCH_COLUMNS,
    TOLERANCE_COLUMNS,
    dropper_columns,
    dropper_rows,
    span_columns,
    span_rows,
)


def span(tolerance=None):
    return SimpleNamespace(section="A", span=2, from_mast="M2", to_mast="M3", length=50.0, presag=0.04612345,
                           e_mid=0.4e-3, e_mast=0.36e-3, delta_e=0.123456e-3, steady_arm_force=-645.04,
                           static_uplift=0.05333, tolerance=tolerance)


def design(rule, spans):
    return SimpleNamespace(options=SimpleNamespace(rule=rule), spans=spans)


def test_span_rows_are_in_table_units():
    (row,) = span_rows(design("proportional", [span()]))
    assert tuple(row) == SPAN_COLUMNS == span_columns(design("proportional", []))
    assert row["presag_mm"] == 46.1 and row["presag_rel_permille"] == 0.9225  # 46.12345 mm / 50 m
    assert row["delta_e_mm_per_N"] == 0.1235 and row["steady_arm_pull_N"] == -645.0
    assert row["static_uplift_mm"] == 53.3


def test_the_robust_rule_adds_each_spans_tolerance_and_leaves_it_empty_for_an_end_span():
    rows = span_rows(design("robust", [span((0.04101, 0.04999)), span(None)]))
    assert span_columns(design("robust", [])) == SPAN_COLUMNS + TOLERANCE_COLUMNS
    assert (rows[0]["presag_tolerance_low_mm"], rows[0]["presag_tolerance_high_mm"]) == (41.0, 50.0)
    assert rows[1]["presag_tolerance_low_mm"] == "" == rows[1]["presag_tolerance_high_mm"]


def test_dropper_rows_round_to_a_tenth_of_a_millimetre():
    d = SimpleNamespace(section="A", span=1, from_mast="M1", to_mast="M2", dropper=3, position=12.34567,
                        length=0.91234, contact_wire_height=5.45678, presag=0.03456)
    (row,) = dropper_rows(SimpleNamespace(droppers=[d]))
    assert (row["x_from_mast_m"], row["dropper_length_mm"], row["contact_wire_height_mm"], row["presag_mm"]) == (
        12.346, 912.3, 5456.8, 34.6)


def test_a_line_with_stitch_droppers_says_where_each_dropper_hangs_from():
    common = dict(section="A", span=1, from_mast="M1", to_mast="M2", length=0.9, contact_wire_height=5.5, presag=0.0)
    plain = SimpleNamespace(dropper=1, position=4.5, stitch=False, **common)
    on_stitch = SimpleNamespace(dropper=2, position=4.0, stitch=True, **common)
    stitched = SimpleNamespace(droppers=[on_stitch, plain])
    assert dropper_columns(stitched) == DROPPER_COLUMNS + STITCH_COLUMNS
    assert [r["hangs_from"] for r in dropper_rows(stitched)] == ["stitch wire", "messenger"]
    simple = SimpleNamespace(droppers=[plain])
    assert dropper_columns(simple) == DROPPER_COLUMNS and "hangs_from" not in dropper_rows(simple)[0]
