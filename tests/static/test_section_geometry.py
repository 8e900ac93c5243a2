"""``presag_opt.static.section_geometry``: the stations, plan and design geometry of a section, against
plane geometry (a circular curve: chord 2R sin(l/2R), heading change l/R) and the design rules (the
pre-sag parabola below the support line, the messenger's parabolic sag w l²/8T)."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from presag_opt.errors import ModelError
from presag_opt.static.section_geometry import (
    design_wire_positions,
    mast_normals,
    messenger_sag_guess,
    section_stations,
    steady_arm_pivots,
    track_plan,
)
from presag_opt.system.components import GRAVITY
from presag_opt.system.loader import load_catenary

IDEAL = load_catenary("st_9.8_ideal")  # 10 × 60 m, 7 droppers per span


def test_stations_hold_every_mast_and_dropper_and_no_element_is_longer_than_asked():
    stations = section_stations(IDEAL, 2.0)
    np.testing.assert_allclose(stations.mast_station, np.arange(11) * 60.0, rtol=0, atol=1e-12)
    np.testing.assert_allclose(stations.station[stations.mast_nodes], stations.mast_station, rtol=0, atol=1e-9)
    assert np.max(np.diff(stations.station)) <= 2.0 + 1e-12 and np.min(np.diff(stations.station)) > 0.0
    drops = IDEAL.droppers.positions_in_span(60.0)
    assert stations.is_dropper.sum() == 10 * len(drops)
    np.testing.assert_allclose(stations.local[stations.is_dropper][:len(drops)], drops, rtol=0, atol=1e-9)
    assert stations.span[stations.mast_nodes[3]] == 3 and stations.span[-1] == 9  # a mast node starts its span
    # between masts and droppers the elements are equal: 4.5 m in ⌈4.5/2⌉ = 3 parts of 1.5 m
    np.testing.assert_allclose(stations.local[:4], [0.0, 1.5, 3.0, 4.5], rtol=0, atol=1e-12)


def test_straight_track_runs_along_x():
    xy, heading = track_plan(np.array([60.0, 45.0, 50.0]), np.zeros(3))
    np.testing.assert_allclose(xy, [[0, 0], [60, 0], [105, 0], [155, 0]], rtol=0, atol=1e-12)
    assert np.all(heading == 0.0)


@pytest.mark.parametrize("radius", [1000.0, -800.0])
def test_a_circular_curve_puts_every_mast_on_its_circle_with_chords_of_2r_sin_l_over_2r(radius):
    spans = np.array([60.0, 55.0, 60.0])
    xy, heading = track_plan(spans, np.full(3, radius))
    centre = np.array([0.0, radius])  # a left curve (R > 0) turns towards +y
    np.testing.assert_allclose(np.linalg.norm(xy - centre, axis=1), abs(radius), rtol=1e-12)
    chords = np.linalg.norm(np.diff(xy, axis=0), axis=1)
    np.testing.assert_allclose(chords, 2 * abs(radius) * np.sin(spans / (2 * abs(radius))), rtol=1e-12)
    np.testing.assert_allclose(heading, np.concatenate([[0.0], np.cumsum(spans / radius)]), rtol=1e-12)


def test_the_mast_normal_is_a_horizontal_unit_vector_to_the_left_of_the_track():
    heading = np.array([0.0, math.pi / 2, 0.3])
    n = mast_normals(heading)
    np.testing.assert_allclose(n[:2], [[0, 1, 0], [-1, 0, 0]], rtol=0, atol=1e-15)
    np.testing.assert_allclose(np.linalg.norm(n, axis=1), 1.0, rtol=1e-15)
    np.testing.assert_allclose(n[2, 0] * math.cos(0.3) + n[2, 1] * math.sin(0.3), 0.0, atol=1e-15)  # ⟂ heading


def test_the_messenger_sag_guess_is_the_sag_of_everything_less_what_the_presagged_wire_carries():
    catenary = IDEAL.with_presag(1e-3)
    drops = catenary.droppers
    n = len(drops.positions_in_span(60.0))  # 7
    w = GRAVITY * (catenary.contact_wire.mass_per_length + catenary.messenger_wire.mass_per_length
                   + n * (drops.mass_per_length * catenary.system_height + 2 * drops.clamp_mass) / 60.0)
    # at mid-span: (w l²/8 − T_CW·S)/T_MW, S = 60 mm; at the masts: none
    expected = (w * 3600.0 / 8.0 - catenary.contact_wire.tension * 0.060) / catenary.messenger_wire.tension
    assert messenger_sag_guess(catenary, 4, np.array([30.0]))[0] == pytest.approx(expected, rel=1e-12)
    np.testing.assert_allclose(messenger_sag_guess(catenary, 4, np.array([0.0, 60.0])), 0.0, rtol=0, atol=1e-15)


def test_the_design_contact_wire_hangs_the_presag_below_its_supports_and_the_messenger_sits_at_the_system_height():
    catenary = IDEAL.with_presag(1e-3)
    stations = section_stations(catenary, 1.0)
    xy, heading = track_plan(np.asarray(catenary.layout.span_lengths), np.zeros(10))
    cw, mw = design_wire_positions(catenary, stations, xy, mast_normals(heading))
    masts = stations.mast_nodes
    np.testing.assert_allclose(cw[masts, 2], catenary.contact_wire_height, rtol=0, atol=1e-12)
    np.testing.assert_allclose(mw[masts, 2], catenary.contact_wire_height + catenary.system_height, rtol=0, atol=1e-12)
    mid = np.flatnonzero(np.isclose(stations.local, 30.0))
    np.testing.assert_allclose(cw[mid, 2], catenary.contact_wire_height - 0.060, rtol=0, atol=1e-12)  # 1 ‰ × 60 m
    np.testing.assert_allclose(cw[masts, 1], catenary.mast_stagger(), rtol=0, atol=1e-12)  # straight: y = stagger


def test_a_steady_arm_without_a_sideways_pull_is_refused():
    """Three contact-wire nodes in a straight line (no stagger, no curve) at mast 1: the arm would carry no
    axial force and so have no vertical stiffness. (The catenary refuses zero stagger itself; a mast
    table can still lead here.)"""
    wire = np.array([[0.0, 0.0, 5.3], [60.0, 0.0, 5.3], [120.0, 0.0, 5.3]])
    with pytest.raises(ModelError, match=r"^steady arm at mast 2 \(of 3\): the contact wire pulls only 0 N sideways there"):
        steady_arm_pivots(IDEAL, wire, np.arange(3), np.arange(3), np.zeros(9), [1])
    assert steady_arm_pivots(IDEAL, wire, np.arange(3), np.arange(3), np.zeros(9), []).shape == (0, 3)
    with pytest.raises(ModelError, match=r"^stagger = 0 m on straight track leaves a steady arm without lateral pull"):
        dataclasses.replace(IDEAL, stagger=0.0)
