"""``presag empirical`` and ``presag recommend`` (the case study by default)."""

from __future__ import annotations

import argparse
import warnings

from presag_opt.cli.common import (
    add_json_flag,
    band,
    float_list,
    model_help,
    output_path,
    positive_float,
    print_json,
    print_warnings,
    progress,
    table,
)
from presag_opt.cli.dynamic_robust import add_dynamic_robust_option, dynamic_robust, dynamic_robust_summary
from presag_opt.design import (
    CASE_STUDY_BAND,
    CASE_STUDY_MODELS,
    CASE_STUDY_SPAN_LENGTH,
    EMPIRICAL_K,
    KMH,
    PRESAG_METHODS,
    EmpiricalPresag,
    OperatingBand,
    Recommendation,
    recommend,
)
from presag_opt.errors import ModelError
from presag_opt.speed import check_speed_limit
from presag_opt.static.discretisation import StaticSettings
from presag_opt.system.loader import load_catenary
from presag_opt.validation import compare_with_paper


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
        help="recommend a pre-sag for an operating band (default: the paper's case study)",
        description="Quasi-static pre-sag over a band of static forces and speeds, for ideal and mixed span "
        "layouts; without options, the case study of Schick, Liu & Stichel (2025): ST 9,8/9,8, F_stat 70–140 N, "
        "up to 90 km/h, α_ae = 0.00097 N/(km/h)².",
    )
    p.add_argument(
        "--models", metavar="MODEL[,MODEL]", default=",".join(CASE_STUDY_MODELS),
        help="a list of " + model_help("catenaries", ",".join(CASE_STUDY_MODELS)),
    )
    add_band_options(p)
    add_dynamic_robust_option(p, "the first model (the case study's ideal section by default)")
    p.add_argument("--method", metavar="{mid-mast,delta-e}", default="delta-e", help=f"quasi-static variant: {' or '.join(PRESAG_METHODS)} (default delta-e)")
    p.add_argument("--force-levels", metavar="N,N,...", type=float_list, default=None, help="elasticity force levels in N (default: 50 N steps around the band)")
    p.add_argument("--step", metavar="M", type=positive_float, default=0.5, help="point spacing of the elasticity curves in m (default 0.5)")
    p.add_argument("--elasticity-method", metavar="{active-set,newton}", default="active-set", help="nonlinear elasticity: active-set (default, fast) or newton")
    p.add_argument("--element-length", metavar="M", type=positive_float, default=0.5, help="longest element in m (default 0.5)")
    p.add_argument(
        "--span-length", metavar="M", type=positive_float, default=CASE_STUDY_SPAN_LENGTH,
        help="span length the recommended pre-sag is stated for, in m (default 60)",
    )
    p.add_argument("--recompute", action="store_true", help="also recompute the elasticity at the recommended pre-sag geometry")
    p.add_argument("--per-span", action="store_true", help="print the pre-sag of every span of the mixed layouts")
    p.add_argument("--compare-paper", action="store_true", help="add our Table 1, Table 2, Fig. 5b and recommendation beside the paper's")
    p.add_argument("--plot", metavar="FILE", default=None,
                   help="save S against F_m, both variants and layouts (like Fig. 5a); the suffix sets the format")
    p.add_argument("--plot-single-curve", metavar="FILE", default=None,
                   help="with --compare-paper: save the Fig. 5b study; the suffix sets the format")
    add_json_flag(p)
    p.set_defaults(handler=recommend_command)


def add_band_options(parser: argparse.ArgumentParser) -> None:
    """``--static-force``, ``--min-speed``, ``--max-speed`` and ``--aero``: the operating band, by default
    the case study's (read back with :func:`operating_band`)."""
    case = CASE_STUDY_BAND
    parser.add_argument(
        "--static-force", metavar="N:N", type=band, default=(case.static_force_low, case.static_force_high),
        help="static contact force band LOW:HIGH in N, or one value (default 70:140)",
    )
    parser.add_argument("--min-speed", metavar="KMH", type=positive_float, default=case.speed_low / KMH,
                        help="lowest speed in km/h (default 0)")
    parser.add_argument("--max-speed", metavar="KMH", type=positive_float, default=case.speed_high / KMH,
                        help="highest speed in km/h (default 90)")
    parser.add_argument(
        "--aero", metavar="N/(KMH)^2", type=positive_float, default=case.aero_coefficient * KMH**2,
        help="aerodynamic uplift coefficient α_ae in N/(km/h)² (default 0.00097)",
    )
    parser.add_argument(
        "--allow-supercritical", action="store_true",
        help="accept a --max-speed at or above β = 0.7 of a model's contact-wire wave speed (EN 50119's limit)",
    )


def check_band_speed(args: argparse.Namespace, models: list) -> None:
    """Refuse a band whose ``--max-speed`` is at or above β = 0.7 on any of the models (catenaries or
    names of model files), before any work, unless ``--allow-supercritical`` accepts it.

    Parameters
    ----------
    args : argparse.Namespace
        The parsed options of a command with :func:`add_band_options`.
    models : list of Catenary or str
        The catenaries the band is designed on, or their model names or paths.
    """
    if args.allow_supercritical:
        return
    for model in models:
        catenary = load_catenary(model) if isinstance(model, str) else model
        check_speed_limit(args.max_speed * KMH, catenary.contact_wire.wave_speed, accept="--allow-supercritical")


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


