"""Study definitions: the shipped paper grid, extra parameters, and bad input (API and command line)."""

from __future__ import annotations

from pathlib import Path

import pytest
import xarray as xr

from presag_opt.errors import ModelError
from presag_opt.studies.definition import load_study
from presag_opt.studies.runner import run_study
from presag_opt.studies.store import units_directory
from presag_opt.studies.work import all_units

MODELS = Path(__file__).parent / "models"


def test_shipped_paper_grid_is_the_papers_400_runs():
    study = load_study("paper_grid_st98")
    grid = study.grid
    assert [round(s * 1e3, 9) for s in grid.presags] == [30, 40, 50, 60, 70]
    assert [round(v * 3.6, 9) for v in grid.speeds] == [50, 60, 70, 80, 90, 100, 120, 140, 160, 180]
    assert list(grid.static_forces) == [50, 65, 80, 95, 110, 125, 140, 155]
    assert study.run_count == 400 and len(all_units(study)) == 50
    assert grid.aero_coefficient == pytest.approx(0.00097 * 3.6**2, rel=1e-12)  # N/(km/h)^2 -> N/(m/s)^2
    assert study.uplift_limit == pytest.approx(0.0835, rel=1e-12)
    assert study.settings.integrator.scheme == "hht" and study.settings.integrator.hht_alpha == -0.005
    assert study.catenary.name.startswith("ST 9,8/9,8") and study.pantograph.stages[1].friction == 5.0


def test_digest_ignores_the_file_but_not_the_content(small_study_path, tmp_path):
    same = tmp_path / "same.toml"
    same.write_text(small_study_path.read_text().replace("st_9.8_short.toml", str(MODELS / "st_9.8_short.toml")))
    assert load_study(same).digest() == load_study(small_study_path).digest()
    other = tmp_path / "other.toml"
    other.write_text(same.read_text().replace("[80, 120]", "[80, 125]"))
    assert load_study(other).digest() != load_study(small_study_path).digest()


def test_extra_parameters_become_grid_axes_and_reach_the_models(tmp_path):
    path = _study(tmp_path, extra=(
        '[[parameters]]\nname = "pantograph.frame.friction"\nvalues = { value = [0, 10], unit = "N", source = "assumed" }\n'
        '[[parameters]]\nname = "catenary.droppers.max_spacing"\n'
        'values = { value = [6.0, 8.5], unit = "m", source = "assumed" }\n'
    ))
    study = load_study(path)
    assert study.shape == (2, 2, 2, 2, 2)
    variant = study.variant((1, 0))
    assert variant.pantograph.stages[1].friction == 10.0
    assert variant.pantograph.stages[0] == study.pantograph.stages[0]
    assert variant.catenary.droppers.max_spacing == 6.0
    assert study.parameter_unit("pantograph.frame.friction") == "N"


BAD_INPUTS = {
    "empty grid": ({"speeds = { value = [140, 180]": "speeds = { value = []"}, "", "grid.speeds is an empty list"),
    "speed at the wave speed": ({"[140, 180]": "[140, 400]"}, "", "grid.speeds[1] = 400 km/h"),
    "unknown parameter": ({}, '[[parameters]]\nname = "pantograph.frame.fricton"\n'
                              'values = { value = [1], unit = "N", source = "assumed" }\n',
                          "unknown parameter 'pantograph.frame.fricton'"),
    "parameter out of range": ({}, '[[parameters]]\nname = "pantograph.frame.friction"\n'
                                   'values = { value = [-1], unit = "N", source = "assumed" }\n',
                               "parameters.pantograph.frame.friction[0] = -1 N is outside the valid range"),
}


@pytest.mark.parametrize("case", sorted(BAD_INPUTS))
def test_bad_study_is_one_clear_line_from_the_api(case, tmp_path):
    changes, extra, message = BAD_INPUTS[case]
    with pytest.raises(ModelError) as info:
        load_study(_study(tmp_path, changes, extra))
    assert message in str(info.value) and "\n" not in str(info.value)


@pytest.mark.parametrize("case", sorted(BAD_INPUTS))
def test_bad_study_is_one_clear_line_from_the_cli_and_leaves_the_store(presag, case, tmp_path):
    changes, extra, message = BAD_INPUTS[case]
    store = _foreign_store(tmp_path)
    before = store.read_bytes()
    proc = _sweep(presag, _study(tmp_path, changes, extra), store)
    assert proc.returncode == 2
    assert proc.stderr.count("\n") == 1 and message in proc.stderr, proc.stderr
    assert store.read_bytes() == before and not units_directory(store).exists()


def test_store_of_another_definition_is_refused_and_untouched(presag, small_study_path, tmp_path):
    store = _foreign_store(tmp_path)
    before = store.read_bytes()
    with pytest.raises(ModelError, match=r"written by a different study definition \(hash 0123456789ab"):
        run_study(load_study(small_study_path), store, workers=1, progress=None)
    proc = _sweep(presag, small_study_path, store)
    assert proc.returncode == 2 and proc.stderr.count("\n") == 1
    assert "written by a different study definition" in proc.stderr
    assert store.read_bytes() == before and not units_directory(store).exists()


def test_units_of_another_definition_are_refused(small_study_path, tmp_path):
    store = tmp_path / "study.nc"
    units = units_directory(store)
    units.mkdir()
    (units / "study.json").write_text('{"study_hash": "feedfacefeedface"}')
    with pytest.raises(ModelError, match="units of a different study definition"):
        run_study(load_study(small_study_path), store, workers=1, progress=None)
    assert sorted(p.name for p in units.iterdir()) == ["study.json"]


def _study(tmp_path: Path, changes: dict[str, str] | None = None, extra: str = "") -> Path:
    """The small test study with text replacements and extra sections, written to tmp_path."""
    text = (MODELS / "small_grid.toml").read_text()
    text = text.replace("st_9.8_short.toml", str(MODELS / "st_9.8_short.toml"))
    for old, new in (changes or {}).items():
        assert old in text
        text = text.replace(old, new)
    path = tmp_path / "study.toml"
    path.write_text(text + "\n" + extra)
    return path


def _foreign_store(tmp_path: Path) -> Path:
    """A store that another study definition wrote (only its hash matters)."""
    store = tmp_path / "existing.nc"
    xr.Dataset(attrs={"study_hash": "0123456789abcdef" * 4}).to_netcdf(store, engine="h5netcdf")
    return store


def _sweep(presag, study: Path, store: Path):
    return presag("sweep", str(study), "--out", str(store), "--workers", "1", "--quiet")
