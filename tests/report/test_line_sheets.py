"""The crew's dropper sheets (presag_opt.report.line_sheets): one per section, a table per span with every
dropper, the print stylesheet, and the same in the workbook with its header row repeated on every page."""

from __future__ import annotations

import re

import openpyxl
import pytest

from presag_opt.design import CASE_STUDY_BAND
from presag_opt.design.line import LineOptions, design_line
from presag_opt.report.line_sheets import PRINT_CSS, SHEET_HEADERS, add_sheets, sheet_row, sheets_html
from presag_opt.system.catenary import SpanLayout
from presag_opt.system.loader import load_catenary
from presag_opt.system.survey import Survey
from presag_opt.system.survey_writing import survey_of_catenary


@pytest.fixture(scope="module")
def design():
    """Two sections of four 40 m spans."""
    base = load_catenary("st_9.8_mixed").with_layout(SpanLayout(span_lengths=(40.0,) * 4))
    first = survey_of_catenary(base, section="A")
    second = survey_of_catenary(base, section="B", start_chainage=210.0)
    masts = (*first.masts, *(m.__class__(**{**m.__dict__, "mast": "B" + m.mast}) for m in second.masts))
    return design_line(Survey(masts=masts, source="two.csv"), base, CASE_STUDY_BAND,
                       LineOptions(element_length=1.0, workers=1, round_step=0.01))


def test_a_sheet_per_section_and_a_table_per_span_with_every_dropper(design):
    html = sheets_html(design)
    sheets = re.findall(r"<section class='sheet' id='sheet-(\w+)'>", html)
    assert sheets == ["A", "B"]
    assert html.count("<table>") == len(design.spans) == 8
    assert html.count("<tr>") - html.count("<thead>") == len(design.droppers)
    assert "rounded to 10 mm" in html and "Dropper sheet — two.csv, section B" in html
    first = design.droppers[0]
    assert sheet_row(first)[:4] == [first.id, f"{first.chainage:.3f}", f"{first.position:.3f}",
                                    f"{first.cut_length * 1e3:.1f}"]
    # on paper: only the sheets, each on its own page, the headers repeated
    assert ".screen-only { display: none; }" in PRINT_CSS and "break-before: page" in PRINT_CSS
    assert "thead { display: table-header-group; }" in PRINT_CSS


def test_the_workbook_has_the_same_sheets(design, tmp_path):
    book = openpyxl.Workbook()
    add_sheets(book, design)
    path = tmp_path / "book.xlsx"
    book.save(path)
    book = openpyxl.load_workbook(path)
    assert book.sheetnames[-2:] == ["sheet A", "sheet B"]
    sheet = book["sheet A"]
    assert sheet.print_title_rows == "$1:$1"  # the header row, repeated on every printed page
    rows = list(sheet.iter_rows(values_only=True))
    assert list(rows[0]) == list(SHEET_HEADERS)
    ids = [r[0] for r in rows if r[0] and r[0].startswith("A/")]
    assert ids == [d.id for d in design.droppers if d.section == "A"]
