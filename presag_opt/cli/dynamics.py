"""``presag simulate``: dynamic pantograph–catenary simulation with EN 50367 statistics."""

from __future__ import annotations

import argparse
import dataclasses
from typing import TYPE_CHECKING

from presag_opt.cli.common import (
    EXIT_NOT_CONVERGED,
    add_json_flag,
    add_plot_option,
    announcer,
    float_list,
    plot_folder,
    positive_float,
    print_json,
    print_warnings,
    progress,
    table,
)
from presag_opt.errors import ModelError
from presag_opt.jobs.simulation import SCHEMES
from presag_opt.speed import check_speed_limit
from presag_opt.system.loader import builtin_model_names
from presag_opt.units import KMH

if TYPE_CHECKING:  # the simulator (scipy.signal) is imported only when `simulate` runs
    from presag_opt.dynamics.case import SimulationCase
    from presag_opt.dynamics.simulate import SimulationResult


def register(subparsers: argparse._SubParsersAction) -> None:
    """Add the ``simulate`` sub-command."""
    cases = ", ".join(builtin_model_names("cases"))
    p = subparsers.add_parser(
        "simulate",
        help="dynamic pantograph-catenary simulation (EN 50367 statistics)",
        description=(
            "Run pantographs under a catenary at constant speed and print the contact-force statistics over the "
            "central spans. Either a catenary MODEL with --pantograph, --speed and --static-force, or a --case "
            f"file that bundles them (built-in cases: {cases})."
        ),
    )
    p.add_argument("model", nargs="?", default=None, help="catenary model file or built-in name")
    p.add_argument("--case", metavar="FILE", default=None, help="case file or built-in case name")
    p.add_argument("--pantograph", metavar="FILE", default=None, help="pantograph model file or built-in name")
    p.add_argument(
        "--speed", metavar="KMH", type=float_list, default=None,
        help="train speed in km/h, or several comma-separated (default with --case: the case's speeds)",
    )
    p.add_argument(
        "--static-force", metavar="N", type=float_list, default=None,
        help="static uplift force in N, or several comma-separated (default with --case: the case's force)",
    )
    p.add_argument(
        "--aero", metavar="N_per_kmh2", type=positive_float, default=None,
        help="aerodynamic uplift coefficient in N/(km/h)^2: F_m = F_stat + aero*v^2 (default 0, or the case's)",
    )
    p.add_argument(
        "--presag", metavar="MM", type=positive_float, default=None,
        help="override the catenary's pre-sag: mid-span pre-sag of the longest span in mm",
    )
    p.add_argument(
        "--spacing", metavar="M", type=float_list, default=None,
        help="several pantographs: distances between consecutive pantographs in m, comma-separated",
    )
    p.add_argument(
        "--time-step", metavar="MS", type=positive_float, default=None,
        help="time step in ms; with this or --element-length the numerics are fixed (default: the case's "
        "numerics, automatic from the speed for the built-in cases, else 2 ms)",
    )
    p.add_argument(
        "--scheme", choices=sorted(SCHEMES), default="hht",
        help="hht: HHT-alpha with alpha = -0.005, the paper's numerical damping (default); "
        "newmark: average acceleration",
    )
    p.add_argument(
        "--element-length", metavar="M", type=positive_float, default=None,
        help="longest element in m; with this or --time-step the numerics are fixed (default: the case's "
        "numerics, automatic from the speed for the built-in cases, else 0.5 m)",
    )
    add_plot_option(p, "contact force against position (one run) or σ/F_m against speed (several)")
    p.add_argument(
        "--allow-supercritical", action="store_true",
        help="accept speeds at or above 0.7 of the contact-wire wave speed (the EN 50119 limit; refused otherwise)",
    )
    add_json_flag(p)
    p.set_defaults(handler=simulate_command)


def simulate_command(args: argparse.Namespace) -> int:
    """Handler of ``presag simulate``: one run in full, or a grid of speeds × static forces in a batch."""
    from presag_opt.jobs.simulation import simulate

    case = _case(args)
    plots = plot_folder(args)
    if not args.allow_supercritical:
        for speed in case.speeds:
            check_speed_limit(speed, case.catenary.contact_wire.wave_speed, accept="--allow-supercritical")
    try:
        with progress(args) as bar:
            answer = simulate(case=case, static_force=args.static_force, scheme=args.scheme,
                              time_step_ms=args.time_step, element_length=args.element_length,
                              allow_supercritical=True, announce=announcer(args), progress=bar)
    except ModelError as exc:  # the job names its keywords, the command line its flags
        raise ModelError(str(exc).replace("element_length=", "--element-length ").replace(
            "with time_step_ms", "with --time-step MS")) from None
    if answer.run is not None:
        return _single_run(args, answer, plots)
    return _batch(args, answer, plots)


