"""The command line on a stitched system: `presag robust` (quasi-static) and `presag report --quick`
work on st_9.8_stitched_ideal and say that it is stitched (slow: each is a minute on 2 cores)."""

from __future__ import annotations

import json

import pytest

from presag_opt.cli import main


@pytest.mark.slow
def test_robust_says_the_system_is_stitched(capsys):
    assert main(["robust", "st_9.8_stitched_ideal", "--json", "--quiet"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["system"].startswith("stitched: a 14 m stitch wire at 2 kN")
    # the stitched system asks for less pre-sag than the simple one's 55.8 mm (docs/robust.md): 35.0 mm here
    assert 25.0 < data["presag_mm"] < 45.0


@pytest.mark.slow
def test_report_quick_says_the_system_is_stitched(tmp_path, capsys):
    assert main(["report", "st_9.8_stitched_ideal", "--quick", "--out", str(tmp_path), "--quiet"]) == 0
    out = capsys.readouterr().out
    assert "System: st_9.8_stitched_ideal, stitched: a 14 m stitch wire" in out
    html = (tmp_path / "index.html").read_text(encoding="utf-8")
    assert "stitch wires (ST 9,8/9,8 stitched (SYT-type), ideal 60 m spans)" in html


@pytest.mark.slow
def test_dynamic_robust_design_runs_on_the_stitched_system(capsys):
    """A small band (2 x 2 points) through the CLI and the API: the system line, a pre-sag inside its
    own tolerance, the uplift limit kept. On the full case-study band it gives 29.2 mm (docs/stitched.md)."""
    assert main(["robust", "st_9.8_stitched_ideal", "--dynamic", "--grid-points", "2,2", "--min-speed", "50",
                 "--max-speed", "70",
                 "--json", "--quiet"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["system"].startswith("stitched:")
    low, high = data["tolerance_mm"]
    assert low <= data["presag_mm"] <= high
    assert data["uplift_max_mm"] <= data["uplift_limit_mm"]
    assert 15.0 < data["presag_mm"] < 50.0
