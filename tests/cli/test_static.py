"""``presag form-find`` and ``presag elasticity`` (in-process, from a folder outside the source tree)."""

from __future__ import annotations

import json

import pytest


def test_form_find_prints_the_dropper_schedule(presag, tmp_path):
    result = presag("form-find", "st_9.8_ideal", "--span", "6", cwd=tmp_path)
    assert result.returncode == 0, result.stderr
    assert "Dropper schedule" in result.stdout
    assert result.stdout.count("\n   6 ") == 7  # seven droppers in span 6


def test_form_find_json(presag, tmp_path):
    result = presag("form-find", "st_9.8_ideal", "--span", "6", "--json", cwd=tmp_path)
    assert result.returncode == 0, result.stderr
    data = json.loads(result.stdout)
    rows = data["droppers"]
    assert [r["position_m"] for r in rows] == pytest.approx([4.5, 13.0, 21.5, 30.0, 38.5, 47.0, 55.5])
    lengths = [r["length_mm"] for r in rows]
    assert lengths == lengths[::-1]  # symmetric ideal span
    assert all(r["force_N"] > 0 for r in rows)
    assert len(data["steady_arms"]) == 11
    stats = data["form_finding"]  # the solver's statistics, as data (those of the original solve if cached)
    assert stats["passes"] == 1 and 1 <= stats["ipopt_iterations"] <= 10 and stats["restarts"] == 0
    assert stats["seconds"] > 0.0 and isinstance(stats["cached"], bool)


def test_elasticity_json_has_the_documented_keys(presag, tmp_path):
    result = presag("elasticity", "st_9.8_ideal", "--forces", "100", "--step", "2", "--linear", "--json", cwd=tmp_path)
    assert result.returncode == 0, result.stderr
    data = json.loads(result.stdout)
    assert data["span"] == 6 and data["x_m"][0] == 0.0 and data["x_m"][-1] == 60.0
    forces = [c["force_N"] for c in data["curves"]]
    assert forces == [100.0, None]
    for curve in data["curves"]:
        for key in ("elasticity_mm_per_N", "e_mid_mm_per_N", "e_mast_mm_per_N", "e_max_mm_per_N", "e_min_mm_per_N"):
            assert key in curve
        # e_mid of ST 9,8/9,8 is near the empirical 0.765 mm/N (0.9…1.4 ×)
        assert 0.9 * 0.765 < curve["e_mid_mm_per_N"] < 1.4 * 0.765


def test_elasticity_table_and_plot(presag, tmp_path):
    result = presag("elasticity", "--forces", "100", "--step", "3", "--plot", "curves", cwd=tmp_path)
    assert result.returncode == 0, result.stderr
    assert "e_mid" in result.stdout and "100" in result.stdout
    assert (tmp_path / "curves" / "elasticity.png").stat().st_size > 10_000


@pytest.mark.parametrize("args,words", [
    (["elasticity", "--span", "12"], "--span = 12 is outside the valid range [1, 10]"),
    (["elasticity", "--forces", "-5"], "force = -5 N"),
    (["form-find", "no_such_model"], "no_such_model"),
])
def test_bad_arguments_end_with_one_line_and_status_2(presag, tmp_path, args, words):
    result = presag(*args, cwd=tmp_path)
    assert result.returncode == 2
    assert "Traceback" not in result.stderr
    lines = result.stderr.strip().splitlines()
    assert len(lines) == 1 and words in lines[0], result.stderr
