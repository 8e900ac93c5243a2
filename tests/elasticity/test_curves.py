"""``presag_opt.elasticity.curves``: the summary values of an elasticity curve (e_mid, e_mast, Δe,
uniformity) on a curve whose values are known in closed form, and the study's JSON layout."""

from __future__ import annotations

import numpy as np
import pytest

from presag_opt.elasticity.curves import ElasticityCurve, ElasticityStudy

L = 60.0
X = np.linspace(0.0, L, 601)  # 0.1 m apart: mid-span is a sample


def _curve(force=100.0, e_mast=0.35e-3, rise=0.5e-3, skew=0.0) -> ElasticityCurve:
    """e(x) = e_mast + rise·sin²(πx/l) + skew·x/l: e_mid = e_mast + rise (+ skew/2), exactly."""
    e = e_mast + rise * np.sin(np.pi * X / L) ** 2 + skew * X / L
    return ElasticityCurve(span=4, span_length=L, force=force, position=X, elasticity=e,
                           slack_droppers=np.zeros(X.size, dtype=int) if force else None)


def test_the_summary_values_of_a_known_curve():
    c = _curve()
    assert c.e_mid == pytest.approx(0.85e-3, rel=1e-12)
    assert c.e_mast == pytest.approx(0.35e-3, rel=1e-12)
    assert (c.e_max, c.e_min) == pytest.approx((0.85e-3, 0.35e-3), rel=1e-12)
    assert c.delta_e == pytest.approx(0.5e-3, rel=1e-12)
    assert c.uniformity == pytest.approx(0.5 / 1.2, rel=1e-12)  # (e_max − e_min)/(e_max + e_min)


def test_e_mast_is_the_mean_of_the_two_ends_of_an_unequal_span():
    c = _curve(skew=0.1e-3)
    assert c.e_mast == pytest.approx(0.35e-3 + 0.05e-3, rel=1e-12)
    assert c.e_mid == pytest.approx(0.85e-3 + 0.05e-3, rel=1e-12)


def test_at_interpolates_linearly_between_the_points():
    c = ElasticityCurve(span=0, span_length=10.0, force=None, position=np.array([0.0, 4.0, 10.0]),
                        elasticity=np.array([1e-4, 5e-4, 2e-4]))
    assert c.at(2.0) == pytest.approx(3e-4, rel=1e-12)
    np.testing.assert_allclose(c.at(np.array([4.0, 7.0])), [5e-4, 3.5e-4], rtol=1e-12)
    assert c.e_mid == pytest.approx(4.5e-4, rel=1e-12)  # x = 5 m, a sixth of the way from 4 to 10 m


def test_summary_in_mm_per_n():
    s = _curve().summary_mm_per_N()
    assert s == pytest.approx({"force_N": 100.0, "e_mid_mm_per_N": 0.85, "e_mast_mm_per_N": 0.35, "e_max_mm_per_N": 0.85,
                               "e_min_mm_per_N": 0.35, "delta_e_mm_per_N": 0.5, "uniformity": 0.5 / 1.2}, rel=1e-12)


def test_a_study_separates_the_linear_curve_and_counts_spans_from_one_in_json():
    study = ElasticityStudy(catenary_name="ST", span=4, curves=(_curve(100.0), _curve(150.0), _curve(None)),
                            warnings=("w",))
    assert [c.force for c in study.nonlinear] == [100.0, 150.0] and study.linear.force is None
    assert ElasticityStudy(catenary_name="ST", span=4, curves=(_curve(100.0),)).linear is None
    data = study.to_dict()
    assert (data["span"], data["span_length_m"], data["warnings"]) == (5, 60.0, ["w"])
    assert data["curves"][0]["elasticity_mm_per_N"][300] == pytest.approx(0.85, rel=1e-12)
    assert "slack_droppers" in data["curves"][0] and "slack_droppers" not in data["curves"][2]
