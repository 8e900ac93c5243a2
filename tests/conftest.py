"""Shared fixtures: form-found states and elasticity sections are expensive (1–5 s), so each is built
once per session; and a headless Chromium driven over the DevTools protocol on a pipe
(``--remote-debugging-pipe``: the standard library is all it needs), which opens the HTML report
(tests/report/) and the documentation site (tests/docs/)."""

from __future__ import annotations

import fcntl
import json
import os
import select
import shutil
import signal
import subprocess
import sys
import time
import warnings
from pathlib import Path

import pytest

from presag_opt.design import recommend, section_elasticity
from presag_opt.static.form_finding import form_find
from presag_opt.system.catenary import SpanLayout
from presag_opt.system.loader import load_catenary


@pytest.fixture(scope="session")
def st98():
    """Form-found ST 9,8/9,8 ideal section (10 × 60 m)."""
    return form_find(load_catenary("st_9.8_ideal"))


@pytest.fixture(scope="session")
def st71():
    """Form-found ST 7,1/7,1 ideal section (10 × 60 m)."""
    return form_find(load_catenary("st_7.1_ideal"))


@pytest.fixture(scope="session")
def st98_mixed():
    """Form-found ST 9,8/9,8 31-span representative section."""
    return form_find(load_catenary("st_9.8_mixed"))


FIG5B_LEVELS = (50.0, 100.0, 150.0, 200.0)


@pytest.fixture(scope="session")
def ideal98(st98):
    """ST 9,8/9,8 central span at 50–200 N (nominal 30 mm geometry)."""
    return section_elasticity(st98, force_levels=FIG5B_LEVELS)


@pytest.fixture(scope="session")
def ideal71(st71):
    """ST 7,1/7,1 central span at 100 and 150 N (they bracket Table 2's 140 N)."""
    return section_elasticity(st71, force_levels=(100.0, 150.0))


@pytest.fixture(scope="session")
def ideal98_70mm():
    """ST 9,8/9,8 central span at 50–200 N on the 70 mm geometry (Fig. 5b)."""
    return section_elasticity(load_catenary("st_9.8_ideal").with_presag(0.070 / 60.0), force_levels=FIG5B_LEVELS)


@pytest.fixture(scope="session")
def short_mixed():
    """A five-span mixed section cut from the stand-in span list (cheap to form-find)."""
    catenary = load_catenary("st_9.8_mixed")
    return catenary.with_layout(SpanLayout(span_lengths=(45.0, 58.4, 24.7, 40.7, 52.0), label="test: five spans"))


@pytest.fixture(scope="session")
def short_recommendation(short_mixed):
    """The case-study band on ideal ST 9,8/9,8 spans and the five-span mixed section, recomputed once."""
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # the case-study band must not warn on these layouts
        return recommend(models=[load_catenary("st_9.8_ideal"), short_mixed], recompute_at_recommended=True)


def _run_folder(tmp_path_factory) -> Path:
    """The folder of this test run: shared by all pytest-xdist workers of the run (the parent of each
    worker's base folder), the base folder itself without xdist."""
    base = tmp_path_factory.getbasetemp()
    return base.parent if os.environ.get("PYTEST_XDIST_WORKER") else base


@pytest.fixture(scope="session", autouse=True)
def _cache_in_a_session_folder(tmp_path_factory):
    """Commands run by the tests cache form-found states and compiled C libraries in one folder of
    this test run, shared by every xdist worker (so a state form-found on one worker is loaded on the
    other; both caches write a file and rename it, safe for concurrent writers), never in the user's
    cache."""
    folder = _run_folder(tmp_path_factory) / "cache"
    folder.mkdir(exist_ok=True)
    with pytest.MonkeyPatch.context() as patch:
        patch.setenv("XDG_CACHE_HOME", str(folder))
        yield


KERNEL_WARM_UP = """
import dataclasses, os, sys
from presag_opt.dynamics.batch import simulate_many
from presag_opt.dynamics.case import load_case
from presag_opt.dynamics.settings import OperatingPoint
from presag_opt.static.form_finding import form_find
from presag_opt.system.catenary import SpanLayout

case = load_case("case_study_st98")
settings = dataclasses.replace(case.settings, lead_in_spans=1, analysed_spans=1, numerics="fixed")
state = form_find(case.catenary.with_layout(SpanLayout(span_lengths=(60.0,) * 3, label="3 spans")), settings.static)
point = OperatingPoint(speed=120 / 3.6, static_force=90.0, aero_coefficient=case.operation.aero_coefficient)
simulate_many(state, case.pantograph, [point], settings=settings, keep_histories=True)
"""
"""A one-run batch on three spans: it compiles (or loads) every numba function of the batch kernel."""

