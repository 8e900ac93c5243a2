"""The design report (``presag_opt.report.content``, written by ``presag_opt.report.html``): the content of
the case-study report and the page in a real headless Chromium (no console errors, every figure
loaded; tier docs). One file, so that the report is written once per test run (pytest-xdist hands out
whole files); the HTML pieces alone are tested in ``test_html.py``, the command's refusals in
``tests/cli/test_report.py``."""

from __future__ import annotations

import base64
import json
import re

import pytest

from presag_opt.errors import ModelError
from presag_opt.report.content import design_report
from presag_opt.system.loader import model_entries


def test_report_is_self_contained_and_has_every_section(case_study_report):
    folder, summary = case_study_report
    page = (folder / "index.html").read_text(encoding="utf-8")
    assert [p.name for p in folder.iterdir()] == ["index.html"]
    for section in ("summary", "recommendation", "robust", "elasticity", "validity", "uplift", "inputs", "assumed"):
        assert f"id='{section}'" in page, section
    # no scripts, no files or addresses to fetch: every image is embedded
    assert "<script" not in page
    sources = re.findall(r'src="([^"]*)"', page)
    assert len(sources) == 6 and all(s.startswith("data:image/png;base64,") for s in sources)
    assert "Draft (<code>--quick</code>)" in page


EXPECTED_FIGURES = {"fig-presag", "fig-waviness", "fig-elasticity-0", "fig-elasticity-1", "fig-validity", "fig-uplift"}
"""Figure ids of the case-study report: Fig. 5a, waviness, elasticity of the ideal and the mixed layout,
the validity range (Fig. 7) and the steady-arm uplift."""

FIGURES = """JSON.stringify([...document.querySelectorAll('figure')].map(f => {
  const img = f.querySelector('img');
  return {id: f.id, complete: img !== null && img.complete, width: img ? img.naturalWidth : 0,
          height: img ? img.naturalHeight : 0};
}))"""


@pytest.mark.docs
def test_report_renders_without_console_errors_and_every_figure_loads(case_study_report, chromium, tmp_path):
    folder, _ = case_study_report
    for domain in ("Page", "Runtime", "Log"):
        chromium.call(f"{domain}.enable", session=True)
    chromium.call("Emulation.setDeviceMetricsOverride", session=True, width=1200, height=900, deviceScaleFactor=1,
                  mobile=False)
    chromium.call("Page.navigate", session=True, url=(folder / "index.html").as_uri())
    chromium.wait_for("Page.loadEventFired")
    figures = json.loads(chromium.call("Runtime.evaluate", session=True, expression=FIGURES,
                                       returnByValue=True)["result"]["value"])
    shot = chromium.call("Page.captureScreenshot", session=True, format="png", captureBeyondViewport=True)
    (tmp_path / "report.png").write_bytes(base64.b64decode(shot["data"]))

    assert not chromium.console_errors()
    assert {f["id"] for f in figures} == EXPECTED_FIGURES
    assert all(f["complete"] and f["width"] > 0 and f["height"] > 0 for f in figures), figures
    assert (tmp_path / "report.png").stat().st_size > 10_000  # a page was drawn, not an empty frame


def test_report_states_the_numbers_of_its_summary(case_study_report):
    folder, summary = case_study_report
    page = (folder / "index.html").read_text(encoding="utf-8")
    decision = summary["decision"]
    assert decision["headline"] in page  # the page is headed by the decision the command printed
    assert page.index("id='decision'") < page.index("id='summary'")
    assert decision["validity"]["sentence"] in page.replace("&#x27;", "'")
    # what the report builds keeps its margins to every interval in force (or says it cannot)
    for interval in decision["intervals"]:
        if interval["in_force"] and decision["status"] != "tolerance-bound":
            assert min(interval["margins_mm"]) >= decision["crew_tolerance_mm"] - 1e-9
    # the quick sweep's lowest speed is the band's top: it is indicative, the paper's limit stays in force
    assert decision["validity"]["from_sweep"] is False and "indicative" in decision["validity"]["note"]
    assert summary["quick"] is True and summary["validity_source"].startswith("reduced sweep")


def test_report_lists_every_input_with_provenance_and_every_assumed_value(case_study_report):
    folder, _ = case_study_report
    page = (folder / "index.html").read_text(encoding="utf-8")
    inputs, assumed = page.split("id='inputs'")[1].split("id='assumed'")
    entries = [*model_entries("st_9.8_ideal"), *model_entries("st_9.8_mixed"),
               *model_entries("case_study_2mass_friction", "pantographs")]
    for entry in entries:
        assert f"<td>{entry.file}</td><td>{entry.key}</td>" in inputs, entry.key
    for entry in (e for e in entries if e.source == "assumed"):
        assert f"<td>{entry.file}</td><td>{entry.key}</td>" in assumed, entry.key
    assert all(f"<td>{e.file}</td><td>{e.key}</td>" not in assumed for e in entries if e.source != "assumed")
    assert "tolerance interval loss" in assumed and "reduced validity sweep" in assumed
    assert "crew&#x27;s build tolerance" in assumed


def test_a_missing_study_store_is_refused_before_any_work(tmp_path):
    with pytest.raises(ModelError, match="no such study store"):
        design_report(study=tmp_path / "nothere.nc")
