"""The kernel's first compilation on two cores (:mod:`presag_opt.dynamics.batch.compilation`).

The helper process (``compiling_elsewhere``) on throwaway modules: it writes the cache and the
caller loads it; none when another process holds the lock or on one core; Ctrl-C kills it and
frees the lock at once. In a fresh process with an empty numba cache, as a first use: the helper's ``newton_steps`` and
the functions compiled beforehand for ``advance`` (:func:`~presag_opt.dynamics.batch.compilation.advance_calls`)
must be the ones ``advance`` calls, each compiled once and for the types ``advance`` passes; a
drift (an argument added to one of ``advance``'s calls, its order changed) compiles the callee a
second time and fails here. About 20 s of processor time: the ``slow`` tier.
"""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
from pathlib import Path

import pytest

from presag_opt.dynamics.batch import compilation
from presag_opt.native import jit
from tests.conftest import KERNEL_WARM_UP
from tests.native.test_jit import _two_files

CHECK = KERNEL_WARM_UP + """
import json
from presag_opt.dynamics.batch import compilation, kernel
from presag_opt.native import sweeps

calls = compilation.advance_calls(sweeps.sweeps(), *[None] * 6)
functions = [kernel.newton_steps, kernel.initialise, kernel.advance, *(function for function, _ in calls)]
print(json.dumps({
    "signatures": {f.py_func.__module__ + "." + f.py_func.__name__: len(f.signatures) for f in functions},
    "newton_steps_hits": sum(kernel.newton_steps.stats.cache_hits.values()),
    "newton_steps_misses": sum(kernel.newton_steps.stats.cache_misses.values()),
}))
"""


AHEAD = """
from presag_opt.dynamics.batch.first_use import compiling_ahead
ahead = compiling_ahead()
assert ahead.__enter__(), "no helper started with the command"
"""
"""What a command that simulates does first (``presag report``, ``presag simulate`` of a grid)."""


@pytest.mark.slow
@pytest.mark.parametrize("started", ["at the first batch", "with the command"])
def test_the_first_compilation_compiles_each_kernel_function_once_for_the_types_advance_uses(tmp_path, started):
    env = {**os.environ, "NUMBA_CACHE_DIR": str(tmp_path / "numba"), "XDG_CACHE_HOME": str(tmp_path / "xdg")}
    env.pop("PRESAG_NO_COMPILE", None)
    if (os.cpu_count() or 1) < 2:
        pytest.skip("one core: the kernel compiles in one process")
    code = CHECK if started == "at the first batch" else AHEAD + CHECK
    ran = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, timeout=600,
                         cwd=Path(__file__).parents[3], check=False)
    assert ran.returncode == 0, ran.stderr
    found = json.loads(ran.stdout.splitlines()[-1])
    assert found["newton_steps_hits"] == 1 and found["newton_steps_misses"] == 0  # the helper compiled it
    assert found["signatures"] == dict.fromkeys(found["signatures"], 1)


@pytest.mark.parametrize("compiled_code", [True, False])
def test_a_first_compilation_is_announced_and_uses_a_helper_only_with_compiled_code_on(monkeypatch, compiled_code):
    """Afresh (nothing cached): the progress display is told, and the helper is asked for only
    where the runtime allows compiled code (``PRESAG_NO_COMPILE`` starts no process); the entry
    points are compiled in this process either way, ``initialise`` before ``advance``."""
    from contextlib import contextmanager

    from presag_opt.dynamics.batch import kernel
    from presag_opt.runtime import current

    compiled, helpers, told = [], [], []

    @contextmanager
    def elsewhere(dispatcher, *args):
        helpers.append(dispatcher)
        yield False

    monkeypatch.setattr(compilation, "is_cached", lambda dispatcher, *args: False)
    monkeypatch.setattr(compilation, "compile_once", lambda dispatcher, *args: compiled.append(dispatcher))
    monkeypatch.setattr(compilation, "compiling_elsewhere", elsewhere)
    with current().replace(compile=compiled_code):
        compilation.compile_kernel(*[None] * 8, progress=told.append)
    assert told == [compilation.FIRST_USE_NOTE]
    assert helpers == ([kernel.newton_steps] if compiled_code else [])
    assert compiled[0] is kernel.initialise and compiled[-1] is kernel.advance


def _lock_is_free(dispatcher) -> bool:
    """Whether nobody holds the kernel function's compile lock (taken and released at once if so)."""
    with jit.lock_file(dispatcher) as handle:
        return jit.try_lock(handle)