KERNEL_WARM_UP_DRIVER = """
import os, subprocess, sys
checkout, done = sys.argv[1], sys.argv[2]
env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
status = subprocess.run([sys.executable, "-c", sys.argv[3]], env={**env, "PYTHONPATH": checkout}).returncode
# the console script (a non-editable install in CI) may import another copy, with its own numba cache
status |= subprocess.run([sys.executable, "-c", sys.argv[3]], env=env, cwd=os.path.dirname(done)).returncode
with open(done + ".tmp", "w") as handle:
    handle.write(str(status))
os.replace(done + ".tmp", done)
"""
"""Warms the cache of the package the tests import and then that of the installed package (the
second is a quick cache hit when they are the same files), then writes the done file."""

KERNEL_FREE = (
    "tests/docs/", "tests/static/", "tests/system/", "tests/native/", "tests/elasticity/", "tests/design/", "tests/test_",
    "tests/cli/test_line.py", "tests/cli/test_static.py",
    *(f"tests/robust/test_{name}.py" for name in ("buildability", "installation", "lp", "monte_carlo", "path",
                                                    "realisation", "rounding", "span_design", "study", "tolerance")),
    *(f"tests/sensitivity/test_{name}.py" for name in ("methods", "quasi_static", "reference", "screening")),
)
"""Test files that never run the batch kernel (checked by running them alone with an empty
``NUMBA_CACHE_DIR``: no kernel function was cached): they run first and do not wait for its
compilation. A file listed here that does run the kernel only compiles it itself."""

_kernel_warm = False
_needs_kernel = True
_warm_up: subprocess.Popen | None = None


@pytest.fixture(scope="session", autouse=True)
def _kernel_compiled_once_per_run(tmp_path_factory, _cache_in_a_session_folder):
    """Compile the batch kernel's numba functions (about 50 s of one core when the in-tree cache is
    cold, as on a fresh checkout) once per test run, in the background, started by the first worker to
    get here; until it is done, a test that may run the kernel waits (:func:`_kernel_ready`) instead
    of compiling it again in its own process and in every command it starts."""
    import presag_opt

    global _warm_up
    folder = _run_folder(tmp_path_factory)
    try:
        handle = os.open(folder / "kernel-warm-up.pid", os.O_CREAT | os.O_EXCL | os.O_WRONLY)
    except FileExistsError:
        yield
        return
    if not _needs_kernel:
        os.close(handle)
        (folder / "kernel-warm-up.done").write_text("not needed")
        yield
        return
    with open(folder / "kernel-warm-up.log", "w") as log:
        process = subprocess.Popen(
            [sys.executable, "-c", KERNEL_WARM_UP_DRIVER, str(Path(presag_opt.__file__).parents[1]),
             str(folder / "kernel-warm-up.done"), KERNEL_WARM_UP],
            stdin=subprocess.DEVNULL, stdout=log, stderr=log, cwd=folder, start_new_session=True,
        )
    os.write(handle, str(process.pid).encode())
    os.close(handle)
    _warm_up = process
    yield
    if process.poll() is None:  # this worker is done first: stop it rather than leave it running
        os.killpg(process.pid, signal.SIGTERM)
        process.wait()


@pytest.fixture(autouse=True)
def _kernel_ready(request, tmp_path_factory, _kernel_compiled_once_per_run):
    """Wait for the kernel's compilation (at most 15 min, and not after the warm-up process is gone)
    unless the test is in :data:`KERNEL_FREE`. Only the time changes: a failed warm-up leaves each
    test to compile the kernel itself."""
    global _kernel_warm
    if _kernel_warm or _test_path(request.node).startswith(KERNEL_FREE):
        return
    folder = _run_folder(tmp_path_factory)
    deadline = time.monotonic() + 900
    while not (folder / "kernel-warm-up.done").exists() and time.monotonic() < deadline:
        if _warm_up is not None:
            if _warm_up.poll() is not None:
                break  # the warm-up process (this worker's child) is gone without finishing
        else:
            try:
                os.kill(int((folder / "kernel-warm-up.pid").read_text() or 0) or os.getpid(), 0)
            except (ProcessLookupError, ValueError):
                break  # the warm-up process (another worker's child) is gone without finishing
        time.sleep(0.5)
    _kernel_warm = True


def _test_path(item) -> str:
    """A test's file relative to the repository (``tests/...``)."""
    return Path(item.path).resolve().relative_to(Path(__file__).resolve().parents[1]).as_posix()


SLOW_FIRST = ("tests/docs/test_site.py", "tests/notebooks/test_07_sensitivity.py",
              "tests/dynamics/test_kernel_cache.py", "tests/cli/test_cli_refusals.py")
"""The longest files, handed out first in their group so that none of them is left for the end of the
run on one worker."""


def pytest_collection_modifyitems(config, items):
    """Kernel-free files first (they run while the kernel compiles), the longest files first within
    each group; otherwise the collection order (a stable sort, the same on every xdist worker). xdist
    hands the files out in this order because ``--no-loadscope-reorder`` (pyproject's addopts) keeps
    it from sorting them by their number of tests."""
    global _needs_kernel
    _needs_kernel = any(not _test_path(item).startswith(KERNEL_FREE) for item in items)

    def order(item):
        path = _test_path(item)
        return (not path.startswith(KERNEL_FREE), path not in SLOW_FIRST)

    items.sort(key=order)


