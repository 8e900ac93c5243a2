"""The validity sweep of a decision (presag_opt.pipeline.validity): the reduced sweep's grid around the
pre-sag, a stored study read as evidence. The reduced sweep itself runs in the report's tests."""

from __future__ import annotations

import pytest

from presag_opt.design import CASE_STUDY_BAND
from presag_opt.design.band import KMH
from presag_opt.pipeline.validity import stored_sweep, sweep_grid
from presag_opt.studies.store import write_store
from presag_opt.system.loader import load_catenary


def test_the_reduced_grid_brackets_the_pre_sag_and_reaches_beta_06():
    catenary = load_catenary("st_9.8_ideal")
    grid = sweep_grid(catenary, CASE_STUDY_BAND, 0.9e-3, quick=False)
    assert grid["presags"] == pytest.approx((0.027, 0.054, 0.081), abs=1e-12)  # 0.5, 1, 1.5 × 54 mm on 60 m
    speeds_kmh = [round(v / KMH) for v in grid["speeds"]]
    # the band's top, 90 km/h, and β 0.2…0.6 of c_CW = 345 km/h rounded to 10 km/h
    assert speeds_kmh == [70, 90, 100, 140, 170, 210]
    assert grid["static_forces"] == (70.0, 105.0, 140.0)
    quick = sweep_grid(catenary, CASE_STUDY_BAND, 0.9e-3, quick=True)
    assert [round(v / KMH) for v in quick["speeds"]] == [90, 210] and len(quick["presags"]) == 2
    assert quick["static_forces"] == (70.0, 140.0)


def test_a_stored_study_is_read_as_the_decision_s_sweep(tmp_path):
    from tests.studies.conftest import synthetic_dataset
    from tests.studies.test_validity_analysis import relative_parabola, rule_mm

    ds = synthetic_dataset(sigma=relative_parabola(0.010), presags_mm=[20, 60, 100], betas=[0.2, 0.4, 0.45, 0.5],
                      static_forces=[50, 100, 150], rule_mm=rule_mm)
    path = tmp_path / "study.nc"
    write_store(ds, path)
    wire = load_catenary("st_9.8_ideal").contact_wire
    swept = stored_sweep(path, CASE_STUDY_BAND, wire.wave_speed)
    assert swept.source == str(path) and swept.record.limit.kind == "study"
    assert swept.record.limit.name == "the validity study study.nc"
    assert swept.record.limit.beta_star == pytest.approx(0.425, abs=1e-9)
    assert swept.uplift_up_to(CASE_STUDY_BAND.speed_high) == pytest.approx(0.05, abs=1e-12)  # below β 0.2: none
