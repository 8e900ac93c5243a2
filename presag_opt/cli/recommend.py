"""``presag empirical`` and ``presag recommend`` (the case study by default)."""

from __future__ import annotations

import argparse
import warnings

from presag_opt.cli.common import (
    add_json_flag,
    add_plot_option,
    float_list,
    model_help,
    plot_folder,
    positive_float,
    print_json,
    print_warnings,
    progress,
    table,
)
from presag_opt.cli.decision_options import (
    add_band_options,
    add_decision_options,
    add_numerics_options,
    announce_dynamic,
    check_band_speed,
    decision_json,
    decision_keywords,
    operating_band,
    print_decision,
    workers_of,
)
from presag_opt.design import (
    CASE_STUDY_MODELS,
    CASE_STUDY_SPAN_LENGTH,
    EMPIRICAL_K,
    KMH,
    PRESAG_METHODS,
    EmpiricalPresag,
    Recommendation,
)
from presag_opt.errors import ModelError
from presag_opt.jobs.options import ELASTICITY_STEP
from presag_opt.system.loader import load_catenary
from presag_opt.validation import compare_with_paper

RECOMMEND_OPTIONS = {"validity_sweep": "--study STORE, a study written by presag sweep",
                     "dynamic_robust": "--dynamic-robust", "installation_monte_carlo": "--dropper-error MM"}
"""The options of ``presag recommend`` that supply each kind of evidence it can miss."""


def register(subparsers: argparse._SubParsersAction) -> None:
    """Add the pre-sag sub-commands."""
    p = subparsers.add_parser(
        "empirical",
        help="empirical pre-sag rule (paper eq. 1-3, Table 1)",
        description="Empirical pre-sag: e_mid = l/(k (T_CW + T_MW)), e_mast = 0.5…0.3 e_mid, "
        "S = F_stat (e_mid − e_mast), S_rel = S/l.",
    )
    p.add_argument("--tension", metavar="CW/MW", default="9.8/9.8", help="contact/messenger wire tension in kN, e.g. 9.8/9.8 (default)")
    p.add_argument("--span", metavar="M", type=positive_float, default=CASE_STUDY_SPAN_LENGTH, help="span length in m (default 60)")
    p.add_argument("--static-force", metavar="N", type=positive_float, default=140.0, help="static contact force in N (default 140)")
    p.add_argument("--k", metavar="FACTOR", type=positive_float, default=EMPIRICAL_K, help=f"factor k of eq. 1 (default {EMPIRICAL_K:g})")
    add_json_flag(p)
    p.set_defaults(handler=empirical_command)

    p = subparsers.add_parser(
        "recommend",
        help="which pre-sag to build for an operating band (default: the paper's case study)",
        description="The decision for a band of static forces and speeds on ideal and mixed span layouts: the "
        "quasi-static Δe rule over the band, the quasi-static robust design with its tolerance, on request a "
        "validity study, the dynamic robust design and the crew tolerance by Monte Carlo, and the one pre-sag to "
        "build with its margins. Without options, the case study of Schick, Liu & Stichel (2025): ST 9,8/9,8, "
        "F_stat 70–140 N, up to 90 km/h, α_ae = 0.00097 N/(km/h)².",
    )
    p.add_argument(
        "--models", metavar="MODEL[,MODEL]", default=",".join(CASE_STUDY_MODELS),
        help="a list of " + model_help("catenaries", ",".join(CASE_STUDY_MODELS)) + "; the first is also the one "
        "of the robust designs",
    )
    add_band_options(p)
    add_decision_options(p, simulated="the first model (the case study's ideal section by default)")
    p.add_argument("--method", metavar="{mid-mast,delta-e}", default="delta-e",
                   help=f"quasi-static variant: {' or '.join(PRESAG_METHODS)} (default delta-e)")
    p.add_argument("--force-levels", metavar="N,N,...", type=float_list, default=None,
                   help="elasticity force levels in N (default: 50 N steps around the band)")
    p.add_argument("--step", metavar="M", type=positive_float, default=ELASTICITY_STEP,
                   help=f"point spacing of the elasticity curves in m (default {ELASTICITY_STEP:g})")
    p.add_argument("--elasticity-method", metavar="{active-set,newton}", default="active-set",
                   help="nonlinear elasticity: active-set (default, fast) or newton")
    add_numerics_options(p)
    p.add_argument("--span-length", metavar="M", type=positive_float, default=None,
                   help="span length the pre-sag is stated for in mm, in m (default: the first model's spans if they "
                        "are all equal, else 60)")
    p.add_argument("--recompute", action="store_true", help="also recompute the Δe rule at its own pre-sag geometry")
    p.add_argument("--per-span", action="store_true", help="print the pre-sag of every span of the mixed layouts")
    p.add_argument("--compare-paper", action="store_true",
                   help="add our Table 1, Table 2, Fig. 5b and recommendation beside the paper's")
    add_plot_option(p, "S against F_m (both variants, every layout, like Fig. 5a) and, with --compare-paper, the "
                       "Fig. 5b study")
    add_json_flag(p)
    p.set_defaults(handler=recommend_command)


