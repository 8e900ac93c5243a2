"""Benchmark of the everyday commands (issue 12). Run: python benchmarks/bench_cli.py [--repeat N]

Times, cold (a fresh process per run: imports, CasADi model building, form-finding, elasticity),

- ``presag recommend`` (target: 3 s wall on an idle machine), and
- ``presag elasticity st_9.8_ideal --linear`` (target: 5 s),

each without the form-finding cache (``--no-cache``) and with a warm cache (one unmeasured run
fills a private cache folder first). Reports the median of N runs (default 5) of the wall time and
of the CPU time (user + system of the process and its children, from ``resource``), which does not
depend on what else the machine runs, and the load average before and after. Prints ``NOT MET`` and
exits with status 1 when a median wall time misses its target.

``--source DIR`` times another checkout of the package instead (``python -m presag_opt.cli`` with
``PYTHONPATH=DIR``), e.g. the code before issue 12 (``git archive 2ab2542 | tar -x -C DIR``); code
without the cache is timed without it only.
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

SCRIPT = Path(sys.executable).parent / "presag"

COMMANDS = {
    "presag recommend": (["recommend"], 3.0),
    "presag elasticity st_9.8_ideal --linear": (["elasticity", "st_9.8_ideal", "--linear"], 5.0),
}
"""Label: (arguments, target wall time [s])."""


def timed_run(command: list[str], args: list[str], env: dict[str, str]) -> tuple[float, float]:
    """Wall and CPU seconds of one fresh ``presag`` process (CPU: user + system, children included).

    Runs in the temporary folder ``env["XDG_CACHE_HOME"]``, so that ``python -m`` does not put a
    checkout in the current folder ahead of ``--source`` on the import path."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    start = time.perf_counter()
    subprocess.run([*command, *args], check=True, stdout=subprocess.DEVNULL, env=env, cwd=env["XDG_CACHE_HOME"])
    wall = time.perf_counter() - start
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    return wall, (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=5, help="runs per command and cache setting (default 5)")
    parser.add_argument("--source", metavar="DIR", default=None, help="time the package in DIR instead")
    options = parser.parse_args()
    missed = []
    print(f"load average before: {' '.join(f'{v:.2f}' for v in os.getloadavg())}; {os.cpu_count()} CPUs")
    with tempfile.TemporaryDirectory() as folder:
        env = {**os.environ, "XDG_CACHE_HOME": folder}
        env.pop("PRESAG_NO_CACHE", None)
        command = [str(SCRIPT)]
        settings = (("no cache", ["--no-cache"]), ("warm cache", []))
        if options.source:
            env["PYTHONPATH"] = str(Path(options.source).resolve())
            command = [sys.executable, "-m", "presag_opt.cli"]
            if not (Path(options.source) / "presag_opt" / "static" / "cache.py").is_file():
                settings = (("no cache", []),)
        for label, (args, target) in COMMANDS.items():
            for setting, extra in settings:
                if setting == "warm cache":
                    timed_run(command, args, env)  # fill the cache
                runs = [timed_run(command, args + extra, env) for _ in range(options.repeat)]
                wall = statistics.median(r[0] for r in runs)
                cpu = statistics.median(r[1] for r in runs)
                verdict = "met" if wall <= target else "NOT MET"
                if wall > target:
                    missed.append(f"{label} ({setting})")
                print(f"{label:42s} {setting:10s}: wall {wall:6.2f} s, CPU {cpu:6.2f} s (median of {len(runs)}; "
                      f"walls {', '.join(f'{r[0]:.1f}' for r in runs)}); target {target:g} s wall: {verdict}")
    print(f"load average after: {' '.join(f'{v:.2f}' for v in os.getloadavg())}")
    if missed:
        print("NOT MET: " + "; ".join(missed))
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
