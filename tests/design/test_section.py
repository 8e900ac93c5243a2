"""Sections (presag_opt.design.section): per-span pre-sag on a mixed section, default spans."""

from __future__ import annotations

import numpy as np
import pytest

from presag_opt.design import default_spans, section_elasticity
from presag_opt.static.discretisation import StaticSettings
from presag_opt.static.form_finding import form_find
from presag_opt.system.loader import load_catenary
from presag_opt.system.survey import Survey


def test_mixed_section_presag_per_span(short_mixed):
    section = section_elasticity(short_mixed, force_levels=(100.0, 150.0), step=1.0)
    assert section.spans == (1, 2, 3)  # end spans excluded by default
    result = section.presag(120.0, "delta-e")
    lengths = np.array([58.4, 24.7, 40.7])
    np.testing.assert_array_equal(result.span_lengths, lengths)
    # Definitions, exact up to rounding: S_i = F_m Δe_i, S_rel,i = S_i/l_i, built S ∝ l.
    np.testing.assert_allclose(result.presag, 120.0 * result.elasticity_difference, rtol=1e-14)
    np.testing.assert_allclose(result.presag_rel, result.presag / lengths, rtol=1e-14)
    assert result.presag_rel_mean == pytest.approx(result.presag_rel.mean(), rel=1e-14)
    np.testing.assert_allclose(result.presag_proportional / lengths, result.presag_rel_mean, rtol=1e-14)
    # Spans of different length do need different relative pre-sag (the paper's Fig. 5a point).
    assert np.ptp(result.presag_rel) > 0.05 * result.presag_rel_mean


def test_default_spans():
    assert default_spans(load_catenary("st_9.8_ideal")) == (5,)
    assert default_spans(load_catenary("st_9.8_mixed")) == tuple(range(1, 30))


def test_a_push_off_arm_that_would_flip_is_refused_with_its_compression():
    """ST 7,1/7,1 on a 500 m curve with 45 m spans, one push-off arm carrying about 645 N of compression on 1 m:
    once the uplift slackens the droppers next to it, the contact wire holds it only by T·(1/a + 1/b), less than
    C/L, and there is no equilibrium beyond about 100 N (measured: at 1 m elements neither the linearised
    tension-only method nor the nonlinear Newton method finds one at 150 N; with the arm carrying 522 N, on a
    620 m curve, both hold to 150 N). The section's curves say so in one error naming the span, the mast and
    the compression."""
    from presag_opt.design.section import section_curves
    from presag_opt.errors import ModelError
    from presag_opt.system.survey import SurveyMast, section_catenary

    masts = tuple(SurveyMast(mast=f"M{i}", chainage=45.0 * i, stagger=-0.2, contact_wire_height=5.5, system_height=1.2,
                             curve_radius=500.0, steady_arm="push-off" if i == 2 else "pull-off") for i in range(5))
    state = form_find(section_catenary(load_catenary("st_7.1_mixed"), Survey(masts=masts).sections()[0]),
                      StaticSettings(element_length=1.0))
    assert -state.steady_arm_forces()[2] == pytest.approx(645.0, rel=0.02)
    with pytest.raises(ModelError, match=r"^span 2: no equilibrium under an uplift up to 150 N; push-off arm\(s\) at "
                                         r"mast 3 \(6\d\d N of compression\)"):
        section_curves(state, (1.0, 150.0), step=3.0)


def test_a_span_the_linearised_method_cannot_solve_falls_back_to_newton(monkeypatch):
    """Where the active-set method fails (here made to, for span 2), the span is computed by Newton's method; at 1 N
    its secant elasticity at the mast equals the linear (tangent) one within 0.1 % (the nonlinearity is O(F))."""
    import presag_opt.design.section as section
    from presag_opt.elasticity import linear_elasticity
    from presag_opt.errors import ConvergenceError
    from presag_opt.system.survey import SurveyMast, section_catenary

    masts = tuple(SurveyMast(mast=f"M{i}", chainage=40.0 * i, stagger=-0.2, contact_wire_height=5.5, system_height=1.2,
                             curve_radius=800.0, steady_arm="push-off" if i == 2 else "pull-off") for i in range(5))
    state = form_find(section_catenary(load_catenary("st_7.1_mixed"), Survey(masts=masts).sections()[0]),
                      StaticSettings(element_length=1.0))
    study = section.elasticity_study

    def cycling(state, span, forces, step, method):
        if method == "active-set" and span == 2:
            raise ConvergenceError("active set: the slack set cycles", {})
        return study(state, span=span, forces=forces, step=step, method=method)

    monkeypatch.setattr(section, "elasticity_study", cycling)
    curves = section.section_curves(state, (1.0, 100.0), step=3.0)
    assert curves.elasticity_method == "newton"
    (span2,) = [s for s in curves.studies if s.span == 2]
    tangent = linear_elasticity(state, span=2, step=3.0).elasticity[0]
    assert span2.nonlinear[0].elasticity[0] == pytest.approx(tangent, rel=1e-3)
