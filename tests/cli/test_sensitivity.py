"""``presag sensitivity`` (in-process), on a tiny case (four 30 m spans)."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

TINY = Path(__file__).parent / "models" / "tiny_case.toml"


def test_morris_on_the_robust_output_json_plot_and_cost_announcement(presag, tmp_path):
    args = ("sensitivity", str(TINY), "--quantity", "robust", "--inputs",
            "catenary.system_height,operation.aero_coefficient", "--samples", "2", "--seed", "3", "--json")
    result = presag(*args, "--plot", "figs", cwd=tmp_path)
    assert result.returncode == 0, result.stderr
    data = json.loads(result.stdout)  # --json: stdout is one JSON object, nothing else
    assert data["evaluations"] == 2 * (2 + 1)  # r (k + 1)
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
