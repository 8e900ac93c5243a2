"""The package as an index would serve it: the sdist and the wheel built with ``python -m build``,
checked with ``twine check``, and the wheel installed into a fresh virtual environment and run from a
folder outside the clone (tier ``wheel``: it installs every dependency into the new environment)."""

from __future__ import annotations

import json
import os
import subprocess
import sys
import venv
import zipfile
from pathlib import Path

import pytest

import presag_opt

pytestmark = pytest.mark.wheel

ROOT = Path(__file__).parents[2]


@pytest.fixture(scope="module")
def dist(tmp_path_factory) -> Path:
    """The sdist and the wheel of this checkout, built in isolation (``python -m build``)."""
    out = tmp_path_factory.mktemp("dist")
    built = subprocess.run([sys.executable, "-m", "build", "--outdir", str(out), str(ROOT)], capture_output=True,
                           text=True, timeout=900, check=False)
    assert built.returncode == 0, built.stdout[-3000:] + built.stderr[-3000:]
    assert "is absent from the `packages` configuration" not in built.stdout + built.stderr
    return out


def _wheel(dist: Path) -> Path:
    (wheel,) = dist.glob("presag_opt-*.whl")
    return wheel


def test_twine_accepts_the_sdist_and_the_wheel(dist):
    files = sorted(str(p) for p in dist.iterdir())
    assert len(files) == 2, files
    checked = subprocess.run([sys.executable, "-m", "twine", "check", "--strict", *files], capture_output=True,
                             text=True, timeout=300, check=False)
    assert checked.returncode == 0, checked.stdout + checked.stderr
    assert checked.stdout.count("PASSED") == 2, checked.stdout


def test_the_sdist_holds_the_source_the_licence_and_the_citation(dist):
    import tarfile

    (sdist,) = dist.glob("presag_opt-*.tar.gz")
    names = {n.split("/", 1)[1] for n in tarfile.open(sdist).getnames() if "/" in n}
    assert {"LICENSE", "CITATION.cff", "README.md", "pyproject.toml", "presag_opt/pipeline/band.py",
            "models/cases/case_study_st98.toml"} <= names
    assert not [n for n in names if n.startswith(("tests/", "notebooks/", "docs/"))]


def test_the_wheel_holds_what_the_package_reads_and_nothing_else(dist):
    wheel = _wheel(dist)
    assert wheel.name == f"presag_opt-{presag_opt.__version__}-py3-none-any.whl"
    names = zipfile.ZipFile(wheel).namelist()
    models = sorted(str(p.relative_to(ROOT / "models")) for p in (ROOT / "models").rglob("*.toml"))
    assert sorted(n.removeprefix("presag_opt/builtin_models/") for n in names
                  if n.startswith("presag_opt/builtin_models/") and n.endswith(".toml")) == models
    for needed in ("presag_opt/native/banded.c", "presag_opt/native/sweeps.c",
                   "presag_opt/sensitivity/data/recommendation_morris.json", "presag_opt/pipeline/band.py"):
        assert needed in names, needed
    licence = [n for n in names if n.endswith("licenses/LICENSE")]
    assert len(licence) == 1, names
    metadata = zipfile.ZipFile(wheel).read(f"presag_opt-{presag_opt.__version__}.dist-info/METADATA").decode()
    assert "License-Expression: MIT" in metadata and "License-File: LICENSE" in metadata
    unwanted = [n for n in names if n.startswith(("tests/", "notebooks/", "docs/", "benchmarks/", "research/"))
                or "__pycache__" in n or n.endswith((".pyc", ".nbi", ".nbc", ".ipynb"))]
    assert not unwanted, unwanted


