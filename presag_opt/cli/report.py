"""``presag report``: a self-contained HTML design report for a line (default: the case study)."""

from __future__ import annotations

import argparse

from presag_opt.cli.common import add_json_flag, model_help, output_folder, print_json, print_warnings, progress
from presag_opt.cli.dynamic_robust import add_dynamic_robust_option, dynamic_robust, dynamic_robust_summary
from presag_opt.cli.recommend import add_band_options, check_band_speed, operating_band
from presag_opt.cli.robust import parse_within
from presag_opt.design.band import KMH
from presag_opt.design.recommendation import CASE_STUDY_MODELS
from presag_opt.system.loader import load_catenary
from presag_opt.system.stitch import stitch_summary


def register(subparsers: argparse._SubParsersAction) -> None:
    """Add the ``report`` sub-command."""
    p = subparsers.add_parser(
        "report",
        help="write a self-contained HTML design report for a line (default: the case study)",
        description=(
            "Compute the recommended pre-sag over the operating band, the robust design and its installation "
            "tolerance, the elasticity, the validity range in speed (from a stored study, or a reduced sweep run "
            "for the report) and the steady-arm uplift, and write them with every input, its provenance and every "
            "assumed value to DIR/index.html (figures embedded). Without options: the paper's case study."
        ),
    )
    p.add_argument("models", nargs="?", default=",".join(CASE_STUDY_MODELS), metavar="MODEL[,MODEL]",
                   help="a list of " + model_help("catenaries", ",".join(CASE_STUDY_MODELS))
                   + "; the first is also used for the robust design and the validity sweep")
    p.add_argument("--out", metavar="DIR", required=True, help="folder to write index.html into (created if missing)")
    add_band_options(p)
    p.add_argument("--pantograph", metavar="FILE", default=None,
                   help=model_help("pantographs", "case_study_2mass_friction") + " (for the validity sweep)")
    p.add_argument("--study", metavar="PATH", default=None,
                   help="a study store written by `presag sweep` to read the validity range from "
                        "(default: a reduced sweep run for the report)")
    p.add_argument("--within", default="10", metavar="PERCENT",
                   help="allowed loss of the tolerance band in %%, e.g. 10 or 10%% (default 10)")
    p.add_argument("--quick", action="store_true",
                   help="a draft in seconds: 1 m elements, 4 ms time step, a 2 x 2 x 2 sweep")
    add_dynamic_robust_option(p, "the first model (the case study's ideal section by default)")
    add_json_flag(p)
    p.set_defaults(handler=report_command)


def report_command(args: argparse.Namespace) -> int:
    """Handler of ``presag report``."""
    import warnings

    from presag_opt.report.content import CASE_STUDY_PANTOGRAPH, design_report
    from presag_opt.report.html import write_report

    folder = output_folder(args.out)
    models = [m.strip() for m in args.models.split(",") if m.strip()]
    within = parse_within(args.within)
    band = operating_band(args)
    check_band_speed(args, models)
    with warnings.catch_warnings(record=True) as caught, progress(args) as report:
        warnings.simplefilter("always")
        result = design_report(models, band=band, pantograph=args.pantograph or CASE_STUDY_PANTOGRAPH,
                               study=args.study, within=within, quick=args.quick, progress=report)
        robust = None
        if args.dynamic_robust:  # the report is then headed by the decision made with it
            import dataclasses

            first = load_catenary(models[0])
            robust = dynamic_robust(args, result.decision, first, band, first.name, report)
            result = dataclasses.replace(result, decision=robust.decision)
        path = write_report(result, folder)
    print_warnings([*(str(w.message) for w in caught), *result.validity.warnings])
    tol, validity, decision = result.robust.tolerance, result.validity, result.decision
    l_ref = result.robust.reference_span
    summary = {
        "index_html": str(path),
        "decision": decision.to_dict(l_ref),
        "presag_rel_permille": decision.chosen.presag_rel * 1e3,
        "presag_mm": decision.chosen.presag_rel * l_ref * 1e3,
        "reference_span_m": l_ref,
        "tolerance_mm": [tol.low * l_ref * 1e3, tol.high * l_ref * 1e3],
        "beta_limit": validity.result.beta_limit,
        "limit_speed_kmh": None if validity.limit_speed is None else validity.limit_speed / KMH,
        "validity_source": validity.source,
        "quick": result.quick,
        "system": stitch_summary(load_catenary(result.models[0])),
    }
    if robust is not None:
        summary["dynamic_robust"] = dynamic_robust_summary(robust)
    if args.json:
        print_json(summary)
        return 0
    low, high = summary["tolerance_mm"]
    print(f"System: {result.models[0]}, {summary['system']}")
    print("\n".join(decision.lines(l_ref)))
    print(f"Quasi-static tolerance {low:.0f}–{high:.0f} mm on {l_ref:g} m")
    print(f"Validity ({'stored study' if args.study else 'reduced sweep'}): {validity.text()}")
    print(f"Report written to {path}")
    return 0
