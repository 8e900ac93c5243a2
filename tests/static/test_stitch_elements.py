"""The stitch wires as elements (presag_opt.static.stitch_elements): chains of new nodes between the
messenger-wire clamps, STITCH_WIRE segments and stitch droppers, at every or at the listed inner masts."""

from __future__ import annotations

import dataclasses

import numpy as np

from presag_opt.static.discretisation import DROPPER, STITCH_WIRE, discretise
from presag_opt.system.loader import load_catenary


def test_discretisation_has_a_stitch_wire_at_every_inner_mast_with_its_droppers():
    cat = load_catenary("st_9.8_stitched_ideal")
    disc = discretise(cat)
    inner_masts = cat.layout.n_spans - 1
    assert len(disc.stitch_chains) == inner_masts
    assert int(disc.stitch_dropper.sum()) == inner_masts * len(cat.stitch_wire.dropper_positions)
    assert np.all(disc.axial.group[disc.dropper_elements] == DROPPER)
    for m, chain in zip(range(1, cat.layout.n_spans), disc.stitch_chains):
        # its ends are the messenger-wire nodes at the clamps, half the stitch length from the mast
        assert np.all(np.isin(chain[[0, -1]], disc.mw_nodes)) and not np.any(np.isin(chain[1:-1], disc.mw_nodes))
        ends = disc.design_positions[chain[[0, -1]], 0]
        assert np.allclose(ends - disc.mast_station[m], [-7.0, 7.0], atol=1e-9)
    stations = disc.mast_station[disc.dropper_span] + disc.dropper_position
    assert np.all(np.diff(stations) > 0.0)  # along-track order, stitch droppers among the others
    rel = (stations[disc.stitch_dropper][:, None] - disc.mast_station[None, 1:-1])
    assert np.allclose(np.sort(np.abs(rel).min(axis=1)), 4.0, atol=1e-9)
    n_segments = sum(len(c) - 1 for c in disc.stitch_chains)
    assert int(np.sum(disc.axial.group == STITCH_WIRE)) == n_segments
def test_only_the_listed_masts_get_a_stitch_wire_and_node_numbers_follow_the_wires():
    cat = load_catenary("st_9.8_stitched_ideal")
    every = discretise(cat)
    some = discretise(dataclasses.replace(cat, stitch_wire=dataclasses.replace(cat.stitch_wire, masts=(2, 7))))
    assert len(some.stitch_chains) == 2
    for m, chain in zip((2, 7), some.stitch_chains):
        assert np.allclose(some.design_positions[chain[[0, -1]], 0] - some.mast_station[m], [-7.0, 7.0], atol=1e-9)
        # the new nodes come after both wires' nodes
        assert chain[1:-1].min() > max(some.cw_nodes.max(), some.mw_nodes.max())
    assert int(some.stitch_dropper.sum()) == 2 * len(cat.stitch_wire.dropper_positions)
    assert int(np.sum(some.axial.group == STITCH_WIRE)) == sum(len(c) - 1 for c in some.stitch_chains)
    # the ordinary droppers are the same in both
    assert np.count_nonzero(~some.stitch_dropper) == np.count_nonzero(~every.stitch_dropper)


def test_a_per_dropper_design_with_stitch_droppers_builds_into_the_catenary():
    """The robust path model's design droppers include the stitch droppers (9 per inner span of
    st_9.8_stitched_ideal), the catenary's profile is per ordinary dropper (7): design_catenary keeps
    the design's depths at the ordinary droppers (the profile is linear between design droppers, and
    the ordinary droppers are design droppers, so they are met exactly)."""
    from types import SimpleNamespace

    from presag_opt.robust.dynamic_check import design_catenary

    cat = load_catenary("st_9.8_stitched_ideal")
    disc = discretise(cat)
    span = 4
    mine = np.flatnonzero(disc.dropper_span == span)
    assert len(mine) == 9 and int(disc.stitch_dropper[mine].sum()) == 2
    fraction = disc.dropper_position[mine] / 60.0
    depths = 0.04 * np.sin(np.pi * fraction)  # any profile
    path = SimpleNamespace(spans=(span,), dropper_span=disc.dropper_span[mine], dropper_fraction=fraction)
    built = design_catenary(cat, path, depths)
    ordinary = ~disc.stitch_dropper[mine]
    for profile in built.presag_profile:
        assert len(profile) == 7
        assert np.allclose(profile, depths[ordinary], atol=1e-12)
