"""Helpers of ``presag design`` (presag_opt.cli.line): the span rule chosen from the options."""

from __future__ import annotations

import argparse

import pytest

from presag_opt.cli.line import _span_rule
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
