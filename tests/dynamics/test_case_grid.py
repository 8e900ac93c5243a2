"""``presag_opt.dynamics.case_grid``: a case run over a grid of speeds and static forces — planned
speed-major, form-found once per element length (longest first), run as one batch per state and the
outcomes put back in the order of the plans. The form-finding and the batch engine are replaced by
recorders here (they have their own tests), so the bookkeeping is checked in milliseconds."""

from __future__ import annotations

from types import SimpleNamespace

import pytest

from presag_opt.dynamics import case_grid
from presag_opt.dynamics.case import load_case
from presag_opt.dynamics.settings import SimulationSettings
from presag_opt.errors import ModelError

CASE = load_case("case_study_st98")


def test_the_grid_is_planned_speed_major_at_each_force():
    plans = case_grid.plan_grid(CASE, [20.0, 30.0], [90.0, 120.0, 150.0], CASE.settings)
    assert list(plans) == [(20.0, 90.0), (20.0, 120.0), (20.0, 150.0), (30.0, 90.0), (30.0, 120.0), (30.0, 150.0)]
    for (speed, force), plan in plans.items():
        assert (plan.operation.speed, plan.operation.static_force) == (speed, force)
        assert plan.operation.aero_coefficient == CASE.operation.aero_coefficient  # the case's, unchanged


def _auto_plans():
    """Automatic numerics: 40 and 50 km/h share the longest elements (0.5 m), 160 km/h needs shorter ones."""
    plans = case_grid.plan_grid(CASE, [40 / 3.6, 160 / 3.6, 50 / 3.6], [120.0], SimulationSettings(numerics="auto"))
    lengths = sorted({p.settings.static.element_length for p in plans.values()}, reverse=True)
    assert len(lengths) == 2, lengths
    return plans, lengths


def test_one_form_finding_per_element_length_longest_first(monkeypatch):
    plans, lengths = _auto_plans()
    found, messages = [], []
    monkeypatch.setattr(case_grid, "form_find", lambda catenary, static: found.append(static.element_length) or static)
    states = case_grid.form_find_states(CASE.catenary, plans, progress=messages.append)
    assert found == lengths and list(states) == lengths
    assert messages == [f"form-finding with {h:g} m elements" for h in lengths]


def test_each_state_runs_its_own_plans_in_one_batch_and_the_outcomes_keep_the_plans_order(monkeypatch):
    plans, lengths = _auto_plans()
    calls = []

    def fake_batch(state, pantograph, points, *, spacings, settings, progress):
        calls.append((state, [(p.speed, p.static_force) for p in points]))
        progress("1 of 1 runs")
        return SimpleNamespace(runs=tuple(("run", state, p.speed) for p in points), wall_time=2.0,
                               catenary_name="c", pantograph_names=("p",))

    monkeypatch.setattr(case_grid, "simulate_many", fake_batch)
    messages = []
    result = case_grid.simulate_grid(CASE, plans, {h: f"state {h}" for h in lengths}, CASE.settings,
                                     progress=messages.append)
    long_keys = [k for k, p in plans.items() if p.settings.static.element_length == lengths[0]]
    assert calls[0] == (f"state {lengths[0]}", long_keys) and len(calls) == 2
    assert [r[2] for r in result.runs] == [k[0] for k in plans]  # back in the order of the plans
    assert all(r[1] == f"state {plans[k].settings.static.element_length}" for r, k in zip(result.runs, plans))
    assert result.wall_time == 4.0  # the sum over the two batches
    assert messages == [f"{h:g} m elements: 1 of 1 runs" for h in lengths]


def test_states_at_no_plans_element_length_are_refused():
    plans = case_grid.plan_grid(CASE, [20.0], [120.0], CASE.settings)
    with pytest.raises(ModelError, match=r"^states: no form-found state at the element length of any plan"):
        case_grid.simulate_grid(CASE, plans, {0.123: None}, CASE.settings)
