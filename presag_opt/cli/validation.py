"""``presag en50318``: the EN 50318-style reference case against the published reference ranges."""

from __future__ import annotations

import argparse
import dataclasses
import sys

from presag_opt.cli.common import (
    add_json_flag,
    announce_form_finding,
    float_list,
    positive_float,
    print_json,
    table,
)
from presag_opt.errors import ModelError
from presag_opt.units import KMH
from presag_opt.validation.en50318 import (
    EN50318_RANGES,
    en50318_ranges,
    en50318_verdicts,
)

REFERENCE_CASE = "en50318_2002"
"""Built-in case file of the EN 50318-style reference model."""


def register(subparsers: argparse._SubParsersAction) -> None:
    """Add the ``en50318`` sub-command."""
    speeds = ",".join(str(v) for v in EN50318_RANGES)
    p = subparsers.add_parser(
        "en50318",
        help="simulate the EN 50318-style reference case and judge it against the published ranges",
        description=(
            f"Run the built-in case {REFERENCE_CASE} and set every published statistic (F_m, σ, F_m ± 3σ, "
            "actual extremes, steady-arm uplift, loss of contact) against its EN 50318 reference range."
        ),
    )
    p.add_argument(
        "--speed", metavar="KMH", type=float_list, default=list(EN50318_RANGES),
        help=f"speeds in km/h with published ranges, comma-separated (default {speeds})",
    )
    p.add_argument(
        "--time-step", metavar="MS", type=positive_float, default=None,
        help="time step in ms; with this or --element-length the numerics are fixed (default: the case's "
        "automatic numerics)",
    )
    p.add_argument(
        "--element-length", metavar="M", type=positive_float, default=None,
        help="longest element in m; with this or --time-step the numerics are fixed (default: automatic)",
    )
    add_json_flag(p)
    p.set_defaults(handler=en50318_command)


def en50318_command(args: argparse.Namespace) -> int:
    """Handler of ``presag en50318``: one run per speed, a verdict per statistic."""
    from presag_opt.dynamics.case import (
        load_case,  # the simulator is imported only when this runs
    )
    from presag_opt.dynamics.case_grid import form_find_states
    from presag_opt.static.run_time import form_find_estimate

    case = load_case(REFERENCE_CASE)
    settings = case.settings
    if args.time_step is not None or args.element_length is not None:
        settings = settings.with_fixed_numerics(
            element_length=args.element_length, time_step=args.time_step and args.time_step * 1e-3)
    if not args.speed:
        raise ModelError("--speed: give at least one speed in km/h")
    plans = {}
    for speed in args.speed:  # every input is checked before the form-finding starts
        en50318_ranges(speed)
        plans[speed] = case.plan(speed * KMH, settings)
    for static in {p.settings.static.element_length: p.settings.static for p in plans.values()}.values():
        announce_form_finding(args, *form_find_estimate(case.catenary, static))
    states = form_find_states(case.catenary, {(speed, 0.0): plan for speed, plan in plans.items()})
    runs = []
    for speed in args.speed:
        if not args.json:
            print(f"simulating {speed:g} km/h ...", file=sys.stderr, flush=True)
        stats = case.run(speed * KMH, state=states[plans[speed].settings.static.element_length],
                         settings=settings).to_dict()
        runs.append((speed, stats, en50318_verdicts(speed, stats)))
    if args.json:
        print_json({
            "case": case.name,
            "runs": [
                {"speed_kmh": speed, "beta": stats["beta"],
                 "verdicts": [dataclasses.asdict(v) | {"inside": v.inside} for v in verdicts]}
                for speed, stats, verdicts in runs
            ],
        })
        return 0
    print(f"{case.name}: numerics {settings.numerics}")
    for speed, stats, verdicts in runs:
        chosen = plans[speed].settings
        print(f"\n{speed:g} km/h (β = {stats['beta']:.3f}; {chosen.static.element_length:g} m elements, "
              f"{chosen.integrator.time_step * 1e3:g} ms time step):")
        print(table(
            ["statistic", "value", "published range", "verdict"],
            [(v.statistic, v.value, f"{v.low:g} – {v.high:g}", "inside" if v.inside else "OUTSIDE")
             for v in verdicts],
            ["{}", "{:.1f}", "{}", "{}"],
        ))
    return 0
