"""β* of the Δe rule with two raised pantographs, beside one pantograph (issue 23, item 7).

Run: python research/two_pantographs.py [--grid small|paper] [--spacing M] [--out DIR] [--workers N]

The paper's grid (``paper_grid_st98``: ST 9,8/9,8 ideal 60 m spans, the case-study pantograph) on
the 9 central spans with 1 m elements and 4 ms steps: ``--grid paper`` keeps its axes (5 pre-sags
30–70 mm × 10 speeds 50–180 km/h × 8 static forces 50–155 N, 400 runs), ``--grid small`` (default)
takes 5 pre-sags × 7 speeds (60–180 km/h) × 4 static forces (65–155 N) (:func:`~presag_opt.studies.reduced.reduced_study`;
coarse numerics locate β* roughly, see that module). Two studies on the same grid: one pantograph,
and a second one ``--spacing`` metres behind (default 100 m, two coupled multiple units). Both are
run as ordinary studies into netCDF stores (resumable) and analysed for the single pantograph and
for the leading and the trailing pantograph of the pair.
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import os
import sys
import time
from pathlib import Path

from presag_opt.studies.definition import StudyTrain, load_study
from presag_opt.studies.reduced import reduced_study
from presag_opt.studies.runner import run_study
from presag_opt.studies.store import open_store
from presag_opt.studies.validity_analysis import validity_analysis
from presag_opt.units import KMH

PRESAGS = (0.030, 0.040, 0.050, 0.060, 0.070)
SPEEDS = tuple(v * KMH for v in (60, 80, 100, 120, 140, 160, 180))
FORCES = (65.0, 95.0, 125.0, 155.0)
SPANS = 9
"""Central spans kept: room for a second pantograph up to 180 m behind the leading one. [-]"""


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--spacing", type=float, default=100.0, help="second pantograph behind the first [m]")
    parser.add_argument("--out", default="two_pantograph_study", help="folder of the stores")
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--grid", choices=("small", "paper"), default="small")
    args = parser.parse_args()
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    base = load_study("paper_grid_st98")
    axes = (PRESAGS, SPEEDS, FORCES) if args.grid == "small" else \
        (base.grid.presags, base.grid.speeds, base.grid.static_forces)
    single = reduced_study(base, presags=axes[0], speeds=axes[1], static_forces=axes[2], span_count=SPANS)
    pair = dataclasses.replace(single, name=f"{single.name}, second pantograph {args.spacing:g} m behind",
                               train=StudyTrain(second_pantograph_at=args.spacing))
    results = {}
    for label, definition in (("single", single), ("pair", pair)):
        started = time.perf_counter()
        store = out / f"{label}.nc"
        run = run_study(definition, store, workers=args.workers,
                        progress=lambda m: print("  " + m, file=sys.stderr, flush=True))
        print(f"{label}: {run.runs_total} runs, {run.runs_failed} failed, {time.perf_counter() - started:.0f} s "
              f"(load average {', '.join(f'{x:.1f}' for x in os.getloadavg())})", flush=True)
        dataset = open_store(store)
        for pantograph in (("leading",) if label == "single" else ("leading", "trailing")):
            result = validity_analysis(dataset, pantograph=pantograph)
            key = "single" if label == "single" else pantograph
            results[key] = {"beta_limit": result.beta_limit, "uncertainty": result.beta_limit_uncertainty,
                            "criterion": result.criterion,
                            "holds": {f"{v.beta:.3f}": v.holds for v in result.per_beta}}
            limit = "not reached" if result.beta_limit is None else \
                f"{result.beta_limit:.3f} ± {result.beta_limit_uncertainty:.3f}"
            print(f"  beta* ({key}): {limit}; holds per beta: "
                  + ", ".join(f"{v.beta:.3f} {'yes' if v.holds else 'no'}" for v in result.per_beta), flush=True)
    (out / "beta_limits.json").write_text(json.dumps(results, indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main())
