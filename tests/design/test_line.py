"""Line design (presag_opt.design.line): a surveyed section designed as its hand-written model, a height
change built as the straight gradient plus the parabola, the dropper schedule read back and solved again,
and a curved section against the curved-track study (notebook 05)."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from presag_opt.design import CASE_STUDY_BAND, OperatingBand
from presag_opt.design.layouts import curve_effects
from presag_opt.design.line import LineOptions, build_line, design_line, size_line
from presag_opt.errors import ModelError
from presag_opt.report.line_report import dropper_rows
from presag_opt.static.discretisation import StaticSettings
from presag_opt.static.equilibrium_newton import newton_equilibrium
from presag_opt.static.form_finding import form_find
from presag_opt.system.catenary import SpanLayout
from presag_opt.system.loader import load_catenary
from presag_opt.system.survey import Survey
from presag_opt.system.survey_writing import survey_of_catenary

# The case study's pin (tests/validation/test_headline.py, MIXED_RANGE) of the mixed section's S_rel range
# over the band [‰]: Δe rule, 0.5 m elements, 0.5 m point spacing, all spans but the end spans; 1e-4 relative
# as there.
MIXED_RANGE = (0.6199784, 1.0860220)
PIN = 1e-4


def straight_survey(heights: list[float], length: float = 50.0) -> Survey:
    """Straight track, alternating ±300 mm, one section, the given contact-wire height per mast. [m]"""
    cat = load_catenary("st_9.8_mixed").with_layout(SpanLayout(span_lengths=(length,) * (len(heights) - 1)))
    survey = survey_of_catenary(cat)
    masts = tuple(dataclasses.replace(m, contact_wire_height=h) for m, h in zip(survey.masts, heights))
    return dataclasses.replace(survey, masts=masts)


def test_the_mixed_section_as_a_survey_gives_the_same_design():
    base = load_catenary("st_9.8_mixed")
    options = LineOptions(element_length=0.5, step=0.5, geometry_tolerance=5e-5, workers=1)
    design = design_line(survey_of_catenary(base), base, CASE_STUDY_BAND, options)
    (section,) = design.sections
    low, high = section.sizing.recommendation.presag_rel_range
    assert low * 1e3 == pytest.approx(MIXED_RANGE[0], rel=PIN)
    assert high * 1e3 == pytest.approx(MIXED_RANGE[1], rel=PIN)
    # built: every span S_rel·l, the same droppers as the TOML model form-found at that S_rel (1e-6 m: the
    # chainages are sums of the span list, so the geometry agrees to round-off, not bit for bit)
    reference = form_find(base.with_presag(design.presag_rel), StaticSettings(element_length=0.5))
    cut = reference.params.unstretched_length[reference.discretisation.dropper_elements]
    assert np.abs(np.array([d.length for d in design.droppers]) - cut).max() < 1e-6
    assert [s.presag for s in design.spans] == pytest.approx(
        [design.presag_rel * length for length in base.layout.span_lengths], rel=1e-12)


@pytest.fixture(scope="module")
def gradient_design():
    """Straight track with the contact wire lowered by 0.2 m over span 4 (5.5 m up to mast 4, 5.3 m after)."""
    heights = [5.5] * 4 + [5.3] * 4
    base = load_catenary("st_9.8_mixed")
    options = LineOptions(element_length=0.5, step=1.0, geometry_tolerance=5e-5, workers=1)
    return design_line(straight_survey(heights), base, CASE_STUDY_BAND, options), heights


def test_a_height_change_is_the_straight_gradient_plus_the_parabola(gradient_design):
    design, heights = gradient_design
    s = design.presag_rel * 50.0
    for d in design.droppers:
        a, b = heights[d.span - 1], heights[d.span]
        t = d.position / 50.0
        expected = a + (b - a) * t - 4.0 * s * t * (1.0 - t)
        # 0.1 mm: the form-finding holds its targets to 0.05 mm (StaticSettings.geometry_tolerance)
        assert d.contact_wire_height == pytest.approx(expected, abs=1e-4)
        assert d.presag == pytest.approx(4.0 * s * t * (1.0 - t), abs=1e-12)
    # the droppers of the lowered span: the higher end's are longer (system height is the same at both ends)
    span4 = [d for d in design.droppers if d.span == 4]
    assert span4[0].length > span4[-1].length - 1e-3


def test_the_dropper_schedule_read_back_gives_the_heights_back(gradient_design, tmp_path):
    design, _ = gradient_design
    rows = [{k: str(v) for k, v in row.items()} for row in dropper_rows(design)]  # as droppers.csv prints them
    assert len(rows) == len(design.droppers)
    # solve the equilibrium again with the cut lengths as printed (0.1 mm) in place of the form-found ones
    state = form_find(design.sections[0].catenary, StaticSettings(element_length=0.5))
    disc = state.discretisation
    lengths = state.params.unstretched_length.copy()
    lengths[disc.dropper_elements] = [float(r["dropper_length_mm"]) * 1e-3 for r in rows]
    params = dataclasses.replace(state.params, unstretched_length=lengths)
    x, _ = newton_equilibrium(state.model, params, state.positions.ravel(), disc.settings)
    heights = x.reshape(-1, 3)[disc.axial.node_a[disc.dropper_elements], 2]
    printed = np.array([float(r["contact_wire_height_mm"]) * 1e-3 for r in rows])
    # 0.1 mm: lengths and heights are printed to 0.1 mm; a dropper's length error moves its clamp by about as much
    assert np.abs(heights - printed).max() < 1e-4


def test_a_curved_section_gives_the_curved_track_study():
    """Notebook 05's section on R = 300 m (its fast numerics), written as a survey, sizes to the same S_rel."""
    base = load_catenary("st_7.1_mixed")
    spans = (40.0, 45.0, 38.5, 42.0, 35.0, 47.5, 41.0, 36.0, 44.0, 39.0, 43.0)
    curved = base.with_layout(SpanLayout(span_lengths=spans, curve_radii=(300.0,) * len(spans)))
    band = OperatingBand(static_force_low=70.0, static_force_high=140.0, speed_high=80 / 3.6,
                         aero_coefficient=0.00097 * 3.6**2)
    settings = StaticSettings(element_length=1.0)
    (effect,) = curve_effects(base.with_layout(SpanLayout(span_lengths=spans)), (300.0,), band=band, step=1.0,
                              settings=settings)
    design = design_line(survey_of_catenary(curved), base, band,
                         LineOptions(element_length=1.0, step=1.0, workers=1))
    rec = design.sections[0].sizing.recommendation
    assert rec.presag_rel_range == pytest.approx(effect.presag_rel_range, rel=1e-9)
    assert design.presag_rel == pytest.approx(effect.presag_rel, rel=1e-9)
    # independent (in the built state, at the line's pre-sag): the mean inner steady-arm pull is the curve's kink T·(l_before + l_after)/(2R); the
    # alternating stagger kinks (±2·0.3 m over each span) cancel on average to within 10 %
    inner = design.sections[0].spans[1:]
    kink = [base.contact_wire.tension * (a + b) / (2 * 300.0) for a, b in zip(spans[:-1], spans[1:])]
    assert np.mean([s.steady_arm_force for s in inner]) == pytest.approx(np.mean(kink), rel=0.10)