def _case(args: argparse.Namespace) -> SimulationCase:
    """The case from ``--case``, or one built from MODEL and the flags; flags override a case's values."""
    from presag_opt.jobs.simulation import simulation_case

    if args.case is not None and args.model is not None:
        raise ModelError("give either a catenary MODEL or --case, not both")
    if args.case is None:
        if args.model is None:
            raise ModelError("give a catenary MODEL (e.g. st_9.8_ideal) or --case FILE")
        missing = [flag for flag, value in (("--pantograph", args.pantograph), ("--speed", args.speed),
                                            ("--static-force", args.static_force)) if value is None]
        if missing:
            raise ModelError(f"{', '.join(missing)} required with a catenary MODEL (or use --case FILE)")
    return simulation_case(args.model, args.pantograph, case=args.case, speed_kmh=args.speed,
                           static_force=args.static_force, aero_coefficient_kmh=args.aero, presag_mm=args.presag,
                           spacing_m=args.spacing)


def _reference_verdicts(args: argparse.Namespace, runs: list[dict]) -> list[list] | None:
    """For the EN 50318-style reference case: each run's statistics against the published ranges
    (None for other cases, or when a speed has no published ranges)."""
    from presag_opt.cli.validation import REFERENCE_CASE
    from presag_opt.validation.en50318 import EN50318_RANGES, en50318_verdicts

    if args.case != REFERENCE_CASE or any(round(r["speed_kmh"], 6) not in EN50318_RANGES for r in runs):
        return None
    return [list(en50318_verdicts(r["speed_kmh"], r)) for r in runs]


def _report_verdicts(runs: list[dict], verdicts: list[list] | None, as_json: bool) -> None:
    """Add the EN 50318 verdicts to the JSON runs, or print them under the table."""
    if verdicts is None:
        return
    if as_json:
        for run, vs in zip(runs, verdicts):
            run["en50318"] = [dataclasses.asdict(v) | {"inside": v.inside} for v in vs]
        return
    flat = [(run["speed_kmh"], v) for run, vs in zip(runs, verdicts) for v in vs]
    outside = [(speed, v) for speed, v in flat if not v.inside]
    print(f"\nEN 50318 reference ranges: {len(flat) - len(outside)} of {len(flat)} statistics inside")
    for speed, v in outside:
        print(f"  OUTSIDE at {speed:g} km/h: {v.statistic} = {v.value:.1f}, published {v.low:g} – {v.high:g}")


def _single_run(args: argparse.Namespace, answer, plots) -> int:
    result = answer.run
    print_warnings(result.warnings)
    plot = None
    if plots:
        from presag_opt.plotting import plot_contact_force

        plot = plot_contact_force([result], plots / "contact_force.png")
    runs = answer.runs()
    verdicts = _reference_verdicts(args, runs)
    if args.json:
        _report_verdicts(runs, verdicts, True)
        print_json(runs[0])
        return 0
    _print_table(answer.case, [result])
    _report_verdicts(runs, verdicts, False)
    if plot:
        print(f"\nPlot saved to {plot}")
    return 0


def _batch(args: argparse.Namespace, answer, plots) -> int:
    batch = answer.grid
    print_warnings(line for run in batch.runs for line in run.warnings)
    plot = None
    if plots:
        from presag_opt.plotting import plot_batch_statistics

        plot = plot_batch_statistics(batch, plots / "sigma_against_speed.png")
    output = answer.to_dict()
    verdicts = _reference_verdicts(args, output["runs"])
    if args.json:
        _report_verdicts(output["runs"], verdicts, True)
        print_json(output)
        return 0
    _print_batch_table(answer.case, batch)
    _report_verdicts(output["runs"], verdicts, False)
    if plot:
        print(f"\nPlot saved to {plot}")
    return 0 if not batch.failed else EXIT_NOT_CONVERGED


