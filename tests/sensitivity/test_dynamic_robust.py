"""The dynamic robust pre-sag as a sensitivity output: what each sample's design is given and returns."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest

import presag_opt.robust.dynamic_study as dynamic_study
from presag_opt.design.band import KMH
from presag_opt.dynamics.case import load_case
from presag_opt.errors import ModelError
from presag_opt.sensitivity.analysis import parse_output, sensitivity_analysis
from presag_opt.sensitivity.dynamic_robust import (
    DYNAMIC_ROBUST_BAND,
    DYNAMIC_ROBUST_VALUES,
    DynamicRobustEvaluator,
    ScreeningNumerics,
)


@pytest.fixture(scope="module")
def case():
    return load_case("case_study_st98")


def test_screening_numerics_are_validated_and_described():
    n = ScreeningNumerics()
    assert (n.span_count, n.element_length, n.time_step, n.presag_tolerance) == (5, 1.0, 2e-3, 1e-3)
    assert n.text() == "5 spans, 1 m elements, 2 ms, S to 1 mm, 4 x 3 points"
    with pytest.raises(ModelError, match=r"time_step = 50 ms is outside the valid range"):
        ScreeningNumerics(time_step=0.05)
    with pytest.raises(ModelError, match=r"span_count = 3 - is outside the valid range \[4, 200\]"):
        ScreeningNumerics(span_count=3)


def test_the_band_is_that_of_presag_robust_dynamic():
    b = DYNAMIC_ROBUST_BAND
    assert (b.static_force_low, b.static_force_high) == (70.0, 140.0)
    assert (b.speed_low, b.speed_high) == pytest.approx((50.0 * KMH, 90.0 * KMH), rel=1e-12)


def friction(pantograph) -> float:
    """The frame's dry friction (the lower stage). [N]"""
    return next(s.friction for s in pantograph.stages if s.name == "frame")


def fake_study(calls):
    """A stand-in for dynamic_robust_study that records its arguments and returns a known design."""
    def study(catenary, pantograph, band, **kwargs):
        calls.append(SimpleNamespace(catenary=catenary, pantograph=pantograph, band=band, **kwargs))
        return SimpleNamespace(design=SimpleNamespace(presag_rel=0.8e-3, worst_case_objective=0.11),
                               tolerance=SimpleNamespace(low=0.5e-3, high=0.95e-3))
    return study


def test_each_sample_designs_its_own_models_at_the_screening_numerics(case, monkeypatch):
    calls = []
    monkeypatch.setattr(dynamic_study, "dynamic_robust_study", fake_study(calls))
    names = ("operation.aero_coefficient", "pantograph.frame.friction", "catenary.droppers.max_spacing")
    evaluator = DynamicRobustEvaluator(catenary=case.catenary, pantograph=case.pantograph, operation=case.operation,
                                       names=names)
    values = evaluator(np.array([0.01, 7.5, 9.0]))
    assert [v for v, _ in DYNAMIC_ROBUST_VALUES] == ["presag_rel", "tolerance_low", "tolerance_high",
                                                      "tolerance_width", "worst_sigma_over_F_m"]
    np.testing.assert_allclose(values, [0.8, 0.5, 0.95, 0.45, 0.11], rtol=1e-12)  # ‰ and -
    (call,) = calls
    assert call.band.aero_coefficient == 0.01 and call.band.speed_low == DYNAMIC_ROBUST_BAND.speed_low
    assert friction(call.pantograph) == 7.5 and friction(case.pantograph) != 7.5
    assert call.catenary.droppers.max_spacing == 9.0
    assert call.catenary.layout.n_spans == 5  # the central five of ten
    s = call.settings
    assert (s.numerics, s.static.element_length, s.integrator.time_step) == ("fixed", 1.0, 2e-3)
    assert (s.lead_in_spans, s.analysed_spans) == (1, 1)
    assert call.search.presag_tolerance == 1e-3 and (call.static_points, call.speed_points) == (4, 3)
    assert call.workers == 1  # the samples run side by side, not the pre-sags of one sample


def test_full_numerics_are_those_of_presag_robust_dynamic(case, monkeypatch):
    calls = []
    monkeypatch.setattr(dynamic_study, "dynamic_robust_study", fake_study(calls))
    DynamicRobustEvaluator(catenary=case.catenary, pantograph=case.pantograph, operation=case.operation, names=(),
                           numerics=None)(np.array([]))
    (call,) = calls
    assert call.catenary is case.catenary and call.settings is None and call.search is None
    assert call.band.aero_coefficient == case.operation.aero_coefficient


def test_the_output_is_named_and_refuses_what_it_cannot_depend_on():
    assert parse_output("dynamic-robust") == ("dynamic-robust", ())
    with pytest.raises(ModelError, match="cannot depend on it.*band of static forces"):
        sensitivity_analysis(output="dynamic-robust", inputs=["operation.static_force"], samples=2)
    with pytest.raises(ModelError, match="cannot depend on it.*equal spans"):
        sensitivity_analysis(output="dynamic-robust", inputs=["catenary.layout.span_lengths"], samples=2)


def test_an_analysis_runs_every_sample_and_ranks_by_the_design(monkeypatch, tmp_path):
    """Through sensitivity_analysis with a stand-in design whose S_rel depends on the friction alone."""
    def study(catenary, pantograph, band, **kwargs):
        s = 0.5e-3 + 0.02e-3 * friction(pantograph)
        return SimpleNamespace(design=SimpleNamespace(presag_rel=s, worst_case_objective=0.1),
                               tolerance=SimpleNamespace(low=s - 1e-4, high=s + 1e-4))
    monkeypatch.setattr(dynamic_study, "dynamic_robust_study", study)
    lines = []
    result = sensitivity_analysis(output="dynamic-robust", inputs=["pantograph.frame.friction", "pantograph.head.mass"],
                                  samples=3, out=tmp_path, announce=lines.append)
    assert result.evaluations == 9 and result.resolution == ScreeningNumerics().text()
    top = result.table("presag_rel").morris
    assert top[0].name == "pantograph.frame.friction" and top[0].mu_star == pytest.approx(0.3, rel=1e-9)  # 0.02 ‰/N × 15 N
    assert top[1].mu_star == 0.0
    assert "timing the first one" in lines[0] and "evaluations ×" in lines[1]
    assert len(list(tmp_path.rglob("evaluation_*.json"))) == 9  # the resumable store
