"""One voice: the same band through ``presag recommend``, ``presag report --quick``, ``presag robust`` and
``presag design`` (the case study's ideal section written as a one-section survey) gives the same decision,
validity sentence and numbers — quasi-static here, with the dynamic robust design in the slow test.

The band commands run one pipeline with the same numerics, so their decisions are equal to the last digit.
The line is sized on its eight inner spans (not the ideal section's central one) and quotes its margins on
its shortest sized span, so its numbers agree to 0.5 mm: the spans' own robust designs differ from the
central span's by the end effects of a ten-span section (measured: 0.1 mm)."""

from __future__ import annotations

import json

import pytest

from presag_opt.system.loader import load_catenary
from presag_opt.system.survey_writing import survey_of_catenary, write_survey_csv

BAND = ("--static-force", "70:140", "--max-speed", "90")


def decisions(presag, tmp_path, dynamic: bool) -> dict[str, dict]:
    def presag_json(*args: str, cwd) -> dict:
        result = presag(*args, "--json", "--quiet", cwd=cwd)
        assert result.returncode == 0, result.stderr
        return json.loads(result.stdout)

    survey = write_survey_csv(survey_of_catenary(load_catenary("st_9.8_ideal")), tmp_path / "case_study.csv")
    extra = ("--dynamic-robust",) if dynamic else ()
    out = {
        "recommend": presag_json("recommend", "--models", "st_9.8_ideal", *BAND, *extra, cwd=tmp_path)["decision"],
        "report": presag_json("report", "st_9.8_ideal", "--out", "report", "--quick", *BAND, *extra,
                              cwd=tmp_path)["decision"],
        "robust": presag_json("robust", "st_9.8_ideal", *BAND, *(("--dynamic",) if dynamic else ()),
                              cwd=tmp_path)["decision"],
        "design": presag_json("design", str(survey), "--system", "st_9.8_ideal", "--out", "line", "--step", "0.5",
                              *BAND, *extra, cwd=tmp_path)["decision"],
    }
    return out


def assert_one_voice(found: dict[str, dict], line_tolerance_mm: float) -> None:
    reference = found["recommend"]
    for command, decision in found.items():
        assert (decision["status"], decision["basis"]) == (reference["status"], reference["basis"]), command
        assert decision["validity"]["sentence"] == reference["validity"]["sentence"], command
        assert decision["crew_tolerance_mm"] == reference["crew_tolerance_mm"], command
        tolerance = line_tolerance_mm if command == "design" else 1e-9
        assert decision["presag_mm"] == pytest.approx(reference["presag_mm"], abs=tolerance), command
        for mine, theirs in zip(decision["intervals"], reference["intervals"]):
            assert mine["name"] == theirs["name"] and mine["in_force"] == theirs["in_force"], command
            assert [mine["low_mm"], mine["high_mm"]] == pytest.approx([theirs["low_mm"], theirs["high_mm"]],
                                                                      abs=tolerance), command


@pytest.mark.slow  # four commands, a reduced sweep among them: a minute (the decision's branches: test_decision)
def test_the_band_commands_and_the_line_give_one_quasi_static_decision(presag, tmp_path):
    assert_one_voice(decisions(presag, tmp_path, dynamic=False), line_tolerance_mm=0.5)


@pytest.mark.slow
def test_with_the_dynamic_robust_design_they_give_one_final_decision(presag, tmp_path):
    """The line's dynamic robust design runs on its worst section at the line's S_rel; the band commands' on
    the ideal section: 1 mm (the dynamic search's resolution is 0.5 mm on 60 m)."""
    found = decisions(presag, tmp_path, dynamic=True)
    assert found["recommend"]["status"] in ("decided", "tolerance-bound")
    assert_one_voice(found, line_tolerance_mm=1.0)
