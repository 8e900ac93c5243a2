"""robust/buildability.py: the limits a line crew can build, and the exact excess of a profile over
them, on the path model of ST 9,8/9,8 (package fixture)."""

from __future__ import annotations

import numpy as np
import pytest

from presag_opt.errors import ModelError
from presag_opt.robust.buildability import Buildability, _violation

LOOSE = dict(max_depth_rel=0.005, max_kink=0.05, min_dropper_length=0.0)
"""Limits no smooth profile of a few centimetres reaches: one limit at a time is tested. [-, -, m]"""


def test_limits_are_validated_with_unit_and_range():
    with pytest.raises(ModelError, match=r"buildability.step = -1 mm is outside the valid range \[0, 50\] mm"):
        Buildability(step=-1e-3)
    with pytest.raises(ModelError, match=r"buildability.max_kink = 60 ‰ is outside the valid range"):
        Buildability(max_kink=0.06)


def test_a_parabola_within_every_limit_has_no_excess(path):
    depths = _parabola(path, 0.5e-3)
    assert _violation(path, depths, Buildability(**LOOSE)) == 0.0


def test_the_excess_is_the_largest_overshoot_of_each_limit(path):
    lengths = np.asarray(path.state.catenary.layout.span_lengths)[path.dropper_span]
    depths = _parabola(path, 0.5e-3)  # 30 mm at mid-span of 60 m
    deepest = float(np.max(depths / lengths))
    # the depth limit 0.2 ‰ below the deepest point: the excess is 0.2 ‰ of that span, exactly
    excess = _violation(path, depths, Buildability(**{**LOOSE, "max_depth_rel": deepest - 0.2e-3}))
    assert excess == pytest.approx(0.2e-3 * lengths[int(np.argmax(depths / lengths))], rel=1e-9)
    # a dropper pulled 2 mm above the support level: 2 mm of excess (its kink stays far below 50 ‰)
    raised = depths.copy()
    raised[int(np.argmin(depths))] = -2e-3
    assert _violation(path, raised, Buildability(**LOOSE)) == pytest.approx(2e-3, rel=1e-9)
    # the kink limit at zero: the excess is the largest slope change at a dropper, > 0 for a parabola
    kink = _violation(path, depths, Buildability(**{**LOOSE, "max_kink": 0.0}))
    assert 0.0 < kink < 0.05


def _parabola(path, presag_rel: float) -> np.ndarray:
    """Depth 4 S_rel L x (1 − x) at each dropper (x the fraction of its span). [m]"""
    lengths = np.asarray(path.state.catenary.layout.span_lengths)[path.dropper_span]
    x = path.dropper_fraction
    return 4.0 * presag_rel * lengths * x * (1.0 - x)
