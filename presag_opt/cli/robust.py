"""``presag robust`` (quasi-static, or ``--dynamic``: by simulation over static forces × speeds) and
``presag tolerance``.

Both take the operating band as every command does (``--static-force``, ``--min-speed``,
``--max-speed``, ``--aero``); ``presag robust`` prints the band's decision
(:func:`presag_opt.pipeline.band.answer_band`), the same as ``presag recommend`` on the same model, above
its own tables.
"""

from __future__ import annotations

import argparse

from presag_opt.cli import tolerance_mc
from presag_opt.cli.common import (
    add_json_flag,
    add_plot_option,
    announcer,
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
    check_band_speed,
    decision_json,
    decision_keywords,
    operating_band,
    print_decision,
    within_percent,
    workers_of,
)
from presag_opt.errors import ModelError
from presag_opt.jobs.options import DROPPER_STEP_MM, ROBUST_MODEL
from presag_opt.robust.dynamic_check import window_settings
from presag_opt.speed import check_speed_limit
from presag_opt.system.loader import load_catenary
from presag_opt.system.stitch import stitch_summary
from presag_opt.units import KMH

DYNAMIC_DEFAULTS = {
    "objective": "sigma-over-fm",
    "pantograph": "case_study_2mass_friction",
    "grid_points": [4.0, 3.0],
    "fleet_shares": None,
    "second_pantograph_at": None,
}
"""Options of ``--dynamic`` and their defaults (the band is the command's, as everywhere: the case study's
F_stat 70–140 N up to 90 km/h is simulated from 50 km/h, the paper's lowest grid speed)."""

CHECK_FORCES = (70.0, 105.0, 140.0)
"""Static contact forces of ``--check-speeds`` by default: the case study's band, its ends and centre. [N]"""

ROBUST_OPTIONS = {"validity_sweep": "--study STORE, a study written by presag sweep", "dynamic_robust": "--dynamic",
                  "installation_monte_carlo": "--dropper-error MM"}
"""The options of ``presag robust`` that supply each kind of evidence it can miss."""


def register(subparsers: argparse._SubParsersAction) -> None:
    """Add the robust-design sub-commands."""
    for name, helptext in (
        ("robust", "pre-sag that minimises the waviness over the band, and the band's decision"),
        ("tolerance", "installation tolerance: the pre-sag interval within a loss of the robust optimum"),
    ):
        p = subparsers.add_parser(name, help=helptext, description=f"{helptext[0].upper()}{helptext[1:]}.")
        p.add_argument("model", nargs="?", default=ROBUST_MODEL, help=model_help("catenaries", ROBUST_MODEL))
        add_band_options(p)
        add_numerics_options(p)
        add_plot_option(p, "R against S over the band" + (" (with --dynamic: the objective against S)"
                                                            if name == "robust" else " (with --monte-carlo: the "
                                                            "histogram of the worst case)"))
        add_json_flag(p)
        if name == "robust":
            add_decision_options(p, simulated="", dynamic_robust=False)
            p.add_argument("--shape", choices=("parabola", "per-dropper"), default="parabola",
                           help="parabola: one pre-sag per span (default); per-dropper: every dropper height free")
            p.add_argument("--risk", metavar="MEASURE", default="minimax",
                           help="minimax (default), mean, or cvar:LEVEL such as cvar:0.9")
            p.add_argument("--step-mm", metavar="MM", type=float, default=None,
                           help=f"construction step of per-dropper heights in mm (default {DROPPER_STEP_MM:g})")
            p.add_argument("--asymmetric", action="store_true", help="allow per-dropper profiles that are not symmetric")
            _add_check_options(p)
            _add_dynamic_options(p)
        else:
            p.add_argument("--within", default="10", metavar="PERCENT",
                           help="allowed loss of the tolerance interval in %%, e.g. 10 or 10%% (default 10)")
            tolerance_mc.add_options(p)
        p.set_defaults(handler=robust_command if name == "robust" else tolerance_command)


def _add_check_options(p: argparse.ArgumentParser) -> None:
    group = p.add_argument_group(
        "dynamic check of the quasi-static designs (--check-speeds)",
        "simulate the designs of the quasi-static study (the Δe rule and the robust design; with --shape "
        "per-dropper the profile built into the catenary and the parabola of the same LP) at every static force x "
        "speed given, with the pantograph of --pantograph and the α_ae of --aero; report per design and regime "
        "(below and above β 0.4) the worst and mean sigma/F_m, the largest steady-arm uplift and the loss of contact",
    )
    group.add_argument("--check-speeds", metavar="KMH,KMH", type=float_list, default=None,
                       help="speeds to simulate the designs at, in km/h, e.g. 50,90,160")
    group.add_argument("--check-forces", metavar="N,N", type=float_list, default=None,
                       help="static contact forces of the check in N (default %s)" % ",".join(
                           f"{f:g}" for f in CHECK_FORCES))


