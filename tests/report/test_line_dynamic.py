"""The dynamic check of a designed line (presag_opt.report.line_dynamic): which section and which points
of the band it simulates, and the decision made again with the simulated uplift. The simulator is
replaced by a recorder (the simulation itself is tested in tests/robust/test_dynamic_check.py and end to
end by ``presag design --dynamic-check`` in tests/cli/test_design.py)."""

from __future__ import annotations

import pytest

from presag_opt.design import CASE_STUDY_BAND
from presag_opt.design.line import LineOptions, design_line
from presag_opt.report import line_dynamic
from presag_opt.robust.dynamic_check import DynamicCheck, DynamicRun
from presag_opt.system.catenary import SpanLayout
from presag_opt.system.loader import load_catenary
from presag_opt.system.survey_writing import survey_of_catenary


@pytest.fixture(scope="module")
def design():
    """Five 50 m spans of ST 9,8/9,8 as a survey, designed by the default rule."""
    base = load_catenary("st_9.8_mixed").with_layout(SpanLayout(span_lengths=(50.0,) * 5))
    options = LineOptions(element_length=1.0, step=1.0, geometry_tolerance=5e-5, workers=1)
    return design_line(survey_of_catenary(base), base, CASE_STUDY_BAND, options)


def _recorder(uplift: float, calls: list):
    def simulate(catenary, designs, **kwargs):
        calls.append((catenary, designs, kwargs))
        runs = tuple(DynamicRun(design="built", presag=0.03, static_force=f, speed=kwargs["speeds"][0], beta=0.2,
                                mean_force=f + 10.0, std_force=0.1 * f, sigma_over_mean=0.09, uplift_max=uplift,
                                loss_of_contact=0.0) for f in kwargs["static_forces"])
        return DynamicCheck(runs=runs)
    return simulate


def test_the_worst_section_is_simulated_at_the_bands_top_speed_and_its_extreme_forces(design, monkeypatch):
    calls = []
    monkeypatch.setattr(line_dynamic, "simulate_designs", _recorder(0.040, calls))
    checked = line_dynamic.dynamic_check(design)
    ((catenary, designs, kwargs),) = calls
    (section,) = design.sections
    assert catenary is section.catenary and designs == {"built": section.catenary}
    assert kwargs["speeds"] == [CASE_STUDY_BAND.speed_high]
    assert kwargs["static_forces"] == [CASE_STUDY_BAND.static_force_low, CASE_STUDY_BAND.static_force_high]
    assert kwargs["aero_coefficient"] == CASE_STUDY_BAND.aero_coefficient
    assert checked.section == section.section and checked.uplift == 0.040  # the largest of the runs, exactly


@pytest.mark.parametrize("uplift", [0.040, 0.120])
def test_the_decision_is_made_again_with_the_simulated_uplift(design, monkeypatch, uplift):
    monkeypatch.setattr(line_dynamic, "simulate_designs", _recorder(uplift, []))
    decision = line_dynamic.dynamic_check(design).design.decision
    assert all(c.uplift == uplift and c.uplift_dynamic for c in decision.inputs.candidates)
    assert not any("dynamic steady-arm uplift" in n for n in decision.inputs.not_checked)
    assert any("at the band's top speed only" in n for n in decision.inputs.not_checked)
    # every answer at 120 mm is over the 83.5 mm limit, so the decision is bound by uplift; 40 mm is within it
    assert (decision.status == "uplift-bound") == (uplift > decision.inputs.uplift_limit)
    if uplift > decision.inputs.uplift_limit:
        assert "at least 120.0 mm" in decision.reason and "dynamic" in decision.reason