def parse_tension(text: str) -> tuple[float, float]:
    """``CW/MW`` (or one value for both) in kN, to N."""
    parts = text.split("/")
    try:
        values = [float(p) for p in parts]
    except ValueError:
        values = []
    if len(values) not in (1, 2):
        raise ModelError(f"--tension = {text!r}: give the contact and messenger wire tensions in kN as CW/MW, e.g. 9.8/9.8")
    cw, mw = values if len(values) == 2 else values * 2
    return cw * 1e3, mw * 1e3


def empirical_command(args: argparse.Namespace) -> int:
    """``presag empirical``: the empirical rule as a table (with the Table 1 rounding) or JSON."""
    cw, mw = parse_tension(args.tension)
    rule = EmpiricalPresag(
        span_length=args.span, contact_wire_tension=cw, messenger_wire_tension=mw, static_force=args.static_force, k=args.k
    )
    if args.json:
        print_json(rule.to_dict())
        return 0
    printed = rule.printed()
    print(
        f"Empirical pre-sag: T = {cw / 1e3:g}/{mw / 1e3:g} kN, l = {rule.span_length:g} m, "
        f"F_stat = {rule.static_force:g} N, k = {rule.k:g}"
    )
    print(f"e_mid = l/(k (T_CW + T_MW)) = {rule.e_mid * 1e3:.4f} mm/N\n")
    print(table(
        ["e_mast/e_mid", "e_mast [mm/N]", "S [mm]", "S_rel [‰]"],
        [(r, e * 1e3, s * 1e3, s_rel * 1e3) for r, e, s, s_rel in zip(rule.e_mast_ratios, rule.e_mast, rule.presag, rule.presag_rel)],
        ["{:g}", "{:.4f}", "{:.2f}", "{:.3f}"],
    ))
    s_lo, s_hi = printed["presag_mm"]
    r_lo, r_hi = printed["presag_rel_permille"]
    print(
        f"\nAs the paper's Table 1 prints it: e_mid {printed['e_mid_mm_per_N']:.3f} mm/N, S {s_lo:.0f}–{s_hi:.0f} mm, "
        f"S_rel {r_lo:.2f}–{r_hi:.2f} ‰ (S rounded to mm, then divided by l)"
    )
    return 0


def recommend_command(args: argparse.Namespace) -> int:
    """``presag recommend``: the band's decision, the Δe rule's layouts, optionally compared and plotted."""
    from presag_opt.dynamics.pantograph import load_pantograph
    from presag_opt.jobs import recommend
    from presag_opt.pipeline.band import CASE_STUDY_PANTOGRAPH
    from presag_opt.static.discretisation import StaticSettings

    plots = plot_folder(args)
    models = [m.strip() for m in args.models.split(",") if m.strip()]
    band = operating_band(args)
    check_band_speed(args, models)
    keywords = decision_keywords(args)
    workers = workers_of(args)
    if args.dynamic_robust:
        announce_dynamic(args, load_catenary(models[0]), band, load_pantograph(CASE_STUDY_PANTOGRAPH), models[0])
    with warnings.catch_warnings(record=True) as caught, progress(args) as report:
        warnings.simplefilter("always")
        # the band's speed was checked above, naming this command's option
        answer = recommend(models, band, dynamic_robust=args.dynamic_robust, method=args.method,
                           force_levels=args.force_levels, step=args.step, elasticity_method=args.elasticity_method,
                           element_length=args.element_length, workers=workers, span_length=args.span_length,
                           recompute=args.recompute, allow_supercritical=True, progress=report, **keywords)
        comparison = None
        if args.compare_paper:
            comparison = compare_with_paper(answer.recommendation, step=args.step,
                                            elasticity_method=args.elasticity_method,
                                            settings=StaticSettings(element_length=args.element_length),
                                            progress=report)
    print_warnings(str(w.message) for w in caught)
    written = []
    if plots:
        from presag_opt.plotting import plot_presag_against_force, plot_single_curve_error

        written.append(plot_presag_against_force(answer.recommendation, plots / "presag_against_force.png"))
        if comparison is not None:
            written.append(plot_single_curve_error(comparison.single_curve_errors, plots / "single_curve_error.png"))
    result = answer.recommendation
    if args.json:
        out = {"decision": decision_json(answer.decision, RECOMMEND_OPTIONS), **result.to_dict(),
               "robust": answer.robust.to_dict()}
        if answer.dynamic is not None:
            out["dynamic_robust"] = answer.dynamic.to_dict()
        if answer.monte_carlo is not None:
            out["installation_monte_carlo"] = {
                "samples": answer.monte_carlo.samples,
                "crew_tolerance_mm": answer.decision.evidence.installation.half_width * 1e3}
        if comparison is not None:
            out["paper_comparison"] = comparison.to_dict()
        print_json(out)
        return 0
    print_decision(answer.decision.lines(RECOMMEND_OPTIONS))
    print_recommendation(result, built_presag_rel=answer.decision.presag_rel, per_span=args.per_span)
    if result.recomputed is not None:
        again = result.recomputed
        print(f"\nRecomputed at the Δe rule's own geometry (S_rel = {result.presag_rel * 1e3:.2f} ‰):")
        print(layout_table(again))
        print(
            f"Δe rule S_rel {again.presag_rel * 1e3:.2f} ‰ = {again.presag * 1e3:.0f} mm on "
            f"{again.nominal_span_length:g} m (first pass {result.presag_rel * 1e3:.2f} ‰, "
            f"change {100 * (again.presag_rel / result.presag_rel - 1):+.1f} %)"
        )
    if comparison is not None:
        print("\nComparison with Schick, Liu & Stichel (2025), doi:10.1108/RS-05-2025-0016:")
        print(table(
            ["quantity", "unit", "ours", "paper", "ours − paper", "relative [%]"],
            [(r.item, r.unit, r.ours, r.paper, r.difference, 100 * r.relative_difference) for r in comparison.rows],
            ["{}", "{}", "{:.3f}", "{:.3f}", "{:+.3f}", "{:+.1f}"],
        ))
    for path in written:
        print(f"\nPlot saved to {path}")
    return 0


