"""``presag robust`` and ``presag tolerance`` (in-process, from a folder outside the source tree)."""

from __future__ import annotations

import json
from pathlib import Path

import pytest


def test_robust_json_and_plot(presag, tmp_path):
    result = presag("robust", "--json", "--plot", "figs", cwd=tmp_path)
    assert result.returncode == 0, result.stderr
    data = json.loads(result.stdout)
    # the band's decision heads it, the one `presag recommend --models st_9.8_ideal` makes
    decision = data["decision"]
    assert decision["basis"] == "quasi-static robust design" and decision["status"] == "provisional"
    assert decision["presag_mm"] == pytest.approx(data["presag_mm"], rel=1e-12)
    for key in ("presag_mm", "worst_case_waviness_mm", "nominal_presag_mm", "nominal_worst_case_waviness_mm", "tolerance_mm"):
        assert key in data
    low, high = data["tolerance_mm"]
    assert low < data["presag_mm"] < high
    assert data["worst_case_waviness_mm"] <= data["nominal_worst_case_waviness_mm"]
    assert data["fm_band_N"] == pytest.approx([70.0, 147.857], abs=1e-9)  # F_stat 70–140 N up to 90 km/h
    # the robust pre-sag lies inside the paper's recommended range for ideal spans, 0.68–1.35 ‰
    assert 0.68 <= data["presag_rel_permille"] <= 1.35
    assert (tmp_path / "figs" / "waviness.png").stat().st_size > 10_000


def test_robust_per_dropper_cvar_table(presag, tmp_path):
    result = presag("robust", "--shape", "per-dropper", "--risk", "cvar:0.9", cwd=tmp_path)
    assert result.returncode == 0, result.stderr
    assert "Dropper depths [mm]" in result.stdout and "cvar:0.90" in result.stdout


def test_tolerance_json(presag, tmp_path):
    result = presag("tolerance", "--static-force", "90:130", "--max-speed", "0", "--within", "5%", "--json",
                    cwd=tmp_path)
    assert result.returncode == 0, result.stderr
    data = json.loads(result.stdout)
    assert data["tolerance_within"] == pytest.approx(0.05)
    assert data["fm_band_N"] == pytest.approx([90.0, 130.0], abs=1e-12)
    assert data["tolerance_mm"][0] < data["presag_mm"] < data["tolerance_mm"][1]
    # each interval belongs to the design printed beside it (issue 12: the nominal Δe design has none)
    low, high = data["centre_optimum_tolerance_mm"]
    assert low < data["centre_optimum_presag_mm"] < high
    assert "nominal_tolerance_mm" not in data


@pytest.mark.parametrize("args,words", [
    (["robust", "--static-force", "148:70"], "static_force_low = 148 N is above static_force_high = 70 N"),
    (["robust", "--uplift-limit", "0.1"], "uplift_limit = 0.1 mm is outside the valid range [1, 1000] mm"),
    (["robust", "--risk", "var"], "is not one of"),
    (["tolerance", "--within", "abc"], "--within"),
    (["robust", "--shape", "per-dropper", "--step-mm", "2"], None),
])
def test_bad_arguments(presag, tmp_path, args, words):
    result = presag(*args, cwd=tmp_path)
    if words is None:  # a valid call, as a control
        assert result.returncode == 0, result.stderr
        return
    assert result.returncode == 2
    assert "Traceback" not in result.stderr
    assert words in result.stderr.strip().splitlines()[-1], result.stderr


SHORT_SPANS = Path(__file__).parents[1] / "robust" / "models" / "st_9.8_six_short_spans.toml"


