"""The batch kernel's numba cache is never stale: an edit of a law in another file takes effect.

numba keys a cached function by its own file only; the kernel's functions are compiled by
:func:`presag_opt.native.jit.kernel_function`, whose cache is keyed by every file they depend on.
The test copies the package (with its warm cache) to a temporary folder, runs a one-run batch there
in a subprocess, multiplies the friction law in ``laws.py`` by 0.8 — a file the cached kernel
(``kernel.advance``) does not live in — and runs the batch again: the kernel must recompile and the
contact force change. Before the fix, such an edit (then in ``batch_newton.py``) passed the whole suite on
the old cached code.
"""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import presag_opt
from presag_opt.dynamics import laws
from presag_opt.dynamics.batch import kernel
from presag_opt.native import jit

PACKAGE = Path(presag_opt.__file__).parent

RUN = """
import dataclasses, json
import presag_opt
from presag_opt.dynamics.batch import kernel
from presag_opt.dynamics.batch import simulate_many
from presag_opt.dynamics.case import load_case
from presag_opt.dynamics.settings import OperatingPoint
from presag_opt.static.form_finding import form_find
from presag_opt.system.catenary import SpanLayout

case = load_case("case_study_st98")
settings = dataclasses.replace(case.settings, lead_in_spans=1, analysed_spans=1, numerics="fixed")
catenary = case.catenary.with_layout(SpanLayout(span_lengths=(60.0,) * 3, label="3 ideal spans"))
state = form_find(catenary, settings.static)
point = OperatingPoint(speed=120 / 3.6, static_force=90.0, aero_coefficient=case.operation.aero_coefficient)
run = simulate_many(state, case.pantograph, [point], settings=settings, keep_histories=True).runs[0]
print(json.dumps({"package": presag_opt.__file__, "force": run.contact_force[:, 0].tolist(),
                  "cache_hits": sum(kernel.advance.stats.cache_hits.values()),
                  "cache_misses": sum(kernel.advance.stats.cache_misses.values())}))
"""


def _run(root: Path) -> dict:
    env = {k: v for k, v in os.environ.items() if k not in ("NUMBA_DISABLE_JIT", "PYTHONPATH")}
    env["PYTHONPATH"] = str(root)
    done = subprocess.run([sys.executable, "-c", RUN], env=env, cwd=root, capture_output=True, text=True, timeout=1200,
                          check=False)
    assert done.returncode == 0, done.stderr[-3000:]
    out = json.loads(done.stdout.strip().splitlines()[-1])
    assert out["package"] == str(root / "presag_opt" / "__init__.py")  # the copy ran, not this checkout
    return out


def test_the_kernel_depends_on_the_laws_and_every_kernel_file():
    files = {Path(f).name for f in jit.dependency_files(kernel.advance.py_func)}
    assert {"kernel.py", "newton_step.py", "forces.py", "woodbury.py", "predictor.py",
            "update.py", "laws.py", "sweeps.py", "linearised.py"} <= files


@pytest.mark.e2e  # three fresh processes on a copy of the package, one of them compiling the kernel
def test_an_edited_law_in_another_file_takes_effect_with_the_cache_warm(tmp_path):
    shutil.copytree(PACKAGE, tmp_path / "presag_opt")  # __pycache__ included: the cache as warm as here
    (tmp_path / "models").symlink_to(PACKAGE.parent / "models")  # the model files, beside the package
    before = _run(tmp_path)
    warm = _run(tmp_path)
    assert warm["cache_hits"] >= 1 and warm["cache_misses"] == 0  # the second run loads the cached kernel
    assert warm["force"] == before["force"]

    source = tmp_path / "presag_opt" / "dynamics" / "laws.py"
    text = source.read_text()
    law = "    return level * th, factor * level"
    assert text.count(law) == 1, "the friction law's return line moved: update this test"
    source.write_text(text.replace(law, "    return 0.8 * level * th, factor * level"))
    edited = _run(tmp_path)

    assert edited["cache_misses"] >= 1  # recompiled, though kernel.py itself did not change
    change = np.max(np.abs(np.subtract(edited["force"], before["force"])))
    assert change > 0.1, f"friction × 0.8 changed the contact force by only {change:g} N: the cache was stale"


def test_the_batch_compiles_the_laws_module_itself():
    """The batch's friction is laws.friction compiled as a kernel part (the edit above reaches the batch)."""
    from presag_opt.dynamics.batch import forces as batch_forces

    assert batch_forces.friction.py_func is laws.friction
    assert batch_forces.contact_force.py_func is laws.contact_force
    assert batch_forces.dropper_axial_force.py_func is laws.dropper_axial_force
