"""``presag sweep`` and ``presag validity``: run a validity study, and analyse its store."""

from __future__ import annotations

import argparse
import warnings

from presag_opt.cli.common import (
    add_json_flag,
    announce_work,
    print_json,
    print_warnings,
    progress,
    table,
)
from presag_opt.cli.decision_options import add_workers_option, workers_of
from presag_opt.errors import ModelError
from presag_opt.system.loader import builtin_model_names

DEFAULT_STUDY = "paper_grid_st98"


def register(subparsers: argparse._SubParsersAction) -> None:
    """Add the ``sweep`` and ``validity`` sub-commands."""
    studies = ", ".join(builtin_model_names("studies"))
    p = subparsers.add_parser(
        "sweep",
        help="run a validity study (pre-sag x speed x static force grid) into a netCDF store",
        description=(
            "Run every point of a study grid with the dynamic simulator and write the statistics to a netCDF "
            "store. Finished units are kept in PATH.units beside the store: a killed study resumes where it "
            f"stopped. Built-in studies: {studies}."
        ),
    )
    p.add_argument("study", nargs="?", default=DEFAULT_STUDY,
                   help=f"study file or built-in name (default {DEFAULT_STUDY})")
    p.add_argument("--out", metavar="PATH", required=True, help="netCDF store to write (e.g. study.nc)")
    add_workers_option(p, scheduler=True)
    p.add_argument("--scheduler", metavar="ADDRESS", default=None,
                   help="Dask distributed scheduler to run on instead (e.g. tcp://host:8786)")
    p.add_argument("--allow-supercritical", action="store_true",
                   help="accept speeds at or above 0.7 of the contact-wire wave speed (the EN 50119 limit)")
    p.set_defaults(handler=sweep_command)

    p = subparsers.add_parser(
        "validity",
        help="validity limit of the quasi-static pre-sag rule from a study store",
        description=(
            "Analyse a study store: optimal F_m per pre-sag (paper Fig. 6/8), optimal and near-optimal pre-sag "
            "per speed ratio beside the quasi-static rules (Fig. 7), the validity limit beta*, the fit "
            "S_dyn = S_stat + k*beta^a, and the steady-arm uplift against its limit."
        ),
    )
    p.add_argument("store", metavar="PATH", help="netCDF store written by `presag sweep`")
    p.add_argument("--select", metavar="NAME=VALUE", action="append", default=[],
                   help="value (SI) of a swept extra parameter; one per extra parameter of the study")
    p.add_argument("--pantograph", choices=("leading", "trailing"), default=None,
                   help="pantograph of a two-pantograph study to analyse (default: trailing, the one that runs "
                        "into the wire the leading one set swinging)")
    p.add_argument("--plot", metavar="DIR", default=None, help="save the figures (PNG) into this folder")
    add_json_flag(p)
    p.set_defaults(handler=validity_command)


def sweep_command(args: argparse.Namespace) -> int:
    """Handler of ``presag sweep``."""
    from pathlib import Path

    from presag_opt.studies.definition import load_study
    from presag_opt.studies.runner import (
        check_study_path,
        check_study_speeds,
        estimate_study,
        run_study,
    )

    with warnings.catch_warnings(record=True) as caught:  # shown only if the study is not refused
        warnings.simplefilter("always")
        definition = load_study(args.study)
    store = Path(args.out)
    check_study_path(store)
    check_study_speeds(definition, args.allow_supercritical)
    print_warnings(str(w.message) for w in caught)
    workers = workers_of(args)
    if args.scheduler is None:
        announce_work(args, estimate_study(definition, store, workers=workers))
    with progress(args, total=None) as report:
        outcome = run_study(definition, store, workers=None if args.scheduler else workers, scheduler=args.scheduler,
                            progress=report, allow_supercritical=args.allow_supercritical)
    print(f"{definition.name}: {outcome.runs_total} runs ({outcome.units_computed} of {outcome.units_total} units "
          f"computed now, the rest resumed), {outcome.runs_failed} failed; store {outcome.store}")
    return 0


def validity_command(args: argparse.Namespace) -> int:
    """Handler of ``presag validity``."""
    from presag_opt.jobs import validity
    from presag_opt.studies.store import open_store
    from presag_opt.studies.validity_analysis import pantograph_view

    dataset, pantograph = pantograph_view(open_store(args.store), args.pantograph)
    result = validity(args.store, select=_selection(args.select), pantograph=args.pantograph)
    if args.plot:
        from presag_opt.studies.plots import save_validity_plots

        paths = save_validity_plots(dataset, result, args.plot, _selection(args.select))
    if args.json:
        print_json(result.to_dict())
        return 0
    summary = result.to_dict()
    limit = summary["beta_limit"]
    print(f"Validity of the quasi-static pre-sag rule: {dataset.attrs.get('study_name', args.store)}")
    if "trailing_F_m" in dataset:
        print(f"pantograph: {pantograph} (of two, the second {dataset.attrs.get('second_pantograph_at')} m behind)")
    print("beta* = " + ("not reached" if limit is None else f"{limit:.3f} ± {summary['beta_limit_uncertainty']:.3f}"))
    print(f"criterion: {summary['criterion']}")
    fit = summary["fit"]
    print("fit S_dyn = S_stat + k*beta^a: " + (f"no fit ({summary['no_fit_reason']})" if fit is None else
                                               f"k = {fit['k_mm']:.1f} mm, a = {fit['a']:.2f}, r² = {fit['r2']:.3f}"))
    uplift = summary["uplift"]
    if uplift is not None:
        verdict = "within" if uplift["within_limit"] else "ABOVE"
        print(f"max steady-arm uplift {uplift['max_mm']:.1f} mm ({verdict} the limit {uplift['limit_mm']:.1f} mm) at "
              f"S {uplift['presag_mm']:.0f} mm, {uplift['speed_kmh']:.0f} km/h, F_stat {uplift['static_force_N']:.0f} N")
    print()
    rows = []
    for entry in summary["per_beta"]:
        bands = entry["bands"]
        inside = sum(b["rule_inside"] for b in bands if b["benefit"])
        benefit = sum(b["benefit"] for b in bands)
        rows.append((entry["beta"], entry["speed_kmh"], benefit, len(bands), inside, "yes" if entry["holds"] else "no"))
    print(table(["β", "v [km/h]", "S matters", "of F_m", "Δe rule in band", "holds"], rows,
                ["{:.3f}", "{:.0f}", "{}", "{}", "{}", "{}"]))
    if args.plot:
        print("\nPlots saved: " + ", ".join(str(p) for p in paths))
    return 0


def _selection(items: list[str]) -> dict[str, float]:
    selection = {}
    for item in items:
        name, sep, value = item.partition("=")
        try:
            selection[name.strip()] = float(value)
        except ValueError:
            sep = ""
        if not sep:
            raise ModelError(f"--select {item!r}: write NAME=VALUE with a number in SI units")
    return selection