@pytest.mark.skipif(not hasattr(os, "fork"), reason="file locks of POSIX")
def test_a_helper_process_compiles_into_the_cache_and_the_caller_loads_it(tmp_path, monkeypatch):
    """compiling_elsewhere, on throwaway modules: a helper process compiles the function for the call's types and writes
    the cache; this process compiles nothing (one cache hit, no miss), and no lock is left held."""
    monkeypatch.setattr(os, "cpu_count", lambda: 2)
    user = _two_files(tmp_path)
    monkeypatch.syspath_prepend(str(tmp_path))  # the helper imports the module by name
    with compilation.compiling_elsewhere(user.user, 1.0) as elsewhere:
        assert elsewhere
    assert not user.user.overloads and jit.is_cached(user.user, 1.0)
    jit.compile_once(user.user, 1.0)
    assert sum(user.user.stats.cache_hits.values()) == 1 and not sum(user.user.stats.cache_misses.values())
    assert user.user(1.0) == 3.0
    assert _lock_is_free(user.user)
    with compilation.compiling_elsewhere(user.user, 2.0) as elsewhere:  # compiled for these types: no helper
        assert not elsewhere


@pytest.mark.skipif(not hasattr(os, "fork"), reason="file locks of POSIX")
def test_no_helper_when_another_process_compiles_or_on_one_core(tmp_path, monkeypatch):
    """A one-core machine: no helper, the caller compiles. A held compile lock (another process
    compiling the function, e.g. a helper started with the command): no second helper, and the block
    says the function is being compiled elsewhere (the caller compiles the rest meanwhile and waits
    for it as compile_once does)."""
    import fcntl

    user = _two_files(tmp_path)
    monkeypatch.syspath_prepend(str(tmp_path))
    monkeypatch.setattr(os, "cpu_count", lambda: 1)
    with compilation.compiling_elsewhere(user.user, 1.0) as elsewhere:
        assert not elsewhere
    monkeypatch.setattr(os, "cpu_count", lambda: 2)
    with jit.lock_file(user.user) as held:
        fcntl.flock(held, fcntl.LOCK_EX)
        with compilation.compiling_elsewhere(user.user, 1.0) as elsewhere:
            assert elsewhere
    assert not jit.is_cached(user.user, 1.0)  # no helper of its own compiled it


@pytest.mark.skipif(not hasattr(os, "fork"), reason="file locks of POSIX")
def test_an_interrupt_kills_the_helper_and_frees_the_lock(tmp_path, monkeypatch):
    """Ctrl-C while the helper compiles: leaving the block kills and reaps it, the lock is free at
    once (the helper here never finishes: it only holds the lock), nothing is cached."""
    monkeypatch.setattr(os, "cpu_count", lambda: 2)
    monkeypatch.setattr(compilation, "_HELPER_CODE", "import sys, time; sys.stdin.buffer.read(); time.sleep(600)")
    user = _two_files(tmp_path)
    started = []
    real_start = compilation.start_helper

    def start(*args):
        started.append(real_start(*args))
        return started[-1]

    monkeypatch.setattr(compilation, "start_helper", start)
    with pytest.raises(KeyboardInterrupt), compilation.compiling_elsewhere(user.user, 1.0) as elsewhere:
        assert elsewhere and not _lock_is_free(user.user)  # the helper holds it
        raise KeyboardInterrupt
    helper = started[0]
    assert helper.returncode == -signal.SIGKILL
    assert _lock_is_free(user.user) and not jit.is_cached(user.user, 1.0)


def _interrupted_inside_a_callback(*args):
    """What numba's compiler does when Ctrl-C arrives in the middle of it: Python code run from a
    ctypes callback (llvmlite's object cache notifications), where an interrupt's KeyboardInterrupt
    is printed and swallowed by ctypes."""
    import ctypes

    @ctypes.CFUNCTYPE(None)
    def callback():
        signal.raise_signal(signal.SIGINT)

    callback()


@pytest.mark.parametrize("warm", [True, False])
def test_an_interrupt_during_a_compilation_stops_the_command_instead_of_vanishing(monkeypatch, warm, capfd):
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)  # as the command line installs it
    try:
        monkeypatch.setattr(compilation, "is_cached", lambda *args: warm)
        monkeypatch.setattr(compilation, "compile_once", _interrupted_inside_a_callback)
        monkeypatch.setattr(compilation.runtime, "current",
                            lambda: type("Off", (), {"compile": False})())  # one process: no helper
        with pytest.raises(KeyboardInterrupt):
            compilation.compile_kernel(None, None, None, None, None, None, None, None)
    finally:
        signal.signal(signal.SIGINT, previous)
    assert "Exception ignored" not in capfd.readouterr().err
