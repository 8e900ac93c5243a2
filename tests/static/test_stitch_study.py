"""The stitched validity-grid study files: they load, carry the stitched system and automatic
numerics, and their runs are planned at each speed's own element length (fast: no simulation)."""

from __future__ import annotations

from pathlib import Path

import pytest

from presag_opt.studies.definition import load_study
from presag_opt.studies.runner import estimate_study
from presag_opt.units import KMH

STUDIES = Path(__file__).resolve().parents[2] / "models" / "studies"


@pytest.mark.parametrize("name", ["paper_grid_st98_stitched", "paper_grid_st98_auto", "paper_grid_st98_stitched_high"])
def test_grid_files_load_with_automatic_numerics(name):
    study = load_study(STUDIES / f"{name}.toml")
    assert study.settings.numerics == "auto"
    assert (study.catenary.stitch_wire is not None) == ("stitched" in name)
    base = load_study("paper_grid_st98")
    # Same pre-sags and static forces as the paper's grid, and its speeds (or the extension above them).
    assert study.grid.presags == base.grid.presags
    assert study.grid.static_forces == base.grid.static_forces
    assert study.grid.aero_coefficient == pytest.approx(base.grid.aero_coefficient, rel=1e-12)
    if "high" not in name:
        assert study.grid.speeds == base.grid.speeds


def test_estimate_counts_one_form_finding_per_element_length(tmp_path):
    """Automatic numerics: 50 km/h keeps 0.5 m, 180 km/h needs 0.28 m, so the study form-finds
    several discretisations (one node count each), the fixed paper grid only one."""
    auto = estimate_study(load_study(STUDIES / "paper_grid_st98_stitched.toml"), tmp_path / "a.nc", workers=2)
    fixed = estimate_study(load_study("paper_grid_st98"), tmp_path / "b.nc", workers=2)
    assert len(fixed.nodes) == 1
    assert len(auto.nodes) >= 5
    study = load_study(STUDIES / "paper_grid_st98_stitched.toml")
    wave = study.catenary.contact_wire.wave_speed
    lengths = {study.settings.for_speed(v, wave).static.element_length for v in study.grid.speeds}
    assert max(lengths) == pytest.approx(0.5, abs=1e-12)
    assert min(lengths) == pytest.approx(0.28, abs=1e-12)  # (c − v)/f_c/8 at 180 km/h, on the 0.01 m grid
    assert study.grid.speeds[-1] == pytest.approx(180 * KMH)
