"""The kernel's first compilation on two cores (:mod:`presag_opt.dynamics.batch.compilation`).

In a fresh process with an empty numba cache, as a first use: the helper's ``newton_steps`` and
the functions compiled beforehand for ``advance`` (:func:`~presag_opt.dynamics.batch.compilation.advance_calls`)
must be the ones ``advance`` calls, each compiled once and for the types ``advance`` passes; a
drift (an argument added to one of ``advance``'s calls, its order changed) compiles the callee a
second time and fails here. About 20 s of processor time: the ``slow`` tier.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

from tests.conftest import KERNEL_WARM_UP

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


@pytest.mark.slow
def test_the_first_compilation_compiles_each_kernel_function_once_for_the_types_advance_uses(tmp_path):
    env = {**os.environ, "NUMBA_CACHE_DIR": str(tmp_path / "numba"), "XDG_CACHE_HOME": str(tmp_path / "xdg")}
    env.pop("PRESAG_NO_COMPILE", None)
    if (os.cpu_count() or 1) < 2:
        pytest.skip("one core: the kernel compiles in one process")
    ran = subprocess.run([sys.executable, "-c", CHECK], env=env, capture_output=True, text=True, timeout=600,
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

    from presag_opt.dynamics.batch import compilation, kernel
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
