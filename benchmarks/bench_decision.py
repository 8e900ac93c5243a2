"""The commands a designer waits for, this tree against a base tree, side by side, caches warm.

Run from the repository root::

    python benchmarks/bench_decision.py --base /tmp/base [--repeat 3] [--only robust]

Make the base tree with ``git worktree add /tmp/base BASE``. Each command runs as
``python -m presag_opt.cli ... --json`` with ``PYTHONPATH=<tree>`` from the tree's folder, with caches
of its own per tree (form-found states, C libraries: ``XDG_CACHE_HOME``; the numba kernel:
``NUMBA_CACHE_DIR``) that one untimed run per tree and command fills first. Then the trees
alternate, ``--repeat`` rounds. Printed: every run's wall and processor time (the process and its
children: the worker processes included), the medians, the ratios this / base, whether the two trees
give the same JSON apart from timings, and the load average before and after (on a loaded machine
the wall times move with the load: compare the ratios of one run).

Commands and targets (wall, warm, on a quiet 2-core machine):

- ``presag robust --dynamic`` (the case-study band, 60 runs): 20 s;
- ``presag recommend --dynamic-robust`` (the final decision): 25 s.
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "benchmarks"))

from _targets import side_by_side  # noqa: E402 - the benchmarks folder is not a package

COMMANDS = {
    "robust": (["robust", "--dynamic"], 20.0),
    "recommend": (["recommend", "--dynamic-robust"], 25.0),
}
"""Name: (arguments, target wall time [s])."""

TIMING_KEYS = ("time", "cost", "wall", "elapsed")
"""JSON keys whose values are timings, left out of the comparison of the answers."""


def without_timings(value: object) -> object:
    """The JSON value with every timing entry (a key containing one of :data:`TIMING_KEYS`) removed."""
    if isinstance(value, dict):
        return {k: without_timings(v) for k, v in value.items() if not any(t in k for t in TIMING_KEYS)}
    if isinstance(value, list):
        return [without_timings(v) for v in value]
    return value


def timed(tree: Path, caches: Path, arguments: list[str]) -> tuple[float, float, object]:
    """Wall and processor time [s] of one command and its JSON answer without timings."""
    env = {**os.environ, "PYTHONPATH": str(tree), "XDG_CACHE_HOME": str(caches / "xdg"),
           "NUMBA_CACHE_DIR": str(caches / "numba")}
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    started = time.perf_counter()
    done = subprocess.run([sys.executable, "-m", "presag_opt.cli", *arguments, "--json"], env=env, check=True,
                          cwd=tree, capture_output=True, text=True)  # cwd: -m puts the working folder first
    wall = time.perf_counter() - started
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return wall, cpu, without_timings(json.loads(done.stdout))


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--only", choices=sorted(COMMANDS), action="append", help="run only this command")
    args, trees = side_by_side(parser, ROOT, 3, "timed runs per tree and command")
    print(f"load average before: {os.getloadavg()}", flush=True)
    missed = []
    with tempfile.TemporaryDirectory(prefix="bench_decision_") as folder:
        caches = {name: Path(folder) / name for name in trees}
        for command in args.only or list(COMMANDS):
            arguments, target = COMMANDS[command]
            print(f"presag {' '.join(arguments)}", flush=True)
            answers = {name: timed(tree, caches[name], arguments)[2] for name, tree in trees.items()}  # warm-up
            times: dict[str, list[tuple[float, float]]] = {name: [] for name in trees}
            for _ in range(args.repeat):
                for name, tree in trees.items():
                    wall, cpu, _ = timed(tree, caches[name], arguments)
                    times[name].append((wall, cpu))
                    print(f"  {name}: {wall:6.1f} s wall, {cpu:6.1f} s processor", flush=True)
            medians = {name: [statistics.median(t[i] for t in runs) for i in (0, 1)] for name, runs in times.items()}
            for name, (wall, cpu) in medians.items():
                print(f"  {name}: median {wall:.1f} s wall, {cpu:.1f} s processor")
            print(f"  this / base: wall {medians['this'][0] / medians['base'][0]:.3f}, "
                  f"processor {medians['this'][1] / medians['base'][1]:.3f}")
            same = answers["this"] == answers["base"]
            print(f"  the same answer (JSON without timings): {'yes' if same else 'NO'}")
            verdict = "met" if medians["this"][0] < target else "NOT MET"
            print(f"  target {target:g} s wall: {medians['this'][0]:.1f} s: {verdict}", flush=True)
            if verdict != "met" or not same:
                missed.append(command)
    print(f"load average after: {os.getloadavg()}")
    for command in missed:
        print(f"NOT MET: {command}")
    return 1 if missed else 0


if __name__ == "__main__":
    raise SystemExit(main())
