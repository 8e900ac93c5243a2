"""Writing a survey (presag_opt.system.survey_writing): a hand-written section as masts, and the CSV read back."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from presag_opt.system.catenary import SpanLayout
from presag_opt.system.loader import load_catenary
from presag_opt.system.survey import COLUMNS, load_survey
from presag_opt.system.survey_writing import survey_of_catenary, survey_table, write_survey_csv


def section():
    cat = load_catenary("st_9.8_mixed")
    return cat.with_layout(SpanLayout(span_lengths=(45.0, 58.4, 24.7, 40.7), label="test: four spans"))


def test_the_survey_of_a_span_list_has_a_mast_per_support():
    cat = section()
    survey = survey_of_catenary(cat, start_chainage=1000.0, section="S1", first_mast=7)
    assert [m.mast for m in survey.masts] == ["M7", "M8", "M9", "M10", "M11"]
    # chainages are the running sums of the span list (exact in binary for these values to 1e-9 m)
    assert np.allclose([m.chainage for m in survey.masts], 1000.0 + np.array([0.0, 45.0, 103.4, 128.1, 168.8]),
                       rtol=0.0, atol=1e-9)
    staggers = [m.stagger for m in survey.masts]
    assert staggers == pytest.approx(list(cat.mast_stagger()), abs=1e-15)
    assert all(m.steady_arm == "pull-off" and m.section == "S1" for m in survey.masts)
    assert {m.contact_wire_height for m in survey.masts} == {cat.contact_wire_height}


def test_the_written_csv_reads_back_to_the_same_survey(tmp_path):
    survey = survey_of_catenary(section())
    path = write_survey_csv(survey, tmp_path / "line.csv")
    header = path.read_text(encoding="utf-8").splitlines()[0].split(",")
    assert header == [*COLUMNS, "section", "stitched", "cant_mm"]
    again = load_survey(path, working_width=survey.working_width)
    assert survey_table(again) == survey_table(survey)  # table units, rounded to 1e-6 (μm, nm of stagger)
    marked = dataclasses.replace(survey, masts=tuple(dataclasses.replace(m, stitched=i % 2 == 0)
                                                     for i, m in enumerate(survey.masts)))
    path = write_survey_csv(marked, tmp_path / "stitched.csv")
    assert [m.stitched for m in load_survey(path, working_width=survey.working_width).masts] == [
        i % 2 == 0 for i in range(len(survey.masts))]
