"""``presag design`` (in-process, from a folder outside the source tree): the outputs
with exactly their columns, the decision at the head, the design rules, and the survey's bad input."""

from __future__ import annotations

import csv
import json
from pathlib import Path

import pytest

from presag_opt.report.line_report import DROPPER_COLUMNS, SPAN_COLUMNS
from presag_opt.system.survey import COLUMNS

FAST = ("--element-length", "1.0", "--step", "2.0")


def survey_file(folder: Path, rows: list[str], name: str = "line.csv") -> Path:
    path = folder / name
    path.write_text("\n".join([",".join((*COLUMNS, "section")), *rows]) + "\n", encoding="utf-8")
    return path


def line_rows(bridge_system_height: float = 1.2) -> list[str]:
    """Two sections of four 30 m spans; a bridge at masts B2 and B3 lowers the wire by 0.3 m."""
    rows = []
    for i in range(5):
        rows.append(f"A{i + 1},{30 * i},{300 if i % 2 == 0 else -300},5.5,1.2,,pull-off,A")
    for i in range(5):
        low = i in (1, 2)
        rows.append(f"B{i + 1},{150 + 30 * i},{300 if i % 2 == 0 else -300},{5.2 if low else 5.5},"
                    f"{bridge_system_height if low else 1.2},,pull-off,B")
    return rows


@pytest.fixture(scope="module")
def designed(presag, tmp_path_factory):
    folder = tmp_path_factory.mktemp("design")
    survey = survey_file(folder, line_rows(bridge_system_height=0.6))
    result = presag("design", str(survey), "--system", "st_9.8_mixed", "--out", "out", "--max-speed", "160",
                    "--xlsx", "--json", "--progress", "--round", "5", *FAST, cwd=folder)
    return folder, result


def test_outputs_have_exactly_their_columns_and_json_stays_pure(designed):
    folder, result = designed
    assert result.returncode == 0, result.stderr
    summary = json.loads(result.stdout)
    assert "sizing" in result.stderr and "building" in result.stderr  # progress on standard error
    with (folder / "out" / "droppers.csv").open(encoding="utf-8") as handle:
        droppers = list(csv.DictReader(handle))
    with (folder / "out" / "spans.csv").open(encoding="utf-8") as handle:
        spans = list(csv.DictReader(handle))
    assert tuple(droppers[0]) == DROPPER_COLUMNS and tuple(spans[0]) == SPAN_COLUMNS
    assert len(spans) == 8 and len(droppers) == summary["droppers"]
    # spans count from 1 within each section, droppers from 1 within each span
    assert [r["span"] for r in spans] == ["1", "2", "3", "4"] * 2
    assert [r["dropper"] for r in droppers if r["section"] == "A" and r["span"] == "1"] == ["1", "2", "3", "4"]
    assert (folder / "out" / "line_design.xlsx").stat().st_size > 1000
    page = (folder / "out" / "index.html").read_text(encoding="utf-8")
    assert summary["decision"]["headline"] in page
    assert page.index("id='decision'") < page.index("id='along'")
    assert "overlap spans between tension sections are not modelled" in page
    # the crew's sheets: one per section on the page and in the workbook, the cut lengths on the 5 mm step
    assert page.count("<section class='sheet'") == 2 and "@media print" in page
    assert all(float(r["cut_length_mm"]) % 5.0 == 0.0 for r in droppers)
    assert droppers[0]["dropper_id"] == "A/A1-A2/1"
    import openpyxl

    book = openpyxl.load_workbook(folder / "out" / "line_design.xlsx", read_only=True)
    assert {"sheet A", "sheet B", "rounding"} <= set(book.sheetnames)
    assert [r["section"] for r in summary["rounding"]] == ["A", "B"]
    assert all(r["waviness_p95_rounded_mm"]["value"] > r["waviness_exact_mm"] for r in summary["rounding"])


