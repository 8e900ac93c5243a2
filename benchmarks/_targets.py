"""Timing helpers shared by the benchmarks: medians of repeated runs and target checks that end a
benchmark with a non-zero exit status and a ``NOT MET`` line when a target is missed."""

from __future__ import annotations

import argparse
import os
import statistics
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

MIN_REPEAT = 3
"""Fewest runs a median is taken over."""


def median_time(fn: Callable[[], Any], repeat: int, *, show: bool = False) -> tuple[float, Any]:
    """Median wall time of ``repeat`` calls (at least :data:`MIN_REPEAT`) and the last result. [s]

    ``show`` prints every run's time, for a spread that a median alone hides.
    """
    if repeat < MIN_REPEAT:
        raise SystemExit(f"--repeat {repeat}: a median needs at least {MIN_REPEAT} runs")
    times, result = [], None
    for _ in range(repeat):
        start = time.perf_counter()
        result = fn()
        times.append(time.perf_counter() - start)
        if show:
            print(f"  run {len(times)}: {times[-1]:.2f} s", flush=True)
    return statistics.median(times), result


class Targets:
    """Collects target checks; :meth:`exit_status` reports the missed ones."""

    def __init__(self) -> None:
        self.missed: list[str] = []

    def below(self, name: str, value: float, limit: float, unit: str = "s") -> bool:
        """Check ``value < limit`` and print the verdict."""
        return self._verdict(name, value < limit, f"{value:.3g} {unit} (target < {limit:g} {unit})")

    def at_least(self, name: str, value: float, limit: float, unit: str = "") -> bool:
        """Check ``value >= limit`` and print the verdict."""
        return self._verdict(name, value >= limit, f"{value:.3g}{unit} (target >= {limit:g}{unit})")

    def _verdict(self, name: str, met: bool, text: str) -> bool:
        print(f"  {name}: {text}: {'met' if met else 'NOT MET'}", flush=True)
        if not met:
            self.missed.append(f"{name}: {text}")
        return met

    def exit_status(self) -> int:
        """0 if every target was met; otherwise print one ``NOT MET`` line per miss and return 1."""
        for line in self.missed:
            print(f"NOT MET: {line}")
        if not self.missed:
            print("all targets met")
        return 1 if self.missed else 0


def side_by_side(parser: argparse.ArgumentParser, root: Path, repeat: int,
                 repeat_help: str) -> tuple[argparse.Namespace, dict[str, Path]]:
    """Parse the options of a benchmark that runs this tree and a base tree side by side (``--base``,
    ``--repeat`` and the parser's own); returns them and the trees by name (``this``, ``base``)."""
    parser.add_argument("--base", type=Path, required=True, help="the base tree (a checkout of the base commit)")
    parser.add_argument("--repeat", type=int, default=repeat, help=repeat_help)
    args = parser.parse_args()
    return args, {"this": root, "base": args.base.resolve()}


def time_side_by_side(title: str, run: Callable[[Path, Path], tuple[float, Any]], trees: dict[str, Path],
                      repeat: int, target: Callable[[str, int], Path], compare: Callable[[Any, Any], str],
                      warm_up: bool = False) -> dict[str, float]:
    """Time one part on this tree and the base tree, alternating, and print every run, the medians, the
    ratio this / base, ``compare(answer this, answer base)`` and the load average before and after.

    Parameters
    ----------
    title : str
        What the part runs.
    run : callable
        ``run(tree, target) -> (wall time [s], answer)``.
    trees : dict
        ``{"this": Path, "base": Path}`` (:func:`side_by_side`).
    repeat : int
        Counted rounds. [-]
    target : callable
        ``target(tree name, round) -> Path`` where a run writes its output.
    compare : callable
        Describes the difference of two answers in one line.
    warm_up : bool
        Run one more round first, not counted (fills caches).

    Returns
    -------
    dict
        The median wall time per tree. [s]
    """
    print(f"{title}: load average before {os.getloadavg()}", flush=True)
    times: dict[str, list[float]] = {name: [] for name in trees}
    answers: dict[str, Any] = {}
    for round_ in range(repeat + int(warm_up)):
        counted = round_ >= int(warm_up)
        for name, tree in trees.items():
            wall, answers[name] = run(tree, target(name, round_))
            if counted:
                times[name].append(wall)
            print(f"  {name}: {wall:7.2f} s{'' if counted else ' (warm-up, not counted)'}", flush=True)
    medians = {name: statistics.median(t) for name, t in times.items()}
    print(f"  medians: this {medians['this']:.2f} s, base {medians['base']:.2f} s; "
          f"this / base {medians['this'] / medians['base']:.3f}")
    print(f"  {compare(answers['this'], answers['base'])}")
    print(f"  load average after {os.getloadavg()}", flush=True)
    return medians
