"""Form-finding to any pre-sag profile: one contact-wire depth per dropper, not only the parabola."""

from __future__ import annotations

import numpy as np
import pytest

from presag_opt.static import cache
from presag_opt.static.discretisation import StaticSettings
from presag_opt.static.form_finding import form_find
from presag_opt.system.catenary import SpanLayout
from presag_opt.system.loader import load_catenary

COARSE = StaticSettings(element_length=1.0)
"""Three 60 m spans at 1 m elements form-find in about 0.3 s."""


@pytest.fixture(scope="module")
def three_spans():
    return load_catenary("st_9.8_ideal").with_layout(SpanLayout(span_lengths=(60.0, 60.0, 60.0)))


def _droppers(catenary, span):
    return catenary.droppers.positions_in_span(catenary.layout.span_lengths[span])


def _lopsided(catenary):
    """A profile no parabola gives: deepest near the first quarter of each span, 10–70 mm. [m]"""
    out = []
    for s, length in enumerate(catenary.layout.span_lengths):
        t = _droppers(catenary, s) / length
        out.append(tuple(0.010 + 0.060 * 27.0 / 4.0 * t * (1.0 - t) ** 2))  # t(1 − t)² peaks at t = 1/3
    return out


def test_contact_wire_meets_an_arbitrary_profile_at_every_dropper(three_spans):
    depths = _lopsided(three_spans)
    catenary = three_spans.with_presag_profile(depths)
    state = form_find(catenary, COARSE)
    disc = state.discretisation
    z_drop = state.positions[disc.axial.node_a[disc.dropper_elements], 2]
    target = catenary.contact_wire_height - np.concatenate(depths)
    assert np.max(np.abs(z_drop - target)) < 1e-4  # 0.1 mm, as for the parabola
    assert np.max(np.abs(state.positions[disc.mast_cw_node, 2] - catenary.contact_wire_height)) < 1e-4
    assert np.all(state.dropper_forces() > 0.0)
    # not a parabola: the deepest dropper sits in the first half of each span
    first = disc.dropper_span == 1
    assert disc.dropper_position[first][np.argmin(z_drop[first])] < 30.0


def test_a_profile_on_the_parabola_form_finds_the_parabola(three_spans):
    parabola = three_spans.with_presag(1.0e-3)
    depths = [tuple(parabola.presag_depth(s, _droppers(parabola, s))) for s in range(3)]
    profiled = three_spans.with_presag_profile(depths)
    assert profiled.presag_rel == pytest.approx(1.0e-3, rel=1e-12)  # mid-span dropper on the parabola
    a, b = form_find(parabola, COARSE), form_find(profiled, COARSE)
    # The same square system from another first guess between the droppers: the same solution within
    # the form-finding tolerances (5e-5 m on the targets, 1e-4 N out of balance).
    assert np.max(np.abs(a.positions - b.positions)) < 1e-6
    assert np.max(np.abs(a.dropper_lengths() - b.dropper_lengths())) < 1e-6


def test_the_profile_is_part_of_the_cache_key(three_spans):
    depths = _lopsided(three_spans)
    moved = [list(span) for span in depths]
    moved[1][2] += 1e-3
    key = cache.state_key(three_spans.with_presag_profile(depths), COARSE)
    assert key != cache.state_key(three_spans.with_presag_profile(moved), COARSE)
    assert key == cache.state_key(three_spans.with_presag_profile(depths), COARSE)
    assert key != cache.state_key(three_spans, COARSE)