def test_a_lowered_wire_at_a_bridge_makes_droppers_too_short_and_the_design_says_so(designed):
    folder, result = designed
    summary = json.loads(result.stdout)
    failing = {(r["section"], r["rule"].split(" ≥")[0]): r for r in summary["rules_failing"]}
    short = failing[("B", "shortest dropper")]
    assert short["status"] == "FAILS"  # the rule applies at 160 km/h
    assert "span 2" in short["worst"] or "span 3" in short["worst"]
    assert not any(section == "A" for section, _ in failing)
    with (folder / "out" / "droppers.csv").open(encoding="utf-8") as handle:
        lengths = [float(r["dropper_length_mm"]) for r in csv.DictReader(handle) if r["section"] == "B"]
    assert min(lengths) < 500.0
    # at 160 km/h (β 0.46 on 9.8 kN) the quasi-static answers are not trusted: provisional, and it says why
    decision = summary["decision"]
    assert decision["status"] == "provisional" and decision["validity"]["verdict"] == "beyond"
    assert "not trusted" in decision["reason"] and "β = 0.46" in decision["validity"]["sentence"]


@pytest.mark.parametrize(("row", "expected"), [
    ("A3,60,450,5.5,1.2,,pull-off,A", "line.csv, row 4, column 'stagger_mm': 450 mm is outside the valid range [-400, 400] mm"),
    ("A3,20,300,5.5,1.2,,pull-off,A", "line.csv, row 4, column 'chainage_m': 20 m does not increase from 30 m"),
    ("A3,60,300,5.5,1.2,,cantilever,A", "line.csv, row 4, column 'steady_arm': 'cantilever' is not a steady-arm type"),
    ("A3,60,300,5.5,1.2,80,pull-off,A", "line.csv, row 4, column 'curve_radius_m': 80 m is outside the valid range"),
])
def test_bad_survey_values_end_with_one_line(presag, tmp_path, row, expected):
    rows = line_rows()
    rows[2] = row
    result = presag("design", str(survey_file(tmp_path, rows)), "--system", "st_9.8_mixed", "--out", "out", *FAST,
                    cwd=tmp_path)
    assert result.returncode == 2, result.stderr
    assert "Traceback" not in result.stderr
    line = result.stderr.strip().splitlines()[-1]
    assert expected in line
    assert not (tmp_path / "out" / "droppers.csv").exists()  # nothing is computed from a table with an error


@pytest.mark.slow  # the decision's use of the check: tests/pipeline/test_line.py; the check: tests/robust/test_dynamic_check.py
def test_dynamic_check_simulates_the_worst_section_and_decides_again(presag, tmp_path):
    rows = [f"A{i + 1},{50 * i},{300 if i % 2 == 0 else -300},5.5,1.2,,pull-off,A" for i in range(7)]
    result = presag("design", str(survey_file(tmp_path, rows)), "--system", "st_9.8_mixed", "--out", "out",
                    "--dynamic-check", "--json", *FAST, cwd=tmp_path)
    assert result.returncode == 0, result.stderr
    decision = json.loads(result.stdout)["decision"]
    assert decision["uplift_kind"] == "dynamic"
    # a dynamic uplift of a 9.8 kN section at 90 km/h and 140 N: tens of mm, within the 83.5 mm limit
    assert 10.0 < decision["uplift_mm"] < 83.5
    assert "dynamic_check" not in decision["not_checked"]
    page = (tmp_path / "out" / "index.html").read_text(encoding="utf-8")
    assert "id='dynamic'" in page and "σ/F_m" in page