def test_a_push_off_arm_softens_its_support_like_an_inverted_pendulum():
    """One mast of a curve turned from pull-off to push-off: the arm's geometric stiffness across it, C·cos²θ/L,
    changes sign, so the support stiffness 1/e_mast (a point spring added at the load's own degree of freedom
    changes 1/e by its stiffness, Sherman–Morrison) falls by 2·C·cos²θ/L. 15 %: the arm is inclined, so its
    stiffness across also couples the clamp's lateral freedom, which this one-spring estimate leaves out
    (measured: 10 %)."""
    from presag_opt.elasticity import linear_elasticity
    from presag_opt.system.survey import SurveyMast, section_catenary

    base = load_catenary("st_7.1_mixed")
    settings = StaticSettings(element_length=0.5)
    out = {}
    for arm_type in ("pull-off", "push-off"):
        masts = tuple(SurveyMast(mast=f"M{i}", chainage=40.0 * i, stagger=-0.2, contact_wire_height=5.5,
                                 system_height=1.2, curve_radius=800.0, steady_arm=arm_type if i == 4 else "pull-off")
                      for i in range(9))
        state = form_find(section_catenary(base, Survey(masts=masts).sections()[0]), settings)
        out[arm_type] = (linear_elasticity(state, span=4, step=0.5).elasticity[0], state.steady_arm_forces()[4],
                         state.steady_arm_angles()[4])
    (e_pull, c_pull, a_pull), (e_push, c_push, a_push) = out["pull-off"], out["push-off"]
    assert c_pull > 0 > c_push and c_push == pytest.approx(-c_pull, rel=0.01)  # same lateral pull, opposite sign
    length = base.contact_wire_support.length
    expected = (c_push * np.cos(a_push) ** 2 - c_pull * np.cos(a_pull) ** 2) / length
    assert 1 / e_push - 1 / e_pull == pytest.approx(expected, rel=0.15)
    assert e_push > 1.3 * e_pull


