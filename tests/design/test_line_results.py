"""The results of a line design (presag_opt.design.line_results): the sized line's records for the decision
(its Δe rule, its spans' robust designs as one record, its worst section) and a span's margins."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest

from presag_opt.design.line_results import LineSizing, SpanDesign


def section(range_rel, uplift, lengths, presag=None, tolerance=None):
    """A SectionSizing stand-in: its Δe range, static uplift, span lengths and span rule."""
    sized = list(range(1, len(lengths) - 1))
    rec = SimpleNamespace(presag_rel_range=range_rel,
                          steady_arm_uplift=SimpleNamespace(uplift=uplift, support_elasticity=uplift / 148.0),
                          at_band_low=SimpleNamespace(spans=sized, span_lengths=np.asarray(lengths)[sized]))
    rule = None if presag is None else SimpleNamespace(presag=np.asarray(presag), tolerance=np.asarray(tolerance))
    return SimpleNamespace(recommendation=rec, span_presags=rule,
                           catenary=SimpleNamespace(layout=SimpleNamespace(span_lengths=tuple(lengths))))


def sizing(sections) -> LineSizing:
    return LineSizing(survey=None, base_name="b", band=None, options=None, sections=(), sizing=tuple(sections),
                      levels=(), settings=None)


NAN = [np.nan, np.nan]


def test_the_line_s_delta_e_rule_is_the_mean_of_every_section_s_range_ends():
    line = sizing([section((0.8e-3, 1.2e-3), 0.050, (50.0, 50.0, 50.0)),
                   section((0.9e-3, 1.5e-3), 0.061, (40.0, 60.0, 40.0))])
    assert line.presag_rel == pytest.approx(np.mean([0.8e-3, 1.2e-3, 0.9e-3, 1.5e-3]), rel=1e-15)
    record = line.delta_e()
    assert record.presag_rel_range == (0.8e-3, 1.5e-3) and record.static_uplift == 0.061
    assert line.worst_section() == 1
    assert line.sized_span_lengths == (50.0, 60.0)


def test_the_spans_robust_designs_are_one_record_of_their_means_in_s_rel():
    first = section((0.8e-3, 1.2e-3), 0.05, (50.0, 50.0, 40.0, 50.0),
                    presag=[0.045, 0.050, 0.032, 0.045], tolerance=[NAN, [0.046, 0.054], [0.028, 0.036], NAN])
    line = sizing([first, section((0.8e-3, 1.2e-3), 0.05, (50.0, 50.0, 50.0))])
    record = line.quasi_static_robust(0.1)
    assert record.presag_rel == pytest.approx(np.mean([0.050 / 50, 0.032 / 40]), rel=1e-12)
    assert record.tolerance == pytest.approx((np.mean([0.046 / 50, 0.028 / 40]), np.mean([0.054 / 50, 0.036 / 40])),
                                             rel=1e-12)
    assert sizing([section((0.8e-3, 1.2e-3), 0.05, (50.0, 50.0, 50.0))]).quasi_static_robust(0.1) is None


def test_a_span_s_margins_to_its_own_tolerance():
    common = dict(section="A", span=2, from_mast="M2", to_mast="M3", chainage=50.0, length=50.0, e_mid=4e-4,
                  e_mast=3e-4, delta_e=1e-4, steady_arm_force=400.0, static_uplift=0.05, sized=True)
    inside = SpanDesign(presag=0.050, tolerance=(0.046, 0.054), **common)
    assert inside.margins() == pytest.approx((0.004, 0.004), abs=1e-15)
    outside = SpanDesign(presag=0.058, tolerance=(0.046, 0.054), **common)
    assert outside.margins()[1] == pytest.approx(-0.004, abs=1e-15)
    assert SpanDesign(presag=0.05, **common).margins() is None