def _add_dynamic_options(p: argparse.ArgumentParser) -> None:
    d = DYNAMIC_DEFAULTS
    group = p.add_argument_group(
        "dynamic design (--dynamic)",
        "choose the parabolic pre-sag by batched simulation over the band's static forces x speeds: the S that "
        "minimises the risk measure of sigma/F_m (or sigma), keeping the steady-arm uplift limit and F_m - 3 sigma > 0; "
        "compared with the Δe rule and the quasi-static robust design; the band's decision is made with it",
    )
    group.add_argument("--dynamic", action="store_true", help="design by dynamic simulation")
    group.add_argument("--objective", choices=("sigma-over-fm", "sigma"), default=None,
                       help=f"loss at each operating point (default {d['objective']})")
    group.add_argument("--pantograph", metavar="FILE[,FILE...]", default=None,
                       help=f"pantograph model file or built-in name (default {d['pantograph']}); several, comma "
                       "separated, design for the fleet; also the pantograph of --check-speeds")
    group.add_argument("--fleet-shares", metavar="A,B", type=float_list, default=None,
                       help="share of the passages of each --pantograph type, normalised to sum 1 (default equal)")
    group.add_argument("--second-pantograph-at", metavar="M", type=positive_float, default=None,
                       help="every train runs a second raised pantograph of its type this many metres behind")
    group.add_argument("--grid-points", metavar="N,N", type=float_list, default=None,
                       help="simulated static forces and speeds across the band (default %g,%g)" % tuple(d["grid_points"]))


def _dynamic_option(args: argparse.Namespace, name: str):
    """An option of ``--dynamic``: its value, or its default; refused without ``--dynamic`` (the
    pantograph also serves ``--check-speeds``)."""
    value = getattr(args, name)
    checking = getattr(args, "check_speeds", None) is not None and name == "pantograph"
    if not args.dynamic and not checking:
        if value is not None:
            raise ModelError(f"--{name.replace('_', '-')} is an option of the dynamic design; add --dynamic")
        return None
    return DYNAMIC_DEFAULTS[name] if value is None else value


