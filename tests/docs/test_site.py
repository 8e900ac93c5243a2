"""The documentation site: built with warnings as errors and every cross-reference into the project
checked (``-W --keep-going -n``), every local link of the built pages resolving to a file and, where it
names one, an anchor, and the site in a real headless Chromium, served over local HTTP: no console errors on
the main pages, and the search page finding a known word. One file, so that the site is built once per test run
(pytest-xdist hands out whole files); tier docs, but for the link check's own test.

The notebooks are rendered without outputs here: executing them again would double the suite's
longest tests (``tests/notebooks/`` runs each in fast mode); ``PRESAG_DOCS_EXECUTE=1`` builds the site
with them executed (docs/project/contributing.md).
"""

from __future__ import annotations

import base64
import functools
import json
import os
import subprocess
import sys
import threading
import time
from html.parser import HTMLParser
from http.server import SimpleHTTPRequestHandler, ThreadingHTTPServer
from pathlib import Path
from urllib.parse import unquote, urlsplit

import pytest

DOCS = Path(__file__).resolve().parents[2] / "docs"


@pytest.fixture(scope="session")
def site(tmp_path_factory) -> Path:
    """The HTML site built from ``docs/`` into a fresh folder; the build's log must hold no warning."""
    out = tmp_path_factory.mktemp("site")
    env = {**os.environ, "PRESAG_DOCS_EXECUTE": "0"}
    result = subprocess.run(
        [sys.executable, "-m", "sphinx", "-W", "--keep-going", "-n", "-q", "-b", "html",
         "-d", str(out / "doctrees"), str(DOCS), str(out / "html")],
        capture_output=True, text=True, timeout=1200, env=env, check=False,
    )
    assert result.returncode == 0, result.stderr[-5000:]
    assert "WARNING" not in result.stderr and "ERROR" not in result.stderr, result.stderr[-5000:]
    return out / "html"


class _Links(HTMLParser):
    """Every href and src of a page, and every id and name it defines."""

    def __init__(self) -> None:
        super().__init__()
        self.links: list[str] = []
        self.anchors: set[str] = set()

    def handle_starttag(self, tag: str, attrs: list[tuple[str, str | None]]) -> None:
        for key, value in attrs:
            if value is None:
                continue
            if key in ("href", "src"):
                self.links.append(value)
            elif key in ("id", "name"):
                self.anchors.add(value)


def _parse(path: Path) -> _Links:
    parser = _Links()
    parser.feed(path.read_text(encoding="utf-8"))
    return parser


def local_link_problems(root: Path) -> list[str]:
    """Links of the built pages to a missing file or a missing anchor (external addresses skipped;
    ``_static/`` holds the theme's files, templates among them, not pages)."""
    pages = {path: _parse(path) for path in root.rglob("*.html") if "_static" not in path.relative_to(root).parts}
    problems = []
    for page, parsed in pages.items():
        for link in parsed.links:
            parts = urlsplit(link)
            if parts.scheme or parts.netloc or link.startswith(("mailto:", "javascript:", "data:")):
                continue
            target = (page.parent / unquote(parts.path)).resolve() if parts.path else page
            if target.is_dir():
                target = target / "index.html"
            if not target.exists():
                problems.append(f"{page.relative_to(root)}: {link} (no such file)")
            elif parts.fragment and target.suffix == ".html":
                anchors = pages[target].anchors if target in pages else _parse(target).anchors
                if unquote(parts.fragment) not in anchors:
                    problems.append(f"{page.relative_to(root)}: {link} (no such anchor)")
    return problems


@pytest.mark.docs
def test_the_site_has_every_part(site):
    for page in ("index.html", "getting_started.html", "guide/index.html", "guide/physics.html",
                 "reference/cli.html", "reference/glossary.html", "reference/validation.html", "api/index.html",
                 "project/changelog.html", "testing.html", "assumptions.html", "search.html"):
        assert (site / page).is_file(), page
    api = {p.stem for p in (site / "api" / "generated").glob("*.html")}
    assert {"presag_opt", "presag_opt.robust", "presag_opt.robust.tolerance", "presag_opt.dynamics.batch"} <= api
    notebooks = {p.stem for p in (site / "notebooks").glob("*.html")}
    assert {p.stem for p in (DOCS.parent / "notebooks").glob("*.ipynb")} == notebooks


@pytest.mark.docs
def test_the_cli_reference_lists_every_verb_and_option(site):
    sys.path.insert(0, str(DOCS / "_ext"))
    try:
        from presag_cli import commands
    finally:
        sys.path.remove(str(DOCS / "_ext"))
    page = (site / "reference" / "cli.html").read_text(encoding="utf-8")
    listed = commands()
    assert {"presag recommend", "presag robust", "presag report", "presag simulate"} <= {c.name for c in listed}
    for command in listed:
        assert f'id="{command.name.replace(" ", "-")}"' in page, command.name
        for option in command.options:
            assert option.names.split(", ")[-1] in page, (command.name, option.names)