@pytest.fixture(scope="session", autouse=True)
def _static_models_built_in_this_session():
    """Start the session with no static model kept in memory (``static_model``'s cache). A mutation
    tester that forks each mutant's session from a process that already ran the tests would otherwise
    reuse discretisations built by the unmutated code, and a mutant in them would seem to survive."""
    from presag_opt.static.equilibrium import _static_model

    _static_model.cache_clear()
    yield


CHROMIUM_FLAGS = (
    "--headless", "--no-sandbox", "--disable-gpu", "--no-first-run", "--disable-background-networking",
    "--disable-component-update", "--disable-sync", "--disable-default-apps", "--mute-audio",
    "--remote-debugging-pipe",
)
"""Headless, no sandbox (CI runs as root), no network traffic of its own, DevTools on fds 3 and 4."""


class Chromium:
    """A headless Chromium process and one page, driven by DevTools protocol messages on a pipe.

    Chromium reads commands from fd 3 and writes replies and events to fd 4, each message a JSON
    object followed by a NUL byte.
    """

    def __init__(self, executable: str, profile: Path, timeout: float = 60.0):
        self.timeout = timeout
        to_browser_read, self._to_browser = os.pipe()
        self._from_browser, from_browser_write = os.pipe()

        def child_fds() -> None:
            # In the child before exec: the pipe ends become fds 3 and 4, by way of copies above 10 so
            # that an end that already is fd 3 or 4 is not overwritten before it is moved.
            high = [fcntl.fcntl(fd, fcntl.F_DUPFD_CLOEXEC, 10) for fd in (to_browser_read, from_browser_write)]
            os.dup2(high[0], 3)
            os.dup2(high[1], 4)

        self.process = subprocess.Popen(
            [executable, *CHROMIUM_FLAGS, f"--user-data-dir={profile}", "about:blank"],
            preexec_fn=child_fds, close_fds=False, stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL,
            stderr=subprocess.DEVNULL,
        )
        os.close(to_browser_read)
        os.close(from_browser_write)
        self._buffer = b""
        self._next_id = 0
        self.events: list[dict] = []
        target = self.call("Target.createTarget", url="about:blank")["targetId"]
        self.session = self.call("Target.attachToTarget", targetId=target, flatten=True)["sessionId"]

    def _read(self, deadline: float) -> dict:
        while b"\0" not in self._buffer:
            left = deadline - time.monotonic()
            if left <= 0 or not select.select([self._from_browser], [], [], left)[0]:
                raise TimeoutError("Chromium did not answer in time")
            chunk = os.read(self._from_browser, 1 << 20)
            if not chunk:
                raise RuntimeError("Chromium closed the DevTools pipe")
            self._buffer += chunk
        message, self._buffer = self._buffer.split(b"\0", 1)
        return json.loads(message)

    def call(self, method: str, session: bool = False, **params) -> dict:
        """Send a command (to the page's session if ``session``) and return its result."""
        self._next_id += 1
        message = {"id": self._next_id, "method": method, "params": params}
        if session:
            message["sessionId"] = self.session
        os.write(self._to_browser, json.dumps(message).encode() + b"\0")
        deadline = time.monotonic() + self.timeout
        while True:
            reply = self._read(deadline)
            if reply.get("id") == self._next_id:
                if "error" in reply:
                    raise RuntimeError(f"{method}: {reply['error']}")
                return reply["result"]
            self.events.append(reply)

    def wait_for(self, method: str) -> dict:
        """The first event of a kind (already received or still to come)."""
        deadline = time.monotonic() + self.timeout
        seen = [e for e in self.events if e.get("method") == method]
        while not seen:
            event = self._read(deadline)
            self.events.append(event)
            if event.get("method") == method:
                seen.append(event)
        return seen[0]

    def console_errors(self) -> list[dict]:
        """Console errors and assertions, uncaught exceptions and error log entries seen so far (with
        the Runtime and Log domains enabled)."""
        return [e for e in self.events if
                (e.get("method") == "Runtime.consoleAPICalled" and e["params"]["type"] in ("error", "assert"))
                or e.get("method") == "Runtime.exceptionThrown"
                or (e.get("method") == "Log.entryAdded" and e["params"]["entry"]["level"] == "error")]

    def close(self) -> None:
        try:
            self.call("Browser.close")
        except (RuntimeError, TimeoutError, OSError):
            pass
        try:
            self.process.wait(timeout=10)
        except subprocess.TimeoutExpired:
            self.process.kill()
            self.process.wait()
        os.close(self._to_browser)
        os.close(self._from_browser)


@pytest.fixture
def chromium(tmp_path):
    """A headless Chromium; missing Chromium fails in CI (``CI`` set) and skips elsewhere."""
    executable = shutil.which("chromium") or shutil.which("chromium-browser")
    if executable is None:
        message = "Chromium is not installed (.ci/run installs Debian's chromium package)"
        if os.environ.get("CI"):
            pytest.fail(message)
        pytest.skip(message)
    browser = Chromium(executable, tmp_path / "profile")
    yield browser
    browser.close()
