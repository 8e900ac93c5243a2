"""Cold compile of the batch kernel, this tree against a base tree, side by side.

Run from the repository root::

    python benchmarks/bench_kernel_compile.py --base /tmp/base [--repeat 2]

Make the base tree with ``git archive BASE | tar -x -C /tmp/base``. Each measurement is a fresh
process with ``PYTHONPATH=<tree>`` and an empty numba cache of its own (``NUMBA_CACHE_DIR``): it
imports the batch engine, form-finds a 3-span section of the case study (from a form-finding cache
this run shares, filled by a first untimed process per tree) and runs a one-run batch, which
compiles every numba function of the kernel. The two trees alternate, ``--repeat`` rounds, so that
both see the same machine; printed are the median wall and processor time of the batch call (the
compile and one short run) per tree and the ratio this / base; with ``--profile``, the wall time of
every numba compilation (inclusive of what it compiles inside it) in each tree's last run. The load
average before and after is printed: on a loaded machine take the processor-time ratio.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "benchmarks"))

from _targets import side_by_side  # noqa: E402 - the benchmarks folder is not a package

WORKER = r'''
import dataclasses, json, time
from numba.core import event

compiles, open_compiles = [], []


class CompileTimes(event.Listener):
    """Inclusive wall time of every numba compilation, with its depth (compiled inside another)."""

    def on_start(self, ev):
        open_compiles.append((ev.data["dispatcher"].py_func.__qualname__, time.perf_counter()))

    def on_end(self, ev):
        name, start = open_compiles.pop()
        compiles.append((len(open_compiles), name, time.perf_counter() - start))


event.register("numba:compile", CompileTimes())
from presag_opt.dynamics.batch import simulate_many
from presag_opt.dynamics.case import load_case
from presag_opt.dynamics.settings import OperatingPoint
from presag_opt.static.form_finding import form_find
from presag_opt.system.catenary import SpanLayout

case = load_case("case_study_st98")
settings = dataclasses.replace(case.settings, lead_in_spans=1, analysed_spans=1, numerics="fixed")
state = form_find(case.catenary.with_layout(SpanLayout(span_lengths=(60.0,) * 3, label="3 spans")), settings.static)
point = OperatingPoint(speed=120 / 3.6, static_force=90.0, aero_coefficient=case.operation.aero_coefficient)
started, cpu = time.perf_counter(), time.process_time()
simulate_many(state, case.pantograph, [point], settings=settings)
print(json.dumps({"wall": time.perf_counter() - started, "cpu": time.process_time() - cpu,
                  "profile": sorted((c for c in compiles if c[2] >= 0.2), key=lambda c: -c[2])}))
'''


def measure(tree: Path, cache: str) -> dict:
    """One cold compile of ``tree``'s kernel in a fresh process: wall and processor time [s]."""
    with tempfile.TemporaryDirectory(prefix="numba_cold_") as numba_cache:
        env = {**os.environ, "PYTHONPATH": str(tree), "NUMBA_CACHE_DIR": numba_cache, "XDG_CACHE_HOME": cache}
        done = subprocess.run([sys.executable, "-c", WORKER], env=env, capture_output=True, text=True, check=True,
                              cwd=tree)  # -c puts the working folder first on the path
    return json.loads(done.stdout.strip().splitlines()[-1])


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--profile", action="store_true", help="print each tree's compile times by function")
    args, trees = side_by_side(parser, ROOT, 2, "cold compiles per tree")
    print(f"load average before: {os.getloadavg()}", flush=True)
    times: dict[str, list[dict]] = {name: [] for name in trees}
    with tempfile.TemporaryDirectory(prefix="bench_kernel_compile_") as cache:
        for tree in trees.values():
            measure(tree, cache)  # fills the shared form-finding and C-library caches
        for _ in range(args.repeat):
            for name, tree in trees.items():
                times[name].append(measure(tree, cache))
                print(f"{name}: {times[name][-1]['wall']:.1f} s wall, {times[name][-1]['cpu']:.1f} s processor",
                      flush=True)
    medians = {name: {key: statistics.median(t[key] for t in runs) for key in ("wall", "cpu")}
               for name, runs in times.items()}
    for name, m in medians.items():
        print(f"{name}: cold compile and one short run, median {m['wall']:.1f} s wall, {m['cpu']:.1f} s processor")
    print(f"this / base: wall {medians['this']['wall'] / medians['base']['wall']:.3f}, "
          f"processor {medians['this']['cpu'] / medians['base']['cpu']:.3f}")
    if args.profile:
        for name, runs in times.items():
            print(f"{name}: wall time of each numba compilation of 0.2 s or more (inclusive, nested by depth), "
                  "last run")
            for depth, function, seconds in runs[-1]["profile"]:
                print(f"  {'  ' * depth}{function:32s} {seconds:6.2f} s")
    print(f"load average after: {os.getloadavg()}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