@pytest.mark.docs
def test_every_local_link_resolves(site):
    problems = local_link_problems(site)
    assert not problems, "\n".join(problems)


def test_the_link_check_finds_a_broken_link_and_a_broken_anchor(tmp_path):
    (tmp_path / "a.html").write_text('<a href="b.html#here">x</a><a href="b.html#gone">y</a>'
                                     '<a href="missing.html">z</a><a href="https://example.org/x">w</a>')
    (tmp_path / "b.html").write_text('<h1 id="here">b</h1>')
    assert local_link_problems(tmp_path) == ["a.html: b.html#gone (no such anchor)",
                                             "a.html: missing.html (no such file)"]


@pytest.fixture
def served(site):
    """The site's address on a local HTTP server for the test's duration: the pages as a hosted site
    serves them (from ``file://`` Chromium refuses the fetches the search page makes for its result
    summaries, an error no reader of the hosted site sees)."""

    class Quiet(SimpleHTTPRequestHandler):
        def log_message(self, *args):  # no request log on stderr
            pass

    server = ThreadingHTTPServer(("127.0.0.1", 0), functools.partial(Quiet, directory=str(site)))
    thread = threading.Thread(target=server.serve_forever, daemon=True)
    thread.start()
    try:
        yield f"http://127.0.0.1:{server.server_address[1]}"
    finally:
        server.shutdown()
        server.server_close()


def _open(chromium, url: str) -> None:
    """Open a page and wait until its network has been idle (the browser's ``networkIdle`` lifecycle
    event of this navigation: every request the page made, the late ones included, has been answered),
    so that every console entry it causes is in :attr:`Chromium.events` when this returns."""
    chromium.events.clear()
    loader = chromium.call("Page.navigate", session=True, url=url)["loaderId"]
    chromium.wait_for("Page.lifecycleEvent", lambda p: p["name"] == "networkIdle" and p["loaderId"] == loader)


def _evaluate(chromium, expression: str):
    return chromium.call("Runtime.evaluate", session=True, expression=expression, returnByValue=True)["result"].get("value")


SEARCH_HITS = "JSON.stringify([...document.querySelectorAll('#search-results li a')].map(a => a.textContent))"


@pytest.mark.docs
def test_the_site_opens_without_console_errors_and_its_search_finds_a_word(served, chromium, tmp_path):
    for domain in ("Page", "Runtime", "Log"):
        chromium.call(f"{domain}.enable", session=True)
    chromium.call("Page.setLifecycleEventsEnabled", session=True, enabled=True)
    chromium.call("Emulation.setDeviceMetricsOverride", session=True, width=1280, height=900, deviceScaleFactor=1,
                  mobile=False)
    errors = {}
    for page in ("index.html", "getting_started.html", "api/generated/presag_opt.robust.html", "reference/cli.html",
                 "reference/glossary.html"):
        _open(chromium, f"{served}/{page}")
        errors[page] = chromium.console_errors()
    shot = chromium.call("Page.captureScreenshot", session=True, format="png")
    (tmp_path / "glossary.png").write_bytes(base64.b64decode(shot["data"]))

    _open(chromium, f"{served}/search.html?q=elasticity")
    deadline = time.monotonic() + 60
    hits = []
    while time.monotonic() < deadline and not hits:
        hits = json.loads(_evaluate(chromium, SEARCH_HITS) or "[]")
        time.sleep(0.2)
    errors["search.html"] = chromium.console_errors()
    # the failure names each error's page and text (a console entry's ``text``, else the whole event)
    assert not any(errors.values()), {page: [e["params"].get("entry", e["params"]).get("text", e) for e in seen]
                                      for page, seen in errors.items() if seen}
    assert hits, "the search for 'elasticity' found nothing"
    assert any("lasticity" in hit for hit in hits), hits
    assert (tmp_path / "glossary.png").stat().st_size > 10_000  # a page was drawn


@pytest.mark.slow
def test_the_site_builds_with_the_notebooks_executed_in_fast_mode(tmp_path):
    """The full build (``PRESAG_DOCS_EXECUTE=1``): every notebook executed in fast mode and rendered
    with its outputs; 6 min 52 s on the 2-core machine under a load average near 18."""
    env = {**os.environ, "PRESAG_DOCS_EXECUTE": "1", "PRESAG_NOTEBOOK_MODE": "fast"}
    result = subprocess.run(
        [sys.executable, "-m", "sphinx", "-W", "--keep-going", "-n", "-q", "-b", "html",
         "-d", str(tmp_path / "doctrees"), str(DOCS), str(tmp_path / "html")],
        capture_output=True, text=True, timeout=3600, env=env, check=False,
    )
    assert result.returncode == 0, result.stderr[-5000:]
    for page in (tmp_path / "html" / "notebooks").glob("*.html"):
        assert "<img" in page.read_text(encoding="utf-8"), f"{page.name}: no figure rendered"
