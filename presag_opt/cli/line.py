"""``presag design``: design a surveyed line (a CSV, xlsx or TOML table of masts) on a system model."""

from __future__ import annotations

import argparse
import shutil
import time
from pathlib import Path

from presag_opt.cli.common import (
    add_json_flag,
    model_help,
    output_folder,
    print_json,
    print_warnings,
    progress,
    report_failures,
)
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
from presag_opt.system.dropper_type import DEFAULT_DROPPER_TYPE


def register(subparsers: argparse._SubParsersAction) -> None:
    """Add the ``design`` sub-command."""
    p = subparsers.add_parser(
        "design",
        help="design a surveyed line: per-span pre-sag, a dropper schedule and one decision",
        description=(
            "Read a survey table (one row per mast: mast, chainage_m, stagger_mm, contact_wire_height_m, "
            "system_height_m, curve_radius_m, steady_arm, optionally section, cant_mm, stitched) and design every tension section "
            "on the system model's wires, tensions, droppers and supports: the decision (what to build and why, "
            "with every sized span's built pre-sag checked against its own tolerance), DIR/droppers.csv (the crew's "
            "schedule: dropper ids, chainages, heights, lateral positions and cut lengths), DIR/spans.csv, "
            "DIR/rounding.csv with --round, and DIR/index.html (the line report with the crew's printable dropper "
            "sheets). With cant_mm the stagger and height are as the pantograph sees them on the canted track. "
            "Overlap spans between sections are not modelled."
        ),
    )
    p.add_argument("survey", metavar="SURVEY", help="survey table: .csv, .xlsx or .toml")
    p.add_argument("--system", metavar="SYSTEM", required=True,
                   help=model_help("catenaries") + "; its layout and geometry are replaced by the survey")
    p.add_argument("--out", metavar="DIR", required=True, help="folder for the outputs (created if missing)")
    add_band_options(p)
    add_decision_options(p, simulated="the line's worst section (the largest static uplift estimate)",
                         monte_carlo=False)
    p.add_argument("--rule", choices=("proportional", "per-span", "robust"), default="proportional",
                   help="pre-sag per span: S = S_rel·l with the line's S_rel (default, Swedish practice); each "
                        "span's own quasi-static S_rel; or each span's own quasi-static robust parabola (minimax "
                        "waviness over the F_m band, below the line between its supports)")
    p.add_argument("--working-width", metavar="MM", type=float, default=400.0,
                   help="half working width of the pantograph: largest stagger accepted, in mm (default 400)")
    add_numerics_options(p)
    p.add_argument("--step", metavar="M", type=float, default=1.0,
                   help="point spacing of the elasticity curves in m (default 1.0)")
    p.add_argument("--dynamic-check", action="store_true",
                   help="also simulate the band's worst points (top speed, lowest and highest static force) on the "
                        "section with the largest static uplift, as built")
    p.add_argument("--round", metavar="MM", type=float, default=0.0,
                   help="round the cut lengths to the crew's cutting step in mm (default 0: exact); the rounding "
                        "error (uniform ±step/2 on every dropper) goes into the installation tolerance: the P95 "
                        "waviness of the rounded schedule beside the exact one, and a crew tolerance never below the "
                        "pre-sag error rounding alone causes")
    p.add_argument("--dropper-type", metavar="TYPE", default=DEFAULT_DROPPER_TYPE,
                   help="dropper type whose terminal and loop allowances make the cut length: a built-in name or a "
                        f"model file (default {DEFAULT_DROPPER_TYPE}, allowances assumed)")
    p.add_argument("--xlsx", action="store_true", help="also write DIR/line_design.xlsx (the tables and the crew's "
                   "sheets)")
    p.add_argument("--dxf", action="store_true", help="also write DIR/line_design.dxf: the longitudinal profile (masts, "
                   "both wires, droppers with their ids) and the developed plan (track centre line, staggers), on named "
                   "layers in metres")
    add_json_flag(p)
    p.set_defaults(handler=design_command)


def design_command(args: argparse.Namespace) -> int:
    """Handler of ``presag design``."""
    from presag_opt.design.line import LineOptions
    from presag_opt.system.dropper_type import check_step, load_dropper_type
    from presag_opt.system.loader import load_catenary
    from presag_opt.system.survey import load_survey

    round_step = check_step(args.round * 1e-3)
    dropper_type = load_dropper_type(args.dropper_type)
    survey = load_survey(args.survey, working_width=args.working_width * 1e-3)
    base = load_catenary(args.system)
    band = operating_band(args)
    check_band_speed(args, [base])
    options = LineOptions(rule=args.rule, element_length=args.element_length, step=args.step, workers=workers_of(args),
                          round_step=round_step, dropper_type=dropper_type)
    settings = decision_settings(args)
    created = not Path(args.out).exists()
    folder = output_folder(args.out)
    try:
        return _design(args, survey, base, band, options, settings, dropper_type, folder)
    except BaseException:
        if created:  # a failed run leaves no folder behind that it made
            shutil.rmtree(folder, ignore_errors=True)
        raise


