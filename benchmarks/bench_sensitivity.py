"""Benchmark of ``presag sensitivity`` (issues 22 and 35). Run from the repository root:
``python benchmarks/bench_sensitivity.py`` times part 1 (``--part dynamic`` or ``all`` for more).

1. Morris screening of the case-study recommendation over all its assumed inputs, r = 10
   trajectories, 2 worker processes, 180 evaluations (target <= 3 min on an idle 2-core machine: issue 35;
   issue 22 had asked for 10 min).
2. Morris on σ and σ/F_m at 50 and 90 km/h (case-study pre-sag 30 mm, F_stat 120 N, reduced numerics:
   5 spans, 1 m elements, 4 ms) over the pantograph's assumed inputs and the structural damping
   ratio, r = 10 (target <= 20 min).

Prints the cost of one evaluation (the first, alone), the total wall time, the CPU time of this
process and its workers (on a busy machine, CPU time / workers is what the wall time would be on an
idle one), the load average before and after and the ranked tables; ``--save DIR``
writes each result as JSON (``sensitivity_recommendation.json``, ``sensitivity_dynamic.json``).
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import sys
import time
from pathlib import Path

from _targets import Targets

from presag_opt.sensitivity import sensitivity_analysis

PARTS = {
    "recommendation": {"output": "recommendation", "inputs": None, "target": 180.0},
    "dynamic": {"output": "dynamic:50,90", "target": 1200.0, "inputs": [
        "pantograph.head.mass", "pantograph.head.stiffness", "pantograph.head.damping", "pantograph.frame.mass",
        "pantograph.frame.damping", "pantograph.frame.friction", "catenary.damping.ratio"]},
}


def _cpu_seconds() -> float:
    """User + system CPU time of this process and of its finished child processes (the workers). [s]"""
    own, children = resource.getrusage(resource.RUSAGE_SELF), resource.getrusage(resource.RUSAGE_CHILDREN)
    return own.ru_utime + own.ru_stime + children.ru_utime + children.ru_stime


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--part", choices=[*PARTS, "all"], default="recommendation")
    parser.add_argument("--trajectories", type=int, default=10)
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--save", type=Path, default=None)
    parser.add_argument("--out", type=Path, default=None, help="resumable store folder (a rerun resumes)")
    args = parser.parse_args()
    targets = Targets()
    for name, part in PARTS.items():
        if args.part not in (name, "all"):
            continue
        print(f"{name}: load average before {os.getloadavg()}", flush=True)
        cpu_before, wall_before = _cpu_seconds(), time.perf_counter()
        result = sensitivity_analysis(
            output=part["output"], inputs=part["inputs"], method="morris", samples=args.trajectories, seed=0,
            workers=args.workers, out=args.out, announce=lambda text: print(f"  {text}", flush=True),
            progress=lambda message: print(f"  {message}", file=sys.stderr, flush=True))
        wall, cpu = time.perf_counter() - wall_before, _cpu_seconds() - cpu_before
        print(f"{name}: {len(result.inputs)} inputs, {result.evaluations} evaluations, one evaluation "
              f"{result.seconds_first:.1f} s, total {result.seconds:.0f} s; load average after {os.getloadavg()}")
        print(f"{name}: wall time {wall:.1f} s = {wall / 60:.2f} min; CPU time (this process and its workers) "
              f"{cpu:.0f} s, i.e. {cpu / args.workers / 60:.2f} min per worker")
        for table in result.indices:
            print(f"  {table.output} [{table.unit}] mean {table.mean:.4g}, std {table.std:.3g}")
            for e in table.morris:
                print(f"    {e.name:45s} mu* {e.mu_star:10.4g} ± {e.mu_star_conf:8.2g}  sigma {e.sigma:10.4g}  "
                      f"rel {e.relative:5.2f}")
        targets.below(f"{name} Morris r = {args.trajectories}", result.seconds, part["target"])
        if args.save:
            args.save.mkdir(parents=True, exist_ok=True)
            (args.save / f"sensitivity_{name}.json").write_text(json.dumps(result.to_dict(), indent=1))
    return targets.exit_status()


if __name__ == "__main__":
    sys.exit(main())