@pytest.fixture(scope="module")
def installed(dist, tmp_path_factory):
    """A fresh virtual environment with only the wheel (and what it depends on) installed, and a
    folder outside the clone to run it in, with its own cache folder."""
    where = tmp_path_factory.mktemp("installed")
    venv.create(where / "venv", with_pip=True)
    python = where / "venv" / "bin" / "python"
    pip = subprocess.run([str(python), "-m", "pip", "install", "--quiet", str(_wheel(dist))], capture_output=True,
                         text=True, timeout=1800, check=False)
    assert pip.returncode == 0, pip.stdout[-3000:] + pip.stderr[-3000:]
    work = where / "work"
    work.mkdir()
    env = {key: value for key, value in os.environ.items() if not key.startswith(("PYTHON", "VIRTUAL_ENV"))}
    env["XDG_CACHE_HOME"] = str(where / "cache")
    env.pop("NUMBA_CACHE_DIR", None)

    def run(*args: str) -> subprocess.CompletedProcess:
        return subprocess.run([str(where / "venv" / "bin" / "presag"), *args], capture_output=True, text=True,
                              cwd=work, env=env, timeout=900, check=False)

    return run, python, work


def test_the_installed_package_is_the_wheels_not_the_clones(installed):
    _, python, work = installed
    found = subprocess.run([str(python), "-c", "import presag_opt; print(presag_opt.__file__)"], capture_output=True,
                           text=True, cwd=work, timeout=120, check=True).stdout.strip()
    assert Path(found).is_relative_to(python.parents[1]) and not Path(found).is_relative_to(ROOT)


def test_version_and_the_case_studys_recommendation(installed):
    run, _, _ = installed
    version = run("--version")
    assert version.returncode == 0 and version.stdout.split() == ["presag", presag_opt.__version__], version
    recommend = run("recommend", "--json")
    assert recommend.returncode == 0, recommend.stderr
    data = json.loads(recommend.stdout)
    # the checkout's answer (tests/validation/test_headline.py pins it): the same package, installed
    assert data["decision"]["status"] == "provisional"
    assert data["decision"]["presag_mm"] == pytest.approx(55.77, abs=0.01)  # mm on the 60 m reference span


def test_one_batch_simulation(installed, presag, tmp_path):
    """Two runs in one batch from the installed wheel: the statistics of the checkout's own command
    (in-process), to round-off, and F_m within 1 % of F_stat + α_ae v² (6.2 N at 80 km/h; the mean
    contact force over the analysed spans differs from the applied mean by about 0.2 %)."""
    run, _, _ = installed
    args = ("simulate", "--case", "case_study_st98", "--speed", "80", "--static-force", "100,120", "--json")
    ran = run(*args)
    assert ran.returncode == 0, ran.stderr
    data = json.loads(ran.stdout)
    here = json.loads(presag(*args, cwd=tmp_path).stdout)
    assert [(r["speed_kmh"], r["static_force_N"]) for r in data["runs"]] == [(80.0, 100.0), (80.0, 120.0)]
    assert not data["failed_runs"]
    for run_, ours in zip(data["runs"], here["runs"], strict=True):
        assert run_["Fm_N"] == pytest.approx(run_["static_force_N"] + 6.208, rel=0.01)
        for key in ("Fm_N", "sigma_N", "stat_max_N", "stat_min_N", "uplift_max_mm"):
            assert run_[key] == pytest.approx(ours[key], rel=1e-9), key


def test_a_line_designed_from_a_survey(installed):
    run, _, work = installed
    header = "mast,chainage_m,stagger_mm,contact_wire_height_m,system_height_m,curve_radius_m,steady_arm,section"
    rows = [f"M{i + 1},{50 * i},{200 if i % 2 == 0 else -200},5.5,1.2,,pull-off,A" for i in range(5)]
    (work / "line.csv").write_text("\n".join([header, *rows]) + "\n", encoding="utf-8")
    designed = run("design", "line.csv", "--system", "st_9.8_ideal", "--out", "line", "--json")
    assert designed.returncode == 0, designed.stderr
    data = json.loads(designed.stdout)
    assert data["spans"] == 4 and data["droppers"] > 0
    assert (work / "line" / "droppers.csv").is_file() and (work / "line" / "index.html").is_file()
