"""The per-span robust rule (presag_opt.robust.span_design): per-mast contact-wire heights in the path model.

A line whose heights are all equal gives the case-study robust design exactly; a uniform height gradient is a
rigid rotation of small angle, so the pre-sag below the sloped support line is the flat one."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from presag_opt.design import CASE_STUDY_BAND, OperatingBand, force_levels_for_band, section_elasticity
from presag_opt.errors import ModelError
from presag_opt.robust import build_path_model, robust_presag
from presag_opt.robust.span_design import RobustSpanRule, span_robust_designs
from presag_opt.static.form_finding import form_find
from presag_opt.system.catenary import SpanLayout
from presag_opt.system.loader import load_catenary
from presag_opt.system.survey import section_catenary
from presag_opt.system.survey_writing import survey_of_catenary


def surveyed(catenary, heights=None):
    """The catenary rebuilt from its survey (per-mast geometry), with the given contact-wire heights. [m]"""
    survey = survey_of_catenary(catenary)
    if heights is not None:
        survey = dataclasses.replace(survey, masts=tuple(dataclasses.replace(m, contact_wire_height=h)
                                                         for m, h in zip(survey.masts, heights)))
    (section,) = survey.sections()
    return section_catenary(catenary, section).with_presag(catenary.presag_rel)


def test_constant_heights_give_the_case_study_robust_design(path, scenarios, band):
    # The case study's path model (scalar height, central span) against the same section built from its survey
    # (per-mast heights, all equal): the same LP on the same numbers up to the discretisation's round-off
    # (positions agree to 1e-9 m), so S agrees to 1e-6 mm. (Run by hand at the relinearised geometry of
    # robust_study: 55.7736 mm both ways, difference 0.0 mm.)
    case = robust_presag(path, scenarios)
    state = form_find(surveyed(path.state.catenary))
    curves = section_elasticity(state, force_levels=path.section.force_levels, spans=path.spans)
    (span,) = span_robust_designs(build_path_model(state, curves), scenarios)
    assert abs(span.presag_rel - case.presag_rel) * 60.0 < 1e-9
    (alone,) = span_robust_designs(path, scenarios)  # of_span of a one-span model is the model itself
    assert alone.presag_rel == pytest.approx(case.presag_rel, abs=1e-12)
    assert alone.tolerance[0] < alone.presag_rel < alone.tolerance[1]


def test_a_uniform_gradient_is_a_rigid_rotation(band, scenarios):
    # Five 60 m spans, contact wire rising 2 ‰ (1:500) along the section: 0.6 m over 300 m. A uniform gradient
    # rotates the whole section by θ = 2e-3 rad; gravity across the wire changes by cos θ − 1 = 2e-6 and the
    # tension along it by the weight's component, w·sin θ·x ≈ 16 N·m⁻¹·2e-3·150 m ≈ 5 N on 9.8 kN (0.05 %), so
    # the pre-sag below the sloped support line should match the flat one to well under 0.1 mm (0.2 %): a test
    # that fails if the path still measured from one level (the 0.12 m rise over the span would be "waviness").
    base = load_catenary("st_9.8_ideal").with_layout(SpanLayout(span_lengths=(60.0,) * 5, label="test: 5 spans"))
    flat = surveyed(base)
    chainage = np.arange(6) * 60.0
    sloped = surveyed(base, heights=list(base.contact_wire_height + 2e-3 * chainage))
    levels = force_levels_for_band(*band)
    out = []
    for cat in (flat, sloped):
        state = form_find(cat)
        curves = section_elasticity(state, force_levels=levels, spans=(2,))
        (span,) = span_robust_designs(build_path_model(state, curves), scenarios)
        out.append(span)
    assert abs(out[1].presag_rel - out[0].presag_rel) * 60.0 < 1e-4
    assert np.abs(np.subtract(out[1].tolerance, out[0].tolerance)).max() * 60.0 < 2e-4


def test_the_rule_refuses_a_bad_within():
    with pytest.raises(ModelError, match="within = 0 %"):
        RobustSpanRule(within=0.0)


def test_a_span_that_is_not_analysed_is_refused(path):
    with pytest.raises(ModelError, match="span 0 is not an analysed span"):
        path.of_span(0)


def test_the_rule_gives_every_span_its_parabola_and_the_end_spans_the_mean(band):
    # Four 50 m spans: spans 2 and 3 sized (no relinearisation, for speed); spans 1 and 4 take their mean and have
    # no tolerance. The per-span S_rel lies inside its own tolerance interval.
    base = load_catenary("st_9.8_ideal").with_layout(SpanLayout(span_lengths=(50.0,) * 4, label="test: 4 spans"))
    state = form_find(surveyed(base))
    curves = section_elasticity(state, force_levels=force_levels_for_band(*band), spans=(1, 2))
    op = OperatingBand(static_force_low=CASE_STUDY_BAND.static_force_low, static_force_high=CASE_STUDY_BAND.static_force_high,
                       speed_low=CASE_STUDY_BAND.speed_low, speed_high=CASE_STUDY_BAND.speed_high,
                       aero_coefficient=CASE_STUDY_BAND.aero_coefficient)
    rule = RobustSpanRule(relinearise=False)(state, curves, (1, 2), op)
    own = rule.presag[1:3] / 50.0
    assert rule.presag[0] == pytest.approx(own.mean() * 50.0, rel=1e-12)
    assert rule.presag[3] == pytest.approx(own.mean() * 50.0, rel=1e-12)
    assert np.isnan(rule.tolerance[0]).all() and np.isnan(rule.tolerance[3]).all()
    assert np.all(rule.tolerance[1:3, 0] < rule.presag[1:3]) and np.all(rule.presag[1:3] < rule.tolerance[1:3, 1])
    # symmetric section: spans 2 and 3 are mirror images (1e-3 relative: their path points and droppers are not placed mirror-exactly on the 0.5 m mesh)
    assert own[0] == pytest.approx(own[1], rel=1e-3)
    assert rule.presag_rel == pytest.approx(own.mean(), rel=1e-12)
