"""``presag_opt.static.section_elements``: the elements of a section collected part by part — a wire's
segments (EA over the unstretched length), its lumped mass and bending triples; droppers (EA/length or
a spring) with their clamps' mass — checked on three-node wires whose numbers follow by hand."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from presag_opt.errors import ModelError
from presag_opt.static.section_elements import CONTACT_WIRE, DROPPER, BendingTriples, SectionElements
from presag_opt.system.components import Droppers, Wire
from presag_opt.system.loader import load_catenary

WIRE = Wire(tension=10e3, mass_per_length=1.0, axial_stiffness=10e6, bending_stiffness=150.0)
POS = np.array([[0.0, 0.0, 5.3], [3.0, 0.0, 5.3], [3.0, 4.0, 5.3]])  # segments of 3 m and 4 m


def _empty(n_nodes: int) -> SectionElements:
    return SectionElements(node_mass=np.zeros(n_nodes), fixed=np.zeros((n_nodes, 3), dtype=bool))


def test_a_wire_segment_is_ea_over_its_unstretched_length_and_its_mass_is_lumped_half_and_half():
    parts = _empty(3)
    parts.add_wire(np.arange(3), WIRE, CONTACT_WIRE, POS)
    axial = parts.axial()
    np.testing.assert_allclose(axial.design_length, [3.0, 4.0], rtol=1e-15)
    # stretched by T/EA = 1e-3 at tension: unstretched = l/(1.001), k = EA/unstretched
    np.testing.assert_allclose(axial.stiffness, 10e6 * 1.001 / np.array([3.0, 4.0]), rtol=1e-14)
    np.testing.assert_array_equal(axial.group, [CONTACT_WIRE] * 2)
    np.testing.assert_allclose(parts.node_mass, [1.5, 3.5, 2.0], rtol=1e-15)  # ρ·l/2 to each end
    bending = parts.bending()
    assert (bending.node_a.tolist(), bending.node_b.tolist(), bending.node_c.tolist()) == ([0], [1], [2])
    assert (bending.spacing_ab[0], bending.spacing_bc[0], bending.bending_stiffness[0]) == (3.0, 4.0, 150.0)


def test_a_pure_cable_has_no_bending_triples():
    parts = _empty(3)
    parts.add_wire(np.arange(3), dataclasses.replace(WIRE, bending_stiffness=0.0), CONTACT_WIRE, POS)
    assert len(parts.bending().node_a) == 0
    assert len(BendingTriples.empty().bending_stiffness) == 0


def test_droppers_carry_ea_over_their_length_or_a_fixed_spring_and_their_clamps_mass():
    catenary = load_catenary("st_9.8_ideal")
    lengths = np.array([1.0, 0.5])
    parts = _empty(4)
    assert parts.add_droppers(catenary, np.array([0, 1]), np.array([2, 3]), lengths) == 2
    spec = catenary.droppers
    axial = parts.axial()
    np.testing.assert_allclose(axial.stiffness, spec.axial_stiffness / lengths, rtol=1e-15)
    np.testing.assert_array_equal(axial.group, [DROPPER, DROPPER])
    half = 0.5 * spec.mass_per_length * lengths + spec.clamp_mass
    np.testing.assert_allclose(parts.node_mass, np.concatenate([half, half]), rtol=1e-15)
    sprung = dataclasses.replace(catenary, droppers=Droppers(stiffness=100e3, mass_per_length=0.1, clamp_mass=0.2))
    spring = _empty(4)
    spring.add_droppers(sprung, np.array([0, 1]), np.array([2, 3]), lengths)
    np.testing.assert_allclose(spring.axial().stiffness, [100e3, 100e3], rtol=0)
    np.testing.assert_allclose(spring.node_mass[:2], [0.25, 0.225], rtol=1e-14)


def test_a_messenger_guess_below_the_contact_wire_is_refused():
    with pytest.raises(ModelError, match=r"^the messenger-wire first guess lies below the contact wire; check system_height$"):
        _empty(2).add_droppers(load_catenary("st_9.8_ideal"), np.array([0]), np.array([1]), np.array([-0.1]))


def test_elements_are_listed_in_the_order_added():
    parts = _empty(5)
    parts.add_wire(np.arange(3), WIRE, CONTACT_WIRE, POS)
    parts.add_droppers(load_catenary("st_9.8_ideal"), np.array([1]), np.array([4]), np.array([1.2]))
    assert parts.n_axial == 3 and len(parts.axial()) == 3
    assert parts.axial().node_a.tolist() == [0, 1, 1] and parts.axial().node_b.tolist() == [1, 2, 4]
