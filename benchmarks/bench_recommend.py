"""Benchmark of ``presag recommend`` (issue 3). Run: python benchmarks/bench_recommend.py [--repeat N]

Measures, on this machine, the wall time of ``presag recommend`` with its defaults (the paper's case
study: ST 9,8/9,8 ideal and mixed spans), cold start: a fresh Python process per run, so imports,
CasADi model building and both form-findings are included. Prints every run and the median
(target < 10 s; a miss ends with a ``NOT MET`` line and exit status 1), then one more fresh run broken into stages (import, form-finding and elasticity
per layout; the S(F_m) evaluation counts with the elasticity) from the API's progress messages,
and the load average, since the figures depend on what else the machine is doing.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys

from _targets import MIN_REPEAT, Targets, median_time

TARGET_S = 10.0

# Runs in a fresh process: times each stage between progress messages of recommend().
STAGES_SCRIPT = """
import json, time
start = time.perf_counter()
from presag_opt.design import recommend
marks = [("import", time.perf_counter())]
recommend(progress=lambda message: marks.append((message, time.perf_counter())))
marks.append(("end", time.perf_counter()))
stages = {"import": marks[0][1] - start}
for (name, t), (_, t_next) in zip(marks[1:], marks[2:]):
    key = name.split(" of span")[0]  # 'X: elasticity of span 3/29' -> 'X: elasticity'
    stages[key] = stages.get(key, 0.0) + t_next - t
print(json.dumps(stages))
"""


def cold_run() -> None:
    """One ``presag recommend`` in a fresh process; stops the benchmark if it fails."""
    run = subprocess.run([sys.executable, "-m", "presag_opt.cli", "recommend"], capture_output=True, text=True, check=False)
    if run.returncode != 0:
        raise SystemExit(f"presag recommend failed ({run.returncode}): {run.stderr.strip()}")


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=MIN_REPEAT, help="runs per median (at least 3)")
    args = parser.parse_args()

    print(f"load average before: {' '.join(f'{v:.2f}' for v in os.getloadavg())} on {os.cpu_count()} CPUs")
    median, _ = median_time(cold_run, args.repeat, show=True)
    print(f"presag recommend, cold start, median of {args.repeat}:")
    targets = Targets()
    targets.below("presag recommend, cold start", median, TARGET_S)

    stages = subprocess.run([sys.executable, "-c", STAGES_SCRIPT], capture_output=True, text=True, check=True)
    print("\nstages of one more fresh run:")
    for name, seconds in json.loads(stages.stdout).items():
        print(f"  {name:60s} {seconds:6.2f} s")
    print(f"load average after: {' '.join(f'{v:.2f}' for v in os.getloadavg())}")
    return targets.exit_status()


if __name__ == "__main__":
    sys.exit(main())
