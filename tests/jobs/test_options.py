"""The jobs' defaults (presag_opt.jobs.options) are what the command line's help states."""

from __future__ import annotations

import pytest

from presag_opt.cli import build_parser
from presag_opt.design.speed_range import STEADY_ARM_UPLIFT_LIMIT
from presag_opt.jobs import options


def _help(*command: str) -> str:
    parser = build_parser()
    sub = next(a for a in parser._actions if a.dest == "command" or getattr(a, "choices", None))
    return " ".join(sub.choices[command[0]].format_help().split())


def test_the_defaults_in_the_designer_s_units():
    assert options.UPLIFT_LIMIT_MM == pytest.approx(STEADY_ARM_UPLIFT_LIMIT * 1e3, rel=1e-12)
    assert options.WITHIN_PERCENT == 10.0 and options.ELEMENT_LENGTH == 0.5  # the paper's 0.5 m elements
    assert 1 <= options.WORKERS <= 64


@pytest.mark.parametrize(("command", "stated"), [
    ("recommend", [f"(default {options.WITHIN_PERCENT:g})", f"(default {options.UPLIFT_LIMIT_MM:g},",
                   f"(default {options.ELASTICITY_STEP:g})", f"(default {options.ELEMENT_LENGTH:g};"]),
    ("design", [f"(default {options.WORKING_WIDTH_MM:g})", f"(default {options.LINE_ELASTICITY_STEP:.1f})"]),
    ("robust", [f"(default {options.DROPPER_STEP_MM:g})", f"default {options.ROBUST_MODEL}"]),
])
def test_the_help_states_the_jobs_defaults(command, stated):
    text = _help(command)
    for part in stated:
        assert part in text, (command, part)