def test_a_band_at_or_above_the_en50119_speed_ratio_is_refused_before_any_work(presag, tmp_path):
    """β ≥ 0.7 at the band's top speed: one line naming the speed, its β and the option that accepts it."""
    survey = survey_file(tmp_path, line_rows())
    result = presag("design", str(survey), "--system", "st_9.8_mixed", "--out", "out", "--max-speed", "260",
                    *FAST, cwd=tmp_path)
    assert result.returncode == 2 and result.stdout == ""
    assert result.stderr.strip().splitlines() == [
        "presag: error: speed = 260 km/h is β = 0.75 of the contact-wire wave speed 345 km/h, at or above the "
        "EN 50119 limit β < 0.7 (speeds below 241 km/h); give --allow-supercritical to run it anyway"]
    assert not (tmp_path / "out").exists()


def test_the_robust_rule_gives_every_span_its_own_presag_and_tolerance(presag, tmp_path):
    # One section of four 30 m spans with the wire lowered 0.3 m at masts B2-B3 (a bridge): --rule robust sizes
    # the inner spans 2 and 3 on their own (depths below the sloped support line) and builds each inside its own
    # tolerance interval (empty for the end spans, which take the mean); the quasi-static robust design enters
    # the decision beside the Δe rule.
    rows = [r for r in line_rows() if r.endswith(",B")]
    survey = survey_file(tmp_path, rows)
    result = presag("design", str(survey), "--system", "st_9.8_mixed", "--out", "out", "--rule", "robust",
                    "--json", *FAST, cwd=tmp_path)
    assert result.returncode == 0, result.stderr
    summary = json.loads(result.stdout)
    methods = {a["method"] for a in summary["decision"]["answers"]}
    assert methods == {"quasi-static robust design", "quasi-static Δe rule"}
    with (tmp_path / "out" / "spans.csv").open(encoding="utf-8") as handle:
        spans = list(csv.DictReader(handle))
    assert tuple(spans[0]) == SPAN_COLUMNS
    assert spans[0]["presag_tolerance_low_mm"] == "" and spans[3]["presag_tolerance_high_mm"] == ""
    assert "termination" in spans[0]["note"] and spans[0]["static_uplift_mm"] == ""
    for row in spans[1:3]:
        low, s, high = float(row["presag_tolerance_low_mm"]), float(row["presag_mm"]), float(row["presag_tolerance_high_mm"])
        assert low < s < high and 5.0 < s < 100.0  # a real pre-sag on 30 m, inside its own interval
    # the end spans take the mean S_rel of the sized ones (to the CSV's 0.1 mm on 30 m)
    mean_rel = (float(spans[1]["presag_mm"]) + float(spans[2]["presag_mm"])) / 60.0
    assert float(spans[0]["presag_mm"]) == pytest.approx(30.0 * mean_rel, abs=0.11)
    page = (tmp_path / "out" / "index.html").read_text(encoding="utf-8")
    assert "own tolerance [mm] (margins)" in page and "— (end span)" in page
    # the headline says what is built: each span its own, the range of the built pre-sags (not S_rel × l)
    built = [float(r["presag_mm"]) for r in spans]
    assert (f"each sized span its own quasi-static robust pre-sag, {min(built):.1f}–{max(built):.1f} mm as built "
            "(the end spans at their section's mean)") in summary["headline"]
    assert "× span length" not in summary["headline"] and summary["advice"] == ""


def test_a_stagger_sign_slip_names_the_surveys_mast_row_and_column_and_leaves_no_folder(presag, tmp_path):
    rows = [f"M{20 + i},{50 * i},{-300 if i % 2 == 0 else 300},5.5,1.2,,pull-off,1" for i in range(7)]
    rows[3] = "M23,150,-300,5.5,1.2,,pull-off,1"  # the slip: the same side as its neighbours
    result = presag("design", str(survey_file(tmp_path, rows, "slip.csv")), "--system", "st_9.8_mixed", "--out", "out",
                    *FAST, cwd=tmp_path)
    assert result.returncode == 2, result.stderr
    line = result.stderr.strip().splitlines()[-1]
    assert "steady arm at mast M23 (slip.csv, row 5)" in line and "survey column 'stagger_mm'" in line
    assert not (tmp_path / "out").exists()
