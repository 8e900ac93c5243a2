"""The job behind ``presag sensitivity``: output names, the choice of inputs, refusals, the result."""

from __future__ import annotations

import json
from types import SimpleNamespace

import numpy as np
import pytest

import presag_opt.robust.dynamic_study as dynamic_study
from presag_opt.design.band import KMH
from presag_opt.errors import ModelError
from presag_opt.sensitivity.analysis import _independent, parse_output, sensitivity_analysis


@pytest.fixture
def constant_design(monkeypatch):
    """The dynamic robust design replaced by a constant one (the analysis around it is what is tested)."""
    def study(catenary, pantograph, band, **kwargs):
        return SimpleNamespace(design=SimpleNamespace(presag_rel=1e-3, worst_case_objective=0.1),
                               tolerance=SimpleNamespace(low=0.9e-3, high=1.1e-3))
    monkeypatch.setattr(dynamic_study, "dynamic_robust_study", study)


def test_output_names_and_speeds():
    assert parse_output("recommendation") == ("recommendation", ())
    kind, speeds = parse_output("dynamic:50,90")
    assert kind == "dynamic" and speeds == pytest.approx((50 * KMH, 90 * KMH), rel=1e-15)
    for text, words in (("dynamic", "is not one of"), ("robust:50", "is not one of"),
                        ("validity:90,50", "increasing"), ("dynamic:700", "(0, 600] km/h"),
                        ("minima:x", "numbers in km/h")):
        with pytest.raises(ModelError, match=words.replace("(", r"\(").replace(")", r"\)").replace("]", r"\]")):
            parse_output(text)


def test_why_an_output_cannot_depend_on_an_input():
    roots = {"catenary": SimpleNamespace(layout=SimpleNamespace(span_lengths=(60.0, 60.0)))}
    assert "quasi-static" in _independent("recommendation", "pantograph.head.mass", roots)
    assert "band of static forces" in _independent("dynamic-robust", "operation.static_force", roots)
    assert _independent("dynamic", "operation.static_force", roots) is None  # one operating point
    assert "equal spans" in _independent("robust", "catenary.layout.span_lengths", roots)
    assert "numerical settings" in _independent("dynamic", "settings.integrator.time_step", roots)
    assert _independent("dynamic-robust", "pantograph.head.mass", roots) is None


def test_default_inputs_are_every_assumed_number_the_output_depends_on(constant_design):
    result = sensitivity_analysis(output="dynamic-robust", samples=2)
    names = [i.name for i in result.inputs]
    assert "pantograph.frame.friction" in names and "catenary.droppers.max_spacing" in names
    assert "operation.aero_coefficient" in names
    assert "operation.static_force" not in names and "catenary.layout.span_lengths" not in names
    assert result.evaluations == 2 * (len(names) + 1)
    # a constant output: every effect is zero, the spread is zero
    table = result.table("presag_rel")
    assert all(e.mu_star == 0.0 for e in table.morris) and table.std == 0.0
    with pytest.raises(ModelError, match="is not one of presag_rel"):
        result.table("sigma")


def test_a_range_override_adds_its_input_and_the_json_is_in_display_units(constant_design):
    result = sensitivity_analysis(output="dynamic-robust", inputs=["pantograph.head.mass"], samples=2, seed=4,
                                  ranges=["pantograph.frame.friction=1:3"])
    assert [i.name for i in result.inputs] == ["pantograph.head.mass", "pantograph.frame.friction"]
    data = json.loads(json.dumps(result.to_dict()))
    design = np.array(data["design"])
    assert design.shape == (6, 2) and design[:, 1].min() >= 1.0 and design[:, 1].max() <= 3.0
    assert data["seed"] == 4 and data["method"] == "morris" and len(data["values"]) == 6


def test_refusals(constant_design):
    with pytest.raises(ModelError, match="--method 'fast' is not one of morris, sobol, spread"):
        sensitivity_analysis(output="dynamic-robust", method="fast")
    with pytest.raises(ModelError, match="names an input twice"):
        sensitivity_analysis(output="dynamic-robust", inputs=["pantograph.head.mass", "pantograph.head.mass"],
                             samples=2)
    with pytest.raises(ModelError, match="has no range in the model files.*--range pantograph.frame.stiffness=LOW:HIGH"):
        sensitivity_analysis(output="dynamic-robust", inputs=["pantograph.frame.stiffness"], samples=2)
