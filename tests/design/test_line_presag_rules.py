"""Each pre-sag rule of a line design against an independent computation of the rule.

A four-span mixed section (45.0, 58.4, 24.7, 52.0 m: inner spans of very different length, so that a
rule applied to the wrong span or at the wrong force shows) is designed with the per-span and the
robust rule of :func:`presag_opt.design.line.design_line`; the proportional rule's S = S_rel·l with
the line's S_rel (the same for every rule, checked here) is pinned on the whole mixed section in
``test_line.py``. The expected pre-sags are computed here from the raw
elasticity curves of the design's sizing pass, by the rule as the paper states it (e interpolated
linearly in force between the two computed levels around F_m, Δe = e_max − e_min, S = F_m·Δe,
S_rel = S/l), without the package's quasi-static functions; the robust rule's parabolas against a
scan of the worst-case waviness of each span alone, without its linear program.

Tolerances: the rule recomputed from the same curves differs only by round-off (1e-9 relative); the
robust scan's step is 0.002 ‰ of S_rel, and the LP's optimum must be within a step of the scan's.
"""

from __future__ import annotations

import numpy as np
import pytest

from presag_opt.design import CASE_STUDY_BAND
from presag_opt.design.line import LineOptions, design_line
from presag_opt.robust import ForceScenarios, build_path_model
from presag_opt.robust.span_design import RobustSpanRule
from presag_opt.static.discretisation import StaticSettings
from presag_opt.static.form_finding import form_find
from presag_opt.system.catenary import SpanLayout
from presag_opt.system.loader import load_catenary
from presag_opt.system.survey_writing import survey_of_catenary

SPANS = (45.0, 58.4, 24.7, 52.0)
INNER = (1, 2)
"""The spans that size the pre-sag: all but the end spans, whose outer support is the termination."""
OPTIONS = dict(element_length=1.0, step=2.0, workers=1)


@pytest.fixture(scope="module")
def base():
    return load_catenary("st_9.8_mixed")


@pytest.fixture(scope="module")
def survey(base):
    return survey_of_catenary(base.with_layout(SpanLayout(span_lengths=SPANS, label="test: four spans")))


@pytest.fixture(scope="module")
def designs(base, survey):
    """The section designed with the per-span and the robust rule (the robust one without its second,
    relinearised pass, so that its sizing geometry is the one scanned here)."""
    return {"per-span": design_line(survey, base, CASE_STUDY_BAND, LineOptions(rule="per-span", **OPTIONS)),
            "robust": design_line(survey, base, CASE_STUDY_BAND, LineOptions(rule="robust", **OPTIONS),
                                  span_rule=RobustSpanRule(relinearise=False))}


def _delta_e_rule(study, force: float) -> float:
    """S_rel of one span by the Δe rule at F_m = ``force``, from its raw curves. [-]"""
    curves = sorted((c for c in study.curves if c.force is not None), key=lambda c: c.force)
    levels = np.array([c.force for c in curves])
    upper = int(np.searchsorted(levels, force))
    lower = max(upper - 1, 0)
    if levels[min(upper, len(levels) - 1)] == force:
        lower = upper = min(upper, len(levels) - 1)
    a, b = curves[lower], curves[upper]
    weight = 0.0 if b.force == a.force else (force - a.force) / (b.force - a.force)
    e = (1.0 - weight) * a.elasticity + weight * b.elasticity
    return force * (e.max() - e.min()) / study.curves[0].span_length


def _expected_rules(design):
    """Per inner span, S_rel at the band's low and high F_m; and the line's S_rel (the mean of the range
    ends of the section's mean S_rel over the band). [-]"""
    (section,) = design.sections
    studies = {s.span: s for s in section.sizing.elasticity.studies}
    low, high = CASE_STUDY_BAND.mean_force_band()
    per_span = {s: (_delta_e_rule(studies[s], low), _delta_e_rule(studies[s], high)) for s in INNER}
    dense = np.linspace(low, high, 201)
    mean = np.array([np.mean([_delta_e_rule(studies[s], f) for s in INNER]) for f in dense])
    return per_span, 0.5 * (mean.min() + mean.max())


def test_the_lines_s_rel_is_the_middle_of_the_sections_range_over_the_band(designs):
    """The S_rel of the proportional rule (and of the end spans under the per-span rule)."""
    for design in designs.values():
        assert design.presag_rel == pytest.approx(_expected_rules(design)[1], rel=1e-9)


def test_the_per_span_rule_builds_each_spans_own_s_rel_at_the_band_middle(designs):
    """An inner span: the mean of its own S_rel at the band's two ends; an end span: the line's S_rel."""
    design = designs["per-span"]
    per_span, line_rel = _expected_rules(design)
    expected = [0.5 * sum(per_span[s]) * SPANS[s] if s in per_span else line_rel * SPANS[s] for s in range(len(SPANS))]
    assert [s.presag for s in design.spans] == pytest.approx(expected, rel=1e-9)
    # the spans' own S_rel differ by more than the tolerance: a rule taking one S_rel for all would fail
    rel = [0.5 * sum(per_span[s]) for s in INNER]
    assert max(rel) / min(rel) > 1.05
    # and the band's ends differ too: a rule taking one end only would fail
    assert all(high / low > 1.2 for low, high in per_span.values())
    # the built geometry: every dropper on its span's parabola (0.05 mm: the form-finding's tolerance)
    for d in design.droppers:
        t = d.position / SPANS[d.span - 1]
        assert d.presag == pytest.approx(4.0 * expected[d.span - 1] * t * (1.0 - t), abs=1e-9)


def test_the_robust_rule_builds_each_spans_minimax_parabola(designs, base):
    design = designs["robust"]
    (section,) = design.sections
    sizing = section.sizing
    state = form_find(sizing.elasticity.catenary, StaticSettings(element_length=OPTIONS["element_length"],
                                                                 geometry_tolerance=5e-4))
    path = build_path_model(state, sizing.elasticity)
    scenarios = ForceScenarios.band(*CASE_STUDY_BAND.mean_force_band())
    built = [s.presag / length for s, length in zip(design.spans, SPANS)]
    grid = np.arange(0.0, 3.0e-3, 0.002e-3)
    for s in INNER:
        span = path.of_span(s)
        uplift = span.uplift(scenarios.forces)
        worst = np.array([np.ptp(span.heights(span.parabola_depths(rel), scenarios.forces, uplift), axis=1).max()
                          for rel in grid])
        best = grid[np.argmin(worst)]
        assert built[s] == pytest.approx(best, abs=0.002e-3), s
        low, high = section.spans[s].tolerance
        assert low < section.spans[s].presag < high
    # the end spans take the mean S_rel of the sized spans
    mean = np.mean([built[s] for s in INNER])
    assert built[0] == pytest.approx(mean, rel=1e-9) and built[-1] == pytest.approx(mean, rel=1e-9)
