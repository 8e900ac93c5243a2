"""Survey input (presag_opt.system.survey): the same table read from CSV, xlsx, TOML and the API, its
mapping to the static model, and every bad value named by file, row, column, value, unit and range."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from presag_opt.static.discretisation import discretise
from presag_opt.system.loader import load_catenary
from presag_opt.system.survey import (
    COLUMNS,
    SurveyError,
    load_survey,
    section_catenary,
    survey_from_rows,
)
from presag_opt.system.survey_writing import (
    survey_of_catenary,
    survey_table,
    write_survey_csv,
)

HEADER = ",".join((*COLUMNS, "section"))


def small_rows() -> list[str]:
    """Six masts in two sections of three spans; a curve, a push-off arm, a lowered wire."""
    return ["M1,0,300,5.5,1.2,,pull-off,A", "M2,50,-300,5.5,1.2,,pull-off,A", "M3,100,-250,5.5,1.2,800,push-off,A",
            "M4,150,-250,5.3,1.0,800,pull-off,A", "M5,200,250,5.5,1.2,0,pull-off,B", "M6,250,-300,5.5,1.2,0,pull-off,B",
            "M7,300,300,5.5,1.2,0,pull-off,B", "M8,350,-300,5.5,1.2,0,pull-off,B"]


def write_csv(path, rows):
    path.write_text("\n".join([HEADER, *rows]) + "\n", encoding="utf-8")
    return path


def without_rows(survey):
    return [dataclasses.replace(m, row="") for m in survey.masts]


def test_csv_xlsx_toml_and_api_read_the_same_survey(tmp_path):
    openpyxl = pytest.importorskip("openpyxl")
    csv_survey = load_survey(write_csv(tmp_path / "line.csv", small_rows()))
    book = openpyxl.Workbook()
    sheet = book.active
    sheet.title = "survey"
    sheet.append([*COLUMNS, "section"])
    for line in small_rows():
        sheet.append([float(v) if v.replace(".", "").replace("-", "").isdigit() else (None if v == "" else v)
                      for v in line.split(",")])
    book.save(tmp_path / "line.xlsx")
    xlsx_survey = load_survey(tmp_path / "line.xlsx")
    toml = "\n".join(
        "[[masts]]\n" + "\n".join(f"{c} = {v!r}" if c in ("mast", "steady_arm", "section") else f"{c} = {v or 0}"
                                  for c, v in zip((*COLUMNS, "section"), line.split(",")))
        for line in small_rows()).replace("'", '"')
    (tmp_path / "line.toml").write_text(toml, encoding="utf-8")
    toml_survey = load_survey(tmp_path / "line.toml")
    api_survey = survey_from_rows([(f"row {i}", dict(zip((*COLUMNS, "section"), line.split(","))))
                                   for i, line in enumerate(small_rows())])
    reference = without_rows(csv_survey)
    for other in (xlsx_survey, toml_survey, api_survey):
        assert without_rows(other) == reference
    m3 = csv_survey.masts[2]
    assert (m3.stagger, m3.curve_radius, m3.steady_arm) == (pytest.approx(-0.25, abs=1e-15), 800.0, "push-off")
    assert [s.section for s in csv_survey.sections()] == ["A", "B"]
    assert [(a.mast, b.mast) for a, b in csv_survey.overlap_spans()] == [("M4", "M5")]
    # written and read back
    again = load_survey(write_survey_csv(csv_survey, tmp_path / "again.csv"))
    assert without_rows(again) == reference
    assert survey_table(again) == survey_table(csv_survey)


def test_the_mixed_section_as_a_survey_is_the_same_model():
    base = load_catenary("st_9.8_mixed")
    survey = survey_of_catenary(base)
    (section,) = survey.sections()
    surveyed = section_catenary(base, section)
    assert surveyed.layout.span_lengths == pytest.approx(base.layout.span_lengths, abs=1e-9)
    a, b = discretise(base), discretise(surveyed)
    # the same nodes, masses and elements to round-off (chainages are sums of the span list)
    assert np.abs(a.design_positions - b.design_positions).max() < 1e-9
    assert np.array_equal(a.axial.node_a, b.axial.node_a) and np.array_equal(a.axial.group, b.axial.group)
    assert np.abs(a.node_mass - b.node_mass).max() < 1e-12


def test_per_mast_geometry_reaches_the_discretisation():
    rows = [(f"row {i + 2}", dict(zip((*COLUMNS, "section"), line.split(",")))) for i, line in enumerate(small_rows())]
    survey = survey_from_rows(rows, source="small.csv")
    section = survey.sections()[0]
    cat = section_catenary(load_catenary("st_9.8_mixed"), section)
    disc = discretise(cat)
    masts = disc.design_positions[disc.mast_cw_node]
    assert masts[:, 2] == pytest.approx([5.5, 5.5, 5.5, 5.3], abs=1e-12)
    mw = disc.design_positions[disc.mast_mw_node]
    assert mw[:, 2] - masts[:, 2] == pytest.approx([1.2, 1.2, 1.2, 1.0], abs=1e-12)
    # signed stagger along the mast normal, from the track centre line (straight from x = 0 to the curve)
    assert masts[:2, 1] == pytest.approx([0.3, -0.3], abs=1e-12)
    # a push-off arm's pivot lies on the side the wire pulls towards and below the clamp
    pivots = disc.design_positions[disc.arm_pivot_nodes]
    assert pivots[2, 2] < masts[2, 2] < pivots[1, 2]


@pytest.mark.parametrize(("line", "column", "expected"), [
    ("M3,100,450,5.5,1.2,,pull-off,A", "stagger_mm", "450 mm is outside the valid range [-400, 400] mm"),
    ("M3,100,-250,5.5,1.2,50,pull-off,A", "curve_radius_m", "50 m is outside the valid range: 0 or empty"),
    ("M3,40,-250,5.5,1.2,,pull-off,A", "chainage_m", "40 m does not increase from 50 m"),
    ("M3,100,-250,5.5,1.2,,swing-arm,A", "steady_arm", "'swing-arm' is not a steady-arm type (valid: pull-off, push-off)"),
    ("M3,100,-250,9.5,1.2,,pull-off,A", "contact_wire_height_m", "9.5 m is outside the valid range [3, 8] m"),
    ("M3,100,-250,5.5,0.1,,pull-off,A", "system_height_m", "0.1 m is outside the valid range [0.2, 4] m"),
    ("M3,100,abc,5.5,1.2,,pull-off,A", "stagger_mm", "'abc' is not a number in mm"),
    ("M3,300,-250,5.5,1.2,,pull-off,A", "chainage_m", "valid span lengths: [5, 120] m"),
    ("M2,100,-250,5.5,1.2,,pull-off,A", "mast", "'M2' repeats the id"),
    ("M3,100,-250,5.5,1.2,,pull-off,B", "section", "section 'A' starts again"),
])
def test_every_bad_value_names_file_row_column_value_and_range(tmp_path, line, column, expected):
    rows = small_rows()
    rows[2] = line
    with pytest.raises(SurveyError) as error:
        load_survey(write_csv(tmp_path / "bad.csv", rows))
    message = str(error.value)
    assert "\n" not in message
    assert message.startswith("bad.csv, row ")
    assert f"column {column!r}" in message and expected in message


def test_working_width_is_a_setting_and_errors_are_all_listed(tmp_path):
    rows = small_rows()
    rows[0] = "M1,0,350,5.5,1.2,,pull-off,A"
    assert load_survey(write_csv(tmp_path / "w.csv", rows), working_width=0.40).masts[0].stagger == pytest.approx(0.35)
    rows[5] = "M6,250,-300,5.5,1.2,20,pull-off,B"
    path = write_csv(tmp_path / "w.csv", rows)
    # both errors in one line, the first in full
    with pytest.raises(SurveyError, match=r"w\.csv, row 2, column 'stagger_mm': 350 mm .*\[-300, 300\] mm .*and 1 more: "
                                          r"w\.csv, row 7, column 'curve_radius_m'"):
        load_survey(path, working_width=0.30)


def test_table_errors(tmp_path):
    (tmp_path / "cols.csv").write_text("mast,chainage_m\nM1,0\n", encoding="utf-8")
    with pytest.raises(SurveyError, match="column 'stagger_mm' is missing"):
        load_survey(tmp_path / "cols.csv")
    (tmp_path / "extra.csv").write_text(HEADER + ",colour\n", encoding="utf-8")
    with pytest.raises(SurveyError, match="unknown column 'colour'"):
        load_survey(tmp_path / "extra.csv")
    with pytest.raises(SurveyError, match="has 3 masts; a tension section needs at least 4"):
        load_survey(write_csv(tmp_path / "few.csv", small_rows()[:7]))
    with pytest.raises(SurveyError, match="unknown format '.txt'"):
        (tmp_path / "x.txt").write_text("", encoding="utf-8")
        load_survey(tmp_path / "x.txt")
    with pytest.raises(SurveyError, match="does not exist"):
        load_survey(tmp_path / "missing.csv")


def test_a_semicolon_separated_survey_with_decimal_commas_is_read(tmp_path):
    path = tmp_path / "semi.csv"
    path.write_text(";".join(COLUMNS) + "\n" + "\n".join(
        f"M{i};{50 * i},0;{300 if i % 2 else -300};5,5;1,2;;pull-off" for i in range(5)) + "\n", encoding="utf-8")
    survey = load_survey(path)
    assert [m.mast for m in survey.masts] == ["M0", "M1", "M2", "M3", "M4"]
    assert survey.masts[1].contact_wire_height == 5.5 and survey.masts[1].system_height == 1.2


def test_a_header_of_one_column_holding_tabs_says_so(tmp_path):
    path = tmp_path / "tabs.csv"
    path.write_text("\t".join(COLUMNS) + "\n" + "M0\t0\t300\t5.5\t1.2\t\tpull-off\n", encoding="utf-8")
    with pytest.raises(SurveyError, match="the header is one column holding tabs"):
        load_survey(path)