def _print_table(case: SimulationCase, results: list[SimulationResult]) -> None:
    first = results[0]
    op = first.operation
    spans = first.analysed_spans
    start, end = first.analysed_section
    print(f"Dynamic simulation: {case.name}")
    print(
        f"catenary: {first.catenary_name}; pantograph: {case.pantograph.name}; F_stat {op.static_force:g} N; "
        f"aero {op.aero_coefficient * KMH**2:g} N/(km/h)^2"
    )
    print(
        f"analysed: spans {spans[0] + 1}-{spans[-1] + 1} ({start:g}-{end:g} m), "
        f"filter {first.settings.cutoff_frequency:g} Hz, time step {first.settings.integrator.time_step * 1e3:g} ms, "
        f"contact-wire wave speed {first.wave_speed / KMH:.0f} km/h\n"
    )
    rows = []
    for r in results:
        d = r.to_dict()
        rows.append((
            d["speed_kmh"], d["beta"], d["Fm_N"], d["sigma_N"], d["sigma_over_Fm"], d["stat_max_N"], d["stat_min_N"],
            d["max_N"], d["min_N"], d["loss_of_contact_pct"], d["uplift_max_mm"], d["slack_droppers_max"],
        ))
    print(table(
        ["v [km/h]", "β", "F_m [N]", "σ [N]", "σ/F_m", "F_m+3σ", "F_m-3σ", "max [N]", "min [N]", "loss [%]",
         "uplift [mm]", "slack droppers"],
        rows,
        ["{:g}", "{:.3f}", "{:.1f}", "{:.2f}", "{:.3f}", "{:.1f}", "{:.1f}", "{:.1f}", "{:.1f}", "{:.2f}", "{:.1f}",
         "{}"],
    ))
    for r in results:
        if len(r.pantographs) > 1:
            print(f"\n{r.operation.speed / KMH:g} km/h, each pantograph:")
            print(table(
                ["offset [m]", "F_m [N]", "σ [N]", "max [N]", "min [N]", "loss [%]"],
                [(p.offset, p.statistics.mean_force, p.statistics.std_force, p.statistics.max_force,
                  p.statistics.min_force, 100 * p.statistics.loss_of_contact) for p in r.pantographs],
                ["{:g}", "{:.1f}", "{:.2f}", "{:.1f}", "{:.1f}", "{:.2f}"],
            ))


def _print_batch_table(case: SimulationCase, batch) -> None:
    settings = batch.settings
    first = batch.runs[0]
    start, end = first.analysed_section
    print(f"Dynamic simulation: {case.name}")
    print(
        f"catenary: {batch.catenary_name}; pantograph: {case.pantograph.name}; "
        f"aero {case.operation.aero_coefficient * KMH**2:g} N/(km/h)^2; {len(batch.runs)} runs in {batch.wall_time:.1f} s"
    )
    print(
        f"analysed: spans {first.analysed_spans[0] + 1}-{first.analysed_spans[-1] + 1} ({start:g}-{end:g} m), "
        f"filter {settings.cutoff_frequency:g} Hz, numerics {settings.numerics}, "
        f"contact-wire wave speed {first.wave_speed / KMH:.0f} km/h\n"
    )
    keys = dict(catenary=batch.catenary_name, pantograph=case.pantograph.name)
    rows = []
    for run in batch.runs:
        d = run.to_dict(**keys)
        rows.append((
            d["speed_kmh"], d["static_force_N"], d["beta"], d["time_step_ms"], d.get("Fm_N"), d.get("sigma_N"), d.get("sigma_over_Fm"),
            d.get("stat_max_N"), d.get("stat_min_N"), d.get("max_N"), d.get("min_N"), d.get("loss_of_contact_pct"),
            d.get("uplift_max_mm"), d.get("slack_droppers_max"),
        ))
    print(table(
        ["v [km/h]", "F_stat [N]", "β", "dt [ms]", "F_m [N]", "σ [N]", "σ/F_m", "F_m+3σ", "F_m-3σ", "max [N]",
         "min [N]", "loss [%]", "uplift [mm]", "slack droppers"],
        rows,
        ["{:g}", "{:g}", "{:.3f}", "{:g}", "{:.1f}", "{:.2f}", "{:.3f}", "{:.1f}", "{:.1f}", "{:.1f}", "{:.1f}",
         "{:.2f}", "{:.1f}", "{}"],
    ))
    for run in batch.failed:
        print(f"failed: {run.point.speed / KMH:g} km/h, {run.point.static_force:g} N: {run.error}")
