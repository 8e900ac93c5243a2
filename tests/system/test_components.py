"""``presag_opt.system.components``: the parts of a catenary — wires, dropper placement, supports and
damping — validated on construction, with the dropper rule checked against hand-counted layouts."""

from __future__ import annotations

import math

import numpy as np
import pytest

from presag_opt.errors import ModelError
from presag_opt.system.components import GRAVITY, Damping, Droppers, SpringSupport, SteadyArm, Wire


def test_the_wave_speed_of_a_wire_is_sqrt_tension_over_mass():
    wire = Wire(tension=9800.0, mass_per_length=1.07, axial_stiffness=12e6)
    assert wire.wave_speed == pytest.approx(math.sqrt(9800.0 / 1.07), rel=1e-15)
    assert wire.bending_stiffness == 0.0 and GRAVITY == 9.81


@pytest.mark.parametrize(("span", "expected"), [
    # 60 m, 4.5 m ends: 51 m inside, at most 8.5 m apart → 6 intervals of exactly 8.5 m (7 droppers)
    (60.0, 4.5 + 8.5 * np.arange(7)),
    # 45 m: 36 m inside → ceil(36/8.5) = 5 intervals of 7.2 m
    (45.0, 4.5 + 7.2 * np.arange(6)),
    # 10 m: 1 m inside → one interval: the two end droppers
    (10.0, np.array([4.5, 5.5])),
])
def test_the_dropper_rule_spaces_the_inner_droppers_evenly_at_most_max_spacing_apart(span, expected):
    positions = Droppers(axial_stiffness=0.2e6).positions_in_span(span)
    np.testing.assert_allclose(positions, expected, rtol=0, atol=1e-12)
    assert np.all(np.diff(positions) <= 8.5 + 1e-12)


def test_explicit_positions_are_used_in_every_span_that_holds_them():
    d = Droppers(positions=[5, 20, 40], stiffness=100e3)
    np.testing.assert_array_equal(d.positions_in_span(60.0), [5.0, 20.0, 40.0])
    with pytest.raises(ModelError, match=r"^droppers.positions: last dropper at 40 m lies outside a span of 40 m$"):
        d.positions_in_span(40.0)


@pytest.mark.parametrize(("kwargs", "message"), [
    ({}, "droppers: give exactly one of axial_stiffness (EA, in MN) or stiffness (spring, in kN/m)"),
    ({"axial_stiffness": 0.2e6, "stiffness": 1e5}, "droppers: give exactly one of axial_stiffness"),
    ({"axial_stiffness": 0.2e6, "positions": [5, 5, 9]}, "droppers.positions = [5.0, 5.0, 9.0] m must be strictly increasing"),
    ({"axial_stiffness": 0.2e6, "end_distance": 0.1}, "end_distance = 0.1 m is outside the valid range [0.5, 20] m"),
])
def test_bad_droppers_are_one_line(kwargs, message):
    with pytest.raises(ModelError) as caught:
        Droppers(**kwargs)
    assert str(caught.value).startswith(message)


def test_end_droppers_that_do_not_fit_the_span_are_refused():
    with pytest.raises(ModelError) as caught:
        Droppers(axial_stiffness=0.2e6, end_distance=6.0).positions_in_span(10.0)
    assert str(caught.value) == ("droppers.end_distance = 6 m does not fit a span of 10 m (needs span length > 12 m)")


def test_a_span_of_exactly_twice_the_end_distance_is_refused_not_given_two_droppers_at_one_point():
    with pytest.raises(ModelError) as caught:
        Droppers(axial_stiffness=0.2e6, end_distance=4.5).positions_in_span(9.0)
    assert str(caught.value) == ("droppers.end_distance = 4.5 m does not fit a span of 9 m (needs span length > 9 m)")
    assert np.allclose(Droppers(axial_stiffness=0.2e6, end_distance=4.5).positions_in_span(9.5), [4.5, 5.0])


@pytest.mark.parametrize(("kwargs", "ok"), [({"ratio": 0.02}, True), ({"rayleigh_alpha": 0.1, "rayleigh_beta": 1e-4}, True),
                                            ({"rayleigh_alpha": 0.1}, True), ({}, False),
                                            ({"ratio": 0.02, "rayleigh_beta": 1e-4}, False)])
def test_damping_is_a_ratio_or_rayleigh_coefficients_never_both(kwargs, ok):
    if ok:
        Damping(**kwargs)
        return
    with pytest.raises(ModelError, match=r"^damping: give either ratio, or rayleigh_alpha and rayleigh_beta$"):
        Damping(**kwargs)


def test_supports_are_validated_in_their_display_units():
    assert SteadyArm(length=1.0, mass=1.0).axial_stiffness == 20e6
    with pytest.raises(ModelError, match=r"^length = 5 m is outside the valid range \[0.3, 3\] m$"):
        SteadyArm(length=5.0, mass=1.0)
    with pytest.raises(ModelError, match=r"^stiffness = 0.5 N/m is outside the valid range \[1, 1e\+08\] N/m$"):
        SpringSupport(stiffness=0.5)