def robust_command(args: argparse.Namespace) -> int:
    """``presag robust``: the band's decision with the quasi-static robust design (or, with ``--dynamic``,
    the dynamic one)."""
    from presag_opt.jobs import robust_design
    from presag_opt.robust import Risk

    Risk.parse(args.risk)  # a bad measure is refused before any work
    for name in DYNAMIC_DEFAULTS:
        _dynamic_option(args, name)
    if args.dynamic:
        return _dynamic_command(args)
    if args.check_forces is not None and args.check_speeds is None:
        raise ModelError("--check-forces sets the static forces of the dynamic check; add --check-speeds")
    step = {} if args.step_mm is None else {"step_mm": args.step_mm}
    pantograph = _check_pantograph(args)
    catenary = load_catenary(args.model)
    band = operating_band(args)
    check_band_speed(args, [catenary])
    window = window_settings(catenary) if args.check_speeds is not None else None
    if args.check_speeds is not None:
        wave_speed = catenary.contact_wire.wave_speed / KMH
        for speed in args.check_speeds:
            if speed >= wave_speed:
                raise ModelError(f"--check-speeds {speed:g} km/h is outside the valid range (0, {wave_speed:.0f}) km/h "
                                 "(below the contact-wire wave speed)")
            if not args.allow_supercritical:
                check_speed_limit(speed * KMH, catenary.contact_wire.wave_speed, accept="--allow-supercritical")
    plots = plot_folder(args)
    with progress(args) as report:
        answer = robust_design(catenary, band, shape=args.shape, risk=args.risk, asymmetric=args.asymmetric,
                        element_length=args.element_length, allow_supercritical=True, progress=report, **step,
                        **decision_keywords(args))
    study = answer.robust
    if plots:
        from presag_opt.plotting import plot_waviness

        plot = plot_waviness(study, plots / "waviness.png")
    data = study.to_dict()
    data["system"] = stitch_summary(catenary)
    check = None
    if args.check_speeds is not None:
        check = _dynamic_check(args, study, catenary, pantograph, window, data["reference_span_m"])
        data["dynamic_check"] = check.summary()
    if args.json:
        print_json({"decision": decision_json(answer.decision, ROBUST_OPTIONS), **data})
        return 0
    print_decision(answer.decision.lines(ROBUST_OPTIONS))
    print(f"Robust pre-sag: {study.catenary_name}, F_m {data['fm_band_N'][0]:.1f}–{data['fm_band_N'][1]:.1f} N, "
          f"{data['shape']}, {data['risk']}")
    print(f"system: {data['system']}")
    rows = [
        ("robust", data["presag_mm"], data["presag_rel_permille"], data["worst_case_waviness_mm"], data["mean_waviness_mm"]),
        ("Δe rule", data["nominal_presag_mm"], data["nominal_presag_mm"] / data["reference_span_m"],
         data["nominal_worst_case_waviness_mm"], data["nominal_mean_waviness_mm"]),
    ]
    print(table(["design", f"S on {data['reference_span_m']:g} m [mm]", "S_rel [‰]", "worst R [mm]", "mean R [mm]"],
                rows, ["{}", "{:.1f}", "{:.3f}", "{:.1f}", "{:.1f}"]))
    if data["shape"] == "per-dropper":
        print(f"\nDropper depths [mm] (rounding: {data['rounding']}, continuous objective "
              f"{data['continuous_objective_mm']:.1f} mm): " + ", ".join(f"{d:.0f}" for d in data["dropper_depths_mm"]))
    low, high = data["tolerance_mm"]
    print(f"\nQuasi-static tolerance (worst-case R within {data['tolerance_within'] * 100:g} %): {low:.1f}–{high:.1f} mm")
    if check is not None:
        print(f"\nDynamic check ({pantograph.name}; F_stat {', '.join(f'{f:g}' for f in _check_forces(args))} N × "
              f"{', '.join(f'{v:g}' for v in args.check_speeds)} km/h; {window.analysed_spans} analysed span(s) after "
              f"{window.lead_in_spans} lead-in, automatic numerics):")
        print(table(["design", "S [mm]", "regime", "runs", "worst σ/F_m", "mean σ/F_m", "max uplift [mm]",
                     "loss of contact [%]"],
                    [(r["design"], r["presag_mm"], r["regime"].replace("beta", "β"), r["runs"],
                      r["worst_sigma_over_Fm"], r["mean_sigma_over_Fm"], r["uplift_max_mm"],
                      r["loss_of_contact_max_pct"]) for r in data["dynamic_check"]],
                    ["{}", "{:.1f}", "{}", "{}", "{:.4f}", "{:.4f}", "{:.1f}", "{:.1f}"]))
    if plots:
        print(f"Plot saved to {plot}")
    return 0


def _check_forces(args: argparse.Namespace) -> list[float]:
    return list(CHECK_FORCES) if args.check_forces is None else args.check_forces


def _check_pantograph(args: argparse.Namespace):
    """The pantograph of ``--check-speeds`` (loaded before the study, so a bad name fails at once)."""
    if args.check_speeds is None:
        return None
    from presag_opt.dynamics.pantograph import load_pantograph

    return load_pantograph(_dynamic_option(args, "pantograph"))


def _dynamic_check(args: argparse.Namespace, study, catenary, pantograph, settings, reference_span: float):
    """``--check-speeds``: the study's designs simulated at every static force × speed given (reference
    span in m)."""
    from presag_opt.design.band import KMH
    from presag_opt.robust import dynamic_check
    from presag_opt.robust.dynamic_check import design_catenary

    designs = {"Δe rule": study.nominal.presag_rel}
    if study.robust.shape == "per-dropper":
        designs["robust parabola (same LP)"] = study.robust_parabola.presag_rel
        designs["robust per-dropper"] = design_catenary(catenary, study.path, study.robust.depths)
    else:
        designs["robust"] = study.robust.presag_rel
    with progress(args) as report:
        return dynamic_check(catenary, designs, pantograph=pantograph, static_forces=_check_forces(args),
                             speeds=[v * KMH for v in args.check_speeds],
                             aero_coefficient=args.aero / KMH**2,
                             reference_span=reference_span, settings=settings, progress=report)


