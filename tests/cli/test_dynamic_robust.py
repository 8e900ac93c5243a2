"""``--dynamic-robust`` on ``presag recommend``: the dynamic robust design of the case study run in the decision
(slow: several minutes on a shared 2-core machine). The decision logic itself is tested fast in
tests/robust/test_dynamic_decision.py."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path
from types import SimpleNamespace

import pytest

from presag_opt.cli.dynamic_robust import dynamic_robust_summary

SCRIPT = Path(sys.executable).parent / "presag"


@pytest.mark.slow
def test_recommend_with_the_dynamic_robust_design_is_final(tmp_path):
    result = subprocess.run([str(SCRIPT), "recommend", "--dynamic-robust", "--json", "--progress"], capture_output=True,
                            text=True, cwd=tmp_path, timeout=3600)
    assert result.returncode == 0, result.stderr
    data = json.loads(result.stdout)  # pure JSON on stdout; the cost and the progress on stderr
    assert "presag: the dynamic robust design of" in result.stderr and "runs on" in result.stderr
    decision = data["decision"]
    assert decision["status"] == "decided"
    methods = {decision["chosen"]["method"], *(a["method"] for a in decision["alternatives"])}
    assert methods == {"quasi-static Δe rule", "quasi-static robust design", "dynamic robust design"}
    dynamic = data["dynamic_robust"]
    # the case study's dynamic robust design (presag robust --dynamic, 50-90 km/h): 45.1 mm, within the search's
    # 0.5 mm resolution; the chosen S lies inside the dynamic tolerance interval
    assert dynamic["presag_mm"] == pytest.approx(45.1, abs=1.0)
    low, high = dynamic["tolerance_mm"]
    assert low - 1e-6 <= decision["chosen"]["presag_mm"] <= high + 1e-6


def test_the_dynamic_robust_summary_keeps_the_figures_a_designer_reads():
    data = {"presag_mm": 45.1, "presag_rel_permille": 0.75, "tolerance_mm": [28.0, 56.1], "uplift_max_mm": 52.9,
            "reference_span_m": 60.0, "runs_used": 60, "wall_time_s": 240.0, "static_force_N": [70.0, 140.0],
            "speed_kmh": [50.0, 90.0], "curve": "left out"}
    result = SimpleNamespace(where="section A", study=SimpleNamespace(to_dict=lambda: data))
    summary = dynamic_robust_summary(result)
    assert summary["where"] == "section A" and summary["presag_mm"] == 45.1 and "curve" not in summary


@pytest.mark.slow
def test_a_report_with_the_dynamic_robust_design_is_headed_by_the_final_decision(tmp_path):
    result = subprocess.run([str(SCRIPT), "report", "--quick", "--dynamic-robust", "--out", str(tmp_path / "r"),
                             "--json"], capture_output=True, text=True, cwd=tmp_path, timeout=3600)
    assert result.returncode == 0, result.stderr
    data = json.loads(result.stdout)
    assert "presag: the dynamic robust design of" in result.stderr
    methods = {data["decision"]["chosen"]["method"], *(a["method"] for a in data["decision"]["alternatives"])}
    assert "dynamic robust design" in methods and "dynamic_robust" in data
    page = (tmp_path / "r" / "index.html").read_text()
    assert f"{data['presag_mm']:.0f} mm" in page  # the page's headline is the decision made with it
