"""Line report tables (presag_opt.report.line_report): units and rounding of the rows, each sized span's own
tolerance with the built pre-sag's margins and flag, and a termination mast without a steady-arm figure."""

from __future__ import annotations

import dataclasses
from types import SimpleNamespace

from presag_opt.design import CASE_STUDY_BAND
from presag_opt.design.line_results import DropperDesign, SpanDesign
from presag_opt.pipeline.line import SPAN_FLAGS, span_flag
from presag_opt.report.line_report import (
    DROPPER_COLUMNS,
    SPAN_COLUMNS,
    STITCH_COLUMNS,
    dropper_columns,
    dropper_rows,
    span_rows,
)

CREW = 2.5e-3


def span(tolerance=None, span=2, presag=0.04612345, note=""):
    termination = span == 1
    return SpanDesign(section="A", span=span, from_mast=f"M{span}", to_mast=f"M{span + 1}", chainage=50.0 * (span - 1),
                      length=50.0, presag=presag, e_mid=0.4e-3, e_mast=0.36e-3, delta_e=0.123456e-3,
                      steady_arm_force=None if termination else -645.04, static_uplift=None if termination else 0.05333,
                      sized=tolerance is not None, tolerance=tolerance,
                      robust_presag=None if tolerance is None else sum(tolerance) / 2, note=note)


def answer(spans):
    """A LineAnswer stand-in with what the rows read: the spans and the crew tolerance's flag."""
    return SimpleNamespace(design=SimpleNamespace(spans=spans, band=CASE_STUDY_BAND), flag=lambda s: span_flag(s, CREW))


def test_span_rows_are_in_table_units():
    (row,) = span_rows(answer([span((0.04101, 0.04999))]))
    assert tuple(row) == SPAN_COLUMNS
    assert row["presag_mm"] == 46.1 and row["presag_rel_permille"] == 0.9225  # 46.12345 mm / 50 m
    assert row["delta_e_mm_per_N"] == 0.1235 and row["steady_arm_pull_N"] == -645.0
    assert row["static_uplift_mm"] == 53.3
    assert (row["presag_tolerance_low_mm"], row["presag_tolerance_high_mm"]) == (41.0, 50.0)
    assert (row["margin_low_mm"], row["margin_high_mm"]) == (5.1, 3.9)  # 46.1 mm inside 41.0–50.0 mm
    assert row["flag"] == "" and row["robust_presag_mm"] == 45.5


def test_each_flag_and_the_end_span_s_note():
    near, outside = span((0.0440, 0.0480)), span((0.0300, 0.0400))
    end = span(None, span=1, note="end span, not sized")
    rows = span_rows(answer([near, outside, end]))
    assert [r["flag"] for r in rows] == [SPAN_FLAGS[1], SPAN_FLAGS[2], SPAN_FLAGS[0]]
    assert rows[1]["margin_high_mm"] == -6.1  # 6.1 mm above the high end
    # the first span's from_mast is the termination: no steady arm, so no pull and no uplift figure
    assert rows[2]["steady_arm_pull_N"] == "" == rows[2]["static_uplift_mm"] == rows[2]["margin_low_mm"]
    assert rows[2]["note"] == "end span, not sized"


def test_dropper_rows_round_to_a_tenth_of_a_millimetre():
    d = DropperDesign(section="A", span=1, from_mast="M1", to_mast="M2", dropper=3, position=12.34567, length=0.91234,
                      contact_wire_height=5.45678, presag=0.03456, chainage=112.34567, messenger_height=6.61234,
                      lateral=-0.123456, cut_length=1.11234)
    (row,) = dropper_rows(SimpleNamespace(droppers=[d]))
    assert tuple(row) == DROPPER_COLUMNS
    assert (row["x_from_mast_m"], row["dropper_length_mm"], row["contact_wire_height_mm"], row["presag_mm"]) == (
        12.346, 912.3, 5456.8, 34.6)
    assert (row["dropper_id"], row["chainage_m"], row["cut_length_mm"], row["messenger_height_mm"],
            row["lateral_mm"]) == ("A/M1-M2/3", 112.346, 1112.3, 6612.3, -123.5)


def test_a_line_with_stitch_droppers_says_where_each_dropper_hangs_from():
    common = dict(section="A", span=1, from_mast="M1", to_mast="M2", length=0.9, contact_wire_height=5.5, presag=0.0)
    plain = DropperDesign(dropper=1, position=4.5, stitch=False, **common)
    on_stitch = DropperDesign(dropper=2, position=4.0, stitch=True, **common)
    stitched = SimpleNamespace(droppers=[on_stitch, plain])
    assert dropper_columns(stitched) == DROPPER_COLUMNS + STITCH_COLUMNS
    assert [r["hangs_from"] for r in dropper_rows(stitched)] == ["stitch wire", "messenger"]
    simple = SimpleNamespace(droppers=[plain])
    assert dropper_columns(simple) == DROPPER_COLUMNS and "hangs_from" not in dropper_rows(simple)[0]


def test_span_rows_flag_a_gradient_over_the_limit_at_the_band_s_speed():
    # the case-study band tops at 90 km/h: gradient ≤ 1/167, change ≤ 1/333
    steep = dataclasses.replace(span(), gradient=-7e-3, gradient_change=4e-3, uniformity=0.123456)
    gentle = dataclasses.replace(span(), gradient=5e-3, gradient_change=2e-3)
    rows = span_rows(answer([steep, gentle]))
    assert rows[0]["gradient_flag"] == "gradient over 1/167; change over 1/333"
    assert rows[0]["gradient_permille"] == -7.0 and rows[0]["uniformity"] == 0.1235
    assert rows[1]["gradient_flag"] == ""
