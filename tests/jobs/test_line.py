"""The line job (presag_opt.jobs.line): the command's defaults, a refusal before any work, the answer in a
notebook with its tables as data frames."""

from __future__ import annotations

import argparse
import inspect
import time

import pytest

from presag_opt import design_line
from presag_opt.cli import line
from presag_opt.cli.decision_options import decision_keywords
from presag_opt.errors import ModelError
from presag_opt.report.line_report import dropper_rows, span_rows
from presag_opt.system.survey import survey_from_rows

ROWS = [(f"row {i}", {"mast": f"M{i}", "chainage_m": 50.0 * i, "stagger_mm": 300 if i % 2 else -300,
                      "contact_wire_height_m": 5.5, "system_height_m": 1.2, "curve_radius_m": 0,
                      "steady_arm": "pull-off"}) for i in range(8)]


def test_the_command_s_defaults_are_the_job_s():
    parser = argparse.ArgumentParser()
    line.register(parser.add_subparsers())
    args = parser.parse_args(["design", "line.csv", "--system", "st_9.8_ideal", "--out", "out"])
    defaults = {n: p.default for n, p in inspect.signature(design_line).parameters.items()}
    keywords = decision_keywords(args)
    for name in ("within_percent", "uplift_limit_mm", "crew_tolerance_mm", "study"):
        assert keywords[name] == defaults[name], name
    assert (args.rule, args.step, args.element_length, args.working_width) == (
        defaults["rule"], defaults["step"], defaults["element_length"], defaults["working_width_mm"])


def test_a_supercritical_band_is_refused_before_any_work():
    from presag_opt import OperatingBand

    band = OperatingBand.from_kmh(static_force=(70, 140), speed_kmh=300, aero_coefficient_kmh=0.00097)
    started = time.monotonic()
    with pytest.raises(ModelError, match="give allow_supercritical=True to run it anyway"):
        design_line(survey_from_rows(ROWS), "st_9.8_ideal", band)
    assert time.monotonic() - started < 5  # no form-finding


def test_a_line_design_shows_its_headline_and_spans_and_gives_its_tables():
    answer = design_line(survey_from_rows(ROWS), "st_9.8_ideal")
    page = answer._repr_html_()
    assert answer.headline() in page.replace("&#x27;", "'") and page.count("<tr>") == len(answer.design.spans) + 1
    spans, droppers = answer.to_frame("spans"), answer.to_frame("droppers")
    assert spans.to_dict("records") == span_rows(answer)
    assert droppers.to_dict("records") == dropper_rows(answer.design)
    assert len(droppers) == len(answer.design.droppers) > 0
    assert list(answer.to_frame("answers")["method"]) == [a.method for a in answer.decision.answers]
    with pytest.raises(ModelError, match="table = .layouts. is not one of spans, droppers, rounding, answers"):
        answer.table("layouts")
