"""``presag design``: design a surveyed line (a CSV, xlsx or TOML table of masts) on a system model."""

from __future__ import annotations

import argparse
import dataclasses
import time

from presag_opt.cli.common import (
    add_json_flag,
    model_help,
    output_folder,
    print_json,
    print_warnings,
    progress,
    report_failures,
)
from presag_opt.cli.dynamic_robust import add_dynamic_robust_option, dynamic_robust, dynamic_robust_summary
from presag_opt.cli.recommend import add_band_options, check_band_speed, operating_band
from presag_opt.errors import ModelError


def register(subparsers: argparse._SubParsersAction) -> None:
    """Add the ``design`` sub-command."""
    p = subparsers.add_parser(
        "design",
        help="design a surveyed line: per-span pre-sag, a dropper schedule and one decision",
        description=(
            "Read a survey table (one row per mast: mast, chainage_m, stagger_mm, contact_wire_height_m, "
            "system_height_m, curve_radius_m, steady_arm, optionally section) and design every tension section "
            "on the system model's wires, tensions, droppers and supports: the decision (what to build and why), "
            "DIR/droppers.csv, DIR/spans.csv and DIR/index.html (the line report). Overlap spans between "
            "sections are not modelled."
        ),
    )
    p.add_argument("survey", metavar="SURVEY", help="survey table: .csv, .xlsx or .toml")
    p.add_argument("--system", metavar="SYSTEM", required=True,
                   help=model_help("catenaries", "st_9.8_mixed") + "; its layout and geometry are replaced by the survey")
    p.add_argument("--out", metavar="DIR", required=True, help="folder for the outputs (created if missing)")
    add_band_options(p)
    p.add_argument("--rule", choices=("proportional", "per-span", "robust"), default="proportional",
                   help="pre-sag per span: S = S_rel·l with the line's S_rel (default, Swedish practice); each "
                        "span's own quasi-static S_rel; or each span's own quasi-static robust parabola (minimax "
                        "waviness over the F_m band, below the line between its supports), with its tolerance "
                        "in spans.csv")
    p.add_argument("--within", metavar="PERCENT", type=float, default=None,
                   help="allowed loss of each span's tolerance interval under --rule robust, in %% (default 10)")
    p.add_argument("--working-width", metavar="MM", type=float, default=400.0,
                   help="half working width of the pantograph: largest stagger accepted, in mm (default 400)")
    p.add_argument("--element-length", metavar="M", type=float, default=0.5, help="longest element in m (default 0.5)")
    p.add_argument("--step", metavar="M", type=float, default=1.0,
                   help="point spacing of the elasticity curves in m (default 1.0)")
    p.add_argument("--workers", metavar="N", type=int, default=2, help="processes for the sections (default 2)")
    p.add_argument("--dynamic-check", action="store_true",
                   help="also simulate the band's worst points (top speed, highest static force) on the section "
                        "with the largest static uplift")
    add_dynamic_robust_option(p, "the line's worst section (the largest static uplift estimate)")
    p.add_argument("--xlsx", action="store_true", help="also write DIR/line_design.xlsx (needs openpyxl)")
    add_json_flag(p)
    p.set_defaults(handler=design_command)


def _span_rule(args: argparse.Namespace):
    """The span rule of ``--rule robust`` (None for the other rules)."""
    if args.rule != "robust":
        if args.within is not None:
            raise ModelError(f"--within is an option of --rule robust, not of --rule {args.rule}")
        return None
    from presag_opt.robust.span_design import RobustSpanRule

    return RobustSpanRule(within=(10.0 if args.within is None else args.within) / 100.0)


def design_command(args: argparse.Namespace) -> int:
    """Handler of ``presag design``."""
    import warnings

    from presag_opt.design.line import LineOptions, design_line
    from presag_opt.report.line_report import write_line_outputs
    from presag_opt.system.loader import load_catenary
    from presag_opt.system.survey import load_survey

    survey = load_survey(args.survey, working_width=args.working_width * 1e-3)
    base = load_catenary(args.system)
    band = operating_band(args)
    check_band_speed(args, [base])
    options = LineOptions(rule=args.rule, element_length=args.element_length, step=args.step, workers=args.workers)
    span_rule = _span_rule(args)
    folder = output_folder(args.out)
    start = time.perf_counter()
    with warnings.catch_warnings(record=True) as caught, progress(args) as report:
        warnings.simplefilter("always")
        design = design_line(survey, base, band, options, progress=report, span_rule=span_rule)
        check = None
        if args.dynamic_check:
            from presag_opt.report.line_dynamic import dynamic_check

            check = dynamic_check(design, progress=report)
            design = check.design
        robust = None
        if args.dynamic_robust:
            worst = max(design.sections, key=lambda sec: max(s.static_uplift for s in sec.spans if s.sized))
            robust = dynamic_robust(args, design.decision, worst.catenary.with_presag(design.presag_rel), band,
                                    f"section {worst.section}", report)
            design = dataclasses.replace(design, decision=robust.decision)
        paths = write_line_outputs(design, folder, xlsx=args.xlsx, dynamic_check=None if check is None else check.html())
    seconds = time.perf_counter() - start
    print_warnings(str(w.message) for w in caught)
    l_nom = design.nominal_span_length
    if args.json:
        print_json({
            "decision": design.decision.to_dict(l_nom),
            "presag_rel_permille": design.presag_rel * 1e3,
            "sections": [s.section for s in design.sections],
            "spans": len(design.spans),
            "droppers": len(design.droppers),
            "rules_failing": [{"section": r.section, "rule": r.rule, "status": r.status, "worst": r.worst}
                              for r in design.rules if not r.passed],
            "notes": list(design.notes),
            "outputs": {k: str(v) for k, v in paths.items()},
            "dynamic_robust": None if robust is None else dynamic_robust_summary(robust),
            "seconds": seconds,
            "failures": [{**e.inputs, "reason": e.failure} for e in design.failures],
        })
        return report_failures("design", design.failure_summary())
    print("\n".join(design.decision.lines(l_nom)))
    print(f"\n{len(design.survey.masts)} masts, {len(design.sections)} sections, {len(design.spans)} spans, "
          f"{len(design.droppers)} droppers designed in {seconds:.1f} s")
    for note in design.notes:
        print(f"Note: {note}")
    for r in design.rules:
        if not r.passed:
            print(f"Design rule, section {r.section}: {r.rule}: {r.worst} — {r.status}")
    for name, path in paths.items():
        print(f"{name}: {path}")
    return report_failures("design", design.failure_summary())
