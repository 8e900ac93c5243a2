"""Cant (presag_opt.system.cant and the survey's cant_mm): the pantograph's lateral shift h·D/s, the frames'
round trip, the level-frame geometry the static model gets, and the refusals."""

from __future__ import annotations

import math

import pytest

from presag_opt.design.line_rules import lateral_excursion
from presag_opt.system.cant import RAIL_CENTRE_DISTANCE, level_frame, track_frame, track_height
from presag_opt.system.survey import Survey, SurveyError, SurveyMast, survey_from_rows


def test_a_wire_above_the_pantograph_lies_h_d_over_s_inside_the_curve():
    # 5.5 m above the rail with 100 mm of cant on 1.5 m between the rails: 0.37 m towards the curve's inside
    y, z = level_frame(0.0, 5.5, 0.100, +1.0)
    assert y == pytest.approx(5.5 * 0.100 / RAIL_CENTRE_DISTANCE, abs=1e-12) and y == pytest.approx(0.3667, abs=1e-4)
    assert z == pytest.approx(5.5 * math.sqrt(1 - (0.1 / 1.5) ** 2), abs=1e-12)
    assert level_frame(0.0, 5.5, 0.100, -1.0)[0] == pytest.approx(-y, abs=1e-12)  # a right-hand curve
    assert level_frame(0.3, 5.5, 0.0, +1.0) == (0.3, 5.5)


@pytest.mark.parametrize(("stagger", "cant", "direction"), [(0.25, 0.06, -1.0), (-0.3, 0.15, 1.0), (0.1, 0.0, 1.0)])
def test_the_frames_turn_back_and_forth(stagger, cant, direction):
    y, z = level_frame(stagger, 5.3, cant, direction)
    assert track_frame(y, z, cant, direction) == pytest.approx((stagger, 5.3), abs=1e-12)
    assert track_height(z, stagger, direction * cant) == pytest.approx(5.3, abs=1e-12)


def masts(cant_mm, radius=800.0, stagger=-0.25):
    rows = [(f"row {i + 2}", {"mast": f"M{i + 1}", "chainage_m": 50 * i, "stagger_mm": stagger * 1e3,
                              "contact_wire_height_m": 5.5, "system_height_m": 1.2,
                              "curve_radius_m": radius if i < 4 else 0, "steady_arm": "pull-off",
                              "cant_mm": cant_mm}) for i in range(5)]
    return survey_from_rows(rows, source="canted.csv")


def test_the_static_model_gets_the_level_frame_and_the_working_width_the_track_frame():
    canted, level = masts(100.0), masts(0.0)
    geometry = canted.sections()[0].mast_geometry()
    shift = 5.5 * 0.1 / RAIL_CENTRE_DISTANCE
    cos = math.sqrt(1 - (0.1 / RAIL_CENTRE_DISTANCE) ** 2)
    assert geometry.stagger[0] == pytest.approx(-0.25 * cos + shift, abs=1e-12)
    assert geometry.contact_wire_height[0] == pytest.approx(5.5 * cos + 0.25 * 0.1 / RAIL_CENTRE_DISTANCE, abs=1e-12)
    # the pantograph sees the surveyed staggers: the working-width check does not move with the cant
    assert lateral_excursion(canted.sections()[0]) == lateral_excursion(level.sections()[0])


def test_cant_out_of_range_or_without_a_curve_is_refused_naming_the_column():
    with pytest.raises(SurveyError, match=r"canted.csv, row 2, column 'cant_mm': 250 mm is outside the valid range \[0, 200\] mm"):
        masts(250.0)
    with pytest.raises(SurveyError, match="column 'cant_mm': 100 mm of cant at a mast between straight spans"):
        masts(100.0, radius=0.0)
    with pytest.raises(SurveyError, match="row 2, column 'cant_mm': 150 mm of cant puts the contact wire 848 mm"):
        masts(150.0, stagger=0.3).sections()[0].mast_geometry()


def test_a_mast_without_cant_is_in_the_level_frame():
    mast = SurveyMast(mast="A", chainage=0.0, stagger=0.3, contact_wire_height=5.5, system_height=1.2, curve_radius=0.0,
                      steady_arm="pull-off")
    assert mast.cant == 0.0
    assert Survey(masts=tuple(SurveyMast(**{**mast.__dict__, "mast": f"A{i}", "chainage": 50.0 * i}) for i in range(4))
                  ).sections()[0].mast_geometry().stagger[0] == 0.3
