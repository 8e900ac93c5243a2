"""``presag sensitivity`` (in-process), on a tiny case (four 30 m spans)."""

from __future__ import annotations

import json
import os
import re
import subprocess
import sys
import time
from pathlib import Path

import pytest

TINY = Path(__file__).parent / "models" / "tiny_case.toml"
SCRIPT = Path(sys.executable).parent / "presag"


def kept_evaluations(cache: Path) -> list[Path]:
    """The evaluation files of the analyses kept in a cache folder."""
    return sorted(cache.glob("presag_opt/evaluations/*/evaluation_*.json"))


def test_morris_on_the_robust_output_json_plot_and_cost_announcement(presag, tmp_path):
    args = ("sensitivity", str(TINY), "--quantity", "robust", "--inputs",
            "catenary.system_height,operation.aero_coefficient", "--samples", "3", "--seed", "3", "--json")
    result = presag(*args, "--plot", "figs", cwd=tmp_path)
    assert result.returncode == 0, result.stderr
    data = json.loads(result.stdout)  # --json: stdout is one JSON object, nothing else
    assert data["evaluations"] == 3 * (2 + 1)  # r (k + 1)
    assert data["failed"] == 0 and len(list(Path(data["store"]).glob("evaluation_*.json"))) == 9  # kept by default
    assert data["solver"]["form_findings"] > 0 and data["solver"]["iterations"]["q50"] > 0
    assert [i["name"] for i in data["inputs"]] == ["catenary.system_height", "operation.aero_coefficient"]
    # the system height's range is declared in the model file; α_ae's is the ±20 % default
    assert data["inputs"][0]["declared"] and (data["inputs"][0]["low"], data["inputs"][0]["high"]) == (1.0, 1.6)
    assert data["inputs"][1]["low"] == pytest.approx(0.8 * 0.00097, rel=1e-12)
    tables = {t["output"]: t for t in data["indices"]}
    assert set(tables) == {"presag_rel", "tolerance_low", "tolerance_high", "tolerance_width"}
    for t in tables.values():
        assert len(t["ranked"]) == 2
        assert t["ranked"][0]["mu_star"] >= t["ranked"][1]["mu_star"]
        assert t["ranked"][0]["mu_star_relative"] == pytest.approx(1.0, abs=1e-12)
    # F_m scales with α_ae over the band's top (+-20 % of 7.9 N at 90 km/h): the robust S_rel must move
    assert tables["presag_rel"]["ranked"][0]["mu_star"] > 1e-3
    assert "evaluations ×" in result.stderr and "min" in result.stderr
    assert len(list((tmp_path / "figs").glob("sensitivity_robust_*_morris.png"))) == 4

    # the seed reached the design (reproducibility with a seed: tests/sensitivity/test_methods.py)
    assert data["seed"] == 3


@pytest.mark.e2e
def test_a_killed_screening_resumes_from_its_kept_evaluations(presag_script, tmp_path):
    """Killed (SIGKILL, nothing can clean up) after three evaluations and run again: it computes only the
    rest and gives the same design, indices and form-findings as a run that was never stopped."""
    args = ("sensitivity", str(TINY), "--quantity", "robust", "--inputs",
            "catenary.system_height,operation.aero_coefficient", "--samples", "3", "--seed", "3", "--json")
    whole = presag_script(*args, cwd=tmp_path, env={**os.environ, "XDG_CACHE_HOME": str(tmp_path / "whole")})
    assert whole.returncode == 0, whole.stderr
    data = json.loads(whole.stdout)
    killed_cache = tmp_path / "killed"
    with subprocess.Popen([str(SCRIPT), *args], cwd=tmp_path, env={**os.environ, "XDG_CACHE_HOME": str(killed_cache)},
                          stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL) as process:
        deadline = time.monotonic() + 300.0  # a bound against a hang only; the loop waits on the files
        while len(kept_evaluations(killed_cache)) < 3 and process.poll() is None and time.monotonic() < deadline:
            time.sleep(0.01)
        process.kill()
    kept = {path: path.stat().st_mtime_ns for path in kept_evaluations(killed_cache)}
    assert 3 <= len(kept) < 9, kept
    resumed = presag_script(*args, cwd=tmp_path, env={**os.environ, "XDG_CACHE_HOME": str(killed_cache)})
    assert resumed.returncode == 0, resumed.stderr
    again = json.loads(resumed.stdout)
    assert again["indices"] == data["indices"] and again["design"] == data["design"]
    # as many form-findings; how many were solved and how many read from the form-finding cache depends on
    # where the kill landed (a state the killed run stored is read back by the resumed one), and with it
    # the iteration quantiles, which count the solved ones
    assert again["solver"]["form_findings"] + again["solver"]["cached"] == (
        data["solver"]["form_findings"] + data["solver"]["cached"])
    assert len(kept_evaluations(killed_cache)) == 9
    assert {path: path.stat().st_mtime_ns for path in kept} == kept  # read back, not computed again
    assert f"{len(kept)} of 9 evaluations read back from {killed_cache}" in resumed.stderr


