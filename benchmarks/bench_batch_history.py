"""Batch engine time per run-step, this tree against a base tree, side by side (issue 19).

Run from the repository root::

    python benchmarks/bench_batch_history.py --base /work/wt/base [--repeat 5] [--json]

Make the base tree with ``git worktree add --detach /work/wt/base 75e655d`` (the commit before the
refactor of issue 19). The two trees have different import paths, so each (tree, sweep back-end)
pair runs in its own worker process with ``PYTHONPATH=<tree>``: the C sweeps (``sweeps.c``) and the
numba sweeps (``PRESAG_NO_COMPILE=1``). Every worker form-finds the case study (ST 9,8/9,8, S = 30
mm), warms numba's caches with one batch, counts the batch's run-steps, and then times the same
batch — by default 12 runs (60–180 km/h × 70, 95, 120 N) — each time the driver asks. The driver
asks the four workers in turn, ``--repeat`` rounds, so that every figure sees the same machine; it
prints the median time per run-step of each, the ratio current / base per back-end, and whether the
two trees' contact-force statistics are identical.

The figure is ``time of simulate_many / Σ_runs n_steps`` [s], the batch's set-up (model,
factorisation, influence columns) included, as a user sees it: the wall time, and the worker's
processor time (``time.process_time``), which a machine loaded by other work disturbs much less.
Timings depend on what else runs: the load average before and after is printed; take the ratios,
measured in one run, not the absolute numbers, from a loaded machine.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

SPEEDS_KMH = (60.0, 100.0, 140.0, 180.0)
"""Speeds of the timed batch. [km/h]"""

STATIC_FORCES = (70.0, 95.0, 120.0)
"""Static contact forces of the timed batch. [N]"""

PRESAG = 30e-3
"""Mid-span pre-sag of the case study's catenary. [m]"""

WORKER = r'''
import dataclasses, hashlib, json, sys, time
try:
    from presag_opt.static.form_finding import form_find
except ImportError:  # trees before issue 19
    from presag_opt.static.equilibrium import form_find
from presag_opt.dynamics.batch import simulate_many
from presag_opt.dynamics.case import load_case
from presag_opt.dynamics.settings import OperatingPoint, SimulationSettings

speeds, forces, presag = json.loads(sys.argv[1])
case = load_case("case_study_st98")
settings = SimulationSettings(analysed_spans=case.settings.analysed_spans, lead_in_spans=case.settings.lead_in_spans)
state = form_find(case.catenary.with_presag(presag / max(case.catenary.layout.span_lengths)), settings.static)
aero = case.operation.aero_coefficient
points = [OperatingPoint(speed=v / 3.6, static_force=f, aero_coefficient=aero) for v in speeds for f in forces]
result = simulate_many(state, case.pantograph, points, settings=settings, keep_histories=True)  # warm-up
run_steps = sum(len(run.time) - 1 for run in result.runs)
numbers = [([sorted(dataclasses.asdict(s).items()) for s in run.statistics], run.uplift_max) for run in result.runs]
digest = hashlib.sha256(repr(numbers).encode()).hexdigest()
print(json.dumps({"run_steps": run_steps, "runs": len(result.runs), "failed": len(result.failed),
                  "digest": digest}), flush=True)
for line in sys.stdin:
    started, cpu = time.perf_counter(), time.process_time()
    simulate_many(state, case.pantograph, points, settings=settings)
    print(json.dumps({"wall": time.perf_counter() - started, "cpu": time.process_time() - cpu}), flush=True)
'''


class Worker:
    """One (tree, back-end) worker process: set up and warmed on start, one timed batch per call."""

    def __init__(self, tree: Path, backend: str, workload: list):
        env = dict(os.environ, PYTHONPATH=str(tree))
        env.pop("PRESAG_NO_COMPILE", None)
        if backend == "numba":
            env["PRESAG_NO_COMPILE"] = "1"
        self.process = subprocess.Popen(
            [sys.executable, "-c", WORKER, json.dumps(workload)], cwd=tree, env=env, text=True,
            stdin=subprocess.PIPE, stdout=subprocess.PIPE,
        )
        self.info = self._reply()

    def _reply(self) -> dict:
        line = self.process.stdout.readline()
        if not line:
            raise SystemExit(f"worker {self.process.args[:1]} stopped (exit status {self.process.wait()})")
        return json.loads(line)

    def time_batch(self) -> dict:
        """Wall and processor time of one batch (``wall``, ``cpu``). [s]"""
        self.process.stdin.write("go\n")
        self.process.stdin.flush()
        return self._reply()

    def close(self) -> None:
        """End the worker (its stdin closed)."""
        self.process.stdin.close()
        self.process.wait()


