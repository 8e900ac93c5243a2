"""A stitched catenary reaches the dynamic model and both simulation engines unchanged.

The dynamic model is built from the static discretisation: the stitch-wire segments enter through
the tangent stiffness and the lumped masses, and the stitch droppers are droppers
(``dropper_elements``), so the dynamic model makes them tension-only like the others. One short run
(5 spans, one analysed, 90 km/h) with ``simulate`` and with the batch engine must agree; the
tolerance is the batch tests' for a frictionless, well-conditioned run (1e-9 relative).
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from presag_opt.dynamics.batch import simulate_many
from presag_opt.dynamics.case import load_case
from presag_opt.dynamics.settings import OperatingPoint
from presag_opt.dynamics.simulate import simulate
from presag_opt.dynamics.structure import structural_model
from presag_opt.static.form_finding import form_find
from presag_opt.system.catenary import SpanLayout
from presag_opt.system.loader import load_catenary

AERO = 0.00097 * 3.6**2  # the case study's α_ae [N/(m/s)²]


@pytest.fixture(scope="module")
def case():
    return load_case("case_study_st98")


@pytest.fixture(scope="module")
def short_stitched(case):
    catenary = load_catenary("st_9.8_stitched_ideal").with_layout(SpanLayout(span_lengths=(60.0,) * 5, label="5 ideal spans"))
    return form_find(catenary, case.settings.static)


def test_stitch_droppers_are_tension_only_droppers_of_the_dynamic_model(short_stitched, case):
    disc = short_stitched.discretisation
    model = structural_model(short_stitched)
    assert len(model.droppers.preload) == len(disc.dropper_elements)
    assert int(disc.stitch_dropper.sum()) == 4 * 2  # four inner masts, two stitch droppers each
    stitch_station = disc.mast_station[disc.dropper_span[disc.stitch_dropper]] + disc.dropper_position[disc.stitch_dropper]
    assert np.all(np.isin(np.round(stitch_station, 9), np.round(model.droppers.station, 9)))


def test_one_short_run_with_both_engines(short_stitched, case):
    settings = dataclasses.replace(case.settings, lead_in_spans=1, analysed_spans=1)
    pantograph = dataclasses.replace(
        case.pantograph, stages=tuple(dataclasses.replace(s, friction=0.0) for s in case.pantograph.stages))
    point = OperatingPoint(speed=90 / 3.6, static_force=110.0, aero_coefficient=AERO)
    single = simulate(short_stitched, pantograph, speed=point.speed, static_force=point.static_force,
                      aero_coefficient=point.aero_coefficient, settings=settings)
    batch = simulate_many(short_stitched, pantograph, [point], settings=settings)
    outcome = batch.runs[0]
    assert outcome.ok, outcome.error
    ref = single.pantographs[0].statistics
    assert 90.0 < ref.mean_force < 150.0  # the static force plus the aerodynamic part, about 115 N
    assert ref.std_force > 0.0
    for name in ("mean_force", "std_force", "max_force", "min_force"):
        assert getattr(outcome.statistics[0], name) == pytest.approx(getattr(ref, name), rel=1e-9), name
    assert outcome.uplift_max == pytest.approx(single.uplift_max, rel=1e-9)
