"""Helpers of ``presag design`` (presag_opt.cli.line): the span rule chosen from the options, the JSON summary
of a dynamic robust decision."""

from __future__ import annotations

import argparse
from types import SimpleNamespace

import pytest

from presag_opt.cli.line import _span_rule, dynamic_robust_summary
from presag_opt.errors import ModelError
from presag_opt.robust.span_design import RobustSpanRule


def test_the_robust_rule_takes_within_in_percent():
    assert _span_rule(argparse.Namespace(rule="robust", within=5.0)) == RobustSpanRule(within=0.05)
    assert _span_rule(argparse.Namespace(rule="robust", within=None)) == RobustSpanRule(within=0.10)
    assert _span_rule(argparse.Namespace(rule="proportional", within=None)) is None
    with pytest.raises(ModelError, match="--within is an option of --rule robust, not of --rule per-span"):
        _span_rule(argparse.Namespace(rule="per-span", within=5.0))
    with pytest.raises(ModelError, match="within = 0 %"):
        _span_rule(argparse.Namespace(rule="robust", within=0.0))


def test_the_dynamic_robust_summary_keeps_the_figures_a_designer_reads():
    data = {"presag_mm": 45.1, "presag_rel_permille": 0.75, "tolerance_mm": [28.0, 56.1], "uplift_max_mm": 52.9,
            "reference_span_m": 60.0, "runs_used": 60, "wall_time_s": 240.0, "static_force_N": [70.0, 140.0],
            "speed_kmh": [50.0, 90.0], "curve": "left out"}
    result = SimpleNamespace(where="section A", study=SimpleNamespace(to_dict=lambda: data))
    summary = dynamic_robust_summary(result)
    assert summary["where"] == "section A" and summary["presag_mm"] == 45.1 and "curve" not in summary
