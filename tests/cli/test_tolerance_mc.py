"""``presag tolerance --monte-carlo`` (in-process, from a folder outside the source tree)."""

from __future__ import annotations

import json

import pytest


def test_monte_carlo_json_and_plot(presag, tmp_path):
    result = presag("tolerance", "--monte-carlo", "--dropper-error", "5", "--height-error", "2", "--samples", "3000",
                    "--seed", "4", "--json", "--plot", "figs", cwd=tmp_path)
    assert result.returncode == 0, result.stderr
    data = json.loads(result.stdout)
    assert data["samples"] == 3000 and data["seed"] == 4
    assert data["dropper_error_mm"] == 5.0 and data["height_error_mm"] == 2.0
    levels = [data[f"p{k}"] for k in (50, 90, 95, 99)]
    for p in levels:
        low, high = p["ci"]
        assert low <= p["value"] <= high
    # errors only add waviness to the minimax design, and the percentiles are ordered
    assert data["nominal_worst_case"] < levels[0]["value"]
    assert [p["value"] for p in levels] == sorted(p["value"] for p in levels)
    low, high = data["s_interval_mm"]
    assert low < data["presag_mm"] < high
    assert (tmp_path / "figs" / "monte_carlo.png").stat().st_size > 10_000


def test_error_free_and_seeded_runs(presag, tmp_path):
    zero = json.loads(presag("tolerance", "--monte-carlo", "--dropper-error", "0", "--samples", "50", "--json",
                             cwd=tmp_path).stdout)
    assert zero["p99"]["value"] == zero["p50"]["value"] == zero["nominal_worst_case"]
    runs = [presag("tolerance", "--monte-carlo", "--dropper-error", "3", "--distribution", "uniform", "--samples",
                   "500", "--seed", "9", "--json", cwd=tmp_path).stdout for _ in range(2)]
    assert runs[0] == runs[1]


def test_find_dropper_tolerance_table(presag, tmp_path):
    result = presag("tolerance", "--monte-carlo", "--find-dropper-tolerance", "--within", "10", "--samples", "2000",
                    cwd=tmp_path)
    assert result.returncode == 0, result.stderr
    assert "Largest dropper error with P95 within 10 %" in result.stdout
    assert "the pre-sag interval within 10 %" in result.stdout


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["--monte-carlo", "--dropper-error", "-2"], "--dropper-error = -2 mm is outside the valid range [0, 100] mm"),
        (["--monte-carlo", "--dropper-error", "5", "--height-error", "abc"], "--height-error = 'abc' is not a number"),
        (["--monte-carlo", "--dropper-error", "5", "--samples", "0"], "--samples = 0 is outside the valid range"),
        (["--monte-carlo"], "--monte-carlo needs --dropper-error MM"),
        (["--dropper-error", "5"], "--dropper-error is an option of the Monte Carlo; add --monte-carlo"),
        (["--monte-carlo", "--find-dropper-tolerance", "--dynamic"], "--find-dropper-tolerance is quasi-static"),
        (["--out", "kept"], "--out is an option of the Monte Carlo; add --monte-carlo --dynamic"),
        (["--monte-carlo", "--dropper-error", "5", "--out", "kept"], "--out keeps the realisations of --dynamic"),
        (["--monte-carlo", "--dynamic", "--dropper-error", "5", "--out", "no/such/folder"],
         "--out no/such/folder: the folder no/such does not exist"),
    ],
)
def test_bad_input_is_one_line(presag, tmp_path, args, message):
    result = presag("tolerance", *args, cwd=tmp_path)
    assert result.returncode == 2
    lines = result.stderr.strip().splitlines()
    assert len(lines) == 1 and message in lines[0], result.stderr
