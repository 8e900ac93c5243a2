"""Benchmark of the batch engine (issue 9). Run: python benchmarks/bench_batch.py [--skip-grid] [--repeat N]

Measures on this machine, in one run so the ratios are side by side:

1. the batch engine (``simulate_many``) on 10 runs of the paper's grid (S = 30 mm, 50–180 km/h,
   F_stat 95 N) with its compiled sweeps and with its numba kernel, alternately (median of N each,
   the ratio, and whether the statistics are identical); then the single-run path (``simulate``) on
   the same runs — wall time per run and the ratio, and the largest relative difference of σ
   between the two paths;
2. peak memory of one 80-run batch (S = 30 mm, all speeds × all static forces), in a fresh process;
3. the paper's 400-run grid (ST 9,8/9,8 ideal spans, case-study pantograph, S 30–70 mm × 10 speeds ×
   8 static forces, the paper's 0.5 m / 2 ms) through ``presag sweep``'s runner with 1 and 2 worker
   processes: wall time and runs per minute.

Requirement: the 400 runs within 10 minutes (``NOT MET`` and exit status 1 otherwise); target: within
3 minutes (reported). Timings depend on what else runs: the load average is printed.
"""

from __future__ import annotations

import argparse
import os
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

REQUIRED_S = 600.0
"""Largest wall time allowed for the 400-run grid. [s]"""

TARGET_S = 180.0
"""Wall time aimed at for the 400-run grid. [s]"""

MEMORY_LIMIT_GIB = 4.0
"""Largest peak memory allowed for one 80-run batch. [GiB]"""


def _case_and_state(presag_mm: float = 30.0):
    from presag_opt.dynamics.case import load_case
    from presag_opt.dynamics.settings import SimulationSettings
    from presag_opt.static.form_finding import form_find

    case = load_case("case_study_st98")
    settings = SimulationSettings(analysed_spans=case.settings.analysed_spans,
                                  lead_in_spans=case.settings.lead_in_spans)  # the paper's fixed 0.5 m / 2 ms
    catenary = case.catenary.with_presag(presag_mm * 1e-3 / max(case.catenary.layout.span_lengths))
    return case, settings, form_find(catenary, settings.static)


def side_by_side(repeat: int) -> None:
    from presag_opt.dynamics.batch import simulate_many
    from presag_opt.dynamics.settings import OperatingPoint
    from presag_opt.dynamics.simulate import simulate
    from presag_opt.native import sweeps as native_sweeps

    case, settings, state = _case_and_state()
    aero = case.operation.aero_coefficient
    speeds = [50, 60, 70, 80, 90, 100, 120, 140, 160, 180]
    points = [OperatingPoint(speed=v / 3.6, static_force=95.0, aero_coefficient=aero) for v in speeds]
    compiled = native_sweeps.available()
    builds = {"compiled sweeps": native_sweeps.available, "numba kernel": lambda: False}
    if not compiled:
        print("no compiled sweeps on this machine (no C compiler or PRESAG_NO_COMPILE): numba kernel only")
        del builds["compiled sweeps"]
    times: dict[str, list[float]] = {name: [] for name in builds}
    results = {}
    try:
        for switch in builds.values():  # compile and warm up
            native_sweeps.available = switch
            simulate_many(state, case.pantograph, points[-1:], settings=settings)
        for _ in range(repeat):  # alternate, so that both see the same machine
            for name, switch in builds.items():
                native_sweeps.available = switch
                started = time.perf_counter()
                results[name] = simulate_many(state, case.pantograph, points, settings=settings)
                times[name].append(time.perf_counter() - started)
    finally:
        native_sweeps.available = builds.get("compiled sweeps", native_sweeps.available)
    medians = {name: statistics.median(t) for name, t in times.items()}
    for name, wall in medians.items():
        print(f"10 runs (S 30 mm, 95 N, 50-180 km/h), one batch, {name}: {wall:.1f} s (median of {repeat}; "
              f"{', '.join(f'{t:.1f}' for t in times[name])})")
    if compiled:
        same = all(a.statistics == b.statistics and a.uplift_max == b.uplift_max
                   for a, b in zip(results["compiled sweeps"].runs, results["numba kernel"].runs))
        print(f"compiled sweeps / numba kernel: {medians['numba kernel'] / medians['compiled sweeps']:.2f}x faster; "
              f"statistics identical: {same}")
    batch_s = min(medians.values())
    batch = results[min(medians, key=medians.get)]
    started = time.perf_counter()
    singles = [simulate(state, case.pantograph, speed=p.speed, static_force=p.static_force, aero_coefficient=aero,
                        settings=settings) for p in points]
    single_s = time.perf_counter() - started
    diff = max(abs(b.statistics[0].std_force / s.statistics.std_force - 1.0) for b, s in zip(batch.runs, singles))
    print(f"batch {batch_s:.1f} s against the single-run path {single_s:.1f} s (once) -> {single_s / batch_s:.1f}x; "
          f"per run {batch_s / 10:.2f} s vs {single_s / 10:.2f} s; largest σ difference {diff:.1e}")


