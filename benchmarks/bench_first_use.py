"""The first command in a fresh environment, this tree against a base tree, side by side.

Run from the repository root::

    python benchmarks/bench_first_use.py --base /tmp/base [--repeat 2] [--command simulate|report-quick]

Make the base tree with ``git worktree add /tmp/base BASE`` (or ``git archive BASE | tar -x -C
/tmp/base``). The command (``python -m presag_opt.cli`` with ``PYTHONPATH=<tree>``) is, with
``--command simulate`` (the default), ``presag simulate --case case_study_st98 --speed 80
--static-force 100,120``, the first dynamic command; with ``--command report-quick``, ``presag
report --quick --out <folder>``, the first report after an installation. A *first use* is a fresh
process with empty caches of its own: no form-found states, no compiled C libraries
(``XDG_CACHE_HOME``) and no compiled numba kernel (``NUMBA_CACHE_DIR``); the *warm* run repeats
the command at once on the caches the first one filled. The trees alternate, ``--repeat`` rounds,
so that both see the same machine. Printed: every run's wall and processor time (the process and
its children), the medians per tree, the first-use cost (first use − warm) and the ratios this /
base, and the load average before and after (on a loaded machine, read the processor times).
The targets: for ``simulate``, a first use at most 10 s more than the warm command; for
``report-quick``, a first use of at most 20 s.
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

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "benchmarks"))

from _targets import Targets, side_by_side  # noqa: E402 - the benchmarks folder is not a package

COMMANDS = {
    "simulate": ["simulate", "--case", "case_study_st98", "--speed", "80", "--static-force", "100,120"],
    "report-quick": ["report", "--quick", "--out", "{caches}/report"],
}
"""The commands by ``--command`` name (``{caches}``: the run's cache folder)."""
FIRST_USE_LIMIT = 10.0
"""Largest first-use cost over the warm command (``simulate``). [s]"""
REPORT_FIRST_USE_LIMIT = 20.0
"""Longest first use of ``report --quick``. [s]"""


def timed(tree: Path, caches: Path, command: list[str]) -> tuple[float, float]:
    """Wall and processor time (the child process and its children: user + system) of the command. [s]"""
    env = {**os.environ, "PYTHONPATH": str(tree), "XDG_CACHE_HOME": str(caches / "xdg"),
           "NUMBA_CACHE_DIR": str(caches / "numba")}
    env.pop("PRESAG_NO_COMPILE", None)
    arguments = [a.format(caches=caches) for a in command]
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    started = time.perf_counter()
    subprocess.run([sys.executable, "-m", "presag_opt.cli", *arguments], env=env, check=True, cwd=tree,  # -m puts
                   stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)  # the working folder first on the path
    wall = time.perf_counter() - started
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    return wall, (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--command", choices=sorted(COMMANDS), default="simulate", help="the command to time")
    args, trees = side_by_side(parser, ROOT, 2, "first uses (each followed by a warm run) per tree")
    command = COMMANDS[args.command]
    print(f"presag {' '.join(command)}")
    print(f"load average before: {os.getloadavg()}", flush=True)
    runs: dict[str, dict[str, list[tuple[float, float]]]] = {name: {"first": [], "warm": []} for name in trees}
    for _ in range(args.repeat):
        for name, tree in trees.items():
            with tempfile.TemporaryDirectory(prefix="bench_first_use_") as caches:
                for kind in ("first", "warm"):
                    runs[name][kind].append(timed(tree, Path(caches), command))
                    wall, cpu = runs[name][kind][-1]
                    print(f"{name} {kind:5s}: {wall:6.1f} s wall, {cpu:6.1f} s processor", flush=True)
    medians = {name: {kind: tuple(statistics.median(t[i] for t in times) for i in (0, 1))
                      for kind, times in by_kind.items()} for name, by_kind in runs.items()}
    cost = {name: tuple(m["first"][i] - m["warm"][i] for i in (0, 1)) for name, m in medians.items()}
    for name, m in medians.items():
        print(f"{name}: first use {m['first'][0]:.1f} s wall ({m['first'][1]:.1f} s processor), warm "
              f"{m['warm'][0]:.1f} s ({m['warm'][1]:.1f} s); first-use cost {cost[name][0]:.1f} s wall "
              f"({cost[name][1]:.1f} s processor)")
    for kind in ("first", "warm"):
        print(f"this / base, {kind}: wall {medians['this'][kind][0] / medians['base'][kind][0]:.3f}, "
              f"processor {medians['this'][kind][1] / medians['base'][kind][1]:.3f}")
    print(f"this / base, first-use cost: wall {cost['this'][0] / cost['base'][0]:.3f}, "
          f"processor {cost['this'][1] / cost['base'][1]:.3f}")
    print(f"load average after: {os.getloadavg()}")
    targets = Targets()
    if args.command == "simulate":
        targets.below("first-use cost over warm (wall)", cost["this"][0], FIRST_USE_LIMIT)
    else:
        targets.below("first use (wall)", medians["this"]["first"][0], REPORT_FIRST_USE_LIMIT)
    return targets.exit_status()


if __name__ == "__main__":
    raise SystemExit(main())
