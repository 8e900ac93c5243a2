"""StitchWire (presag_opt.system.stitch): input checks, the masts it is fitted at, and the clamp and
stitch-dropper positions it puts into each span."""

from __future__ import annotations

import pytest

from presag_opt.errors import ModelError
from presag_opt.system.stitch import StitchWire

GOOD = {"length": 14.0, "tension": 2000.0, "mass_per_length": 0.31, "axial_stiffness": 3.5e6,
        "dropper_positions": (-2.0, 2.0)}


@pytest.mark.parametrize(("change", "message"), [
    ({"tension": 30e3}, "tension = 30 kN is outside the valid range [0.1, 20] kN"),
    ({"length": 50.0}, "length = 50 m is outside the valid range [2, 40] m"),
    ({"axial_stiffness": 1e3}, "axial_stiffness = 0.001 MN is outside the valid range [0.1, 100] MN"),
    ({"dropper_positions": (-2.0, 8.0)}, "dropper_positions[1] = 8 m is outside the valid range"),
    ({"dropper_positions": (2.0, -2.0)}, "must be strictly increasing"),
    ({"dropper_positions": (0.0,)}, "not at the support"),
])
def test_bad_stitch_wire_input_names_field_value_unit_and_range(change, message):
    with pytest.raises(ModelError, match=message.replace("[", r"\[").replace("(", r"\(")):
        StitchWire(**{**GOOD, **change})
@pytest.mark.parametrize(("masts", "message"), [
    ((0, 2), "must be strictly increasing inner masts, each >= 1"),
    ((3, 2), "must be strictly increasing inner masts"),
    ((), "must be strictly increasing inner masts"),
    ((1.5,), "must be whole mast numbers"),
    ((True,), "must be whole mast numbers"),
])
def test_bad_mast_lists_are_one_line(masts, message):
    with pytest.raises(ModelError, match=r"^stitch_wire\.masts = .*" + message):
        StitchWire(**GOOD, masts=masts)


def test_every_inner_mast_or_the_listed_ones():
    every = StitchWire(**GOOD)
    assert [every.at_mast(m, 4) for m in range(5)] == [False, True, True, True, False]
    some = StitchWire(**GOOD, masts=[3])
    assert some.masts == (3,)
    assert [some.at_mast(m, 4) for m in range(5)] == [False, False, False, True, False]
    assert not some.at_mast(3, 3)  # the last mast of a 3-span section is an end mast


def test_clamps_and_stitch_droppers_in_each_span():
    stitch = StitchWire(**{**GOOD, "dropper_positions": (-4.0, -1.0, 3.0)})
    # first span: only the stitch wire of its last mast (mast 1): clamp at 60 - 7, droppers 56 and 59 m
    assert stitch.points_in_span(0, 3, 60.0) == ([53.0], [56.0, 59.0])
    # middle span: both masts' stitch wires
    assert stitch.points_in_span(1, 3, 60.0) == ([7.0, 53.0], [3.0, 56.0, 59.0])
    # last span: only its first mast's
    assert stitch.points_in_span(2, 3, 60.0) == ([7.0], [3.0])
    only_first = StitchWire(**{**GOOD, "dropper_positions": (-4.0, -1.0, 3.0)}, masts=(1,))
    assert only_first.points_in_span(1, 3, 60.0) == ([7.0], [3.0])


def test_summary_says_simple_or_stitched_and_where():
    import dataclasses

    from presag_opt.system.loader import load_catenary
    from presag_opt.system.stitch import stitch_summary

    assert stitch_summary(load_catenary("st_9.8_ideal")) == "simple (no stitch wires)"
    stitched = load_catenary("st_9.8_stitched_ideal")
    assert stitch_summary(stitched) == ("stitched: a 14 m stitch wire at 2 kN at every inner mast (counted from 1), "
                                        "stitch droppers at -4, 4 m from the support")
    some = dataclasses.replace(stitched, stitch_wire=dataclasses.replace(stitched.stitch_wire, masts=(2, 5)))
    assert "at masts 3, 6 (counted from 1)" in stitch_summary(some)