def _design(args, survey, base, band, options, settings, dropper_type, folder) -> int:
    """The work of ``presag design`` once its input is read and checked (see :func:`design_command`)."""
    import warnings

    from presag_opt.dynamics.pantograph import load_pantograph
    from presag_opt.pipeline.band import CASE_STUDY_PANTOGRAPH, DynamicOptions
    from presag_opt.pipeline.line import answer_line
    from presag_opt.report.line_report import LINE_OPTIONS, write_line_outputs

    round_step = options.round_step
    dynamic = None
    if args.dynamic_robust:
        dynamic = DynamicOptions(workers=workers_of(args))
        announce_dynamic(args, base, band, load_pantograph(CASE_STUDY_PANTOGRAPH), "the line's worst section")
    start = time.perf_counter()
    with warnings.catch_warnings(record=True) as caught, progress(args) as report:
        warnings.simplefilter("always")
        answer = answer_line(survey, base, band, options=options, within=settings["within"],
                             uplift_limit=settings["uplift_limit"], crew=settings["crew"], study=settings["study"],
                             check=args.dynamic_check, dynamic=dynamic, progress=report)
        paths = write_line_outputs(answer, folder, xlsx=args.xlsx, dxf=args.dxf)
    seconds = time.perf_counter() - start
    print_warnings(str(w.message) for w in caught)
    design = answer.design
    lengths = [s.length for s in design.spans]
    if args.json:
        print_json({
            "headline": answer.headline(),
            "decision": decision_json(answer.decision, LINE_OPTIONS, lengths),
            "presag_rel_permille": design.presag_rel * 1e3,
            "sections": [s.section for s in design.sections],
            "spans": len(design.spans),
            "spans_flagged": {flag: [f"{s.section}/{s.from_mast}-{s.to_mast}" for s in spans]
                              for flag, spans in answer.flagged().items()},
            "advice": answer.advice(),
            "droppers": len(design.droppers),
            "dropper_type": dropper_type.describe(),
            "round_mm": round_step * 1e3,
            "rounding": [{"section": section, "step_mm": r.step * 1e3, "waviness_exact_mm": r.waviness_exact * 1e3,
                          "waviness_p95_rounded_mm": {"value": r.waviness_p95 * 1e3,
                                                      "ci": [v * 1e3 for v in r.waviness_p95_ci]},
                          "presag_error_p95_mm": r.presag_error_p95 * 1e3, "samples": r.samples}
                         for section, r in design.rounding()],
            "rules_failing": [{"section": r.section, "rule": r.rule, "status": r.status, "worst": r.worst}
                              for r in design.rules if not r.passed],
            "notes": list(design.notes),
            "outputs": {k: str(v) for k, v in paths.items()},
            "dynamic_robust": None if answer.dynamic is None else answer.dynamic.to_dict(),
            "seconds": seconds,
            "failures": [{**e.inputs, "reason": e.failure} for e in design.failures],
        })
        return report_failures("design", design.failure_summary())
    print_decision(answer.lines(LINE_OPTIONS))
    print(f"{len(design.survey.masts)} masts, {len(design.sections)} sections, {len(design.spans)} spans, "
          f"{len(design.droppers)} droppers designed in {seconds:.1f} s")
    for flag, spans in answer.flagged().items():
        for s in spans:
            low, high = s.tolerance
            print(f"Span {s.section}/{s.from_mast}–{s.to_mast}: built {s.presag * 1e3:.1f} mm, {flag} "
                  f"{low * 1e3:.1f}–{high * 1e3:.1f} mm")
    print(f"Cut lengths: {dropper_type.describe()}, "
          + (f"rounded to {round_step * 1e3:g} mm" if round_step else "exact (no --round)"))
    for section, r in design.rounding():
        print(f"Rounding to {r.step * 1e3:g} mm, section {section}: P95 waviness {r.waviness_p95 * 1e3:.1f} mm "
              f"({r.waviness_p95_ci[0] * 1e3:.1f}–{r.waviness_p95_ci[1] * 1e3:.1f}) beside {r.waviness_exact * 1e3:.1f} mm "
              f"exact; mid-span pre-sag error P95 ±{r.presag_error_p95 * 1e3:.1f} mm")
    if answer.advice():
        print(f"Advice: {answer.advice()}")
    for note in design.notes:
        print(f"Note: {note}")
    for r in design.rules:
        if not r.passed:
            print(f"Design rule, section {r.section}: {r.rule}: {r.worst} — {r.status}")
    for name, path in paths.items():
        print(f"{name}: {path}")
    return report_failures("design", design.failure_summary())
