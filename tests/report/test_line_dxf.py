"""The line's DXF (presag_opt.report.line_dxf) read back with ezdxf: units, the named layers, and every dropper
found at its chainage between its clamp heights with its id."""

from __future__ import annotations

import collections

import ezdxf
import pytest

from presag_opt.design import CASE_STUDY_BAND
from presag_opt.design.line import LineOptions, design_line
from presag_opt.report.line_dxf import LAYERS, write_dxf
from presag_opt.system.catenary import SpanLayout
from presag_opt.system.loader import load_catenary
from presag_opt.system.survey_writing import survey_of_catenary


@pytest.fixture(scope="module")
def design():
    base = load_catenary("st_9.8_mixed").with_layout(SpanLayout(span_lengths=(50.0, 45.0, 50.0, 40.0)))
    return design_line(survey_of_catenary(base), base, CASE_STUDY_BAND, LineOptions(element_length=1.0, workers=1))


def test_every_dropper_is_read_back_with_its_id_at_its_place(design, tmp_path):
    doc = ezdxf.readfile(write_dxf(design, tmp_path / "line.dxf"))
    assert doc.units == ezdxf.units.M
    assert set(LAYERS) <= {layer.dxf.name for layer in doc.layers}
    space = doc.modelspace()
    ids = {e.dxf.text: e for e in space.query("TEXT[layer=='PROFILE_DROPPER_IDS']")}
    lines = {round(e.dxf.start.x, 6): e for e in space.query("LINE[layer=='PROFILE_DROPPERS']")}
    assert len(ids) == len(lines) == len(design.droppers) > 0
    for d in design.droppers:
        assert d.id in ids
        line = lines[round(d.chainage, 6)]
        assert (line.dxf.start.y, line.dxf.end.y) == pytest.approx((d.contact_wire_height, d.messenger_height), abs=1e-9)
    counts = collections.Counter(e.dxf.layer for e in space)
    assert counts["PROFILE_MASTS"] == 2 * len(design.survey.masts)  # a line and an id each
    assert counts["PLAN_CONTACT_WIRE"] == counts["PROFILE_CONTACT_WIRE"] == len(design.sections)