@pytest.mark.slow
def test_robust_dynamic_json_table_and_plot(presag, tmp_path):
    args = ("robust", "--dynamic", str(SHORT_SPANS), "--static-force", "80:140", "--min-speed", "120",
            "--max-speed", "140", "--grid-points", "2,2")
    result = presag(*args, "--json", "--plot", "figs", cwd=tmp_path)
    assert result.returncode == 0, result.stderr
    data = json.loads(result.stdout)
    for key in ("presag_mm", "worst_case_objective", "objective", "runs_used", "tolerance_mm",
                "quasi_static_presag_mm", "uplift_max_mm"):
        assert key in data, key
    low, high = data["tolerance_mm"]
    assert low <= data["presag_mm"] <= high
    assert data["runs_used"] == 4 * data["presags_simulated"]
    assert data["objective"] == data["worst_case_objective"]  # minimax
    assert data["uplift_max_mm"] <= data["uplift_limit_mm"]
    methods = {m["method"]: m for m in data["methods"]}
    dynamic, quasi_static = methods["dynamic robust design"], methods["quasi-static robust design"]
    assert dynamic["worst_case_objective"] <= quasi_static["worst_case_objective"]
    assert quasi_static["presag_mm"] == data["quasi_static_presag_mm"]
    assert data["decision"]["status"] in ("decided", "tolerance-bound", "uplift-bound")  # the dynamic tolerance known
    assert (tmp_path / "figs" / "dynamic_objective.png").stat().st_size > 10_000
    # the quasi-static design is the one `presag robust` gives for the same band
    quasi = json.loads(presag("robust", str(SHORT_SPANS), *args[3:9], "--json", cwd=tmp_path).stdout)
    assert quasi["presag_mm"] == pytest.approx(data["quasi_static_presag_mm"], rel=1e-9)
    assert quasi["decision"]["validity"]["sentence"] == data["decision"]["validity"]["sentence"]
    table = presag(*args, "--risk", "mean", cwd=tmp_path)
    assert table.returncode == 0, table.stderr
    assert "Pre-sag to build" in table.stdout and "Dynamic tolerance" in table.stdout


SHORT_MODEL = Path(__file__).parents[1] / "studies" / "models" / "st_9.8_short.toml"


@pytest.mark.slow  # three designs simulated at 160 km/h; the check itself: tests/robust/test_dynamic_check.py
def test_robust_per_dropper_with_a_dynamic_check(presag, tmp_path):
    """``--check-speeds``: the nominal Δe design, the parabola of the LP and the per-dropper profile
    built into the catenary, simulated at 105 N and 160 km/h (β 0.46, above the quasi-static limit),
    in the JSON. (The split of the runs by regime is ``tests/robust/test_dynamic_check.py``'s.)"""
    result = presag("robust", str(SHORT_MODEL), "--shape", "per-dropper", "--check-speeds", "160",
                    "--check-forces", "105", "--json", "--quiet", cwd=tmp_path)
    assert result.returncode == 0, result.stderr
    data = json.loads(result.stdout)
    rows = data["dynamic_check"]
    assert [(r["design"], r["regime"]) for r in rows] == [
        (design, "beta >= 0.4") for design in ("Δe rule", "robust parabola (same LP)", "robust per-dropper")]
    for r in rows:
        assert r["runs"] == 1 and r["worst_sigma_over_Fm"] == r["mean_sigma_over_Fm"]
        assert 0.01 < r["worst_sigma_over_Fm"] < 0.5 and 0.0 < r["uplift_max_mm"] < 200.0
    by_design = {r["design"]: r["presag_mm"] for r in rows}
    assert by_design["Δe rule"] == pytest.approx(data["nominal_presag_mm"], abs=0.05)
    assert by_design["robust per-dropper"] != by_design["robust parabola (same LP)"]
    # the three designs differ, and so do their runs
    assert len({r["worst_sigma_over_Fm"] for r in rows}) == 3


@pytest.mark.parametrize("args, words", [
    (("--check-forces", "105"), "add --check-speeds"),
    (("--check-speeds", "400"), "--check-speeds 400 km/h is outside the valid range"),
    (("--dynamic", "--check-speeds", "90"), "--check-speeds is an option of the quasi-static design"),
    (("--pantograph", "case_study_2mass_friction"), "add --dynamic"),
])
def test_dynamic_check_bad_options(presag, tmp_path, args, words):
    result = presag("robust", *args, cwd=tmp_path)
    assert result.returncode == 2, result.stderr
    assert "Traceback" not in result.stderr and words in result.stderr.strip().splitlines()[-1]
