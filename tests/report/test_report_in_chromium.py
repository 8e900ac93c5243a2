"""The case-study report opened in a real headless Chromium: no console errors, every figure loaded."""

from __future__ import annotations

import base64
import json

EXPECTED_FIGURES = {"fig-presag", "fig-waviness", "fig-elasticity-0", "fig-elasticity-1", "fig-validity", "fig-uplift"}
"""Figure ids of the case-study report: Fig. 5a, waviness, elasticity of the ideal and the mixed layout,
the validity range (Fig. 7) and the steady-arm uplift."""

FIGURES = """JSON.stringify([...document.querySelectorAll('figure')].map(f => {
  const img = f.querySelector('img');
  return {id: f.id, complete: img !== null && img.complete, width: img ? img.naturalWidth : 0,
          height: img ? img.naturalHeight : 0};
}))"""


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

    errors = [e for e in chromium.events if
              (e.get("method") == "Runtime.consoleAPICalled" and e["params"]["type"] in ("error", "assert"))
              or e.get("method") == "Runtime.exceptionThrown"
              or (e.get("method") == "Log.entryAdded" and e["params"]["entry"]["level"] == "error")]
    assert not errors
    assert {f["id"] for f in figures} == EXPECTED_FIGURES
    assert all(f["complete"] and f["width"] > 0 and f["height"] > 0 for f in figures), figures
    assert (tmp_path / "report.png").stat().st_size > 10_000  # a page was drawn, not an empty frame