def test_a_section_that_cannot_be_designed_is_set_apart_and_the_line_goes_on():
    """Section B's 0.4 m system height leaves no room for its droppers: it is refused (before any solve)
    and recorded with its masts; section A is designed exactly as it is alone."""
    base = load_catenary("st_9.8_mixed")
    options = LineOptions(element_length=1.0, step=1.0, workers=1)

    def section(name: str, first: int, system_height: float):
        return tuple(dataclasses.replace(m, mast=f"{name}{i}", section=name, chainage=m.chainage + 50.0 * first,
                                         system_height=system_height)
                     for i, m in enumerate(straight_survey([5.5] * 4).masts))

    survey = Survey(masts=section("A", 0, 1.2) + section("B", 4, 0.4))
    design = design_line(survey, base, CASE_STUDY_BAND, options)
    assert [s.section for s in design.sections] == ["A"]
    (failure,) = design.failures
    assert failure.inputs == {"section": "B", "from_mast": "B0", "to_mast": "B3", "chainage_m": [200.0, 350.0]}
    assert failure.failure.startswith("sizing: ") and "the messenger wire sags to about" in failure.failure
    assert design.failure_summary().startswith("1 of 2 sections could not be designed (first: section B, sizing: ")
    alone = design_line(Survey(masts=section("A", 0, 1.2)), base, CASE_STUDY_BAND, options)
    assert design.presag_rel == alone.presag_rel
    assert [d.length for d in design.droppers] == [d.length for d in alone.droppers]
    with pytest.raises(ModelError, match="the messenger wire sags to about"):
        design_line(Survey(masts=section("B", 4, 0.4)), base, CASE_STUDY_BAND, options)


def test_the_elasticity_as_built_is_the_sizing_pass_s_where_the_built_presag_is_the_base_model_s():
    base = load_catenary("st_9.8_mixed").with_layout(SpanLayout(span_lengths=(50.0,) * 5))
    options = LineOptions(element_length=1.0, step=1.0, workers=1)
    sizing = size_line(survey_of_catenary(base), base, CASE_STUDY_BAND, options)
    design = build_line(sizing, base.presag_rel)
    centre = 0.5 * sum(CASE_STUDY_BAND.mean_force_band())
    sized = dict(zip(sizing.sizing[0].elasticity.spans, sizing.sizing[0].elasticity.curves_at(centre)))
    for s in design.spans:
        np.testing.assert_allclose(s.curve.elasticity, sized[s.span - 1].elasticity, rtol=1e-9)
        assert s.uniformity == pytest.approx(sized[s.span - 1].uniformity, rel=1e-9)
        assert 0.0 < s.uniformity < 1.0



def test_the_static_uplift_of_each_arm_is_the_decision_s_estimate_at_the_top_of_the_band():
    """F_m,top · e(F_m,top) at every steady arm, the law of the decision's static estimate: on a curve with
    push-off arms the elasticity at a support grows with the force (droppers next to the arm go slack), so the
    elasticity at the band centre would understate it (here by up to 40 %). Built at the sizing pass's own
    pre-sag, the largest arm's value is the decision's estimate itself."""
    from presag_opt.system.survey import SurveyMast

    base = load_catenary("st_7.1_mixed")
    lengths, masts, chainage = (42.0, 45.0, 48.0, 40.0, 36.0, 44.0, 50.0, 38.0, 46.0), [], 0.0
    for i, length in enumerate(lengths):
        radius = -800.0 if 3 <= i < 8 else 0.0
        masts.append(SurveyMast(mast=f"B{i:02d}", chainage=chainage, stagger=0.2 if i >= 3 else 0.3 * (-1) ** i,
                                contact_wire_height=5.5, system_height=1.2, curve_radius=radius,
                                steady_arm="push-off" if i >= 3 and i % 2 else "pull-off"))
        chainage += length
    sizing = size_line(Survey(masts=tuple(masts)), base, CASE_STUDY_BAND,
                       LineOptions(element_length=1.0, step=2.0, workers=1))
    design = build_line(sizing, base.presag_rel)
    low, top = CASE_STUDY_BAND.mean_force_band()
    centre = 0.5 * (low + top)
    curves = sizing.sizing[0].elasticity
    at_top = dict(zip(curves.spans, curves.curves_at(top)))
    at_centre = dict(zip(curves.spans, curves.curves_at(centre)))
    arms = [s for s in design.spans if s.static_uplift is not None]
    for s in arms:
        assert s.static_uplift == pytest.approx(top * at_top[s.span - 1].elasticity[0], rel=1e-6)
    understated = max(s.static_uplift / (top * at_centre[s.span - 1].elasticity[0]) for s in arms)
    assert understated > 1.2  # the case tells the two forces apart
    decision = sizing.sizing[0].recommendation.steady_arm_uplift.uplift
    assert max(s.static_uplift for s in arms) == pytest.approx(decision, rel=1e-6)