def tolerance_command(args: argparse.Namespace) -> int:
    """``presag tolerance``: the installation tolerance interval of the robust study, or (``--monte-carlo``)
    the design's worst case over random installation errors."""
    from presag_opt.jobs import tolerance

    tolerance_mc.check_options(args)
    keywords = tolerance_mc.tolerance_keywords(args)
    plots = plot_folder(args)
    catenary = load_catenary(args.model)
    check_band_speed(args, [catenary])
    within = within_percent(args.within)
    with progress(args) as report:  # the robust study's steps, then the Monte Carlo's, each with its own count
        answer = tolerance(catenary, operating_band(args), within_percent=within, element_length=args.element_length,
                           allow_supercritical=True, announce=announcer(args), progress=report, **keywords)
    if keywords:
        return tolerance_mc.print_answer(args, answer, None if plots is None else plots / "monte_carlo.png")
    study, data = answer.study, answer.to_dict()
    written = None
    if plots:
        from presag_opt.plotting import plot_waviness

        written = plot_waviness(study, plots / "waviness.png")
    if args.json:
        print_json(data)
        return 0
    (low, high), (clow, chigh) = data["tolerance_mm"], data["centre_optimum_tolerance_mm"]
    print(f"Installation tolerance: {study.catenary_name}, F_m {data['fm_band_N'][0]:.1f}–{data['fm_band_N'][1]:.1f} N, "
          f"within {data['tolerance_within'] * 100:g} % of the optimum")
    print(table(["design", "S [mm]", "tolerance [mm]", "width [mm]"], [
        ("robust over the band", data["presag_mm"], f"{low:.1f}–{high:.1f}", high - low),
        ("optimum for the band centre only", data["centre_optimum_presag_mm"], f"{clow:.1f}–{chigh:.1f}",
         chigh - clow),
        ("Δe rule over the band", data["nominal_presag_mm"], None, None),
    ], ["{}", "{:.1f}", "{}", "{:.1f}"]))
    if written:
        print(f"Plot saved to {written}")
    return 0


def _dynamic_command(args: argparse.Namespace) -> int:
    """``presag robust --dynamic``: the band's decision with the dynamic robust design, and the three
    methods compared by simulation."""
    from presag_opt.jobs import dynamic_robust_design
    from presag_opt.robust import Risk

    for option, given in (("--step-mm", args.step_mm is not None), ("--asymmetric", args.asymmetric),
                          ("--shape per-dropper", args.shape != "parabola"),
                          ("--check-speeds", args.check_speeds is not None),
                          ("--check-forces", args.check_forces is not None)):
        if given:
            raise ModelError(f"{option} is an option of the quasi-static design; --dynamic designs a parabola "
                             "over the band's static forces and speeds")
    points = _dynamic_option(args, "grid_points")
    if len(points) != 2 or any(p != int(p) for p in points):
        raise ModelError(f"--grid-points {','.join(f'{p:g}' for p in points)}: give two whole numbers, static forces "
                         "and speeds, e.g. 4,3")
    band = operating_band(args)
    plots = plot_folder(args)
    catenary = load_catenary(args.model)
    check_band_speed(args, [catenary])
    keywords = decision_keywords(args)
    names = [n.strip() for n in _dynamic_option(args, "pantograph").split(",")]
    if len(names) > 1 or args.fleet_shares is not None or args.second_pantograph_at is not None:
        if plots:
            raise ModelError("--plot is not drawn for a fleet design; drop it")
        return _fleet_command(args, catenary, names, band, Risk.parse(args.risk), keywords, points)
    from presag_opt.cli.decision_options import announce_dynamic
    from presag_opt.dynamics.pantograph import load_pantograph

    pantograph = load_pantograph(names[0])
    announce_dynamic(args, catenary, band, pantograph, catenary.name)
    with progress(args) as report:
        answer = dynamic_robust_design(catenary, band, pantograph=pantograph, objective=_dynamic_option(args, "objective"),
                                risk=args.risk, grid_points=(int(points[0]), int(points[1])),
                                element_length=args.element_length, workers=workers_of(args),
                                allow_supercritical=True, progress=report, **keywords)
    study = answer.dynamic
    written = None
    if plots:
        from presag_opt.plotting import plot_dynamic_objective

        written = plot_dynamic_objective(study, plots / "dynamic_objective.png")
    data = study.to_dict()
    data["system"] = stitch_summary(catenary)
    print_warnings(data["warnings"])
    if args.json:
        print_json({"decision": decision_json(answer.decision, ROBUST_OPTIONS), **data})
        return 0
    print_decision(answer.decision.lines(ROBUST_OPTIONS))
    loss = "σ/F_m" if data["objective_name"] == "sigma-over-fm" else "σ [N]"
    fmt = "{:.4f}" if data["objective_name"] == "sigma-over-fm" else "{:.2f}"
    within = keywords["within_percent"] / 100.0
    print(f"Dynamic robust pre-sag: {study.where()}")
    print(f"system: {data['system']}")
    beta_low, beta_high = data["beta"]
    print(f"simulated band: β {beta_low:.2f}–{beta_high:.2f}; objective: {data['risk']} of {loss}; "
          f"uplift limit {data['uplift_limit_mm']:g} mm")
    rows = [(m["method"], m["presag_mm"], m["objective"], m["worst_case_objective"], m["mean_objective"],
             m["uplift_max_mm"], m["cost_s"], "yes" if m["within_tolerance"] else "no") for m in data["methods"]]
    print(table(["method", f"S on {data['reference_span_m']:g} m [mm]", "objective", f"worst {loss}", f"mean {loss}",
                 "max uplift [mm]", "cost [s]", "in dynamic tolerance"],
                rows, ["{}", "{:.1f}", fmt, fmt, fmt, "{:.1f}", "{:.0f}", "{}"]))
    low, high = data["tolerance_mm"]
    print(f"\nDynamic tolerance (worst case within {100 * within:g} % of its minimum): {low:.1f}–{high:.1f} mm")
    print(f"Simulation: {data['runs_used']} runs at {data['presags_simulated']} pre-sags "
          f"(search {data['search_runs']} runs, {data['search_time_s']:.0f} s; whole study {data['wall_time_s']:.0f} s)")
    if written:
        print(f"Plot saved to {written}")
    return 0