def operating_band(args: argparse.Namespace) -> OperatingBand:
    """The band from the command-line options (validated by :class:`OperatingBand`)."""
    low, high = args.static_force
    return OperatingBand(
        static_force_low=low,
        static_force_high=high,
        speed_low=args.min_speed * KMH,
        speed_high=args.max_speed * KMH,
        aero_coefficient=args.aero / KMH**2,
    )


def recommend_command(args: argparse.Namespace) -> int:
    """``presag recommend``: the recommendation, optionally recomputed, compared and plotted."""
    if args.plot_single_curve and not args.compare_paper:
        raise ModelError("--plot-single-curve needs --compare-paper (the Fig. 5b study is part of the comparison)")
    plot = output_path(args.plot) if args.plot else None
    plot_single = output_path(args.plot_single_curve, "--plot-single-curve") if args.plot_single_curve else None
    models = [m.strip() for m in args.models.split(",") if m.strip()]
    band = operating_band(args)
    check_band_speed(args, models)
    with warnings.catch_warnings(record=True) as caught, progress(args) as report:
        warnings.simplefilter("always")
        common = dict(
            step=args.step, elasticity_method=args.elasticity_method,
            settings=StaticSettings(element_length=args.element_length), progress=report,
        )
        result = recommend(
            models=models, band=band, method=args.method, force_levels=args.force_levels,
            nominal_span_length=args.span_length, recompute_at_recommended=args.recompute, **common,
        )
        comparison = compare_with_paper(result, **common) if args.compare_paper else None
        robust = None
        if args.dynamic_robust:
            import dataclasses

            first = load_catenary(models[0])
            robust = dynamic_robust(args, result.decision, first, band, first.name, report)
            result = dataclasses.replace(result, decision=robust.decision)
    print_warnings(str(w.message) for w in caught)
    if plot:
        from presag_opt.plotting import plot_presag_against_force

        plot = plot_presag_against_force(result, plot)
    if plot_single:
        from presag_opt.plotting import plot_single_curve_error

        plot_single = plot_single_curve_error(comparison.single_curve_errors, plot_single)
    if args.json:
        out = result.to_dict()
        if comparison is not None:
            out["paper_comparison"] = comparison.to_dict()
        if robust is not None:
            out["dynamic_robust"] = dynamic_robust_summary(robust)
        print_json(out)
        return 0
    print_recommendation(result, per_span=args.per_span)
    if result.recomputed is not None:
        again = result.recomputed
        print(f"\nRecomputed at the recommended geometry (S_rel = {result.presag_rel * 1e3:.2f} ‰):")
        print(layout_table(again))
        print(
            f"Recommended S_rel {again.presag_rel * 1e3:.2f} ‰ = {again.presag * 1e3:.0f} mm on "
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
    for path in (plot, plot_single):
        if path:
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


def print_recommendation(result: Recommendation, per_span: bool = False) -> None:
    """The readable report of a recommendation."""
    band = result.band
    low, high = result.mean_force_band
    method = "Δe = e_max − e_min" if result.method == "delta-e" else "e_mid − e_mast"
    if result.decision is not None:
        print("\n".join(result.decision.lines(result.nominal_span_length)) + "\n")
    print(f"Quasi-static pre-sag, S = F_m·({method})")
    print(
        f"Operating band: F_stat {band.static_force_low:g}–{band.static_force_high:g} N, "
        f"{band.speed_low / KMH:g}–{band.speed_high / KMH:g} km/h, α_ae = {band.aero_coefficient * KMH**2:g} N/(km/h)² "
        f"-> F_m {low:.1f}–{high:.1f} N\n"
    )
    print(layout_table(result))
    print(
        f"\nRecommended S_rel = {result.presag_rel * 1e3:.2f} ‰ -> S = {result.presag * 1e3:.0f} mm on a "
        f"{result.nominal_span_length:g} m span (mean of the layouts' range ends; range "
        f"{result.presag_rel_range[0] * 1e3:.2f}–{result.presag_rel_range[1] * 1e3:.2f} ‰)"
    )
    seen = set()
    for lay in result.layouts:
        speed = lay.speed
        if speed.wave_speed in seen:
            continue
        seen.add(speed.wave_speed)
        validity = "valid" if speed.quasi_static_valid else "NOT valid"
        print(
            f"Speed: c_CW = {speed.wave_speed:.1f} m/s ({speed.wave_speed / KMH:.0f} km/h), β_max = {speed.beta_max:.2f} "
            f"at {speed.speed_high / KMH:g} km/h, Doppler factor {speed.doppler_factor_min:.2f}; quasi-static rule "
            f"{validity} (β ≤ {speed.beta_limit:g}, up to {speed.limit_speed / KMH:.0f} km/h)"
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
        print(f"\nPer span, {lay.catenary_name} (S_rel at F_m {low:.0f} and {high:.0f} N; built S = S_rel,rec·l):")
        print(table(
            ["span", "l [m]", f"S_rel@{low:.0f} [‰]", f"S_rel@{high:.0f} [‰]", "built S [mm]"],
            [
                (s + 1, length, a * 1e3, b * 1e3, result.presag_rel * length * 1e3)
                for s, length, a, b in zip(lo.spans, lo.span_lengths, lo.presag_rel, hi.presag_rel)
            ],
            ["{}", "{:.1f}", "{:.2f}", "{:.2f}", "{:.0f}"],
        ))
