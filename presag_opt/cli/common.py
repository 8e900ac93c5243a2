"""Shared pieces of the command line: running a handler, errors, tables, JSON."""

from __future__ import annotations

import argparse
import json
import math
import sys
from collections.abc import Callable, Sequence
from typing import Any

import numpy as np

from presag_opt.errors import ConvergenceError, ModelError

EXIT_BAD_INPUT = 2
EXIT_NOT_CONVERGED = 3


def run(handler: Callable[[argparse.Namespace], int | None], args: argparse.Namespace) -> int:
    """Run a sub-command handler, turning expected errors into a one-line message and exit code."""
    try:
        return handler(args) or 0
    except ModelError as exc:
        print(f"presag: error: {exc}", file=sys.stderr)
        return EXIT_BAD_INPUT
    except ConvergenceError as exc:
        print(f"presag: error: {exc}", file=sys.stderr)
        return EXIT_NOT_CONVERGED
    except KeyboardInterrupt:
        print("presag: interrupted", file=sys.stderr)
        return 130


def add_json_flag(parser: argparse.ArgumentParser) -> None:
    """Add ``--json``."""
    parser.add_argument("--json", action="store_true", help="print one JSON object instead of tables")


def print_json(obj: Any) -> None:
    """Print an object as JSON (numpy arrays and scalars converted; NaN/inf become null)."""
    print(json.dumps(_plain(obj), indent=2, allow_nan=False))


def _plain(obj: Any) -> Any:
    if isinstance(obj, dict):
        return {str(k): _plain(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [_plain(v) for v in obj]
    if isinstance(obj, np.ndarray):
        return _plain(obj.tolist())
    if isinstance(obj, (np.floating, float)):
        value = float(obj)
        return value if math.isfinite(value) else None
    if isinstance(obj, np.integer):
        return int(obj)
    if isinstance(obj, np.bool_):
        return bool(obj)
    return obj


def table(headers: Sequence[str], rows: Sequence[Sequence[Any]], formats: Sequence[str] | None = None) -> str:
    """A plain-text table with right-aligned columns."""
    formats = formats or ["{}"] * len(headers)
    cells = [[fmt.format(v) if v is not None else "-" for fmt, v in zip(formats, row)] for row in rows]
    widths = [max(len(h), *(len(r[i]) for r in cells)) if cells else len(h) for i, h in enumerate(headers)]
    lines = ["  ".join(h.rjust(w) for h, w in zip(headers, widths)), "  ".join("-" * w for w in widths)]
    lines += ["  ".join(c.rjust(w) for c, w in zip(row, widths)) for row in cells]
    return "\n".join(lines)


def positive_float(text: str) -> float:
    """argparse type: a finite number (range checks are the API's)."""
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a number") from None
    if not math.isfinite(value):
        raise argparse.ArgumentTypeError(f"{text!r} is not a finite number")
    return value


def float_list(text: str) -> list[float]:
    """argparse type: comma-separated numbers, e.g. ``50,100,150``."""
    return [positive_float(part) for part in text.split(",") if part.strip()]
