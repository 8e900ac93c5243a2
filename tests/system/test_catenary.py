"""``presag_opt.system.catenary``: the span layout and the tension section — the parabolic pre-sag
4·S·t(1 − t), a profile of depths at the droppers, the support line between unequal mast heights, the
per-mast arrays — and their refusals in one line. No form-finding here: the catenary is the input."""

from __future__ import annotations

import numpy as np
import pytest

from presag_opt.errors import ModelError
from presag_opt.system.catenary import SpanLayout
from presag_opt.system.loader import load_catenary

IDEAL = load_catenary("st_9.8_ideal")


@pytest.fixture(scope="module")
def three_spans():
    return IDEAL.with_layout(SpanLayout(span_lengths=(60.0, 60.0, 60.0)))


def _profile(catenary):
    """A valid profile: 10–70 mm, deepest at the first third of each span (no parabola gives it). [m]"""
    out = []
    for length in catenary.layout.span_lengths:
        t = catenary.droppers.positions_in_span(length) / length
        out.append(tuple(0.010 + 0.060 * 27.0 / 4.0 * t * (1.0 - t) ** 2))
    return out


def test_with_presag_drops_a_profile(three_spans):
    profiled = three_spans.with_presag_profile(_profile(three_spans))
    assert profiled.with_presag(0.5e-3).presag_profile is None



@pytest.mark.parametrize("change,words", [
    (lambda d: d[:2], "presag_profile has 2 spans but the layout has 3"),
    (lambda d: [d[0], d[1][:-1], d[2]], "presag_profile[1] has 6 depths but span 1 has 7 droppers"),
    (lambda d: [d[0], d[1], (*d[2][:3], 0.31, *d[2][4:])],
     "presag_profile[2][3] = 310 mm is outside the valid range [0, 300] mm"),
    (lambda d: [d[0], (-0.001, *d[1][1:]), d[2]], "presag_profile[1][0] = -1 mm is outside the valid range"),
    (lambda d: [d[0], d[1], (float("nan"), *d[2][1:])], "presag_profile[2][0] = nan mm is outside the valid range"),
])
def test_a_malformed_profile_is_refused_with_one_line(three_spans, change, words):
    depths = _profile(three_spans)
    with pytest.raises(ModelError) as error:
        three_spans.with_presag_profile(change(depths))
    assert words in str(error.value)
    assert "\n" not in str(error.value)



def test_the_parabolic_presag_is_s_at_mid_span_and_zero_at_the_masts():
    c = IDEAL.with_presag(1.12e-3)
    x = np.array([0.0, 15.0, 30.0, 60.0])
    # 4·S·t(1 − t) with S = 1.12 ‰ × 60 m = 67.2 mm: 0, 3/4·S, S, 0
    np.testing.assert_allclose(c.presag_depth(3, x), [0.0, 0.75 * 0.0672, 0.0672, 0.0], rtol=1e-12, atol=1e-15)
    assert c.presag_of_span(3) == pytest.approx(0.0672, rel=1e-12)


def test_a_profile_is_straight_between_the_masts_and_the_droppers_and_labels_its_mean_mid_span_depth(three_spans):
    depths = _profile(three_spans)
    shaped = three_spans.with_presag_profile(depths)
    drops = three_spans.droppers.positions_in_span(60.0)
    np.testing.assert_allclose(shaped.presag_depth(1, drops), depths[1], rtol=1e-15)
    half = 0.5 * (drops[0] + drops[1])
    assert shaped.presag_depth(1, np.array([half]))[0] == pytest.approx(0.5 * (depths[1][0] + depths[1][1]), rel=1e-12)
    assert shaped.presag_depth(0, np.array([0.0, 60.0])) == pytest.approx([0.0, 0.0], abs=0.0)
    mid = np.mean([float(shaped.presag_depth(s, np.array([30.0]))[0]) for s in range(3)]) / 60.0
    assert shaped.presag_rel == pytest.approx(mid, rel=1e-12)


def test_the_support_line_runs_straight_between_the_contact_wire_heights_of_the_two_masts():
    c = IDEAL
    heights = c.mast_contact_wire_height()
    assert heights.shape == (c.layout.n_spans + 1,) and np.all(heights == c.contact_wire_height)
    np.testing.assert_allclose(c.support_line(2, np.array([0.0, 30.0, 60.0])), [c.contact_wire_height] * 3, rtol=1e-15)


def test_the_stagger_alternates_from_mast_to_mast_without_a_mast_table():
    stagger = IDEAL.mast_stagger()
    np.testing.assert_array_equal(stagger, IDEAL.stagger * np.array([1, -1] * 5 + [1], dtype=float))
    assert not IDEAL.mast_push_off().any() and np.all(IDEAL.mast_system_height() == IDEAL.system_height)


def test_the_central_span_is_the_middle_one_the_later_of_two():
    assert SpanLayout(span_lengths=(60,) * 5).central_span == 2
    assert SpanLayout(span_lengths=(60,) * 10).central_span == 5
    assert SpanLayout(span_lengths=(60,) * 3).radii == (0.0, 0.0, 0.0)


@pytest.mark.parametrize(("kwargs", "message"), [
    ({"span_lengths": (60.0, 60.0)}, "layout.span_lengths has 2 spans; a section needs at least 3"),
    ({"span_lengths": (60.0, 4.0, 60.0)}, "span_lengths[1] = 4 m is outside the valid range [5, 120] m"),
    ({"span_lengths": (60.0,) * 3, "curve_radii": (0.0, 500.0)}, "layout.curve_radii has 2 values but there are 3 spans"),
    ({"span_lengths": (60.0,) * 3, "curve_radii": (0.0, -99.0, 0.0)},
     "layout.curve_radii[1] = -99 m: a curve radius must be 0 (straight) or at least 100 m in size"),
])
def test_a_bad_layout_is_one_line(kwargs, message):
    with pytest.raises(ModelError) as caught:
        SpanLayout(**kwargs)
    assert str(caught.value).startswith(message) and "\n" not in str(caught.value)
