"""The dropper schedule of a built section (presag_opt.design.line_droppers): ids in track order, the absolute
chainage, the lateral position on the chord, both heights, the cut length; on a canted curve the heights
perpendicular to the track plane (turned back from the level frame the model works in)."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from presag_opt.design import CASE_STUDY_BAND
from presag_opt.design.line import LineOptions, design_line
from presag_opt.design.line_rules import lateral_offset
from presag_opt.system.cant import RAIL_CENTRE_DISTANCE
from presag_opt.system.catenary import SpanLayout
from presag_opt.system.loader import load_catenary
from presag_opt.system.survey import Survey
from presag_opt.system.survey_writing import survey_of_catenary

OPTIONS = LineOptions(element_length=1.0, workers=1, round_step=0.005)


def curved(cant: float) -> Survey:
    """Five 40 m spans on a left-hand 800 m curve, the wire registered 0.2 m to the outside."""
    base = load_catenary("st_9.8_mixed").with_layout(SpanLayout(span_lengths=(40.0,) * 5, curve_radii=(800.0,) * 5))
    survey = survey_of_catenary(base)
    return Survey(masts=tuple(dataclasses.replace(m, stagger=-0.2, cant=cant) for m in survey.masts),
                  source="curve.csv")


@pytest.fixture(scope="module")
def level_and_canted():
    base = load_catenary("st_9.8_mixed")
    return tuple(design_line(curved(cant), base, CASE_STUDY_BAND, OPTIONS) for cant in (0.0, 0.06))


def test_every_dropper_has_its_id_chainage_lateral_position_and_cut_length(level_and_canted):
    design = level_and_canted[0]
    masts = {m.mast: m for m in design.survey.masts}
    ids = [d.id for d in design.droppers]
    assert len(set(ids)) == len(ids) and ids[0] == "1/M1-M2/1"
    for d in design.droppers:
        a, b = masts[d.from_mast], masts[d.to_mast]
        assert d.chainage == pytest.approx(a.chainage + d.position, abs=1e-12)
        assert d.lateral == pytest.approx(float(lateral_offset(a, b, np.array([d.position]))[0]), abs=1e-15)
        assert round(d.cut_length / 0.005) * 0.005 == pytest.approx(d.cut_length, abs=1e-12)
        assert abs(d.cut_length - (d.length + 0.2)) <= 0.0025 + 1e-12
        assert d.messenger_height - d.contact_wire_height == pytest.approx(d.length, abs=0.02)


def test_on_a_canted_curve_the_heights_are_taken_perpendicular_to_the_track_plane(level_and_canted):
    level, canted = level_and_canted
    # the same surveyed heights (in the track frame) at the masts: the wire hangs alike, but where it runs
    # inwards of its registration (the chord inside the arc) the canted track plane lies lower under it, so
    # the pantograph sees it higher by the lateral move times sin θ (θ = asin(60 mm / 1.5 m))
    sin = 0.06 / RAIL_CENTRE_DISTANCE
    moves = []
    for a, b in zip(level.droppers, canted.droppers, strict=True):
        moves.append(b.lateral + 0.2)
        assert b.contact_wire_height - a.contact_wire_height == pytest.approx((b.lateral + 0.2) * sin, abs=5e-4)
    assert max(moves) * sin > 5e-3  # the effect is larger than the tolerance it is checked to
