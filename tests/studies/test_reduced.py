"""``presag_opt.studies.reduced``: a small version of a study — the central spans of its section, one
lead-in and one analysed span, fixed coarse numerics, a small grid — checked as a definition (its run is
the report's reduced sweep, covered by ``tests/report/test_content.py``)."""

from __future__ import annotations

import dataclasses

import pytest

from presag_opt.errors import ModelError
from presag_opt.studies.definition import load_study
from presag_opt.studies.parameters import ParameterSweep
from presag_opt.studies.reduced import REDUCED_SPANS, reduced_study
from presag_opt.system.catenary import SpanLayout
from presag_opt.system.loader import load_catenary

BASE = load_study("paper_grid_st98")


def test_a_reduced_study_keeps_the_central_spans_and_sets_coarse_fixed_numerics():
    study = reduced_study(BASE, presags=(0.03, 0.06), speeds=(20.0, 30.0), static_forces=(100.0,))
    n = BASE.catenary.layout.n_spans
    first = (n - REDUCED_SPANS) // 2
    assert study.catenary.layout.span_lengths == BASE.catenary.layout.span_lengths[first:first + REDUCED_SPANS]
    assert study.catenary.layout.curve_radii is None  # straight track stays straight
    s = study.settings
    assert (s.numerics, s.static.element_length, s.integrator.time_step) == ("fixed", 1.0, 4e-3)
    assert (s.analysed_spans, s.lead_in_spans) == (1, 1)
    assert study.grid.presags == (0.03, 0.06) and study.grid.aero_coefficient == BASE.grid.aero_coefficient
    assert study.pantograph == BASE.pantograph and study.uplift_limit == BASE.uplift_limit
    assert study.description == "2 pre-sags x 2 speeds x 1 static forces on 5 spans, 1 m elements, 4 ms"


def test_a_curved_section_keeps_the_radii_of_its_central_spans():
    curved = load_catenary("st_9.8_ideal").with_layout(SpanLayout(span_lengths=(60.0,) * 7,
                                                                  curve_radii=(0, 0, 800, 900, -1000, 0, 0)))
    study = reduced_study(BASE, presags=(0.05,), speeds=(20.0,), static_forces=(100.0,), catenary=curved,
                          aero_coefficient=0.0)
    assert study.catenary.layout.curve_radii == (0.0, 800.0, 900.0, -1000.0, 0.0)  # spans 1–5 of 0–6
    assert study.grid.aero_coefficient == 0.0


def test_too_few_spans_or_a_study_with_extra_parameters_are_refused():
    with pytest.raises(ModelError, match=r"^span_count = 3 is below the smallest valid value 4$"):
        reduced_study(BASE, presags=(0.05,), speeds=(20.0,), static_forces=(100.0,), span_count=3)
    swept = dataclasses.replace(BASE, parameters=(ParameterSweep(name="pantograph.frame.friction", values=(0, 5)),))
    with pytest.raises(ModelError, match="^reduced_study: the base study sweeps extra parameters"):
        reduced_study(swept, presags=(0.05,), speeds=(20.0,), static_forces=(100.0,))
