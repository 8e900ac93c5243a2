"""``presag_opt.studies.parameters``: an extra swept parameter named by a dotted path into the catenary,
the pantograph (its stages by name) or the settings — its spec found, its value applied to a copy and
validated there, and every wrong path refused with the valid names at the level it went wrong."""

from __future__ import annotations

import pytest

from presag_opt.dynamics.pantograph import load_pantograph
from presag_opt.dynamics.settings import SimulationSettings
from presag_opt.errors import ModelError
from presag_opt.studies.parameters import ParameterSweep, apply_parameter, parameter_spec
from presag_opt.system.loader import load_catenary

ROOTS = {"catenary": load_catenary("st_9.8_ideal"), "pantograph": load_pantograph("case_study_2mass_friction"),
         "settings": SimulationSettings()}


def test_the_spec_of_a_path_is_its_fields_quantity():
    spec = parameter_spec("catenary.contact_wire.tension", ROOTS)
    assert (spec["dimension"], spec["display"], spec["low"], spec["high"]) == ("force", "kN", 0.5, 60.0)
    assert parameter_spec("pantograph.frame.friction", ROOTS)["dimension"] == "force"
    assert parameter_spec("settings.run_out", ROOTS)["dimension"] == "time"


def test_a_value_is_applied_to_a_copy_the_original_unchanged():
    catenary = ROOTS["catenary"]
    changed = apply_parameter(catenary, ["contact_wire", "tension"], 12e3, "catenary.contact_wire.tension")
    assert changed.contact_wire.tension == 12e3 and catenary.contact_wire.tension == 9800.0
    assert changed.messenger_wire == catenary.messenger_wire
    pantograph = ROOTS["pantograph"]
    lighter = apply_parameter(pantograph, ["frame", "friction"], 2.5, "pantograph.frame.friction")
    assert [s.friction for s in lighter.stages] == [pantograph.stages[0].friction, 2.5]
    assert pantograph.stages[1].friction == 5.0


def test_a_value_the_model_refuses_is_named_as_the_parameter():
    with pytest.raises(ModelError) as caught:
        apply_parameter(ROOTS["catenary"], ["contact_wire", "tension"], 70e3, "catenary.contact_wire.tension")
    assert str(caught.value) == ("parameters.catenary.contact_wire.tension: tension = 70 kN is outside the valid range "
                                 "[0.5, 60] kN")


@pytest.mark.parametrize(("name", "message"), [
    ("catenary.presag_rel", "parameters: 'catenary.presag_rel' cannot be swept: the pre-sag is the study's own grid "
                            "axis ([grid] presag)"),
    ("track.speed", "parameters: unknown parameter 'track.speed'; a name starts with one of catenary, pantograph, "
                    "settings, train followed by a dotted field path (e.g. pantograph.frame.friction)"),
    ("catenary", "parameters: unknown parameter 'catenary'; a name starts with one of"),
    ("pantograph.arm.mass", "parameters: unknown parameter 'pantograph.arm.mass': 'arm' is not one of head, frame, "
                            "name"),
    ("catenary.name", "parameters: 'catenary.name' is not a numeric quantity and cannot be swept"),
    ("catenary.contact_wire.tension.x", "parameters: unknown parameter 'catenary.contact_wire.tension.x': 'x' is "
                                        "below a value without fields"),
])
def test_a_wrong_path_is_one_line_naming_what_is_valid(name, message):
    with pytest.raises(ModelError) as caught:
        parameter_spec(name, ROOTS)
    assert str(caught.value).startswith(message)


def test_a_sweep_needs_distinct_values():
    assert ParameterSweep(name="pantograph.frame.friction", values=[0, 5]).root == "pantograph"
    with pytest.raises(ModelError, match=r"^parameters.x.y: the list of values is empty; give at least one value$"):
        ParameterSweep(name="x.y", values=[])
    with pytest.raises(ModelError, match=r"^parameters.x.y: values \[1.0, 1.0\] repeat a value$"):
        ParameterSweep(name="x.y", values=[1, 1.0])
