"""``presag_opt.dynamics.cost``: the time and memory a set of runs will take, from the rates the module
declares, and the refusals of runs a 2-core machine cannot carry. The estimate is checked against its
own formula (rate × nodes × steps), not against a stopwatch: the rates are rough on purpose."""

from __future__ import annotations

import pytest

from presag_opt.dynamics import cost
from presag_opt.dynamics.pantograph import load_pantograph
from presag_opt.dynamics.run_plan import plan_run
from presag_opt.dynamics.settings import SimulationSettings
from presag_opt.errors import ModelError
from presag_opt.static.run_time import form_find_estimate
from presag_opt.system.loader import load_catenary

IDEAL = load_catenary("st_9.8_ideal")
PANTOGRAPH = load_pantograph("case_study_2mass_friction")


@pytest.fixture
def no_cache(test_runtime):
    """No form-finding cache: every form-finding is counted at its full estimated time."""
    with test_runtime.replace(state_cache=None):
        yield


@pytest.mark.parametrize(("seconds", "text"), [(0.4, "0 s"), (89.4, "89 s"), (90.0, "2 min"), (5399.0, "90 min"),
                                               (5400.0, "1.5 h"), (8280.0, "2.3 h")])
def test_a_duration_is_given_in_the_unit_people_read(seconds, text):
    assert cost.duration(seconds) == text


def test_the_description_is_one_line_of_runs_nodes_time_and_memory():
    estimate = cost.WorkEstimate(nodes=(2413, 120013), form_finding_seconds=100.0, runs=1, run_seconds=500.0,
                                 memory=3.25e9)
    assert estimate.seconds == 600.0
    assert estimate.describe() == ("1 run on 2 413, 120 013 nodes: about 10 min and 3.2 GB of memory on a 2-core "
                                   "machine")
    assert cost.WorkEstimate(nodes=(5,), form_finding_seconds=0, runs=3, run_seconds=1, memory=0).describe().startswith(
        "3 runs on 5 nodes")


def test_runs_are_priced_per_node_step_with_one_form_finding_per_element_length(no_cache):
    settings = SimulationSettings()
    plans = [plan_run(IDEAL, PANTOGRAPH, speed=v, static_force=120.0, settings=settings) for v in (30.0, 50.0)]
    n_nodes, form_seconds = form_find_estimate(IDEAL, settings.static)
    steps = [p.step_count(settings.integrator.time_step) for p in plans]
    single = cost.estimate_runs(IDEAL, plans, batch=False)
    batch = cost.estimate_runs(IDEAL, plans, batch=True)
    assert single.nodes == batch.nodes == (n_nodes,) and single.runs == 2
    assert single.form_finding_seconds == pytest.approx(form_seconds, rel=1e-12)  # once, not once per run
    assert single.run_seconds == pytest.approx(cost.SINGLE_SECONDS_PER_NODE_STEP * n_nodes * sum(steps), rel=1e-12)
    assert batch.run_seconds == pytest.approx(cost.BATCH_SECONDS_PER_NODE_STEP * n_nodes * sum(steps), rel=1e-12)
    # the single runs keep histories (16 B per node-step) of the longest run; the batch keeps none
    assert single.memory == pytest.approx(cost.BASE_MEMORY + max(
        cost.SINGLE_RUN_BYTES_PER_NODE_STEP * n_nodes * max(steps), cost.FORM_FINDING_BYTES_PER_NODE * n_nodes), rel=1e-12)
    assert batch.memory == pytest.approx(cost.BASE_MEMORY + cost.FORM_FINDING_BYTES_PER_NODE * n_nodes, rel=1e-12)


def test_automatic_numerics_below_five_centimetres_are_refused_naming_the_fix(monkeypatch):
    """330 km/h is β = 0.96 on ST 9,8/9,8 (c = 345 km/h): the automatic rule asks for 2 cm elements."""
    with pytest.warns(UserWarning, match="exceeds 0.7"):
        plan = plan_run(IDEAL, PANTOGRAPH, speed=330 / 3.6, static_force=120.0,
                        settings=SimulationSettings(numerics="auto"))
        fine = plan_run(IDEAL, PANTOGRAPH, speed=330 / 3.6, static_force=120.0,
                        settings=SimulationSettings().with_fixed_numerics(element_length=0.01, time_step=1e-4))
    estimate = cost.WorkEstimate(nodes=(10,), form_finding_seconds=0.0, runs=1, run_seconds=1.0, memory=1e9)
    monkeypatch.setattr(cost, "physical_memory", lambda: 8e9)
    if plan.settings.static.element_length >= cost.MIN_AUTO_ELEMENT_LENGTH:
        pytest.fail(f"300 km/h on ST 9,8 should need elements below 5 cm, got {plan.settings.static.element_length}")
    with pytest.raises(ModelError, match=r"^speed = 330 km/h \(β = 0\.96\): automatic numerics need elements of "
                                         r"0\.0\d+ m, below the limit 0\.05 m \(1 run on 10 nodes: .*\); give --fix"):
        cost.check_run_size([plan], estimate, fix="--fix")
    cost.check_run_size([fine], estimate, fix="--fix")  # fixed numerics are the user's choice
    too_big = cost.WorkEstimate(nodes=(10,), form_finding_seconds=0.0, runs=1, run_seconds=1.0, memory=20e9)
    with pytest.raises(ModelError, match=r"^the runs need about 20 GB of memory, more than this machine's 8 GB "
                                         r"\(1 run on 10 nodes: .*\); give longer elements or time steps \(--fix\)"):
        cost.check_run_size([fine], too_big, fix="--fix")
    monkeypatch.setattr(cost, "physical_memory", lambda: None)
    cost.check_run_size([fine], too_big, fix="--fix")  # unknown memory: not refused


def test_physical_memory_is_a_positive_number_of_bytes_on_linux():
    memory = cost.physical_memory()
    assert memory is not None and 1e8 < memory < 1e14
