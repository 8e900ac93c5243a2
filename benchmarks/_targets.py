"""Timing helpers shared by the benchmarks: medians of repeated runs and target checks that end a
benchmark with a non-zero exit status and a ``NOT MET`` line when a target is missed."""

from __future__ import annotations

import argparse
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
