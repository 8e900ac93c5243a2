"""The quasi-static answer's own work (elasticity, the rule's curves, the report): this tree against a
base tree, side by side.

Run from the repository root::

    python benchmarks/bench_quasi_static.py --base /tmp/base [--repeat 3] [--only curves]

Make the base tree with ``git worktree add /tmp/base BASE``. Every run is a fresh interpreter with
``PYTHONPATH=<tree>``, started from the tree's folder; the trees alternate, ``--repeat`` rounds, and
the medians and the ratio this / base are printed with the load average before and after each part
(on a loaded machine compare the ratios of one run).

Parts:

- ``curves``: the elasticity of the case study's two layouts at the band's force levels
  (``section_elasticity``, the mixed section's 29 spans) and their layout recommendation
  (``layout_recommendation``), timed inside the interpreter on states form-found before the clock
  starts (its start, imports and form-finding left out); the largest difference of every curve and
  of the recommendations' S_rel between the trees is printed.
- ``recommend``: ``presag recommend --json`` (interpreter start included; the form-finding cache on,
  warmed by the first round).
- ``report``: ``presag report --json --out DIR`` (the same); issue 35's target is a full report in
  at most :data:`REPORT_TARGET` on a quiet 2-core machine, checked on this tree's median.
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "benchmarks"))

from _targets import Targets, side_by_side, time_side_by_side  # noqa: E402 - the benchmarks folder is not a package
from bench_form_finding_reuse import command_part, largest_difference  # noqa: E402

CURVES = """
import sys, time, warnings
import numpy as np
from presag_opt.design.band import CASE_STUDY_BAND, force_levels_for_band
from presag_opt.design.recommendation import layout_recommendation
from presag_opt.design.section import section_elasticity
from presag_opt.runtime import Runtime
from presag_opt.static.form_finding import form_find
from presag_opt.system.loader import load_catenary

warnings.simplefilter("ignore")  # the uplift and speed notes are not what is timed
Runtime.from_environment(state_cache=True).activate()
states = [form_find(load_catenary(name)) for name in ("st_9.8_ideal", "st_9.8_mixed")]
levels = force_levels_for_band(*CASE_STUDY_BAND.mean_force_band())
out, started = {}, time.perf_counter()
for name, state in zip(("ideal", "mixed"), states):
    section = section_elasticity(state, force_levels=levels, step=0.5)
    layout = layout_recommendation(section, CASE_STUDY_BAND)
    for study in section.studies:
        for curve in study.nonlinear:
            out[f"{name}.span{study.span}.{curve.force:g}N"] = curve.elasticity
    out[f"{name}.presag_rel_range"] = np.array(layout.presag_rel_range)
    out[f"{name}.delta_e_curve"] = layout.presag_rel_delta_e
seconds = time.perf_counter() - started
np.savez(sys.argv[1], **out)
print(seconds)
"""
"""The ``curves`` part, run in each tree's interpreter: prints its wall time [s], saves the curves."""


def _curves(tree: Path, out: Path) -> tuple[float, object]:
    done = subprocess.run([sys.executable, "-c", CURVES, str(out)], env={**os.environ, "PYTHONPATH": str(tree)},
                          cwd=tree, check=True, capture_output=True, text=True)
    return float(done.stdout.split()[-1]), np.load(out)


REPORT_TARGET = 10.0
"""Longest warm ``presag report`` (issue 35). [s]"""


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--only", choices=("curves", "recommend", "report"), action="append", help="run only this part")
    args, trees = side_by_side(parser, ROOT, 3, "timed runs per tree and part")
    parts = {
        "curves": ("elasticity and layout recommendation of st_9.8_ideal and st_9.8_mixed", _curves),
        "recommend": ("presag recommend", command_part(["recommend"], cache=True)),
        "report": ("presag report", command_part(["report"], with_out=True, cache=True)),
    }
    targets = Targets()
    with tempfile.TemporaryDirectory(prefix="bench_quasi_static_") as folder:
        for part in args.only or list(parts):
            title, run = parts[part]
            medians = time_side_by_side(title, run, trees, args.repeat,
                              lambda name, round_, part=part: Path(folder) / (f"{part}_{name}_{round_}.npz"
                                                                              if part == "curves" else f"{part}_{name}_{round_}"),
                              largest_difference, warm_up=True)
            if part == "report":
                targets.below("presag report (full), warm", medians["this"], REPORT_TARGET)
    return targets.exit_status()


if __name__ == "__main__":
    raise SystemExit(main())