def memory_80() -> None:
    """Print the peak RSS of an 80-run batch measured in a fresh interpreter."""
    code = (
        "import resource, sys; sys.path.insert(0, %r); import bench_batch as b;"
        "from presag_opt.dynamics.batch import simulate_many; from presag_opt.dynamics.settings import OperatingPoint;"
        "case, settings, state = b._case_and_state();"
        "pts = [OperatingPoint(speed=v / 3.6, static_force=f, aero_coefficient=case.operation.aero_coefficient)"
        " for v in (50, 60, 70, 80, 90, 100, 120, 140, 160, 180) for f in range(50, 156, 15)];"
        "import time; t = time.perf_counter(); r = simulate_many(state, case.pantograph, pts, settings=settings);"
        "print(len(r.runs), len(r.failed), time.perf_counter() - t,"
        " resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 2**20)"
    ) % str(Path(__file__).parent)
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout.split()
    runs, failed, wall, peak = int(out[0]), int(out[1]), float(out[2]), float(out[3])
    verdict = "met" if peak < MEMORY_LIMIT_GIB else "NOT MET"
    print(f"80-run batch: {runs} runs ({failed} failed) in {wall:.1f} s, peak memory {peak:.2f} GiB "
          f"(limit {MEMORY_LIMIT_GIB:g} GiB: {verdict})")
    if peak >= MEMORY_LIMIT_GIB:
        raise SystemExit(1)


def grid(workers: int) -> float:
    from presag_opt.studies.definition import load_study
    from presag_opt.studies.runner import run_study

    study = load_study("paper_grid_st98")
    with tempfile.TemporaryDirectory(prefix=f"bench_batch_{workers}w_") as folder:
        started = time.perf_counter()
        result = run_study(study, Path(folder) / "grid.nc", workers=workers)
        wall = time.perf_counter() - started
    print(f"400-run grid, {workers} worker(s): {wall:.1f} s wall, {study.run_count / wall * 60:.0f} runs/min, "
          f"{result.runs_failed} failed", flush=True)
    return wall


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=3, help="repetitions of the batch in the side-by-side test")
    parser.add_argument("--skip-grid", action="store_true", help="leave out the 400-run grid")
    parser.add_argument("--workers", default="2,1", help="worker counts for the grid (default 2,1)")
    args = parser.parse_args()
    print(f"CPUs: {os.cpu_count()}; load average before: {os.getloadavg()}", flush=True)
    side_by_side(args.repeat)
    memory_80()
    status = 0
    if not args.skip_grid:
        walls = {w: grid(w) for w in (int(x) for x in args.workers.split(","))}
        best = min(walls.values())
        if len(walls) > 1 and 1 in walls and 2 in walls:
            print(f"scaling 1 -> 2 workers: {walls[1] / walls[2]:.2f}x")
        print(f"requirement (<= {REQUIRED_S:.0f} s): {'met' if best <= REQUIRED_S else 'NOT MET'}; "
              f"target (<= {TARGET_S:.0f} s): {'met' if best <= TARGET_S else 'NOT MET'}")
        status = 0 if best <= REQUIRED_S else 1
    print(f"load average after: {os.getloadavg()}; peak memory of this process "
          f"{resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 2**20:.2f} GiB")
    return status


if __name__ == "__main__":
    sys.exit(main())
