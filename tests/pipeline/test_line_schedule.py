"""The crew's schedule of a decided line (presag_opt.pipeline.line with --round): cut lengths with the
dropper type's allowances, rounding to the step as an installation error (the rounding Monte Carlo and
the crew tolerance it sets a floor to), and the dropper's place on the line."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from presag_opt.design import CASE_STUDY_BAND
from presag_opt.design.evidence import crew_tolerance
from presag_opt.design.line import LineOptions
from presag_opt.design.line_results import RoundingEffect
from presag_opt.pipeline.line import answer_line, with_rounding
from presag_opt.system.catenary import SpanLayout
from presag_opt.system.loader import load_catenary
from presag_opt.system.survey_writing import survey_of_catenary

OPTIONS = LineOptions(element_length=1.0, step=1.0, geometry_tolerance=5e-5, workers=1)
STEP = 0.010


@pytest.fixture(scope="module")
def line():
    base = load_catenary("st_9.8_mixed").with_layout(SpanLayout(span_lengths=(50.0,) * 5))
    return survey_of_catenary(base), base


@pytest.fixture(scope="module")
def exact(line):
    return answer_line(*line, CASE_STUDY_BAND, options=OPTIONS)


@pytest.fixture(scope="module")
def rounded(line):
    return answer_line(*line, CASE_STUDY_BAND, options=dataclasses.replace(OPTIONS, round_step=STEP))


def test_step_zero_cuts_the_clamp_length_plus_the_allowances_exactly(exact):
    droppers = exact.design.droppers
    assert not exact.design.rounding()
    assert all(d.cut_length == d.length + 0.2 for d in droppers)
    assert droppers[0].id == "1/M1-M2/1" and droppers[-1].id.startswith("1/M5-M6/")
    masts = {m.mast: m for m in exact.design.survey.masts}
    for d in droppers:
        assert d.chainage == pytest.approx(masts[d.from_mast].chainage + d.position, abs=1e-12)
        assert d.messenger_height - d.contact_wire_height == pytest.approx(d.length, abs=0.02)


def test_rounded_cut_lengths_are_whole_steps_within_half_a_step(rounded):
    cut = np.array([d.cut_length for d in rounded.design.droppers])
    exact = np.array([d.length + 0.2 for d in rounded.design.droppers])
    np.testing.assert_allclose(cut / STEP, np.round(cut / STEP), atol=1e-9)
    assert np.abs(cut - exact).max() <= STEP / 2 + 1e-12


def test_rounding_widens_the_waviness_and_sets_a_floor_to_the_crew_tolerance(rounded):
    [(section, effect)] = rounded.design.rounding()
    assert section == "1" and effect.step == STEP and effect.samples >= 1000
    assert effect.waviness_p95_ci[0] <= effect.waviness_p95 <= effect.waviness_p95_ci[1]
    assert effect.waviness_p95 > effect.waviness_exact * 1.01
    # a uniform ±5 mm dropper error moves the mid-span pre-sag by millimetres, never by more than it
    assert 0.5e-3 < effect.presag_error_p95 < 2 * STEP
    crew = rounded.decision.evidence.installation
    assert crew.half_width == pytest.approx(max(2.5e-3, effect.presag_error_p95), abs=1e-15)


def test_the_crew_tolerance_is_never_below_what_rounding_alone_causes():
    def effect(error: float) -> RoundingEffect:
        return RoundingEffect(step=0.01, waviness_exact=0.02, waviness_p95=0.025, waviness_p95_ci=(0.024, 0.026),
                              presag_error_p95=error, samples=4000, seed=0)

    assumed = crew_tolerance()
    assert with_rounding(assumed, ()) is assumed
    assert with_rounding(assumed, [("A", effect(1.0e-3))]) is assumed
    larger = with_rounding(assumed, [("A", effect(1.0e-3)), ("B", effect(3.1e-3))])
    assert larger.half_width == 3.1e-3 and larger.kind == "monte-carlo"
    assert "rounding the cut lengths to 10 mm" in larger.source and "section B" in larger.source
    assert with_rounding(crew_tolerance(4e-3), [("B", effect(3.1e-3))]).half_width == 4e-3