BAD = [
    (["--quantity", "robust", "--inputs", "pantograph.head.mass"],
     ["input pantograph.head.mass", "cannot depend on it", "quasi-static"]),
    (["--quantity", "robust", "--inputs", "catenary.contact_wire.colour"], ["unknown input", "colour"]),
    (["--quantity", "robust", "--range", "catenary.system_height=2:1"], ["--range catenary.system_height", "LOW < HIGH"]),
    (["--quantity", "robust", "--range", "catenary.system_height=0.5:9"], ["9 m", "outside the valid range"]),
    (["--quantity", "robust", "--range", "catenary.system_height"], ["NAME=LOW:HIGH"]),
    (["--quantity", "sigma"], ["--quantity 'sigma' is not one of", "recommendation"]),
    (["--quantity", "dynamic:fast"], ["speeds must be numbers in km/h"]),
    (["--quantity", "robust", "--method", "sobol", "--samples", "100"], ["power of two"]),
    (["--quantity", "robust", "--inputs", "operation.static_force"], ["cannot depend on it", "band of static forces"]),
    (["--quantity", "dynamic-robust", "--inputs", "operation.static_force"],
     ["output dynamic-robust cannot depend on it", "band of static forces"]),
    (["--quantity", "dynamic-robust:50"], ["--quantity 'dynamic-robust:50' is not one of", "dynamic-robust"]),
]


@pytest.mark.parametrize("args,words", BAD, ids=[b[1][0] for b in BAD])
def test_bad_input_ends_with_one_line(presag, tmp_path, args, words):
    result = presag("sensitivity", str(TINY), *args, cwd=tmp_path)
    assert result.returncode == 2, result.stderr
    lines = result.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("presag: error: "), result.stderr
    for word in words:
        assert word in lines[0], f"{word!r} missing from: {lines[0]}"


def test_an_analysis_with_failed_evaluations_ends_with_status_5_and_one_line(presag, tmp_path):
    """System heights down to 0.2 m leave no room for the droppers of the lowest samples (refused, with
    the reason); the spread rests on the others, and says so."""
    result = presag("sensitivity", str(TINY), "--quantity", "robust", "--inputs", "operation.aero_coefficient",
                    "--range", "catenary.system_height=0.2:0.4", "--method", "spread", "--samples", "8", "--seed",
                    "1", "--json", cwd=tmp_path)
    assert result.returncode == 5, result.stderr
    data = json.loads(result.stdout)
    assert data["failed"] == 2 and len(data["failures"]) == 2
    for failure in data["failures"]:
        assert failure["inputs"]["catenary.system_height"] < 0.25  # m, the display unit
        assert "dropper" in failure["reason"] and "100 mm" in failure["reason"]
    assert all((t["samples"], t["dropped"]) == (6, 2) for t in data["indices"])
    assert sum(v is None for row in data["values"] for v in row) == 2 * len(data["indices"])
    last = result.stderr.strip().splitlines()[-1]
    assert re.match(r"presag sensitivity: 2 of 8 evaluations failed \(first: evaluation \d, ", last), last
    assert "the indices rest on 6 of 8 points; kept in " in last
