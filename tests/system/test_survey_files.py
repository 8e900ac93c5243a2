"""Survey files (presag_opt.system.survey_files): the rows of a CSV with commas or semicolons, a workbook's
survey sheet and TOML tables, each row named for messages, and every file or header error in one line."""

from __future__ import annotations

import pytest

from presag_opt.system.survey import COLUMNS, OPTIONAL_COLUMNS, load_survey
from presag_opt.system.survey_files import SurveyError, file_rows


def rows(path):
    return file_rows(path, COLUMNS, OPTIONAL_COLUMNS)


def test_a_semicolon_separated_survey_with_decimal_commas_is_read(tmp_path):
    path = tmp_path / "semi.csv"
    path.write_text(";".join(COLUMNS) + "\n" + "\n".join(
        f"M{i};{50 * i},0;{300 if i % 2 else -300};5,5;1,2;;pull-off" for i in range(5)) + "\n", encoding="utf-8")
    read = rows(path)
    assert [where for where, _ in read] == [f"row {n}" for n in range(2, 7)]  # the file's own line numbers
    assert read[1][1]["contact_wire_height_m"] == "5,5"
    survey = load_survey(path)
    assert [m.mast for m in survey.masts] == ["M0", "M1", "M2", "M3", "M4"]
    assert survey.masts[1].contact_wire_height == 5.5 and survey.masts[1].system_height == 1.2


def test_blank_lines_are_skipped_and_rows_keep_their_line_numbers(tmp_path):
    path = tmp_path / "gaps.csv"
    path.write_text(",".join(COLUMNS) + "\nM1,0,300,5.5,1.2,,pull-off\n,,,,,,\nM2,50,-300,5.5,1.2,,pull-off\n",
                    encoding="utf-8")
    assert [(where, row["mast"]) for where, row in rows(path)] == [("row 2", "M1"), ("row 4", "M2")]


def test_the_header_of_one_column_holding_tabs_says_so(tmp_path):
    path = tmp_path / "tabs.csv"
    path.write_text("\t".join(COLUMNS) + "\n" + "M0\t0\t300\t5.5\t1.2\t\tpull-off\n", encoding="utf-8")
    with pytest.raises(SurveyError, match="the header is one column holding tabs"):
        rows(path)


def test_the_workbook_sheet_named_survey_is_read_whatever_its_place(tmp_path):
    openpyxl = pytest.importorskip("openpyxl")
    book = openpyxl.Workbook()
    book.active.title = "notes"
    book.active.append(["not", "a", "survey"])
    sheet = book.create_sheet("survey")
    sheet.append(list(COLUMNS))
    sheet.append(["M1", 0.0, 300.0, 5.5, 1.2, None, "pull-off"])
    sheet.append([None] * len(COLUMNS))
    book.save(tmp_path / "line.xlsx")
    assert rows(tmp_path / "line.xlsx") == [("row 2", dict(zip(COLUMNS, ["M1", 0.0, 300.0, 5.5, 1.2, None, "pull-off"])))]


@pytest.mark.parametrize(("name", "text", "words"), [
    ("x.txt", "", "unknown format '.txt'"),
    ("bad.toml", "[[masts]\n", "not valid TOML"),
    ("keys.toml", "[line]\nname = 'a'\n", "unknown key 'line'"),
    ("none.toml", "", r"no \[\[masts\]\] tables"),
    ("cols.csv", "mast,chainage_m\nM1,0\n", "column 'stagger_mm' is missing"),
    ("extra.csv", ",".join(COLUMNS) + ",colour\n", "unknown column 'colour'"),
    ("book.xlsx", "not a zip", "not a readable xlsx workbook"),
])
def test_file_errors_name_the_file_and_what_to_do(tmp_path, name, text, words):
    (tmp_path / name).write_text(text, encoding="utf-8")
    with pytest.raises(SurveyError, match=words) as error:
        rows(tmp_path / name)
    assert name in str(error.value) and "\n" not in str(error.value)


def test_a_missing_file_is_named(tmp_path):
    with pytest.raises(SurveyError, match="missing.csv does not exist"):
        rows(tmp_path / "missing.csv")


def test_a_survey_path_given_as_text_is_read(tmp_path):
    path = tmp_path / "line.csv"
    path.write_text(",".join(COLUMNS) + "\n" + "\n".join(
        f"M{i},{50 * i},{300 if i % 2 else -300},5.5,1.2,,pull-off" for i in range(5)) + "\n", encoding="utf-8")
    assert load_survey(str(path)).source == "line.csv"