def layout_table(result: Recommendation) -> str:
    """One row per layout: spans analysed, force levels, S_rel range, S range on the nominal span, uplift."""
    span = result.nominal_span_length
    rows = [
        (
            lay.layout_kind,
            lay.catenary_name,
            len(lay.section.spans),
            ",".join(f"{f:g}" for f in lay.section.force_levels),
            f"{lay.presag_rel_range[0] * 1e3:.2f}–{lay.presag_rel_range[1] * 1e3:.2f}",
            f"{lay.presag_rel_range[0] * span * 1e3:.0f}–{lay.presag_rel_range[1] * span * 1e3:.0f}",
            f"{lay.steady_arm_uplift.uplift * 1e3:.1f}" + ("" if lay.steady_arm_uplift.within_limit else " (over)"),
        )
        for lay in result.layouts
    ]
    return table(
        ["layout", "system", "spans", "levels [N]", "S_rel [‰]", f"S on {span:g} m [mm]", "static StA uplift [mm]"],
        rows,
    )


def print_recommendation(result: Recommendation, built_presag_rel: float, per_span: bool = False) -> None:
    """The readable table of the Δe rule over the band (the decision is printed above it).

    Parameters
    ----------
    result : Recommendation
        The Δe rule over the band.
    built_presag_rel : float
        The decision's S_rel, built in every span of the mixed layouts (``per_span``). [-]
    per_span : bool
        Also print every span of the mixed layouts.
    """
    band = result.band
    low, high = result.mean_force_band
    method = "Δe = e_max − e_min" if result.method == "delta-e" else "e_mid − e_mast"
    print(f"Quasi-static rule, S = F_m·({method})")
    print(
        f"Operating band: F_stat {band.static_force_low:g}–{band.static_force_high:g} N, "
        f"{band.speed_low / KMH:g}–{band.speed_high / KMH:g} km/h, α_ae = {band.aero_coefficient * KMH**2:g} N/(km/h)² "
        f"-> F_m {low:.1f}–{high:.1f} N\n"
    )
    print(layout_table(result))
    print(
        f"\nΔe rule: S_rel = {result.presag_rel * 1e3:.2f} ‰ -> S = {result.presag * 1e3:.0f} mm on a "
        f"{result.nominal_span_length:g} m span (mean of the layouts' range ends; range "
        f"{result.presag_rel_range[0] * 1e3:.2f}–{result.presag_rel_range[1] * 1e3:.2f} ‰)"
    )
    for speed in {lay.speed.wave_speed: lay.speed for lay in result.layouts}.values():
        print(
            f"Speed: c_CW = {speed.wave_speed:.1f} m/s ({speed.wave_speed / KMH:.0f} km/h), β_max = {speed.beta_max:.2f} "
            f"at {speed.speed_high / KMH:g} km/h, Doppler factor {speed.doppler_factor_min:.2f}"
        )
    print(
        "Steady-arm uplift: static estimate F_m·e_mast at the top of the band, limit "
        f"{result.layouts[0].steady_arm_uplift.limit * 1e3:g} mm (the dynamic uplift is larger)"
    )
    if not per_span:
        return
    for lay in result.layouts:
        if lay.layout_kind != "mixed":
            continue
        lo, hi = lay.at_band_low, lay.at_band_high
        print(f"\nPer span, {lay.catenary_name} (S_rel at F_m {low:.0f} and {high:.0f} N; built S = the decision's "
              "S_rel × l):")
        print(table(
            ["span", "l [m]", f"S_rel@{low:.0f} [‰]", f"S_rel@{high:.0f} [‰]", "built S [mm]"],
            [
                (s + 1, length, a * 1e3, b * 1e3, built_presag_rel * length * 1e3)
                for s, length, a, b in zip(lo.spans, lo.span_lengths, lo.presag_rel, hi.presag_rel)
            ],
            ["{}", "{:.1f}", "{:.2f}", "{:.2f}", "{:.0f}"],
        ))
