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


def test_a_heavily_compressed_push_off_arm_converges_and_agrees_with_the_tangent_at_a_small_load():
    """ST 7,1/7,1 on a 500 m curve with 45 m spans, one push-off arm: it carries about 645 N of compression, more
    than the contact wire's vertical stiffness around it once the droppers next to it are slack (T·(1/a + 1/b)
    against C/L), so the linearised tension-only (active-set) problem cycles from about 125 N. The section's
    curves fall back to the geometrically nonlinear Newton method there and converge; at 1 N the secant
    elasticity at the push-off mast must equal the linear (tangent) one within 0.1 % (the nonlinearity is O(F):
    measured 0.011 %), and at 150 N it is far softer (measured 2.25 against 0.889 mm/N)."""
    from presag_opt.design.section import section_curves
    from presag_opt.elasticity import linear_elasticity
    from presag_opt.system.survey import SurveyMast, section_catenary

    masts = tuple(SurveyMast(mast=f"M{i}", chainage=45.0 * i, stagger=-0.2, contact_wire_height=5.5, system_height=1.2,
                             curve_radius=500.0, steady_arm="push-off" if i == 4 else "pull-off") for i in range(9))
    cat = section_catenary(load_catenary("st_7.1_mixed"), Survey(masts=masts).sections()[0])
    state = form_find(cat, StaticSettings(element_length=0.5))
    assert -state.steady_arm_forces()[4] == pytest.approx(645.0, rel=0.02)
    curves = section_curves(state, (1.0, 150.0), step=3.0)
    assert curves.elasticity_method == "newton"  # some span needed the fallback
    (study,) = [s for s in curves.studies if s.span == 4]
    tangent = linear_elasticity(state, span=4, step=3.0).elasticity[0]
    small, large = (c.elasticity[0] for c in study.nonlinear)
    assert small == pytest.approx(tangent, rel=1e-3)
    assert large > 2.0 * tangent


def test_a_push_off_arm_without_equilibrium_is_named_with_its_force(monkeypatch):
    """Where the Newton method finds no equilibrium either (here made to fail: no real survey at hand that flips
    an arm within the test budget), one error names the span, the push-off mast and its compression."""
    import presag_opt.design.section as section
    from presag_opt.errors import ConvergenceError, ModelError
    from presag_opt.system.survey import SurveyMast, section_catenary

    masts = tuple(SurveyMast(mast=f"M{i}", chainage=45.0 * i, stagger=-0.2, contact_wire_height=5.5, system_height=1.2,
                             curve_radius=500.0, steady_arm="push-off" if i == 2 else "pull-off") for i in range(5))
    state = form_find(section_catenary(load_catenary("st_7.1_mixed"), Survey(masts=masts).sections()[0]),
                      StaticSettings(element_length=1.0))

    def no_equilibrium(*args, **kwargs):
        raise ConvergenceError("newton: no convergence", {})

    monkeypatch.setattr(section, "elasticity_study", no_equilibrium)
    with pytest.raises(ModelError, match=r"span 1: no equilibrium under an uplift up to 150 N; push-off arm\(s\) at "
                                         r"mast 3 \(6\d\d N of compression\)"):
        section.section_curves(state, (100.0, 150.0), step=3.0)
