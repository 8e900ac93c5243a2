"""Which method the dynamic study recommends, from the simulated comparison (no simulation here)."""

from __future__ import annotations

import pytest

from presag_opt.robust.dynamic_design import DynamicTolerance
from presag_opt.robust.dynamic_study import DELTA_E, DYNAMIC, QUASI_STATIC, MethodResult, _recommend

SPAN = 60.0
TOLERANCE = DynamicTolerance(low=0.040 / SPAN, high=0.058 / SPAN, within=0.10, worst_case_min=0.0925, runs_used=0,
                             wall_time=0.0)


def methods(quasi_mm, quasi_worst, quasi_uplift=0.050, inside=True):
    def row(name, presag_mm, worst, uplift, within):
        return MethodResult(method=name, presag_rel=presag_mm * 1e-3 / SPAN, objective=worst, worst_case=worst,
                            mean=0.07, uplift_max=uplift, cost=7.0, within_tolerance=within)

    return [row(DELTA_E, 61.4, 0.1154, 0.0498, False), row(QUASI_STATIC, quasi_mm, quasi_worst, quasi_uplift, inside),
            row(DYNAMIC, 45.1, 0.0925, 0.0529, True)]


def test_the_quasi_static_design_is_enough_inside_the_tolerance():
    method, reason = _recommend(methods(55.8, 0.1008), TOLERANCE, 0.26, 7.0, 0.0835, SPAN)
    assert method == QUASI_STATIC
    assert "lies inside the dynamic tolerance interval; its worst case is +9.0 % from the dynamic design's" in reason
    assert "β ≤ 0.26, inside the quasi-static validity limit 0.4" in reason


def test_outside_the_tolerance_the_dynamic_design_is_recommended():
    method, reason = _recommend(methods(61.4, 0.1154, inside=False), TOLERANCE, 0.45, 7.0, 0.0835, SPAN)
    assert method == DYNAMIC
    assert "lies outside the dynamic tolerance interval 40.0–58.0 mm; its worst case is +24.8 %" in reason
    assert "β up to 0.45, above the quasi-static validity limit 0.4" in reason


def test_a_quasi_static_design_above_the_uplift_limit_is_not_recommended():
    method, reason = _recommend(methods(65.9, 0.0900, quasi_uplift=0.0865, inside=False), TOLERANCE, 0.50, 5.0,
                                0.0835, SPAN)
    assert method == DYNAMIC
    assert "lifts the steady arms by 86.5 mm, above the 83.5 mm limit" in reason


@pytest.mark.parametrize("beta", [0.2, 0.6])
def test_the_speed_ratio_alone_does_not_decide(beta):
    assert _recommend(methods(55.8, 0.1008), TOLERANCE, beta, 7.0, 0.0835, SPAN)[0] == QUASI_STATIC
    assert _recommend(methods(61.4, 0.1154, inside=False), TOLERANCE, beta, 7.0, 0.0835, SPAN)[0] == DYNAMIC