def _fleet_command(args: argparse.Namespace, catenary, names: list[str], band, risk, keywords: dict,
                   points) -> int:
    """``presag robust --dynamic --pantograph A,B,...``: the fleet design beside each type's own optimum (a
    fleet design is not yet evidence of the band's decision: it prints no decision)."""
    from presag_opt.dynamics.pantograph import load_pantograph
    from presag_opt.robust.dynamic_design import DynamicObjective
    from presag_opt.robust.dynamic_study import simulated_band
    from presag_opt.robust.fleet import fleet_robust_study

    objective = DynamicObjective(loss=_dynamic_option(args, "objective"), risk=risk,
                                 uplift_limit=keywords["uplift_limit_mm"] * 1e-3)
    within = keywords["within_percent"] / 100.0

    shares = args.fleet_shares
    if shares is not None:
        if len(shares) != len(names) or any(s < 0 for s in shares) or sum(shares) <= 0:
            raise ModelError(f"--fleet-shares {','.join(f'{s:g}' for s in shares)}: give {len(names)} non-negative "
                             "shares, one per --pantograph type, not all zero")
        shares = [s / sum(shares) for s in shares]
    pantographs = [load_pantograph(n) for n in names]
    with progress(args) as report:
        design = fleet_robust_study(catenary, pantographs, simulated_band(band), shares=shares,
                                    spacing=args.second_pantograph_at, objective=objective, within=within,
                                    static_points=int(points[0]), speed_points=int(points[1]), workers=workers_of(args),
                                    progress=report)
    data = design.to_dict()
    data["catenary"] = catenary.name
    print_warnings(data["warnings"])
    if args.json:
        print_json(data)
        return 0
    fmt = "{:.4f}" if data["objective_name"] == "sigma-over-fm" else "{:.2f}"
    train = "" if data["second_pantograph_at_m"] is None else f", two raised pantographs {data['second_pantograph_at_m']:g} m apart"
    print(f"Fleet robust pre-sag: {catenary.name}; {', '.join(f'{n} ({s:.0%})' for n, s in zip(data['pantographs'], data['fleet_shares']))}{train}")
    rows = [("fleet design", data["presag_mm"], data["objective"], data["worst_case_objective"], data["uplift_max_mm"])]
    rows += [(f"own optimum of {t['pantograph']}", t["own_presag_mm"], t["fleet_objective"],
              t["fleet_worst_case_objective"], t["fleet_uplift_max_mm"]) for t in data["per_pantograph"]]
    print(table(["design", f"S on {data['reference_span_m']:g} m [mm]", f"fleet {data['risk']}", "fleet worst case",
                 "fleet max uplift [mm]"], rows, ["{}", "{:.1f}", fmt, fmt, "{:.1f}"]))
    low, high = data["tolerance_mm"]
    print(f"\nTolerance of the fleet design (fleet worst case within {100 * within:g} %): {low:.1f}–{high:.1f} mm")
    print(f"Simulation: {data['runs_used']} runs, {data['wall_time_s']:.0f} s")
    return 0
