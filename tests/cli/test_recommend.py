"""``presag empirical`` and ``presag recommend`` (in-process)."""

from __future__ import annotations

import json

import pytest


@pytest.fixture(scope="module")
def case_study_json(presag):
    """``presag recommend --json`` with no other arguments: the paper's case study."""
    run = presag("recommend", "--json")
    assert run.returncode == 0, run.stderr
    return json.loads(run.stdout)


def test_empirical_json_reproduces_table1(presag):
    run = presag("empirical", "--tension", "9.8/9.8", "--span", "60", "--static-force", "140", "--json")
    assert run.returncode == 0, run.stderr
    out = json.loads(run.stdout)
    # The paper's Table 1 row for 9.8/9.8, exactly (values are rounded to the printed digits).
    assert out["printed_as_table1"] == {"e_mid_mm_per_N": 0.765, "presag_mm": [54.0, 75.0], "presag_rel_permille": [0.90, 1.25]}
    assert out["e_mid_mm_per_N"] == pytest.approx(60.0 / (4 * 19.6e3) * 1e3, rel=1e-12)  # eq. 1, exact arithmetic


def test_empirical_table_output(presag):
    run = presag("empirical", "--tension", "7.1/7.1")
    assert run.returncode == 0, run.stderr
    assert "e_mid 1.056 mm/N, S 74–104 mm, S_rel 1.23–1.73 ‰" in run.stdout


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["empirical", "--static-force", "0"], "static_force = 0 N is outside the valid range (0, 1000] N"),
        (["empirical", "--tension", "9.8/abc"], "--tension = '9.8/abc'"),
        (["recommend", "--static-force", "0:140"], "static_force_low = 0 N is outside the valid range (0, 1000] N"),
        (["recommend", "--static-force=-5:140"], "static_force_low = -5 N is outside the valid range"),
        (["recommend", "--static-force", "150:70"], "static_force_low = 150 N is above static_force_high = 70 N"),
        (["recommend", "--max-speed", "345"], "speed = 345 km/h is outside the valid range [0, 344.5"),
        (["recommend", "--method", "max-min"], "method = 'max-min' is not one of mid-mast, delta-e"),
        (["recommend", "--force-levels", "100,150"], "do not cover the mean-force band"),
    ],
)
def test_bad_input_gives_one_line_and_exit_2(presag, args, message):
    run = presag(*args)
    assert run.returncode == 2
    assert run.stdout == ""
    lines = run.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("presag: error: ")
    assert message in lines[0]


def test_recommend_json_has_the_documented_keys(case_study_json):
    out = case_study_json
    for key in ("decision", "robust", "presag_mm", "presag_rel_permille", "presag_rel_range_permille", "fm_band_N",
                "beta_max"):
        assert key in out
    low, high = out["fm_band_N"]
    assert low == pytest.approx(70.0, abs=1e-9) and high == pytest.approx(147.857, abs=1e-9)  # exact arithmetic
    assert out["beta_max"] == pytest.approx(0.26, abs=0.01)  # the paper's value, printed to 0.01
    decision = out["decision"]
    assert decision["validity"]["verdict"] == "holds" and decision["status"] == "provisional"
    assert decision["basis"] == "quasi-static robust design"
    assert decision["presag_mm"] == pytest.approx(out["robust"]["presag_mm"], rel=1e-12)
    assert decision["not_checked"] == ["validity_sweep", "dynamic_robust", "installation_monte_carlo"]
    assert any("--dynamic-robust" in text for text in decision["not_checked_text"])
    r_low, r_high = out["presag_rel_range_permille"]
    assert 0.0 < r_low < out["presag_rel_permille"] < r_high
    assert out["presag_mm"] == pytest.approx(out["presag_rel_permille"] * 60.0, rel=1e-12)  # ‰ × m = mm
    assert [lay["layout"] for lay in out["layouts"]] == ["ideal", "mixed"]
    assert len(out["layouts"][1]["spans"]) == 29  # 31 spans less the two end spans


def test_recommend_table_and_plot(presag, tmp_path):
    figures = tmp_path / "figs"
    run = presag("recommend", "--models", "st_9.8_ideal", "--method", "mid-mast", "--plot", str(figures))
    assert run.returncode == 0, run.stderr
    fig5a = figures / "presag_against_force.png"
    for text in ("Pre-sag to build (provisional):", "margins:", "Validity: limit β = 0.35–0.40, 121–138 km/h",
                 "S = F_m·(e_mid − e_mast)", "F_m 70.0–147.9 N", "β_max = 0.26", f"Plot saved to {fig5a}"):
        assert text in run.stdout
    assert run.stdout.index("Pre-sag to build") < run.stdout.index("Quasi-static rule")  # the decision first
    assert fig5a.stat().st_size > 10_000  # a rendered figure, not an empty file


@pytest.mark.slow
def test_recommend_compare_paper(presag, tmp_path):
    run = presag("recommend", "--compare-paper", "--plot", str(tmp_path), "--json")
    fig5b = tmp_path / "single_curve_error.png"
    assert run.returncode == 0, run.stderr
    rows = {r["item"]: r for r in json.loads(run.stdout)["paper_comparison"]}
    assert rows["Table 1 9.8/9.8 S_rel low"]["difference"] == 0.0
    for item in ("Table 2 7.1/7.1 S delta-e", "S_rel mixed high (delta-e)", "Fig. 5b error at 179 N, 70 mm geometry"):
        assert item in rows
    assert fig5b.stat().st_size > 10_000
