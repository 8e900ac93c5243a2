"""The survey's ``stitched`` column (presag_opt.system.survey_stitch): its values, its errors, the
stitch wire at the marked masts only, and a surveyed line whose masts are all stitched giving the
dropper lengths of the stitched model file."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from presag_opt.design import CASE_STUDY_BAND
from presag_opt.design.line import LineOptions, design_line
from presag_opt.static.discretisation import StaticSettings, discretise
from presag_opt.static.form_finding import form_find
from presag_opt.system.catenary import SpanLayout
from presag_opt.system.loader import load_catenary
from presag_opt.system.survey import COLUMNS, Survey, SurveyError, load_survey, section_catenary
from presag_opt.system.survey_stitch import stitched_value
from presag_opt.system.survey_writing import survey_of_catenary

SETTINGS = StaticSettings(element_length=1.0)


def stitched_base(spans: int = 4):
    """The stitched ST 9,8/9,8 model file on a short section (fast)."""
    base = load_catenary("st_9.8_stitched_ideal")
    return base.with_layout(SpanLayout(span_lengths=(60.0,) * spans))


def write_survey(path, marks, extra=""):
    """Masts every 60 m, alternating stagger, with the given ``stitched`` cells."""
    lines = [",".join((*COLUMNS, "stitched"))]
    for i, mark in enumerate(marks):
        lines.append(f"M{i + 1},{60 * i},{300 if i % 2 == 0 else -300},5.5,1.2,,pull-off,{mark}")
    path.write_text("\n".join(lines) + "\n" + extra, encoding="utf-8")
    return path


@pytest.mark.parametrize(("cell", "expected"), [
    ("yes", True), ("YES", True), ("True", True), ("1", True), (1, True), (1.0, True), (True, True),
    ("no", False), ("false", False), ("0", False), (0, False), (False, False), ("", None), (None, None), ("  ", None),
])
def test_accepted_values(cell, expected):
    assert stitched_value("f.csv, row 2", cell) == (expected, [])


@pytest.mark.parametrize("cell", ["maybe", "2", "y", "stitched", 0.5])
def test_any_other_value_is_one_error_naming_file_row_column_value_and_valid_values(tmp_path, cell):
    path = write_survey(tmp_path / "line.csv", ["no", "yes", cell, "yes", "no"])
    with pytest.raises(SurveyError) as info:
        load_survey(path)
    message = str(info.value)
    assert message == (f"line.csv, row 4, column 'stitched': {str(cell)!r} is not a valid value "
                       "(valid: yes, no, true, false, 1, 0; empty: not given)")


def test_a_stitched_mast_on_a_system_without_stitch_wire_data_is_one_error(tmp_path):
    survey = load_survey(write_survey(tmp_path / "line.csv", ["no", "no", "yes", "yes", "no"]))
    with pytest.raises(SurveyError, match=r"^line\.csv, row 4, column 'stitched': mast 'M3' is stitched but the "
                                          r"system .* has no stitch-wire data \(give a --system file with a "
                                          r"\[stitch_wire\] section, or mark the mast no\)$"):
        section_catenary(load_catenary("st_9.8_ideal"), survey.sections()[0])
    # marked no everywhere: fine on a simple system, and it makes a stitched system simple
    plain = load_survey(write_survey(tmp_path / "plain.csv", ["no"] * 5)).sections()[0]
    assert section_catenary(load_catenary("st_9.8_ideal"), plain).stitch_wire is None
    assert section_catenary(stitched_base(), plain).stitch_wire is None


def test_stitch_wires_only_at_the_marked_inner_masts(tmp_path):
    survey = load_survey(write_survey(tmp_path / "line.csv", ["yes", "no", "yes", "no", "", "yes", "yes"]))
    cat = section_catenary(stitched_base(6), survey.sections()[0])
    assert cat.stitch_wire.masts == (2, 5)  # the end masts are never stitched; empty = not stitched here
    disc = discretise(cat, SETTINGS)
    clamps = [float(disc.design_positions[chain[[0, -1]], 0].mean()) for chain in disc.stitch_chains]
    assert clamps == pytest.approx([120.0, 300.0], abs=1e-9)
    assert int(np.count_nonzero(disc.stitch_dropper)) == 2 * len(cat.stitch_wire.dropper_positions)
    # no column: the system decides (a stitch wire at every inner mast)
    unmarked = survey_of_catenary(stitched_base(6))
    assert section_catenary(stitched_base(6), unmarked.sections()[0]).stitch_wire.masts is None


def test_xlsx_and_toml_booleans(tmp_path):
    openpyxl = pytest.importorskip("openpyxl")
    book = openpyxl.Workbook()
    sheet = book.active
    sheet.append([*COLUMNS, "stitched"])
    for i, mark in enumerate([False, True, 1, "Yes", None]):
        sheet.append([f"M{i + 1}", 60 * i, 300 if i % 2 == 0 else -300, 5.5, 1.2, None, "pull-off", mark])
    book.save(tmp_path / "line.xlsx")
    assert [m.stitched for m in load_survey(tmp_path / "line.xlsx").masts] == [False, True, True, True, None]
    rows = "".join(f'[[masts]]\nmast = "M{i + 1}"\nchainage_m = {60 * i}\nstagger_mm = {300 if i % 2 == 0 else -300}\n'
                   'contact_wire_height_m = 5.5\nsystem_height_m = 1.2\ncurve_radius_m = 0\nsteady_arm = "pull-off"\n'
                   f"stitched = {mark}\n" for i, mark in enumerate(["false", "true", "true", "true", "false"]))
    (tmp_path / "line.toml").write_text(rows, encoding="utf-8")
    assert [m.stitched for m in load_survey(tmp_path / "line.toml").masts] == [False, True, True, True, False]


def test_every_mast_stitched_gives_the_model_files_dropper_lengths(tmp_path):
    """Every mast marked yes (the end masts are not modelled stitched, as in the model file): the
    surveyed section form-finds to the model file's droppers, stitch droppers included, within
    1e-6 m (both are the same nodes and elements; the solver's own tolerance is far below)."""
    base = stitched_base()
    survey = load_survey(write_survey(tmp_path / "line.csv", ["yes"] * 5))
    surveyed = section_catenary(base, survey.sections()[0])
    assert surveyed.stitch_wire.masts == (1, 2, 3)
    a, b = form_find(base, SETTINGS), form_find(surveyed, SETTINGS)
    assert np.array_equal(a.discretisation.stitch_dropper, b.discretisation.stitch_dropper)
    assert np.count_nonzero(b.discretisation.stitch_dropper) == 6
    assert np.abs(a.dropper_lengths() - b.dropper_lengths()).max() < 1e-6
    ua = a.params.unstretched_length[a.discretisation.dropper_elements]
    ub = b.params.unstretched_length[b.discretisation.dropper_elements]
    assert np.abs(ua - ub).max() < 1e-6


@pytest.mark.slow
def test_design_line_schedules_the_stitch_droppers(tmp_path):
    """design_line on the all-stitched survey: its dropper schedule holds the stitch droppers and its
    cut lengths equal the model file's form-found at the design's pre-sag within 1e-6 m."""
    base = stitched_base()
    survey: Survey = load_survey(write_survey(tmp_path / "line.csv", ["yes"] * 5))
    design = design_line(survey, base, CASE_STUDY_BAND, LineOptions(element_length=1.0, geometry_tolerance=SETTINGS.geometry_tolerance, workers=1))
    reference = form_find(dataclasses.replace(base, presag_rel=design.presag_rel), SETTINGS)
    lengths = np.array([d.length for d in design.droppers])
    assert len(lengths) == len(reference.discretisation.dropper_elements)
    positions = sorted({round(d.position, 6) for d in design.droppers if d.span == 2})
    assert positions[0] == pytest.approx(4.0) and positions[-1] == pytest.approx(56.0)  # stitch droppers ±4 m
    cut = reference.params.unstretched_length[reference.discretisation.dropper_elements]  # the schedule's cut lengths
    assert np.abs(lengths - cut).max() < 1e-6
    # the schedule says which droppers hang from the stitch wire: exactly the model's stitch droppers
    assert [d.stitch for d in design.droppers] == list(reference.discretisation.stitch_dropper)
