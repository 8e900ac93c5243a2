"""Inputs of a sensitivity analysis: names, ranges, the span-list input, and refusals."""

from __future__ import annotations

import numpy as np
import pytest

from presag_opt.dynamics.case import load_case
from presag_opt.errors import ModelError
from presag_opt.sensitivity.analysis import sensitivity_analysis
from presag_opt.sensitivity.inputs import (
    PAPER_MIXED_SECTION,
    SPAN_LIST,
    apply_inputs,
    model_inputs,
    parse_range_override,
    random_span_list,
    span_list_bank,
    span_list_of,
)
from presag_opt.system.loader import load_catenary


@pytest.fixture(scope="module")
def case():
    return load_case("case_study_st98")


def roots_of(case):
    roots = {"catenary": case.catenary, "pantograph": case.pantograph, "operation": case.operation}
    provenance = {"catenary": case.catenary.provenance, "pantograph": case.pantograph.provenance,
                  "operation": case.provenance}
    return roots, provenance


def test_assumed_inputs_are_named_as_presag_sweep_names_them(case):
    inputs = model_inputs(*roots_of(case))
    assert "pantograph.frame.friction" in inputs and "catenary.droppers.max_spacing" in inputs
    assert "catenary.system_height" in inputs and "operation.aero_coefficient" in inputs
    # not assumed (paper): tensions, contact stiffness; a zero without a declared range: frame stiffness
    for name in ("catenary.contact_wire.tension", "pantograph.contact.stiffness", "pantograph.frame.stiffness"):
        assert name not in inputs
    friction = inputs["pantograph.frame.friction"]
    assert (friction.low, friction.high, friction.declared) == (0.0, 15.0, True)
    support = inputs["catenary.contact_wire_support.axial_stiffness"]  # no declared range: ±20 %
    assert (support.low, support.high) == pytest.approx((16e6, 24e6), rel=1e-12) and not support.declared
    # an ideal section has no span-list input
    assert SPAN_LIST not in inputs


def test_random_span_lists_meet_the_papers_summary():
    rng = np.random.default_rng(1)
    for _ in range(50):
        spans = random_span_list(rng, **PAPER_MIXED_SECTION)
        assert len(spans) == 31
        assert sum(spans) == pytest.approx(1340.2, abs=1e-9)
        assert min(spans) == 24.7 and max(spans) == 58.4
    bank = span_list_bank()
    assert bank == span_list_bank()  # fixed by its seed
    assert span_list_of(0.0) == bank[0] and span_list_of(1.0) == bank[-1]
    assert len(set(bank)) == len(bank)


def test_apply_inputs_sets_fields_and_the_span_list():
    mixed = load_catenary("st_9.8_mixed")
    out = apply_inputs({"catenary": mixed}, {SPAN_LIST: 0.5, "catenary.droppers.max_spacing": 10.0})
    assert out["catenary"].layout.span_lengths == span_list_of(0.5)
    assert out["catenary"].droppers.max_spacing == 10.0
    assert out["catenary"].presag_rel == mixed.presag_rel
    assert mixed.droppers.max_spacing == 8.5  # the original is untouched


def test_range_override_in_the_display_unit(case):
    roots, _ = roots_of(case)
    item = parse_range_override("pantograph.head.mass=6:8", roots)
    assert (item.low, item.high, item.value) == (6.0, 8.0, 7.2)
    mm = parse_range_override("catenary.system_height=1.1:1.3", roots)
    assert (mm.low, mm.high) == (1.1, 1.3)


@pytest.mark.parametrize("kwargs,words", [
    ({"output": "recommendation", "inputs": ["pantograph.head.mass"]}, ["cannot depend on it", "quasi-static"]),
    ({"output": "robust", "inputs": [SPAN_LIST]}, ["cannot depend on it", "equal spans"]),
    ({"output": "minima:50", "inputs": ["operation.static_force"]}, ["band of static forces"]),
    ({"output": "dynamic:50", "inputs": ["settings.integrator.time_step"]}, ["numerical settings"]),
    ({"output": "validity:50"}, ["at least two speeds"]),
    ({"output": "dynamic:90,50"}, ["increasing"]),
    ({"output": "recommendation", "method": "fast"}, ["--method 'fast'"]),
])
def test_refusals_are_one_line(kwargs, words):
    with pytest.raises(ModelError) as info:
        sensitivity_analysis("case_study_st98", **kwargs)
    message = str(info.value)
    assert "\n" not in message
    for word in words:
        assert word in message, (word, message)
