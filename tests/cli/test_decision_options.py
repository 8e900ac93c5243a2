"""The options every command that answers "which pre-sag?" shares (presag_opt.cli.decision_options): one
grammar, one default each, shown in the help, and the pipeline's keywords in SI."""

from __future__ import annotations

import argparse

import pytest

from presag_opt.cli import build_parser
from presag_opt.cli.decision_options import (
    WORKERS,
    add_band_options,
    add_decision_options,
    add_numerics_options,
    decision_settings,
    operating_band,
    within_percent,
    workers_of,
)
from presag_opt.design import CASE_STUDY_BAND
from presag_opt.design.evidence import CREW_TOLERANCE
from presag_opt.design.speed_range import STEADY_ARM_UPLIFT_LIMIT
from presag_opt.errors import ModelError

BAND_COMMANDS = ("recommend", "robust", "report", "design")
"""The commands that decide for a band (report and design need their positional arguments)."""


def parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser()
    add_band_options(p)
    add_decision_options(p, simulated="the test model")
    add_numerics_options(p)
    return p


def test_the_defaults_are_the_case_study_s_and_the_toolkit_s_constants():
    args = parser().parse_args([])
    assert operating_band(args) == CASE_STUDY_BAND
    settings = decision_settings(args)
    assert settings == {"within": 0.10, "uplift_limit": pytest.approx(STEADY_ARM_UPLIFT_LIMIT, rel=1e-15),
                        "crew": None, "installation_errors": None, "study": None}
    assert args.element_length == 0.5 and workers_of(args) == WORKERS


@pytest.mark.parametrize(("text", "value"), [("10", 10.0), ("10%", 10.0), (" 12.5 % ", 12.5), ("0", 0.0)])
def test_within_takes_a_number_or_a_percentage(text, value):
    assert within_percent(text) == pytest.approx(value, rel=1e-15)


def test_within_that_is_not_a_number_is_one_line():
    with pytest.raises(ModelError, match=r"--within = 'ten': write a percentage such as 10 \(or 10%\)"):
        within_percent("ten")


def test_the_crew_tolerance_and_the_dropper_error_reach_the_pipeline_in_metres():
    args = parser().parse_args(["--crew-tolerance", "3", "--uplift-limit", "100", "--within", "5%"])
    assert decision_settings(args)["crew"] == pytest.approx(3e-3) and decision_settings(args)["within"] == 0.05
    errors = decision_settings(parser().parse_args(["--dropper-error", "2"]))["installation_errors"]
    assert errors.dropper_length == pytest.approx(2e-3) and errors.distribution == "normal"
    with pytest.raises(ModelError, match="--crew-tolerance or --dropper-error, not both"):
        decision_settings(parser().parse_args(["--crew-tolerance", "3", "--dropper-error", "2"]))


def test_workers_have_one_default_and_exclude_a_scheduler():
    args = argparse.Namespace(workers=None, scheduler=None)
    assert workers_of(args) == WORKERS
    with pytest.raises(ModelError, match="either --workers or --scheduler"):
        workers_of(argparse.Namespace(workers=2, scheduler="tcp://x:8786"))
    with pytest.raises(ModelError, match=r"--workers = 0 is outside the valid range \[1, 64\]"):
        workers_of(argparse.Namespace(workers=0))


@pytest.mark.parametrize("command", BAND_COMMANDS)
def test_every_deciding_command_has_the_one_grammar_with_its_defaults_in_the_help(command):
    sub = build_parser()._subparsers._group_actions[0].choices[command]
    options = {o for action in sub._actions for o in action.option_strings}
    assert {"--static-force", "--min-speed", "--max-speed", "--aero", "--within", "--uplift-limit",
            "--crew-tolerance", "--study", "--element-length", "--workers"} <= options
    assert "--fm-band" not in options and "--output" not in options
    text = sub.format_help()
    assert "(default 70:140)" in text and "(default 0.00097)" in text and "N/(KMH)^2" in text
    assert f"default {CREW_TOLERANCE * 1e3:g}" in text and "(default 83.5" in text
