"""Interpolation between force levels and the quasi-static rule (presag_opt.design.quasi_static)."""

from __future__ import annotations

import numpy as np
import pytest

from presag_opt.design import interpolate_elasticity, presag_quasi_static
from presag_opt.elasticity import ElasticityCurve
from presag_opt.errors import ModelError


def synthetic_curve(force, values, span=0):
    """An elasticity curve on five points of a 60 m span. [m/N]"""
    return ElasticityCurve(
        span=span, span_length=60.0, force=force, position=np.linspace(0.0, 60.0, 5), elasticity=np.asarray(values)
    )


def test_interpolation_returns_a_computed_level_exactly(ideal98):
    curves = ideal98.studies[0].nonlinear
    assert interpolate_elasticity(curves, 100.0) is curves[1]


def test_interpolation_between_levels_lies_between_them(ideal98):
    curves = ideal98.studies[0].nonlinear
    below, above = curves[2], curves[3]  # 150 and 200 N: droppers slacken in between
    lower = np.minimum(below.elasticity, above.elasticity)
    upper = np.maximum(below.elasticity, above.elasticity)
    for force in (151.0, 175.0, 199.0):
        e = interpolate_elasticity(curves, force).elasticity
        # A convex combination; 1e-15 m/N is rounding on values of ~1e-3 m/N.
        assert np.all(e >= lower - 1e-15) and np.all(e <= upper + 1e-15)
    # The curves differ where droppers go slack, so "between" is not trivially "equal".
    assert np.abs(above.elasticity - below.elasticity).max() > 1e-5


def test_interpolation_is_linear_in_force():
    a, b = synthetic_curve(100.0, [1.0, 2.0, 3.0, 2.0, 1.0]), synthetic_curve(150.0, [2.0, 2.0, 1.0, 4.0, 3.0])
    e = interpolate_elasticity([b, a], 110.0).elasticity  # order of the input does not matter
    np.testing.assert_allclose(e, 0.8 * a.elasticity + 0.2 * b.elasticity, rtol=1e-14)


@pytest.mark.parametrize("force", [40.0, 210.0])
def test_interpolation_refuses_to_extrapolate(ideal98, force):
    with pytest.raises(ModelError, match=r"outside the computed force levels \[50, 200\] N"):
        interpolate_elasticity(ideal98.studies[0].nonlinear, force)


def test_interpolation_rejects_curves_of_different_spans():
    with pytest.raises(ModelError, match="one span"):
        interpolate_elasticity([synthetic_curve(100.0, [1, 1, 1, 1, 1]), synthetic_curve(150.0, [1, 1, 1, 1, 1], span=2)], 120.0)


# ----- quasi-static rule ----------------------------------------------------------------------------


def test_quasi_static_variants_on_a_known_curve():
    curve = synthetic_curve(100.0, np.array([0.4, 0.9, 0.8, 0.3, 0.5]) * 1e-3)
    # e_mid = 0.8, e_mast = (0.4 + 0.5)/2 = 0.45, Δe = 0.9 − 0.3 = 0.6 mm/N; exact arithmetic.
    assert presag_quasi_static(curve, 120.0, "mid-mast") == pytest.approx(120.0 * 0.35e-3, rel=1e-12)
    assert presag_quasi_static(curve, 120.0, "delta-e") == pytest.approx(120.0 * 0.6e-3, rel=1e-12)
    with pytest.raises(ModelError, match=r"method = 'max-min' is not one of mid-mast, delta-e"):
        presag_quasi_static(curve, 120.0, "max-min")
    with pytest.raises(ModelError, match=r"mean force = 0 N"):
        presag_quasi_static(curve, 0.0)


def test_interpolated_curve_keeps_the_positions_and_the_default_rule_is_delta_e():
    a = synthetic_curve(100.0, np.array([0.4, 0.9, 0.8, 0.3, 0.5]) * 1e-3)
    b = synthetic_curve(150.0, np.array([0.5, 1.0, 0.9, 0.4, 0.6]) * 1e-3)
    between = interpolate_elasticity([a, b], 125.0)
    np.testing.assert_array_equal(between.position, a.position)  # same stations, copied exactly
    # The paper's recommendation uses the Δe variant; it is the default (exact: the same arithmetic).
    assert presag_quasi_static(a, 120.0) == presag_quasi_static(a, 120.0, "delta-e")


def test_interpolation_refuses_repeated_or_missing_levels():
    a = synthetic_curve(100.0, np.full(5, 1e-3))
    with pytest.raises(ModelError, match=r"force levels \[100.0, 100.0\] N are not distinct"):
        interpolate_elasticity([a, synthetic_curve(100.0, np.full(5, 2e-3))], 100.0)
    with pytest.raises(ModelError, match="needs nonlinear curves"):
        interpolate_elasticity([], 100.0)
