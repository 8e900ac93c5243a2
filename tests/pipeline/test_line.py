"""The decision for a surveyed line (presag_opt.pipeline.line): sized, decided once, built at the decision,
every sized span checked against its own tolerance; the dynamic check of the worst section at the pre-sags
the decision may build. The simulator is replaced by a recorder (the simulation itself is tested in
tests/robust/test_dynamic_check.py and end to end by ``presag design --dynamic-check``)."""

from __future__ import annotations

import numpy as np
import pytest

from presag_opt.design import CASE_STUDY_BAND
from presag_opt.design.line import LineOptions
from presag_opt.pipeline import line as pipeline_line
from presag_opt.pipeline.line import SPAN_FLAGS, answer_line, span_flag
from presag_opt.robust.dynamic_check import DynamicCheck, DynamicRun
from presag_opt.system.catenary import SpanLayout
from presag_opt.system.loader import load_catenary
from presag_opt.system.survey_writing import survey_of_catenary

OPTIONS = LineOptions(element_length=1.0, step=1.0, geometry_tolerance=5e-5, workers=1)


@pytest.fixture(scope="module")
def line():
    """Five 50 m spans of ST 9,8/9,8 as a one-section survey (sized spans 2–4)."""
    base = load_catenary("st_9.8_mixed").with_layout(SpanLayout(span_lengths=(50.0,) * 5))
    return survey_of_catenary(base), base


@pytest.fixture(scope="module")
def answered(line):
    survey, base = line
    return answer_line(survey, base, CASE_STUDY_BAND, options=OPTIONS)


def test_the_line_is_built_at_the_decision_and_every_sized_span_checked(answered):
    decision, design = answered.decision, answered.design
    assert decision.evidence.scope == "line"
    assert design.presag_rel == decision.presag_rel
    assert all(s.presag == pytest.approx(decision.presag_rel * s.length, rel=1e-12) for s in design.spans)
    sized = [s for s in design.spans if s.sized]
    assert [s.span for s in sized] == [2, 3, 4] and all(s.tolerance is not None for s in sized)
    # the line's quasi-static robust record is the mean of its sized spans' own designs
    record = decision.evidence.quasi_static_robust
    assert record.presag_rel == pytest.approx(np.mean([s.robust_presag / s.length for s in sized]), rel=1e-12)
    assert record.tolerance[0] == pytest.approx(np.mean([s.tolerance[0] / s.length for s in sized]), rel=1e-12)
    # the reference span of a line is its shortest sized span; the headline is S_rel × span length
    assert decision.reference_span == 50.0
    assert "‰ × span length" in answered.headline()
    ends = [s for s in design.spans if not s.sized]
    assert [s.span for s in ends] == [1, 5] and all("termination" in s.note for s in ends)
    assert design.spans[0].static_uplift is None and design.spans[0].steady_arm_force is None


def test_span_flags_follow_the_margins_and_the_crew(answered):
    crew = answered.decision.evidence.installation.half_width
    for s in answered.design.spans:
        flag = span_flag(s, crew)
        if s.tolerance is None:
            assert flag == SPAN_FLAGS[0]
            continue
        low, high = s.margins()
        assert flag == (SPAN_FLAGS[2] if min(low, high) < 0 else SPAN_FLAGS[1] if min(low, high) < crew
                        else SPAN_FLAGS[0])
    flagged = answered.flagged()
    assert sum(len(v) for v in flagged.values()) == sum(1 for s in answered.design.spans if answered.flag(s))


def _recorder(uplift: float, calls: list):
    def simulate(catenary, designs, **kwargs):
        calls.append((catenary, designs, kwargs))
        runs = tuple(DynamicRun(design=label, presag=s * kwargs["reference_span"], static_force=f,
                                speed=kwargs["speeds"][0], beta=0.2, mean_force=f + 10.0, std_force=0.1 * f,
                                sigma_over_mean=0.09, uplift_max=uplift + 0.01 * s * 1e3, loss_of_contact=0.0)
                     for label, s in designs.items() for f in kwargs["static_forces"])
        return DynamicCheck(runs=runs)
    return simulate


@pytest.mark.parametrize("uplift", [0.040, 0.120])
def test_the_dynamic_check_simulates_the_worst_section_at_the_pre_sags_the_decision_may_build(line, monkeypatch,
                                                                                              uplift):
    calls = []
    monkeypatch.setattr(pipeline_line, "dynamic_check", _recorder(uplift, calls))
    survey, base = line
    answered = answer_line(survey, base, CASE_STUDY_BAND, options=OPTIONS, check=True)
    ((catenary, designs, kwargs),) = calls
    evidence = answered.decision.evidence
    quasi, delta_e = evidence.quasi_static_robust, evidence.delta_e
    assert sorted(designs.values()) == sorted({*quasi.tolerance, quasi.presag_rel, delta_e.presag_rel})
    assert kwargs["speeds"] == [CASE_STUDY_BAND.speed_high]
    assert kwargs["static_forces"] == [CASE_STUDY_BAND.static_force_low, CASE_STUDY_BAND.static_force_high]
    assert catenary.presag_rel == base.presag_rel  # the section as sized: each pre-sag is form-found by the check
    record = evidence.dynamic_check
    assert [s for s, _ in record.simulated] == pytest.approx(sorted(designs.values()), rel=1e-12)
    assert all(u == pytest.approx(uplift + 0.01 * s * 1e3, rel=1e-9) for s, u in record.simulated)
    assert "dynamic_check" not in answered.decision.missing
    if uplift > evidence.uplift_limit:
        assert answered.decision.status == "uplift-bound"
    else:
        assert answered.decision.uplift_kind == "dynamic"
        assert answered.decision.uplift <= uplift + 0.01 * max(designs.values()) * 1e3



def test_the_curve_and_the_bridge_spans_of_a_survey_are_flagged():
    """Eight 60 m spans: a 900 m curve over spans 3–4, the wire lowered to 5.0 m at M7 (a bridge). One S_rel
    (the default rule) cannot sit inside every span's own tolerance: the curve's spans want less pre-sag
    (their steady arms pull the wire sideways and stiffen the supports), the bridge's spans more (the
    height change puts a kink into the support line); each is flagged and counted in the headline."""
    from presag_opt.system.survey import Survey, SurveyMast

    masts = tuple(SurveyMast(mast=f"M{i + 1}", chainage=60.0 * i,
                             stagger=-0.2 if i in (2, 3, 4) else (0.3 if i % 2 == 0 else -0.3),
                             contact_wire_height=5.0 if i == 6 else 5.5, system_height=1.2,
                             curve_radius=900.0 if i in (2, 3) else 0.0, steady_arm="pull-off") for i in range(9))
    answered = answer_line(Survey(masts=masts), load_catenary("st_9.8_mixed"), CASE_STUDY_BAND,
                           options=LineOptions(element_length=1.0, step=2.0, workers=1))
    flags = {s.span: answered.flag(s) for s in answered.design.spans}
    assert [flags[s] for s in (3, 4, 5, 6)] == [SPAN_FLAGS[2]] * 4
    curve, straight, bridge = (answered.design.spans[i - 1].tolerance for i in (3, 2, 6))
    assert curve[1] < straight[1] < bridge[1]
    assert "4 of 6 sized spans outside their own tolerance" in answered.headline()
    assert "--rule robust" in answered.advice()  # the way out is named
