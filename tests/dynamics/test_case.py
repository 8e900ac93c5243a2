"""``presag_opt.dynamics.case``: case files read with their documented values, and every malformed
section refused with one line naming it. No simulation runs here (``SimulationCase.run`` is covered by
``tests/dynamics/test_case_study_sigma.py`` and the CLI tests)."""

from __future__ import annotations

import shutil

import pytest

from presag_opt.dynamics.case import case_from_dict, load_case
from presag_opt.errors import ModelError
from presag_opt.system.loader import resolve_model_path

SPEED = {"value": [90, 120], "unit": "km/h", "source": "assumed"}
FORCE = {"value": 100, "unit": "N", "source": "assumed"}


def test_case_files_load_with_their_documented_values():
    """docs/assumptions.md §4.3: 115 N, no aerodynamics, 250 and 300 km/h, two central spans, 20 Hz. The case
    study: ST 9,8/9,8 ideal spans, 120 N, 0.00097 N/(km/h)² (12.57 mN/(m/s)²), the paper's speeds."""
    en = load_case("en50318_2002")
    assert en.catenary.name == "EN 50318-style reference catenary"
    assert en.pantograph.stages[1].stiffness == 50.0
    assert (en.operation.static_force, en.operation.aero_coefficient) == (115.0, 0.0)
    assert [round(v * 3.6, 9) for v in en.speeds] == [250.0, 300.0]
    assert (en.settings.analysed_spans, en.settings.cutoff_frequency) == (2, 20.0)
    study = load_case("case_study_st98")
    assert study.catenary.contact_wire.tension == 9800.0
    assert study.pantograph.stages[1].friction == 5.0
    assert study.operation.static_force == 120.0
    assert study.operation.aero_coefficient == pytest.approx(0.00097 * 3.6**2, rel=1e-12)
    assert [round(v * 3.6, 9) for v in study.speeds] == [50, 60, 70, 80, 90, 100, 120, 140, 160, 180]
    assert study.provenance["operation.static_force"].source == "assumed"



def test_case_file_with_an_unknown_key_names_it(tmp_path):
    text = (
        '[case]\nname = "x"\ncatenary = "st_9.8_ideal"\npantograph = "en50318_2mass"\n'
        '[operation]\nstatic_force = { value = 100, unit = "N", source = "assumed" }\n'
        'speeds = { value = [90], unit = "km/h", source = "assumed" }\n'
        '[analysis]\nelement_size = { value = 0.5, unit = "m", source = "assumed" }\n'
    )
    path = tmp_path / "case.toml"
    path.write_text(text, encoding="utf-8")
    with pytest.raises(ModelError, match=r"case.toml: \[analysis\]: unknown key 'element_size'; valid keys: analysed_"):
        load_case(path)
    valid_analysis = text.replace("element_size", "run_out").replace('"m"', '"s"')
    path.write_text(valid_analysis.replace("[90]", "[-90]"), encoding="utf-8")
    with pytest.raises(ModelError, match=r"operation.speeds\[0\] = -90 km/h is outside the valid range \(0, 600\]"):
        load_case(path)



def _data(**sections):
    data = {"case": {"name": "x", "catenary": "st_9.8_ideal", "pantograph": "en50318_2mass"},
            "operation": {"static_force": FORCE, "speeds": SPEED}}
    data.update(sections)
    return {k: v for k, v in data.items() if v is not None}


def test_speeds_are_read_in_m_s_and_the_operation_runs_at_the_first():
    case = case_from_dict(_data())
    assert case.speeds == pytest.approx((25.0, 120 / 3.6), rel=1e-12)  # km/h / 3.6, exact to round-off
    assert case.operation.speed == case.speeds[0]
    assert case.operation.aero_coefficient == 0.0 and case.description == ""
    assert case.provenance["operation.speeds"].source == "assumed"


@pytest.mark.parametrize(("data", "message"), [
    (_data(extra={}), "unknown section [extra]; valid sections: case, operation, analysis"),
    (_data(operation=None), "missing section [operation]"),
    (_data(case={"name": "x", "catenary": "st_9.8_ideal"}),
     "[case] needs 'name', 'catenary' and 'pantograph' (and optionally 'description') and nothing else"),
    (_data(case={"name": "x", "catenary": 3, "pantograph": "en50318_2mass"}), "[case]: model name 3 must be a string"),
    (_data(operation={"static_force": FORCE}), "[operation]: missing required key(s) speeds"),
    (_data(operation=[1]), "[operation] must be a table"),
    (_data(analysis=5), "[analysis] must be a table"),
])
def test_a_malformed_case_is_one_line_naming_the_section(data, message):
    with pytest.raises(ModelError) as caught:
        case_from_dict(data)
    assert str(caught.value) == message


def test_models_are_found_beside_the_case_file_before_the_built_in_ones(tmp_path):
    """A name that is a file in the case's folder means that file (here a copy renamed "mine")."""
    shutil.copy(resolve_model_path("st_9.8_ideal"), tmp_path / "mine.toml")
    case = case_from_dict(_data(case={"name": "x", "catenary": "mine.toml", "pantograph": "en50318_2mass"}),
                          base=tmp_path)
    assert case.catenary.contact_wire.tension == 9800.0
    with pytest.raises(ModelError, match="'mine.toml' is neither a file nor a built-in catenary model"):
        case_from_dict(_data(case={"name": "x", "catenary": "mine.toml", "pantograph": "en50318_2mass"}))


def test_the_plan_of_a_case_uses_its_own_operation_and_analysis_window():
    """Planning is the cheap check before a run (no form-finding): the case's force and analysed spans."""
    case = load_case("en50318_2002")
    plan = case.plan(case.speeds[1])
    assert plan.operation.speed == case.speeds[1] and plan.operation.static_force == 115.0
    assert len(plan.analysed_spans) == case.settings.analysed_spans == 2
