"""``presag_opt.design.layouts``: the layout studies — mixed against ideal spans, and a section built on
a curve. The curve study is checked against the statics of a staggered wire: the steady-arm pull is
the curve's kink T·l/R plus the alternating stagger kink ±T·4a/l."""

from __future__ import annotations

from types import SimpleNamespace

import pytest

from presag_opt.design import layouts
from presag_opt.design.layouts import MixedFinding, curve_effects, mixed_versus_ideal
from presag_opt.errors import ModelError
from presag_opt.static.discretisation import StaticSettings
from presag_opt.system.catenary import SpanLayout
from presag_opt.system.loader import load_catenary


def _recommendation(*layouts_):
    return SimpleNamespace(layouts=[SimpleNamespace(layout_kind=k, presag_rel_range=r) for k, r in layouts_])


def test_a_finding_compares_the_mean_presag_of_mixed_and_ideal_spans():
    finding = MixedFinding.from_recommendation("v", _recommendation(("mixed", (0.8e-3, 1.6e-3)),
                                                                     ("ideal", (0.7e-3, 1.3e-3))))
    assert finding.ideal_range == (0.7e-3, 1.3e-3) and finding.mixed_range == (0.8e-3, 1.6e-3)
    assert finding.ratio == pytest.approx(1.2, rel=1e-12) and not finding.mixed_needs_less
    assert MixedFinding(label="x", ideal_range=(1.0, 1.0), mixed_range=(0.5, 0.9)).mixed_needs_less


@pytest.mark.parametrize("kinds", [("ideal",), ("ideal", "ideal"), ("ideal", "mixed", "mixed")])
def test_a_finding_needs_one_ideal_and_one_mixed_layout(kinds):
    with pytest.raises(ModelError, match=r"^variant 'v': give one ideal and one mixed layout$"):
        MixedFinding.from_recommendation("v", _recommendation(*((k, (1.0, 2.0)) for k in kinds)))


def test_each_variant_is_recommended_on_its_own_pair(monkeypatch):
    calls, messages = [], []

    def fake_recommend(*, models, band, step, settings):
        calls.append(tuple(models))
        return _recommendation(("ideal", (1.0, 2.0)), ("mixed", (1.0, 1.0)))

    monkeypatch.setattr(layouts, "recommend", fake_recommend)
    found = mixed_versus_ideal({"a": ("i1", "m1"), "b": ("i2", "m2")}, progress=messages.append)
    assert calls == [("i1", "m1"), ("i2", "m2")] and [f.label for f in found] == ["a", "b"]
    assert messages == ["mixed against ideal: a", "mixed against ideal: b"]
    with pytest.raises(ModelError, match=r"^variants is empty; give at least one \(ideal, mixed\) pair$"):
        mixed_versus_ideal({})


def test_on_a_curve_the_steady_arms_pull_the_curves_kink_plus_or_minus_the_stagger_kink():
    """Six 60 m spans of ST 9,8/9,8 (T = 9.8 kN, stagger a = ±0.3 m): on straight track every inner arm
    pulls T·4a/l = 196 N sideways (its tension is a little more: it also carries part of the wire's
    weight, hence up to 15 %); on R = 1000 m the kinks add at one mast and subtract at the next:
    T(l/R ± 4a/l) = 588 ± 196 N, to 5 % (the arm's vertical share again, and the chords on the curve).
    The form-finding holds its standard geometry tolerance (0.05 mm) on the curve too."""
    catenary = load_catenary("st_9.8_ideal")
    settings = StaticSettings(element_length=1.0)
    messages = []
    straight, curved = curve_effects(catenary.with_layout(SpanLayout(span_lengths=(60.0,) * 6)), (0.0, 1000.0),
                                     step=2.0, settings=settings, progress=messages.append)
    assert messages == ["curve radius 0 m", "curve radius 1000 m"]
    tension, stagger, span = catenary.contact_wire.tension, catenary.stagger, 60.0
    stagger_kink, curve_kink = tension * 4 * stagger / span, tension * span / 1000.0
    low, high = straight.steady_arm_pull_range
    assert high - low < 1e-3 * low  # the same at every inner mast
    assert stagger_kink <= straight.steady_arm_pull <= 1.15 * stagger_kink
    low, high = curved.steady_arm_pull_range
    assert 0.5 * (high + low) == pytest.approx(curve_kink, rel=0.05)
    assert 0.5 * (high - low) == pytest.approx(stagger_kink, rel=0.05)
    assert curved.e_mast < straight.e_mast  # a harder-pulled arm is a stiffer support
    assert curved.presag_rel == pytest.approx(sum(curved.presag_rel_range) / 2, rel=1e-15)
