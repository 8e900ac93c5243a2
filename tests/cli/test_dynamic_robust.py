"""``--dynamic-robust`` on ``presag recommend`` and ``presag report``: the dynamic robust design of the case
study run in the one decision (slow: minutes on a shared 2-core machine). The decision logic itself is
tested fast in tests/design/test_decision.py, its agreement across commands in tests/pipeline/."""

from __future__ import annotations

import json

import pytest


@pytest.mark.slow
def test_recommend_with_the_dynamic_robust_design_is_final(presag_script, tmp_path):
    result = presag_script("recommend", "--dynamic-robust", "--json", "--progress", cwd=tmp_path, timeout=3600)
    assert result.returncode == 0, result.stderr
    data = json.loads(result.stdout)  # pure JSON on stdout; the cost and the progress on stderr
    assert "presag: the dynamic robust design of" in result.stderr and "runs on" in result.stderr
    decision = data["decision"]
    assert decision["status"] == "decided"
    assert {a["method"] for a in decision["answers"]} == {"quasi-static Δe rule", "quasi-static robust design",
                                                           "dynamic robust design"}
    # the case study's dynamic robust design (50–90 km/h): 45.1 mm, within the search's 0.5 mm resolution;
    # the pre-sag built keeps at least the crew's tolerance to every interval in force
    assert data["dynamic_robust"]["presag_mm"] == pytest.approx(45.1, abs=1.0)
    for interval in decision["intervals"]:
        assert interval["in_force"] and min(interval["margins_mm"]) >= decision["crew_tolerance_mm"] - 1e-9


@pytest.mark.slow
def test_a_report_with_the_dynamic_robust_design_is_headed_by_the_final_decision(presag_script, tmp_path):
    result = presag_script("report", "--quick", "--dynamic-robust", "--out", str(tmp_path / "r"), "--json",
                           cwd=tmp_path, timeout=3600)
    assert result.returncode == 0, result.stderr
    data = json.loads(result.stdout)
    assert "presag: the dynamic robust design of" in result.stderr
    assert "dynamic robust design" in {a["method"] for a in data["decision"]["answers"]}
    page = (tmp_path / "r" / "index.html").read_text()
    assert data["decision"]["headline"] in page and "id='dynamic'" in page
