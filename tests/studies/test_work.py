"""Work units of a study (presag_opt.studies.work): the units of the grid, their grouping into tasks that
share a form-found state, the unit files' round trip, the nominal F_m and the one-line failure reasons.
The worker function itself runs in tests/studies/test_runner.py and tests/studies/test_two_pantographs.py."""

from __future__ import annotations

import json
import math

import pytest

from presag_opt.errors import ConvergenceError, ModelError
from presag_opt.studies.definition import load_study
from presag_opt.studies.work import (
    STATISTICS,
    TASK_UNITS,
    UnitResult,
    WorkUnit,
    all_units,
    failure_reason,
    nominal_mean_force,
    task_groups,
)


@pytest.fixture(scope="module")
def paper():
    return load_study("paper_grid_st98")


def test_a_unit_key_names_its_indices():
    assert WorkUnit(parameter_indices=(), presag_index=2, speed_index=5).key == "s2_v5"
    assert WorkUnit(parameter_indices=(0, 1), presag_index=2, speed_index=5).key == "p0-1_s2_v5"


def test_every_pre_sag_and_speed_is_one_unit_with_a_unique_key(paper):
    units = all_units(paper)
    assert len(units) == len(paper.grid.presags) * len(paper.grid.speeds) == 50
    assert len({u.key for u in units}) == 50 and units == sorted(units)


def test_tasks_hold_at_most_task_units_of_one_pre_sag_and_lose_none(paper):
    units = all_units(paper)
    groups = task_groups(units)
    assert [u for g in groups for u in g] == units
    assert all(1 <= len(g) <= TASK_UNITS for g in groups)
    assert all(len({u.presag_index for u in g}) == 1 for g in groups)
    # 10 speeds per pre-sag in tasks of 4: 4 + 4 + 2, five times
    assert [len(g) for g in groups] == [4, 4, 2] * 5
    assert [len(g) for g in task_groups(units, size=1)] == [1] * 50


def test_the_nominal_mean_force_is_f_stat_plus_alpha_v_squared(paper):
    speed = 100 / 3.6
    expected = 95.0 + paper.grid.aero_coefficient * speed**2  # 0.00097 N/(km/h)² · (100 km/h)² = 9.7 N
    assert nominal_mean_force(paper, speed, 95.0) == pytest.approx(expected, rel=1e-15)
    assert expected == pytest.approx(104.7, rel=1e-12)


def _result(trailing: bool) -> UnitResult:
    unit = WorkUnit(parameter_indices=(1,), presag_index=0, speed_index=3)
    stats = {name: (1.0 / 3.0, math.nan) for name in STATISTICS}
    return UnitResult(
        unit=unit, **stats, uplift_max=(0.05, math.nan), speed_ratio=0.2612, failure=("", "did not converge"),
        presag_delta_e=(0.061, math.nan), presag_mid_mast=(0.048, math.nan), rule_failure="",
        trailing={name: (0.7, 0.1) for name in STATISTICS} if trailing else None)


@pytest.mark.parametrize("trailing", [False, True])
def test_a_unit_result_survives_its_json_file_exactly(trailing):
    result = _result(trailing)
    back = UnitResult.from_dict(json.loads(json.dumps(result.to_dict())))
    assert back.unit == result.unit and back.trailing == result.trailing
    assert back.mean_force[0] == 1.0 / 3.0 and math.isnan(back.mean_force[1])  # floats round-trip exactly
    assert back.failure == result.failure and back.speed_ratio == result.speed_ratio


def test_a_single_pantograph_units_file_without_a_trailing_key_still_loads():
    data = _result(False).to_dict()
    del data["trailing"]
    assert UnitResult.from_dict(data).trailing is None


@pytest.mark.parametrize(("exc", "reason"), [
    (ConvergenceError("Newton did not converge at step 12\nmore detail"), "Newton did not converge at step 12"),
    (ModelError("speed = 400 km/h is outside the valid range"), "speed = 400 km/h is outside the valid range"),
    (MemoryError(), "MemoryError: out of memory"),
    (MemoryError("cannot allocate 3 GB"), "MemoryError: cannot allocate 3 GB"),
    (ZeroDivisionError("float division by zero"), "ZeroDivisionError: float division by zero"),
    (KeyError(), "KeyError"),
])
def test_a_failure_is_one_line_that_names_unexpected_errors_by_type(exc, reason):
    assert failure_reason(exc) == reason
