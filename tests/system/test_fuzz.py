"""Input fuzzing: any number in any field gives either a valid object or a ModelError — never a
NaN that slips through, a silent clip, or another exception."""

from __future__ import annotations

import math

from hypothesis import given, settings
from hypothesis import strategies as st

from presag_opt.errors import ModelError
from presag_opt.system.catenary import Droppers, SpanLayout, SteadyArm, Wire

numbers = st.one_of(st.floats(allow_nan=True, allow_infinity=True), st.integers(-10**9, 10**9))


@settings(max_examples=300, deadline=None)
@given(tension=numbers, mass=numbers, ea=numbers, ei=numbers)
def test_wire_accepts_exactly_the_valid_range(tension, mass, ea, ei):
    try:
        wire = Wire(tension=tension, mass_per_length=mass, axial_stiffness=ea, bending_stiffness=ei)
    except ModelError as exc:
        assert "valid range" in str(exc) or "not a finite number" in str(exc)
        return
    assert 500.0 <= wire.tension <= 60e3 and math.isfinite(wire.tension)
    assert 0.05 <= wire.mass_per_length <= 5.0
    assert 0.1e6 <= wire.axial_stiffness <= 100e6
    assert 0.0 <= wire.bending_stiffness <= 5000.0
    assert wire.tension == tension  # stored as given, never clipped


@settings(max_examples=200, deadline=None)
@given(end=numbers, spacing=numbers, span=st.floats(5.0, 120.0))
def test_dropper_rule_places_droppers_inside_the_span_or_says_why(end, spacing, span):
    try:
        droppers = Droppers(end_distance=end, max_spacing=spacing, axial_stiffness=1e6)
        positions = droppers.positions_in_span(span)
    except ModelError:
        return
    assert positions[0] == droppers.end_distance
    assert abs(positions[-1] - (span - droppers.end_distance)) < 1e-9
    assert all(0.0 < p < span for p in positions)
    assert max(b - a for a, b in zip(positions, positions[1:])) <= droppers.max_spacing + 1e-9


@settings(max_examples=200, deadline=None)
@given(lengths=st.lists(numbers, min_size=0, max_size=6), radius=numbers)
def test_layout_never_accepts_nonsense(lengths, radius):
    try:
        layout = SpanLayout(span_lengths=tuple(lengths), curve_radii=(radius,) * len(lengths))
    except ModelError:
        return
    assert len(layout.span_lengths) >= 3
    assert all(5.0 <= v <= 120.0 for v in layout.span_lengths)
    assert all(r == 0.0 or 100.0 <= abs(r) <= 1e6 for r in layout.radii)


@settings(max_examples=100, deadline=None)
@given(length=numbers, mass=numbers)
def test_steady_arm(length, mass):
    try:
        arm = SteadyArm(length=length, mass=mass)
    except ModelError:
        return
    assert 0.3 <= arm.length <= 3.0 and 0.0 <= arm.mass <= 10.0
