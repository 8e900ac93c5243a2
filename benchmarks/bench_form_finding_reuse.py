"""Form-finding with its IPOPT solver built once per topology: this tree against a base tree, side by side.

Run from the repository root::

    python benchmarks/bench_form_finding_reuse.py --base /tmp/base [--repeat 3] [--only tensions]
        [--trajectories 2]

Make the base tree with ``git worktree add /tmp/base BASE``. Every run is a fresh interpreter with
``PYTHONPATH=<tree>``, started from the tree's folder, with no form-finding cache (``--no-cache``,
``PRESAG_NO_CACHE=1``); the trees alternate, ``--repeat`` rounds, and the medians and the ratio this /
base are printed with every run's wall time and the load average before and after each part (on a
loaded machine the wall times move with the load: compare the ratios of one run).

Parts:

- ``tensions``: 10 form-findings of the case study's ideal layout (``st_9.8_ideal``) at contact-wire
  tensions 24–30 kN and messenger-wire tensions 13–17 kN, one topology with other numbers, timed inside
  the interpreter (its start and imports left out); the largest difference of the form-found states
  (positions, dropper lengths, spring references) between the trees is printed.
- ``morris``: ``presag sensitivity --quantity recommendation --method morris --samples R --workers 2``
  (R = ``--trajectories``, 2 by default: 36 evaluations; the full screening is R = 10, 180); the
  largest difference of the JSON's numbers between the trees is printed.
- ``design``: ``presag design`` on the made-up 5 km line of ``bench_line_design.py`` (4 sections of
  25 spans, ``--system st_9.8_mixed --xlsx``, 2 workers); the answers compared as for ``morris``.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "benchmarks"))

from _targets import side_by_side, time_side_by_side  # noqa: E402 - the benchmarks folder is not a package
from bench_line_design import write_survey  # noqa: E402

TENSIONS = """
import dataclasses, sys, time
import numpy as np
from presag_opt.static.form_finding import form_find
from presag_opt.system.loader import load_catenary

base = load_catenary("st_9.8_ideal")
states, started = {}, time.perf_counter()
for k, share in enumerate(np.linspace(0.0, 1.0, 10)):
    catenary = dataclasses.replace(
        base, contact_wire=dataclasses.replace(base.contact_wire, tension=24e3 + 6e3 * share),
        messenger_wire=dataclasses.replace(base.messenger_wire, tension=13e3 + 4e3 * share))
    state = form_find(catenary)
    d = state.discretisation
    states[f"{k}.positions"] = state.positions
    states[f"{k}.droppers"] = state.params.unstretched_length[d.dropper_elements]
    states[f"{k}.springs"] = state.params.spring_reference
seconds = time.perf_counter() - started
np.savez(sys.argv[1], **states)
print(seconds)
"""
"""The ``tensions`` part, run in each tree's interpreter: prints its wall time [s], saves the states."""


def _environment(tree: Path, cache: bool = False) -> dict[str, str]:
    env = {**os.environ, "PYTHONPATH": str(tree)}
    return env if cache else {**env, "PRESAG_NO_CACHE": "1"}


def _tensions(tree: Path, out: Path) -> tuple[float, object]:
    """Wall time of the 10 form-findings [s] and their states (an npz file)."""
    done = subprocess.run([sys.executable, "-c", TENSIONS, str(out)], env=_environment(tree), cwd=tree,
                          check=True, capture_output=True, text=True)
    return float(done.stdout.split()[-1]), np.load(out)


def command_part(arguments: list[str], *, with_out: bool = False, cache: bool = False):
    """A part that runs ``presag ARGUMENTS --json`` (with ``--no-cache`` unless ``cache``, with ``--out``
    the run's own folder if ``with_out``): wall time [s] (interpreter start included) and the JSON answer."""
    def run(tree: Path, out: Path) -> tuple[float, object]:
        started = time.perf_counter()
        done = subprocess.run([sys.executable, "-m", "presag_opt.cli", *arguments, "--json",
                               *([] if cache else ["--no-cache"]), *(["--out", str(out)] if with_out else [])],
                              env=_environment(tree, cache), cwd=tree, check=True, capture_output=True, text=True)
        return time.perf_counter() - started, json.loads(done.stdout)
    return run


def _numbers(value: object, path: str = "") -> dict[str, float]:
    """Every number of a JSON value by its path (timings and paths of files left out)."""
    if isinstance(value, dict):
        return {k: v for key, item in value.items() if not any(t in key for t in ("time", "second", "wall", "cost"))
                for k, v in _numbers(item, f"{path}/{key}").items()}
    if isinstance(value, list):
        return {k: v for i, item in enumerate(value) for k, v in _numbers(item, f"{path}[{i}]").items()}
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        return {}
    return {path: float(value)}


def largest_difference(this: object, base: object) -> str:
    """The largest difference between two answers: of the arrays of two npz files, or of the numbers
    of two JSON values (absolute, and where it is)."""
    if isinstance(this, np.lib.npyio.NpzFile):
        worst = max((float(np.abs(this[k] - base[k]).max()), k) for k in this.files if this[k].size)
        return f"largest difference of the saved arrays {worst[0]:.2e} in their unit ({worst[1]})"
    a, b = _numbers(this), _numbers(base)
    if a.keys() != b.keys():
        return f"the answers differ in their fields: {sorted(a.keys() ^ b.keys())[:5]}"
    worst = max(((abs(a[k] - b[k]), k) for k in a if np.isfinite(a[k]) and np.isfinite(b[k])), default=(0.0, "-"))
    return f"largest difference of the answers' numbers {worst[0]:.2e} (at {worst[1]})"


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--only", choices=("tensions", "morris", "design"), action="append", help="run only this part")
    parser.add_argument("--trajectories", type=int, default=2, help="Morris trajectories of the morris part")
    args, trees = side_by_side(parser, ROOT, 3, "timed runs per tree and part")
    with tempfile.TemporaryDirectory(prefix="bench_form_finding_reuse_") as folder:
        survey = write_survey(Path(folder) / "five_km_line.csv")
        parts = {
            "tensions": ("10 form-findings of st_9.8_ideal, other tensions", _tensions),
            "morris": (f"presag sensitivity: Morris of the recommendation, r = {args.trajectories}",
                       command_part(["sensitivity", "--quantity", "recommendation", "--method", "morris",
                                     "--samples", str(args.trajectories), "--workers", "2"])),
            "design": ("presag design, 5 km line", command_part(["design", str(survey), "--system", "st_9.8_mixed",
                                                                 "--xlsx", "--workers", "2"], with_out=True)),
        }
        for part in args.only or list(parts):
            title, run = parts[part]
            time_side_by_side(title, run, trees, args.repeat,
                              lambda name, round_, part=part: Path(folder) / (f"{part}_{name}_{round_}.npz"
                                                                              if part == "tensions" else f"{part}_{name}_{round_}"),
                              largest_difference)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
