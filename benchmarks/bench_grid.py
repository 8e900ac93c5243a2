"""The paper's 400-run grid (``presag sweep paper_grid_st98``), this tree against a base tree, side by side.

Run from the repository root::

    python benchmarks/bench_grid.py --base /tmp/base [--repeat 2] [--workers 2]

Make the base tree with ``git worktree add /tmp/base BASE``. Each tree runs ``python -m presag_opt.cli
sweep paper_grid_st98 --out STORE --workers N --quiet`` with ``PYTHONPATH=<tree>`` from the tree's
folder and caches of its own (``XDG_CACHE_HOME``, ``NUMBA_CACHE_DIR``), which one untimed sweep per
tree fills first (the compiled kernel and the grid's five form-found states: the issue's "caches
warm"; 3d2ddf8's cold form-findings add about 36 s to a round, which a first timed round would mix
into the ratio). The trees alternate, ``--repeat`` rounds.
Printed: every run's wall time, the medians, the ratio this / base (target: at most 0.5, twice as
fast), the largest relative difference of σ and F_m between the two trees' stores, and the load
average before and after.
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "benchmarks"))

from _targets import Targets, side_by_side, time_side_by_side  # noqa: E402 - the benchmarks folder is not a package

TARGET_RATIO = 0.5
"""Largest wall-time ratio this / base aimed at (issue 35: the grid twice as fast). [-]"""

COMPARED = ("sigma", "F_m")
"""Variables of the two stores compared (σ and F_m). [N]"""


def _environment(tree: Path, caches: Path) -> dict[str, str]:
    return {**os.environ, "PYTHONPATH": str(tree), "XDG_CACHE_HOME": str(caches / "xdg"),
            "NUMBA_CACHE_DIR": str(caches / "numba")}


def _command(tree: Path, caches: Path, arguments: list[str]) -> float:
    """Wall time of one command of a tree. [s]"""
    started = time.perf_counter()
    subprocess.run([sys.executable, "-m", "presag_opt.cli", *arguments], env=_environment(tree, caches),
                   cwd=tree, check=True, capture_output=True)  # cwd: -m puts the working folder first
    return time.perf_counter() - started


def _largest_difference(this: Path, base: Path) -> str:
    import xarray as xr

    with xr.open_dataset(this) as a, xr.open_dataset(base) as b:
        parts = []
        for name in COMPARED:
            if name not in a or name not in b:
                parts.append(f"{name}: not in both stores")
                continue
            x, y = a[name].values, b[name].values
            ok = np.isfinite(x) & np.isfinite(y)
            parts.append(f"{name}: largest relative difference {np.max(np.abs(x[ok] / y[ok] - 1.0)):.2e} "
                         f"over {int(ok.sum())} runs")
    return "; ".join(parts)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--workers", type=int, default=2, help="worker processes of each sweep (default 2)")
    args, trees = side_by_side(parser, ROOT, 2, "timed rounds per tree")
    targets = Targets()
    with tempfile.TemporaryDirectory(prefix="bench_grid_") as folder:
        caches = {name: Path(folder) / f"caches_{name}" for name in trees}
        for name, tree in trees.items():  # one untimed sweep: the compiled kernel and the form-found states
            _command(tree, caches[name], ["sweep", "paper_grid_st98", "--out", str(Path(folder) / f"warm_{name}.nc"),
                                          "--workers", str(args.workers), "--quiet"])

        def run(tree: Path, store: Path) -> tuple[float, Path]:
            name = next(n for n, t in trees.items() if t == tree)
            return _command(tree, caches[name], ["sweep", "paper_grid_st98", "--out", str(store),
                                                 "--workers", str(args.workers), "--quiet"]), store

        medians = time_side_by_side(
            f"presag sweep paper_grid_st98 --workers {args.workers} (400 runs)", run, trees, args.repeat,
            lambda name, round_: Path(folder) / f"{name}_{round_}.nc", _largest_difference)
    targets.below("this / base", medians["this"] / medians["base"], TARGET_RATIO + 1e-12, "")
    return targets.exit_status()


if __name__ == "__main__":
    raise SystemExit(main())
