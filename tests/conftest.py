"""Shared fixtures: the test run's runtime (one form-finding cache for every worker, module and command
of the run); ``presag`` (a command run in-process) and ``presag_script`` (the installed console
script as a process); form-found states and elasticity sections, expensive (1–5 s), built once per
session; and a headless Chromium driven over the DevTools protocol on a pipe
(``--remote-debugging-pipe``: the standard library is all it needs), which opens the HTML report
(tests/report/) and the documentation site (tests/docs/)."""

from __future__ import annotations

import contextlib
import fcntl
import io
import json
import os
import select
import shutil
import subprocess
import sys
import tempfile
import time
import warnings
from dataclasses import dataclass
from pathlib import Path

import pytest

from presag_opt.cli import main
from presag_opt.design import recommend, section_elasticity
from presag_opt.runtime import NO_CACHE_ENV, Runtime
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
def test_runtime(tmp_path_factory) -> Runtime:
    """The runtime of the whole test run: one form-finding cache and one folder of compiled libraries
    in the run's folder, shared by every xdist worker, every module, every command a test runs
    (in-process or as a process: ``XDG_CACHE_HOME`` points there too) and every worker process those
    start; never the user's cache. Both caches write a file and rename it, safe for concurrent writers.
    A test that needs another runtime enters its own (``with test_runtime.replace(...)``)."""
    folder = _run_folder(tmp_path_factory) / "cache"
    folder.mkdir(exist_ok=True)
    with pytest.MonkeyPatch.context() as patch:
        patch.setenv("XDG_CACHE_HOME", str(folder))
        patch.delenv(NO_CACHE_ENV, raising=False)
        with Runtime.from_environment(state_cache=True) as runtime:
            yield runtime


@dataclass(frozen=True)
class Ran:
    """A finished ``presag`` command: its exit status and what it printed (text)."""

    returncode: int
    stdout: str
    stderr: str


def _presag_in_process(*args: str, cwd: Path | None = None) -> Ran:
    """``presag ARGS`` run by :func:`presag_opt.cli.main` in this process, in ``cwd``, with standard
    output and standard error captured."""
    out, err = io.StringIO(), io.StringIO()
    with contextlib.chdir(cwd or os.getcwd()), contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = main(list(args))
    return Ran(code, out.getvalue(), err.getvalue())


@pytest.fixture(scope="session")
def presag():
    """Run a ``presag`` command in this process (``presag("recommend", "--json", cwd=tmp_path)``):
    :func:`presag_opt.cli.main` with its output captured, in its own runtime built from its options
    and the environment (the test run's caches), leaving nothing behind. Returns a :class:`Ran`."""
    return _presag_in_process


SCRIPT = Path(sys.executable).parent / "presag"
"""The installed console script."""


@pytest.fixture(scope="session")
def presag_script():
    """Run the installed ``presag`` console script as a process (``presag_script("sweep", ..., cwd=...)``;
    keyword arguments go to :func:`subprocess.run`, with a 600 s timeout unless given): for what only a
    real process shows (exit status at the shell, signals, a closed pipe, the process tree). Returns
    the :class:`subprocess.CompletedProcess` (text output)."""
    assert SCRIPT.exists(), f"the presag console script is not installed next to {sys.executable}"

    def run(*args: str, **kwargs) -> subprocess.CompletedProcess:
        kwargs.setdefault("timeout", 600)
        return subprocess.run([str(SCRIPT), *args], capture_output=True, text=True, check=False, **kwargs)

    return run


KERNEL_WARM_UP = """
import dataclasses
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
"""A one-run batch on three spans: it compiles (or loads) the batch kernel's numba functions."""


def pytest_sessionstart(session):
    """In the process that hands tests to pytest-xdist workers (it runs none itself): compile the
    batch kernel in a background process of its own while the workers start on the tests. The kernel
    takes about a minute of one core on a fresh clone; a worker that needs it meanwhile waits on its
    compile lock and then loads it (:func:`presag_opt.native.jit.compile_once`), instead of idling
    while the other worker compiles it too."""
    config = session.config
    if hasattr(config, "workerinput") or not getattr(config.option, "numprocesses", None):
        return
    scratch = Path(tempfile.mkdtemp(prefix="presag-kernel-"))
    env = {**os.environ, "XDG_CACHE_HOME": str(scratch)}
    config._presag_kernel = (subprocess.Popen([sys.executable, "-c", KERNEL_WARM_UP], cwd=Path(__file__).parents[1],
                                              env=env, stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL,
                                              stderr=subprocess.DEVNULL), scratch)


def pytest_sessionfinish(session):
    """Stop the background compilation if the tests are done first (nothing outlives the run)."""
    started = getattr(session.config, "_presag_kernel", None)
    if started:
        process, scratch = started
        process.kill()
        process.wait()
        shutil.rmtree(scratch, ignore_errors=True)


@pytest.fixture(scope="session", autouse=True)
def _static_models_built_in_this_session():
    """Start the session with no static model, form-finding equations or IPOPT solver kept in memory
    (the memos of ``static_model`` and of the form-finding's topologies). A mutation tester that forks
    each mutant's session from a process that already ran the tests would otherwise reuse what the
    unmutated code built, and a mutant in it would seem to survive."""
    from presag_opt.static import form_finding_equations, form_finding_solver
    from presag_opt.static.equilibrium import _static_model

    for memo in (_static_model, form_finding_equations.topology_system, form_finding_equations._target_jacobians,
                 form_finding_solver._solver):
        memo.cache_clear()
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

    def wait_for(self, method: str, where=lambda params: True) -> dict:
        """The first event of a kind whose parameters satisfy ``where`` (already received or still to come)."""
        deadline = time.monotonic() + self.timeout

        def wanted(event: dict) -> bool:
            return event.get("method") == method and where(event.get("params", {}))

        seen = [e for e in self.events if wanted(e)]
        while not seen:
            event = self._read(deadline)
            self.events.append(event)
            if wanted(event):
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
