"""Time ``presag design`` on a made-up 5 km line: 100 spans in 4 tension sections, every output.

Run: ``python benchmarks/bench_line_design.py [--repeat N] [--python PY] [--extra "--round 5 --dxf"]``.
Writes the survey as a CSV, runs the command line (``PY -m presag_opt.cli design``, with ``--xlsx`` and the
options of ``--extra``) ``--repeat`` times and prints the median wall time, the fastest and the slowest run
(a cold start of the interpreter included: what a user waits for). ``--python`` times another checkout's
interpreter on the same survey (side by side, e.g. the one at the branch point), ``--target`` sets the
time the median must stay below. The line: ST 9,8/9,8 wires on spans of 45–55 m, two curves (R 800 m and
−1200 m, the latter with 60 mm of cant where the survey has a ``cant_mm`` column) with the wire registered
to the outside, and a bridge lowering the contact wire by 0.2 m at two masts.
"""

from __future__ import annotations

import argparse
import csv
import shlex
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

COLUMNS = ("mast", "chainage_m", "stagger_mm", "contact_wire_height_m", "system_height_m", "curve_radius_m",
           "steady_arm", "section")


def five_km_rows(spans_per_section: int = 25, sections: int = 4, cant: bool = False) -> list[dict[str, object]]:
    """The survey rows of the 5 km line (4 × 25 spans of 45–55 m, two curves and a bridge). [m], [mm]"""
    rows, chainage, k = [], 0.0, 0
    for sec in range(sections):
        for i in range(spans_per_section + 1):
            if sec and i == 0:
                chainage += 50.0  # the overlap span to the previous section (not modelled)
            radius = 800.0 if 30 <= k < 45 else -1200.0 if 70 <= k < 85 else 0.0
            stagger = -0.25 if radius > 0 else 0.25 if radius < 0 else (0.3 if k % 2 == 0 else -0.3)
            height = 5.3 if k in (55, 56) else 5.5  # a bridge
            row = {"mast": f"M{k + 1}", "chainage_m": round(chainage, 3), "stagger_mm": stagger * 1e3,
                   "contact_wire_height_m": height, "system_height_m": 1.2 if k not in (55, 56) else 1.0,
                   "curve_radius_m": radius, "steady_arm": "pull-off", "section": f"S{sec + 1}"}
            if cant:
                row["cant_mm"] = 60.0 if radius < 0 else 0.0
            rows.append(row)
            chainage += 45.0 + 10.0 * ((k * 7) % 11) / 10.0 if i < spans_per_section else 0.0
            k += 1
    return rows


def write_survey(path: Path, cant: bool = False) -> Path:
    """The 5 km survey as a CSV file."""
    rows = five_km_rows(cant=cant)
    with path.open("w", newline="", encoding="utf-8") as handle:
        writer = csv.DictWriter(handle, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)
    return path


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--python", default=sys.executable, help="interpreter whose presag_opt is timed")
    parser.add_argument("--extra", default="", help="further options of presag design, e.g. \"--round 5 --dxf\"")
    parser.add_argument("--cant", action="store_true", help="the survey with a cant_mm column")
    parser.add_argument("--target", type=float, default=None, help="the median must stay below this [s]")
    args = parser.parse_args()
    times = []
    with tempfile.TemporaryDirectory(prefix="presag-bench-line-") as tmp:
        survey = write_survey(Path(tmp) / "five_km_line.csv", cant=args.cant)
        for run in range(args.repeat):
            out = Path(tmp) / f"out{run}"
            command = [args.python, "-m", "presag_opt.cli", "design", str(survey), "--system", "st_9.8_mixed",
                       "--out", str(out), "--xlsx", "--no-cache", *shlex.split(args.extra)]
            start = time.perf_counter()
            done = subprocess.run(command, capture_output=True, text=True)
            times.append(time.perf_counter() - start)
            if done.returncode != 0:
                print(done.stdout + done.stderr, file=sys.stderr)
                return done.returncode
            print(f"  run {run + 1}: {times[-1]:.1f} s", flush=True)
        print(done.stdout.splitlines()[0])
    median = statistics.median(times)
    print(f"presag design, 5 km line ({args.python} {args.extra}): median {median:.1f} s over {len(times)} runs "
          f"(fastest {min(times):.1f} s, slowest {max(times):.1f} s)")
    if args.target is not None and median >= args.target:
        print(f"NOT MET: median {median:.1f} s, target < {args.target:g} s")
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
