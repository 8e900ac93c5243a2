"""Whether the paper's grid could run fewer steps: its statistics against a longer time step at the
low speeds and against fewer lead-in spans.

Run: python research/grid_numerics.py [--quick]

The 400-run grid (``paper_grid_st98``) spends most of its time stepping the slow runs: at 2 ms a run at
50 km/h is 8 765 steps, one at 180 km/h 2 525. Two ways to fewer steps are measured here on a part of
the grid (S 30 and 70 mm × F_stat 50, 110 and 155 N), each against its own reference, with the
grid's 0.5 m elements:

- the time step at 50–120 km/h, where the automatic numerics' rule
  (:func:`presag_opt.dynamics.numerics.numerics_for_speed`) would allow 2.0–2.7 ms without its 2 ms
  cap: 2.0, 2.5 and 3.0 ms against 0.5 ms;
- the lead-in before the two analysed spans at 50, 90, 140 and 180 km/h and 2 ms: 1, 2 and 3 spans
  against 4 (the pantograph then starts at the section's first mast).

Printed per speed: the largest relative change over the pre-sags and forces of σ, F_m and the
largest steady-arm uplift, and the wall time of each rung (one process). ``--quick`` runs two rungs
per ladder and one pre-sag.
"""

from __future__ import annotations

import argparse
import dataclasses
import time

import numpy as np

from presag_opt.studies.definition import load_study
from presag_opt.studies.reduced import run_in_process
from presag_opt.units import KMH

COMPARED = ("sigma", "F_m", "uplift_max")
"""Store variables compared: σ, F_m [N] and the largest steady-arm uplift [m]."""

FORCES = (50.0, 110.0, 155.0)
"""Static forces of the part of the grid run. [N]"""

TIME_STEPS_MS = (2.0, 2.5, 3.0, 0.5)
"""Time-step ladder at 0.5 m elements, reference last. [ms]"""

STEP_SPEEDS = (50, 60, 70, 80, 90, 100, 120)
"""Speeds of the time-step ladder: those where the rule's step exceeds 2 ms. [km/h]"""

LEAD_INS = (1, 2, 3, 4)
"""Lead-in spans ladder, reference last. [-]"""

LEAD_SPEEDS = (50, 90, 140, 180)
"""Speeds of the lead-in ladder. [km/h]"""


def _run(base, presags_mm, speeds_kmh, *, time_step=None, lead_in=None):
    settings = base.settings
    if time_step is not None:
        integrator = dataclasses.replace(settings.integrator, time_step=time_step)
        settings = dataclasses.replace(settings, integrator=integrator)
    if lead_in is not None:
        settings = dataclasses.replace(settings, lead_in_spans=lead_in)
    grid = dataclasses.replace(base.grid, presags=tuple(s * 1e-3 for s in presags_mm),
                               speeds=tuple(v * KMH for v in speeds_kmh), static_forces=FORCES)
    started = time.perf_counter()
    dataset = run_in_process(dataclasses.replace(base, grid=grid, settings=settings))
    return dataset, time.perf_counter() - started


def _table(title, labels, datasets, seconds, speeds_kmh):
    reference = datasets[-1]
    print(f"\n{title}: largest |change| over pre-sags and forces against {labels[-1]}, per speed [%]")
    print(f"{'':10} {'':>10} " + " ".join(f"{v:>6}" for v in speeds_kmh) + "   wall [s]")
    for label, dataset, wall in zip(labels[:-1], datasets[:-1], seconds[:-1], strict=True):
        for name in COMPARED:
            change = np.abs(dataset[name] / reference[name] - 1.0).squeeze()
            worst = change.max(dim=[d for d in change.dims if d != "speed"]).values
            print(f"{label:10} {name:>10} " + " ".join(f"{100 * w:6.2f}" for w in worst) + f"   {wall:8.1f}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="two rungs per ladder, one pre-sag")
    args = parser.parse_args()
    base = load_study("paper_grid_st98")
    presags = (30.0,) if args.quick else (30.0, 70.0)
    steps = (TIME_STEPS_MS[0], TIME_STEPS_MS[-1]) if args.quick else TIME_STEPS_MS
    leads = (LEAD_INS[1], LEAD_INS[-1]) if args.quick else LEAD_INS
    runs = [_run(base, presags, STEP_SPEEDS, time_step=dt * 1e-3) for dt in steps]
    _table("time step, 0.5 m elements, 2 lead-in spans", [f"{dt:g} ms" for dt in steps],
           [d for d, _ in runs], [w for _, w in runs], STEP_SPEEDS)
    runs = [_run(base, presags, LEAD_SPEEDS, lead_in=n) for n in leads]
    _table("lead-in, 0.5 m and 2 ms", [f"{n} span(s)" for n in leads], [d for d, _ in runs], [w for _, w in runs],
           LEAD_SPEEDS)


if __name__ == "__main__":
    main()
