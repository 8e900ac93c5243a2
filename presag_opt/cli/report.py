"""``presag report``: a self-contained HTML design report for a line (default: the case study)."""

from __future__ import annotations

import argparse

from presag_opt.cli.common import add_json_flag, model_help, output_folder, print_json, print_warnings, progress
from presag_opt.cli.decision_options import (
    add_band_options,
    add_decision_options,
    add_numerics_options,
    announce_dynamic,
    check_band_speed,
    decision_json,
    decision_settings,
    operating_band,
    print_decision,
    workers_of,
)
from presag_opt.design.recommendation import CASE_STUDY_MODELS
from presag_opt.system.loader import load_catenary
from presag_opt.system.stitch import stitch_summary


def register(subparsers: argparse._SubParsersAction) -> None:
    """Add the ``report`` sub-command."""
    p = subparsers.add_parser(
        "report",
        help="write a self-contained HTML design report for a line (default: the case study)",
        description=(
            "The band's decision (the same as presag recommend gives for the same models and band) with everything "
            "behind it: the Δe rule over the band, the robust design and its tolerance, the elasticity, the validity "
            "range in speed (from a stored study, or a reduced sweep run for the report), the steady-arm uplift, and "
            "every input with its provenance and every assumed value, written to DIR/index.html (figures embedded). "
            "Without options: the paper's case study."
        ),
    )
    p.add_argument("models", nargs="?", default=",".join(CASE_STUDY_MODELS), metavar="MODEL[,MODEL]",
                   help="a list of " + model_help("catenaries", ",".join(CASE_STUDY_MODELS))
                   + "; the first is also used for the robust designs and the validity sweep")
    p.add_argument("--out", metavar="DIR", required=True, help="folder to write index.html into (created if missing)")
    add_band_options(p)
    add_decision_options(p, simulated="the first model (the case study's ideal section by default)")
    add_numerics_options(p)
    p.add_argument("--pantograph", metavar="FILE", default=None,
                   help=model_help("pantographs", "case_study_2mass_friction") + " (the validity sweep and "
                   "--dynamic-robust)")
    p.add_argument("--quick", action="store_true",
                   help="a draft: a validity sweep of two pre-sags, speeds and static forces (the decision's "
                        "quasi-static parts are the same as without it)")
    add_json_flag(p)
    p.set_defaults(handler=report_command)


def report_command(args: argparse.Namespace) -> int:
    """Handler of ``presag report``."""
    import warnings

    from presag_opt.dynamics.batch.first_use import compiling_ahead
    from presag_opt.dynamics.pantograph import load_pantograph
    from presag_opt.pipeline.band import CASE_STUDY_PANTOGRAPH, DynamicOptions
    from presag_opt.report.content import REPORT_OPTIONS, design_report
    from presag_opt.report.html import write_report

    folder = output_folder(args.out)
    models = [m.strip() for m in args.models.split(",") if m.strip()]
    band = operating_band(args)
    check_band_speed(args, models)
    settings = decision_settings(args)
    pantograph = args.pantograph or CASE_STUDY_PANTOGRAPH
    dynamic = None
    if args.dynamic_robust:
        dynamic = DynamicOptions(pantograph=pantograph, workers=workers_of(args))
        announce_dynamic(args, load_catenary(models[0]), band, load_pantograph(pantograph), models[0])
    with warnings.catch_warnings(record=True) as caught, progress(args) as report, compiling_ahead():
        warnings.simplefilter("always")
        result = design_report(models, band=band, pantograph=pantograph, quick=args.quick, dynamic=dynamic,
                               element_length=args.element_length, progress=report, **settings)
        path = write_report(result, folder)
    answer = result.answer
    notes = [] if answer.validity is None or not answer.validity.record.note else [answer.validity.record.note]
    print_warnings([*(str(w.message) for w in caught), *notes])
    decision = answer.decision
    if args.json:
        print_json({"index_html": str(path), "decision": decision_json(decision, REPORT_OPTIONS),
                    "validity_source": None if answer.validity is None else answer.validity.source,
                    "quick": result.quick, "system": stitch_summary(load_catenary(models[0]))})
        return 0
    print(f"System: {models[0]}, {stitch_summary(load_catenary(models[0]))}")
    print_decision(decision.lines(REPORT_OPTIONS))
    print(f"Validity sweep: {answer.validity.source}" if answer.validity is not None else "")
    print(f"Report written to {path}")
    return 0
