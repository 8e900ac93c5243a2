"""Stitch wires in the system model: catenary-level limits, model files and form-finding (the input
checks of StitchWire are in tests/system/test_stitch.py, its elements in tests/static/test_stitch_elements.py)."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from presag_opt.errors import ModelError
from presag_opt.static.discretisation import (
    MESSENGER_WIRE,
    STITCH_WIRE,
)
from presag_opt.static.form_finding import form_find
from presag_opt.system.loader import (
    catenary_from_dict,
    load_catenary,
    read_toml,
    resolve_model_path,
)
from presag_opt.system.stitch import StitchWire

GOOD = {"length": 14.0, "tension": 2000.0, "mass_per_length": 0.31, "axial_stiffness": 3.5e6,
        "dropper_positions": (-2.0, 2.0)}


@pytest.fixture(scope="module")
def stitched():
    """Form-found ST 9,8/9,8 stitched section."""
    return form_find(load_catenary("st_9.8_stitched_ideal"))


def test_catenary_refuses_a_stitch_wire_that_reaches_past_the_first_droppers_or_outpulls_the_messenger():
    cat = load_catenary("st_9.8_ideal")  # first droppers 4.5 m from the masts
    with pytest.raises(ModelError, match=r"stitch_wire.length = 14 m is outside the valid range \(0, 9\] m"):
        dataclasses.replace(cat, stitch_wire=StitchWire(**GOOD))
    with pytest.raises(ModelError, match=r"stitch_wire.tension = 4.95 kN is outside the valid range \(0, 4.9\] kN"):
        dataclasses.replace(cat, stitch_wire=StitchWire(**{**GOOD, "length": 9.0, "tension": 4950.0}))


def test_model_file_errors_carry_the_section_and_file():
    data = read_toml(resolve_model_path("st_9.8_stitched_ideal"))
    data["stitch_wire"]["tension"]["value"] = 25.0
    with pytest.raises(ModelError, match=r"stitch_wire.tension = 25 kN is outside the valid range"):
        catenary_from_dict(data)
    data["stitch_wire"]["colour"] = {"value": 1, "unit": "-", "source": "assumed"}
    with pytest.raises(ModelError, match=r"\[stitch_wire\]: unknown key 'colour'"):
        catenary_from_dict(data)


@pytest.mark.parametrize("name", ["st_9.8_stitched_ideal", "en50318_stitched"])
def test_stitched_model_files_load_with_provenance(name):
    cat = load_catenary(name)
    assert cat.stitch_wire is not None
    for key in ("length", "tension", "mass_per_length", "axial_stiffness", "dropper_positions"):
        assert cat.provenance[f"stitch_wire.{key}"].source in ("assumed", "secondary-source", "paper", "standard")


def test_form_finding_meets_the_simple_catenary_tolerances_and_the_stitch_tension(stitched):
    disc = stitched.discretisation
    cat = stitched.catenary
    settings = disc.settings
    # the contact wire on its target at every dropper, stitch droppers included (5e-5 m, as for simple systems)
    z = stitched.positions[disc.axial.node_a[disc.dropper_elements], 2]
    span = disc.dropper_span
    target = np.array([cat.support_line(s, [x])[0] - cat.presag_depth(s, np.array([x]))[0]
                       for s, x in zip(span, disc.dropper_position)])
    assert np.max(np.abs(z - target)) <= settings.geometry_tolerance
    assert np.all(stitched.dropper_forces()[disc.stitch_dropper] > 0.0)  # taut, so tension-only is not active
    # the stitch wire at its tension: horizontal force within 1e-4 of 2 kN in every segment (the
    # Newton relaxation after the string pass lets the nodes move by the wires' stretch; measured 3.3e-2 N)
    assert np.max(np.abs(stitched.horizontal_tension(STITCH_WIRE) - cat.stitch_wire.tension)) < 0.2
    # between the clamps the messenger wire carries its tension less the stitch wire's (along-track balance)
    mw = stitched.horizontal_tension(MESSENGER_WIRE)
    x_mid = 0.5 * (stitched.positions[disc.mw_nodes[:-1], 0] + stitched.positions[disc.mw_nodes[1:], 0])
    near = np.abs(x_mid - disc.mast_station[5]) < 7.0
    far = np.abs(x_mid - disc.mast_station[5] - 30.0) < 20.0
    assert np.allclose(mw[near], cat.messenger_wire.tension - cat.stitch_wire.tension, atol=1.0)
    assert np.allclose(mw[far], cat.messenger_wire.tension, atol=1.0)
    # the dropper schedule lists the stitch droppers too, with buildable lengths
    rows = stitched.dropper_schedule()
    assert len(rows) == len(disc.dropper_elements)
    assert min(stitched.dropper_lengths()) >= settings.min_dropper_length
