"""``presag_opt.static.discretisation``: the discretised section in its design state — nodes at every
mast and dropper, loads shared by the linear shape functions, the in-element string compliance
h·t(1 − t)/T — and the settings' refusals. No form-finding (milliseconds)."""

from __future__ import annotations

import numpy as np
import pytest

from presag_opt.errors import ModelError
from presag_opt.static.discretisation import CONTACT_WIRE, DROPPER, StaticSettings, discretise, discretise_lone_wire
from presag_opt.system.components import GRAVITY, Wire
from presag_opt.system.loader import load_catenary

IDEAL = load_catenary("st_9.8_ideal")  # 10 × 60 m, 7 droppers per span
DISC = discretise(IDEAL, StaticSettings(element_length=1.0))


def test_the_masts_and_droppers_are_nodes_at_their_stations():
    np.testing.assert_allclose(DISC.cw_station[np.searchsorted(DISC.cw_nodes, DISC.mast_cw_node)], DISC.mast_station,
                               rtol=0, atol=1e-9)
    drops = IDEAL.droppers.positions_in_span(60.0)
    assert len(DISC.dropper_elements) == 10 * len(drops)
    np.testing.assert_allclose(DISC.dropper_position, np.tile(drops, 10), rtol=0, atol=1e-9)
    np.testing.assert_array_equal(DISC.dropper_span, np.repeat(np.arange(10), len(drops)))
    assert np.all(DISC.axial.group[DISC.dropper_elements] == DROPPER)
    assert np.max(np.diff(DISC.cw_station)) <= 1.0 + 1e-12
    assert DISC.n_dofs == 3 * DISC.n_nodes and DISC.cw_tension == IDEAL.contact_wire.tension


def test_the_weight_vector_is_minus_g_times_each_nodes_mass_on_z_only():
    f = DISC.gravity_force()
    np.testing.assert_array_equal(f[0::3], 0.0)
    np.testing.assert_array_equal(f[1::3], 0.0)
    np.testing.assert_allclose(f[2::3], -GRAVITY * DISC.node_mass, rtol=1e-15)
    # both wires' mass is in it (the design wires are a little longer than the track: stagger and sag), and
    # the droppers, clamps and half steady arms add less than 10 %
    wires = (IDEAL.contact_wire.mass_per_length + IDEAL.messenger_wire.mass_per_length) * 600.0
    assert wires < DISC.node_mass.sum() < 1.1 * wires


def test_a_point_force_is_shared_between_the_two_nodes_of_its_element_by_the_linear_shape_functions():
    i = 40
    a, b = DISC.cw_station[i], DISC.cw_station[i + 1]
    f = DISC.cw_load_vector(a + 0.25 * (b - a), 100.0)
    z = f[2::3]
    assert z.sum() == pytest.approx(100.0, rel=1e-14)
    assert z[DISC.cw_nodes[i]] == pytest.approx(75.0, rel=1e-12) and z[DISC.cw_nodes[i + 1]] == pytest.approx(25.0, rel=1e-12)
    assert np.count_nonzero(f) == 2


def test_the_shape_functions_are_a_partition_of_unity_that_reproduces_linear_functions():
    stations = np.linspace(0.0, 600.0, 997)
    shape = DISC.cw_shape(stations)
    np.testing.assert_allclose(np.asarray(shape.sum(axis=1)).ravel(), 1.0, rtol=1e-14)
    np.testing.assert_allclose(shape @ DISC.cw_station, stations, rtol=0, atol=1e-9)
    with pytest.raises(ModelError, match=r"^station -1\.\.10 m lies outside the section \[0, 600\] m$"):
        DISC.cw_shape(np.array([-1.0, 10.0]))


def test_the_in_element_compliance_is_that_of_a_string_element_with_held_ends():
    """h·t(1 − t)/T: zero at the nodes, h/(4T) in the middle of an element."""
    h = DISC.cw_station[11] - DISC.cw_station[10]
    stations = DISC.cw_station[10] + np.array([0.0, 0.5, 1.0]) * h
    np.testing.assert_allclose(DISC.cw_element_compliance(stations), [0.0, h / (4 * IDEAL.contact_wire.tension), 0.0],
                               rtol=1e-12, atol=1e-18)


def test_a_lone_wire_has_two_masts_one_span_and_pinned_or_sprung_ends():
    wire = Wire(tension=20e3, mass_per_length=1.35, axial_stiffness=20e6)
    pinned = discretise_lone_wire(wire, 60.0, StaticSettings(element_length=2.0))
    assert pinned.n_nodes == 31 and pinned.catenary is None
    np.testing.assert_allclose(pinned.mast_station, [0.0, 60.0], rtol=0)
    assert np.all(pinned.axial.group == CONTACT_WIRE) and len(pinned.spring_dofs) == 0
    assert pinned.fixed_dofs[2] and pinned.fixed_dofs[3 * 30 + 2]  # both ends held vertically
    sprung = discretise_lone_wire(wire, 60.0, StaticSettings(element_length=2.0), support_stiffness=1e9)
    assert not sprung.fixed_dofs[2::3].any() and list(sprung.spring_stiffness) == [1e9, 1e9]
    assert pinned.node_mass.sum() == pytest.approx(1.35 * 60.0, rel=1e-12)


def test_settings_are_validated():
    with pytest.raises(ModelError, match=r"^settings.element_length = 10 m is outside the valid range \[0.01, 5\] m$"):
        StaticSettings(element_length=10.0)
    with pytest.raises(ModelError, match=r"^settings.max_newton_iterations = 0 is outside the valid range \[1, 1000\]$"):
        StaticSettings(max_newton_iterations=0)
