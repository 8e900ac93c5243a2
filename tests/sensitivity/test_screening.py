"""The shipped screening of the recommendation and the report's "what this answer depends on" section."""

from __future__ import annotations

import json
from importlib import resources

from presag_opt.report.html import _dependence_section
from presag_opt.sensitivity.screening import SHIPPED, recommendation_dependence


def test_the_shipped_screening_is_read_ranked_with_its_ranges():
    data = json.loads(resources.files("presag_opt.sensitivity").joinpath("data", SHIPPED).read_text())
    dep = recommendation_dependence(top=5)
    assert dep is not None and dep.unit == "‰" and len(dep.rows) == 5
    mu = [row[1] for row in dep.rows]
    assert mu == sorted(mu, reverse=True) and dep.rows[0][2] == 1.0
    assert all(row[3] for row in dep.rows)  # every input with the range it was varied over
    assert f"r = {data['samples']}" in dep.note and "built-in" in dep.note


def test_the_report_section_lists_the_top_inputs():
    html = _dependence_section()
    assert "What this answer depends on" in html
    assert recommendation_dependence().rows[0][0] in html
