"""The dynamic check of robust designs (presag_opt.robust.dynamic_check) on a small section."""

from __future__ import annotations

import pytest

from presag_opt.dynamics.pantograph import load_pantograph
from presag_opt.dynamics.simulate import SimulationSettings, simulate
from presag_opt.robust import dynamic_check
from presag_opt.static.equilibrium import form_find
from presag_opt.system.catenary import SpanLayout
from presag_opt.system.loader import load_catenary


def test_dynamic_check_runs_each_design_and_sorts_runs_by_regime():
    catenary = load_catenary("st_9.8_ideal").with_layout(SpanLayout(span_lengths=(60.0, 60.0, 60.0)))
    pantograph = load_pantograph("case_study_2mass_friction")
    settings = SimulationSettings(analysed_spans=1, lead_in_spans=0)
    speeds = (90 / 3.6, 180 / 3.6)  # β = 0.26 and 0.52 on 9.8 kN: one run either side of 0.4
    check = dynamic_check(
        catenary, {"robust": 0.93e-3}, pantograph=pantograph, static_forces=(100.0,), speeds=speeds,
        aero_coefficient=0.0, reference_span=60.0, settings=settings,
    )
    assert [(r.design, r.speed) for r in check.runs] == [("robust", s) for s in speeds]
    # Each run is the simulation of the design's own geometry: identical to a direct call (same code,
    # same inputs, deterministic).
    direct = simulate(form_find(catenary.with_presag(0.93e-3)), pantograph, speed=speeds[0], static_force=100.0,
                      settings=settings)
    assert check.runs[0].sigma_over_mean == direct.statistics.sigma_over_mean
    assert check.runs[0].presag == pytest.approx(0.93e-3 * 60.0, rel=1e-15)
    summary = check.summary()
    assert [row["regime"] for row in summary] == ["beta < 0.4", "beta >= 0.4"]
    assert [row["runs"] for row in summary] == [1, 1]
    assert summary[1]["worst_sigma_over_Fm"] == check.runs[1].sigma_over_mean