def measure(trees: dict[str, Path], repeat: int, workload: list, progress) -> dict:
    """Median time per run-step of every (tree, back-end), the batches interleaved."""
    workers = {}
    try:
        for backend in ("C", "numba"):
            for name, tree in trees.items():
                progress(f"starting {name} tree, {backend} sweeps (form-finding, warm-up)")
                workers[name, backend] = Worker(tree, backend, workload)
        walls: dict = {key: [] for key in workers}
        for round_ in range(repeat):
            progress(f"round {round_ + 1} of {repeat}")
            for key, worker in workers.items():
                walls[key].append(worker.time_batch())
    finally:
        for worker in workers.values():
            worker.close()
    table = {}
    for backend in ("C", "numba"):
        rows = {}
        for name in trees:
            info = workers[name, backend].info
            wall = statistics.median(t["wall"] for t in walls[name, backend])
            cpu = statistics.median(t["cpu"] for t in walls[name, backend])
            rows[name] = {"per_run_step_us": wall / info["run_steps"] * 1e6, "cpu_per_run_step_us":
                          cpu / info["run_steps"] * 1e6, "batch_s": wall, "walls_s": [t["wall"] for t in walls[name, backend]],
                          "cpus_s": [t["cpu"] for t in walls[name, backend]], "run_steps": info["run_steps"],
                          "runs": info["runs"], "failed": info["failed"], "digest": info["digest"]}
        rows["ratio"] = rows["current"]["per_run_step_us"] / rows["base"]["per_run_step_us"]
        rows["cpu_ratio"] = rows["current"]["cpu_per_run_step_us"] / rows["base"]["cpu_per_run_step_us"]
        rows["identical_statistics"] = rows["current"]["digest"] == rows["base"]["digest"]
        table[backend] = rows
    return table


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--base", type=Path, required=True, help="the base tree (a worktree of 75e655d)")
    parser.add_argument("--current", type=Path, default=ROOT, help="the current tree (default: this repository)")
    parser.add_argument("--repeat", type=int, default=5, help="timed batches per tree and back-end (default 5)")
    parser.add_argument("--speeds", default=",".join(f"{v:g}" for v in SPEEDS_KMH), help="speeds in km/h")
    parser.add_argument("--forces", default=",".join(f"{f:g}" for f in STATIC_FORCES), help="static forces in N")
    parser.add_argument("--json", action="store_true", help="print one JSON object instead of the table")
    args = parser.parse_args()
    if not (args.base / "presag_opt").is_dir():
        parser.error(f"--base {args.base}: no presag_opt package there (make it with git worktree add)")
    if args.repeat < 1:
        parser.error(f"--repeat {args.repeat}: must be at least 1")
    workload = [[float(v) for v in args.speeds.split(",")], [float(f) for f in args.forces.split(",")], PRESAG]
    trees = {"base": args.base.resolve(), "current": args.current.resolve()}
    load_before = os.getloadavg()
    table = measure(trees, args.repeat, workload, lambda text: print(text, file=sys.stderr, flush=True))
    load_after = os.getloadavg()
    if args.json:
        print(json.dumps({"trees": {k: str(v) for k, v in trees.items()}, "repeat": args.repeat,
                          "speeds_kmh": workload[0], "static_forces_n": workload[1], "cpus": os.cpu_count(),
                          "load_before": load_before, "load_after": load_after, "backends": table}, indent=2))
        return 0
    runs = table["C"]["current"]["runs"]
    print(f"batch of {runs} runs (case study, S = {PRESAG * 1e3:g} mm, {args.speeds} km/h × {args.forces} N), "
          f"median of {args.repeat}, interleaved; CPUs {os.cpu_count()}, load average {load_before[0]:.2f} before, "
          f"{load_after[0]:.2f} after")
    print(f"{'sweeps':<7} {'time':<10} {'base µs/run-step':>17} {'current µs/run-step':>20} {'current/base':>13}  "
          "identical statistics")
    for backend, rows in table.items():
        for label, key, ratio in (("wall", "per_run_step_us", "ratio"), ("processor", "cpu_per_run_step_us", "cpu_ratio")):
            print(f"{backend:<7} {label:<10} {rows['base'][key]:>17.2f} {rows['current'][key]:>20.2f} "
                  f"{rows[ratio]:>12.3f}x  {'yes' if rows['identical_statistics'] else 'NO'}")
    print(f"base: {trees['base']}\ncurrent: {trees['current']}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
