"""Rounding the cut lengths as an installation error (presag_opt.robust.cut_rounding): the P95 waviness above the
exact schedule's within its interval, and the mid-span pre-sag error linear in the step (a linearised response
on common draws)."""

from __future__ import annotations

import dataclasses

import pytest

from presag_opt.design import CASE_STUDY_BAND
from presag_opt.design.band import force_levels_for_band
from presag_opt.design.section import section_curves
from presag_opt.robust.cut_rounding import rounding_effect
from presag_opt.robust.path import build_path_model
from presag_opt.robust.scenarios import ForceScenarios
from presag_opt.static.discretisation import StaticSettings
from presag_opt.static.form_finding import form_find
from presag_opt.system.catenary import SpanLayout
from presag_opt.system.loader import load_catenary


@pytest.fixture(scope="module")
def path():
    base = load_catenary("st_9.8_mixed").with_layout(SpanLayout(span_lengths=(50.0,) * 5))
    state = form_find(base, StaticSettings(element_length=1.0))
    curves = section_curves(state, force_levels_for_band(*CASE_STUDY_BAND.mean_force_band()), 1.0)
    sized = dataclasses.replace(curves, studies=tuple(s for s in curves.studies if s.span in (1, 2, 3)))
    return build_path_model(state, sized)


def test_rounding_widens_the_waviness_and_its_presag_error_is_linear_in_the_step(path):
    scenarios = ForceScenarios.band(*CASE_STUDY_BAND.mean_force_band())
    five = rounding_effect(path, path.reference_depth, scenarios, 0.005, samples=2000)
    ten = rounding_effect(path, path.reference_depth, scenarios, 0.010, samples=2000)
    assert five.waviness_exact == ten.waviness_exact
    for effect in (five, ten):
        assert effect.waviness_p95_ci[0] <= effect.waviness_p95 <= effect.waviness_p95_ci[1]
        assert effect.waviness_p95 > effect.waviness_exact
    assert ten.waviness_p95 > five.waviness_p95
    assert ten.presag_error_p95 == pytest.approx(2 * five.presag_error_p95, rel=1e-9)
    # a uniform ±2.5 mm error on every dropper moves the mid-span pre-sag by about as much
    assert 0.5e-3 < five.presag_error_p95 < 5e-3
