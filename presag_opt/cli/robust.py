"""``presag robust`` (quasi-static, or ``--dynamic``: by simulation over static forces × speeds) and
``presag tolerance``."""

from __future__ import annotations

import argparse
import os

from presag_opt.cli import tolerance_mc
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
from presag_opt.errors import ModelError
from presag_opt.speed import check_speed_limit
from presag_opt.system.loader import load_catenary
from presag_opt.system.stitch import stitch_summary
from presag_opt.units import KMH

DEFAULT_MODEL = "st_9.8_ideal"
CASE_STUDY_FM_BAND = "70:148"
DYNAMIC_DEFAULTS = {
    "static_force": (70.0, 140.0),
    "speed": (50.0, 90.0),
    "objective": "sigma-over-fm",
    "pantograph": "case_study_2mass_friction",
    "aero": 0.00097,
    "uplift_limit": 83.5,
    "grid_points": [4.0, 3.0],
    "workers": min(2, os.cpu_count() or 1),
    "fleet_shares": None,
    "second_pantograph_at": None,
}
"""Options of ``--dynamic`` and their defaults: the case study (F_stat 70–140 N up to 90 km/h, simulated
from 50 km/h, the paper's lowest grid speed; α_ae 0.00097 N/(km/h)²; uplift limit 83.5 mm)."""

CHECK_FORCES = (70.0, 105.0, 140.0)
"""Static contact forces of ``--check-speeds`` by default: the case study's band, its ends and centre. [N]"""

SHARED_WITH_CHECK = ("pantograph", "aero")
"""Options of ``--dynamic`` that ``--check-speeds`` uses too."""


def register(subparsers: argparse._SubParsersAction) -> None:
    """Add the robust-design sub-commands."""
    for name, helptext in (
        ("robust", "pre-sag that minimises the waviness over a band of mean contact forces"),
        ("tolerance", "installation tolerance: the pre-sag interval within a loss of the robust optimum"),
    ):
        p = subparsers.add_parser(name, help=helptext, description=f"{helptext[0].upper()}{helptext[1:]}.")
        p.add_argument("model", nargs="?", default=DEFAULT_MODEL, help=model_help("catenaries", DEFAULT_MODEL))
        p.add_argument("--fm-band", default=None, metavar="N:N",
                       help=f"mean contact force band LOW:HIGH in N (default {CASE_STUDY_FM_BAND}, the case study)")
        p.add_argument("--within", default="10", metavar="PERCENT",
                       help="allowed loss of the tolerance band in %%, e.g. 10 or 10%% (default 10)")
        p.add_argument("--plot", metavar="FILE", default=None,
                       help="save R against S over the band; the suffix sets the format (.png, .pdf, .svg, ...)")
        add_json_flag(p)
        if name == "robust":
            p.add_argument("--shape", choices=("parabola", "per-dropper"), default="parabola",
                           help="parabola: one pre-sag per span (default); per-dropper: every dropper height free")
            p.add_argument("--risk", metavar="MEASURE", default="minimax",
                           help="minimax (default), mean, or cvar:LEVEL such as cvar:0.9")
            p.add_argument("--step-mm", metavar="MM", type=float, default=None,
                           help="construction step of per-dropper heights in mm (default 5)")
            p.add_argument("--asymmetric", action="store_true", help="allow per-dropper profiles that are not symmetric")
            _add_check_options(p)
            _add_dynamic_options(p)
            p.add_argument("--allow-supercritical", action="store_true",
                           help="accept simulated speeds at or above β = 0.7 of the contact-wire wave speed "
                           "(EN 50119's limit) in --check-speeds and --dynamic")
        else:
            tolerance_mc.add_options(p)
        p.set_defaults(handler=robust_command if name == "robust" else tolerance_command)


def _add_check_options(p: argparse.ArgumentParser) -> None:
    group = p.add_argument_group(
        "dynamic check of the quasi-static designs (--check-speeds)",
        "simulate the designs of the quasi-static study (the Δe rule at the band centre and the robust design; with "
        "--shape per-dropper the profile built into the catenary and the parabola of the same LP) at every static force x "
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
        "choose the parabolic pre-sag by batched simulation over a band of static forces x speeds: the S that "
        "minimises the risk measure of sigma/F_m (or sigma), keeping the steady-arm uplift limit and F_m - 3 sigma > 0; "
        "compared with the Δe rule and the quasi-static robust design, with a recommendation",
    )
    group.add_argument("--dynamic", action="store_true", help="design by dynamic simulation")
    group.add_argument("--static-force", metavar="N:N", type=band, default=None,
                       help="static contact force band LOW:HIGH in N (default %g:%g)" % d["static_force"])
    group.add_argument("--speed", metavar="KMH:KMH", type=band, default=None,
                       help="speed band LOW:HIGH in km/h (default %g:%g)" % d["speed"])
    group.add_argument("--objective", choices=("sigma-over-fm", "sigma"), default=None,
                       help=f"loss at each operating point (default {d['objective']})")
    group.add_argument("--pantograph", metavar="FILE[,FILE...]", default=None,
                       help=f"pantograph model file or built-in name (default {d['pantograph']}); several, comma "
                       "separated, design for the fleet")
    group.add_argument("--fleet-shares", metavar="A,B", type=float_list, default=None,
                       help="share of the passages of each --pantograph type, normalised to sum 1 (default equal)")
    group.add_argument("--second-pantograph-at", metavar="M", type=positive_float, default=None,
                       help="every train runs a second raised pantograph of its type this many metres behind")
    group.add_argument("--aero", metavar="N_per_kmh2", type=positive_float, default=None,
                       help=f"aerodynamic uplift coefficient in N/(km/h)^2 (default {d['aero']:g})")
    group.add_argument("--uplift-limit", metavar="MM", type=positive_float, default=None,
                       help=f"steady-arm uplift limit in mm (default {d['uplift_limit']:g}, the case study)")
    group.add_argument("--grid-points", metavar="N,N", type=float_list, default=None,
                       help="simulated static forces and speeds across the band (default %g,%g)" % tuple(d["grid_points"]))
    group.add_argument("--workers", metavar="N", type=int, default=None,
                       help="processes that simulate pre-sags side by side when the search asks for two at once "
                       f"(default {d['workers']})")


def _dynamic_option(args: argparse.Namespace, name: str):
    """An option of ``--dynamic``: its value, or its default; refused without ``--dynamic``."""
    value = getattr(args, name)
    checking = getattr(args, "check_speeds", None) is not None and name in SHARED_WITH_CHECK
    if not args.dynamic and not checking:
        if value is not None:
            raise ModelError(f"--{name.replace('_', '-')} is an option of the dynamic design; add --dynamic")
        return None
    return DYNAMIC_DEFAULTS[name] if value is None else value


def parse_within(text: str) -> float:
    """``10`` or ``10%`` (percent) -> 0.1; the range is the API's to check."""
    try:
        return float(text.removesuffix("%")) / 100.0
    except ValueError:
        raise ModelError(f"--within = {text!r}: write a percentage such as 10 (or 10%)") from None


def _study(args: argparse.Namespace, catenary=None, **kwargs):
    from presag_opt.robust import robust_study  # cvxpy is imported only when a robust command runs

    try:
        fm_band = band(args.fm_band or CASE_STUDY_FM_BAND)
    except argparse.ArgumentTypeError as exc:
        raise ModelError(f"--fm-band {exc}") from None
    within = parse_within(args.within)
    plot = output_path(args.plot) if args.plot else None
    catenary = catenary or load_catenary(args.model)
    with progress(args) as report:
        study = robust_study(catenary, fm_band, within=within, progress=report, **kwargs)
    return study, plot


def robust_command(args: argparse.Namespace) -> int:
    """``presag robust``: the quasi-static robust design (or, with ``--dynamic``, the dynamic one)."""
    from presag_opt.robust import Buildability, Risk

    risk = Risk.parse(args.risk)
    for name in DYNAMIC_DEFAULTS:
        _dynamic_option(args, name)
    if args.dynamic:
        return _dynamic_command(args, risk)
    if args.check_forces is not None and args.check_speeds is None:
        raise ModelError("--check-forces sets the static forces of the dynamic check; add --check-speeds")
    step = 5.0 if args.step_mm is None else args.step_mm
    build = Buildability(step=step * 1e-3, symmetric=not args.asymmetric) if args.shape == "per-dropper" else None
    pantograph = _check_pantograph(args)
    catenary = load_catenary(args.model)
    window = check_settings(catenary) if args.check_speeds is not None else None
    if args.check_speeds is not None:
        wave_speed = catenary.contact_wire.wave_speed / KMH
        for speed in args.check_speeds:
            if speed >= wave_speed:
                raise ModelError(f"--check-speeds {speed:g} km/h is outside the valid range (0, {wave_speed:.0f}) km/h "
                                 "(below the contact-wire wave speed)")
            if not args.allow_supercritical:
                check_speed_limit(speed * KMH, catenary.contact_wire.wave_speed, accept="--allow-supercritical")
    study, plot = _study(args, catenary, shape=args.shape, risk=risk, buildability=build)
    _plot(args, study, plot)
    data = study.to_dict()
    data["system"] = stitch_summary(catenary)
    check = None
    if args.check_speeds is not None:
        check = _dynamic_check(args, study, catenary, pantograph, window, data["reference_span_m"])
        data["dynamic_check"] = check.summary()
    if args.json:
        print_json(data)
        return 0
    print(f"Robust pre-sag: {study.catenary_name}, F_m {data['fm_band_N'][0]:g}–{data['fm_band_N'][1]:g} N, "
          f"{data['shape']}, {data['risk']}")
    print(f"system: {data['system']}")
    rows = [
        ("robust", data["presag_mm"], data["presag_rel_permille"], data["worst_case_waviness_mm"], data["mean_waviness_mm"]),
        ("nominal Δe at band centre", data["nominal_presag_mm"], data["nominal_presag_mm"] / data["reference_span_m"],
         data["nominal_worst_case_waviness_mm"], data["nominal_mean_waviness_mm"]),
    ]
    print(table(["design", f"S on {data['reference_span_m']:g} m [mm]", "S_rel [‰]", "worst R [mm]", "mean R [mm]"],
                rows, ["{}", "{:.1f}", "{:.3f}", "{:.1f}", "{:.1f}"]))
    if data["shape"] == "per-dropper":
        print(f"\nDropper depths [mm] (rounding: {data['rounding']}, continuous objective "
              f"{data['continuous_objective_mm']:.1f} mm): " + ", ".join(f"{d:.0f}" for d in data["dropper_depths_mm"]))
    low, high = data["tolerance_mm"]
    print(f"\nInstallation tolerance (worst-case R within {data['tolerance_within'] * 100:g} %): {low:.1f}–{high:.1f} mm")
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

    designs = {"nominal Δe": study.nominal.presag_rel}
    if study.robust.shape == "per-dropper":
        designs["robust parabola (same LP)"] = study.robust_parabola.presag_rel
        designs["robust per-dropper"] = design_catenary(catenary, study.path, study.robust.depths)
    else:
        designs["robust"] = study.robust.presag_rel
    with progress(args) as report:
        return dynamic_check(catenary, designs, pantograph=pantograph, static_forces=_check_forces(args),
                             speeds=[v * KMH for v in args.check_speeds],
                             aero_coefficient=_dynamic_option(args, "aero") / KMH**2,
                             reference_span=reference_span, settings=settings, progress=report)


def check_settings(catenary):
    """Numerics of ``--check-speeds``: automatic, two lead-in and two analysed spans where the section
    has them, fewer on a short one (lead-in spans on both sides of the analysed ones).

    Parameters
    ----------
    catenary : Catenary
        The section to be simulated.
    """
    from presag_opt.dynamics.settings import SimulationSettings

    spans = catenary.layout.n_spans
    lead_in = min(2, (spans - 1) // 2)
    return SimulationSettings(numerics="auto", lead_in_spans=lead_in, analysed_spans=min(2, spans - 2 * lead_in))


def tolerance_command(args: argparse.Namespace) -> int:
    """``presag tolerance``: the installation tolerance interval of the robust study."""
    tolerance_mc.check_options(args)
    if args.monte_carlo:
        return tolerance_mc.monte_carlo_command(args, lambda a: _study(a)[0], parse_within(args.within),
                                                 DYNAMIC_DEFAULTS)
    study, plot = _study(args)
    _plot(args, study, plot)
    data = study.to_dict()
    if args.json:
        print_json({k: data[k] for k in ("catenary", "fm_band_N", "reference_span_m", "presag_mm", "worst_case_waviness_mm",
                                         "tolerance_mm", "tolerance_within", "centre_optimum_presag_mm",
                                         "centre_optimum_tolerance_mm", "nominal_presag_mm",
                                         "nominal_worst_case_waviness_mm")})
        return 0
    (low, high), (clow, chigh) = data["tolerance_mm"], data["centre_optimum_tolerance_mm"]
    print(f"Installation tolerance: {study.catenary_name}, F_m {data['fm_band_N'][0]:g}–{data['fm_band_N'][1]:g} N, "
          f"within {data['tolerance_within'] * 100:g} % of the optimum")
    print(table(["design", "S [mm]", "tolerance [mm]", "width [mm]"], [
        ("robust over the band", data["presag_mm"], f"{low:.1f}–{high:.1f}", high - low),
        ("optimum for the band centre only", data["centre_optimum_presag_mm"], f"{clow:.1f}–{chigh:.1f}",
         chigh - clow),
        ("nominal: Δe rule at the band centre", data["nominal_presag_mm"], None, None),
    ], ["{}", "{:.1f}", "{}", "{:.1f}"]))
    return 0


def _plot(args: argparse.Namespace, study, plot) -> None:
    if plot:
        from presag_opt.plotting import plot_waviness

        written = plot_waviness(study, plot)
        if not args.json:
            print(f"Plot saved to {written}")


def _dynamic_command(args: argparse.Namespace, risk) -> int:
    """``presag robust --dynamic``: the dynamic robust study of a band, printed or as JSON."""
    from presag_opt.design.band import KMH, OperatingBand
    from presag_opt.dynamics.pantograph import load_pantograph
    from presag_opt.robust.dynamic_design import DynamicObjective
    from presag_opt.robust.dynamic_study import dynamic_robust_study

    for option, given in (("--fm-band", args.fm_band is not None), ("--step-mm", args.step_mm is not None),
                          ("--asymmetric", args.asymmetric), ("--shape per-dropper", args.shape != "parabola"),
                          ("--check-speeds", args.check_speeds is not None),
                          ("--check-forces", args.check_forces is not None)):
        if given:
            raise ModelError(f"{option} is an option of the quasi-static design; --dynamic designs a parabola "
                             "over a band of static forces and speeds (--static-force, --speed)")
    points = _dynamic_option(args, "grid_points")
    if len(points) != 2 or any(p != int(p) for p in points):
        raise ModelError(f"--grid-points {','.join(f'{p:g}' for p in points)}: give two whole numbers, static forces "
                         "and speeds, e.g. 4,3")
    (f_low, f_high), (v_low, v_high) = _dynamic_option(args, "static_force"), _dynamic_option(args, "speed")
    band = OperatingBand(static_force_low=f_low, static_force_high=f_high, speed_low=v_low * KMH,
                         speed_high=v_high * KMH, aero_coefficient=_dynamic_option(args, "aero") / KMH**2)
    objective = DynamicObjective(loss=_dynamic_option(args, "objective"), risk=risk,
                                 uplift_limit=_dynamic_option(args, "uplift_limit") * 1e-3)
    within = parse_within(args.within)
    plot = output_path(args.plot) if args.plot else None
    catenary = load_catenary(args.model)
    if not args.allow_supercritical and band.speed_high < catenary.contact_wire.wave_speed:
        # (a speed at or above the wave speed gets the study's own range error, whatever the option)
        check_speed_limit(band.speed_high, catenary.contact_wire.wave_speed, accept="--allow-supercritical")
    names = [n.strip() for n in _dynamic_option(args, "pantograph").split(",")]
    if len(names) > 1 or args.fleet_shares is not None or args.second_pantograph_at is not None:
        if plot:
            raise ModelError("--plot is not drawn for a fleet design; drop it")
        return _fleet_command(args, catenary, names, band, objective, within, points)
    pantograph = load_pantograph(names[0])
    with progress(args) as report:
        study = dynamic_robust_study(catenary, pantograph, band, objective=objective, within=within,
                                     static_points=int(points[0]), speed_points=int(points[1]),
                                     workers=_dynamic_option(args, "workers"), progress=report)
    if plot:
        from presag_opt.plotting import plot_dynamic_objective

        written = plot_dynamic_objective(study, plot)
    data = study.to_dict()
    data["system"] = stitch_summary(catenary)
    print_warnings(data["warnings"])
    if args.json:
        print_json(data)
        return 0
    loss = "σ/F_m" if data["objective_name"] == "sigma-over-fm" else "σ [N]"
    fmt = "{:.4f}" if data["objective_name"] == "sigma-over-fm" else "{:.2f}"
    print(f"Dynamic robust pre-sag: {study.catenary_name}, {study.pantograph_name}")
    print(f"system: {data['system']}")
    beta_low, beta_high = data["beta"]
    print(f"band: F_stat {f_low:g}–{f_high:g} N × {v_low:g}–{v_high:g} km/h (β {beta_low:.2f}–{beta_high:.2f}), "
          f"{int(points[0])} × {int(points[1])} simulated points; objective: {data['risk']} of {loss}; "
          f"uplift limit {data['uplift_limit_mm']:g} mm")
    rows = [(m["method"], m["presag_mm"], m["objective"], m["worst_case_objective"], m["mean_objective"],
             m["uplift_max_mm"], m["cost_s"], "yes" if m["within_tolerance"] else "no") for m in data["methods"]]
    print(table(["method", f"S on {data['reference_span_m']:g} m [mm]", "objective", f"worst {loss}", f"mean {loss}",
                 "max uplift [mm]", "cost [s]", f"within {100 * within:g} %"],
                rows, ["{}", "{:.1f}", fmt, fmt, fmt, "{:.1f}", "{:.0f}", "{}"]))
    low, high = data["tolerance_mm"]
    print(f"\nInstallation tolerance (worst case within {100 * within:g} % of its minimum): {low:.1f}–{high:.1f} mm")
    print(f"Simulation: {data['runs_used']} runs at {data['presags_simulated']} pre-sags "
          f"(search {data['search_runs']} runs, {data['search_time_s']:.0f} s; whole study {data['wall_time_s']:.0f} s)")
    print(f"Recommendation: build the {data['recommendation']['method']} design — {data['recommendation']['reason']}")
    if plot:
        print(f"Plot saved to {written}")
    return 0


def _fleet_command(args: argparse.Namespace, catenary, names: list[str], band, objective, within: float,
                   points) -> int:
    """``presag robust --dynamic --pantograph A,B,...``: the fleet design beside each type's own optimum."""
    from presag_opt.dynamics.pantograph import load_pantograph
    from presag_opt.robust.fleet import fleet_robust_study

    shares = args.fleet_shares
    if shares is not None:
        if len(shares) != len(names) or any(s < 0 for s in shares) or sum(shares) <= 0:
            raise ModelError(f"--fleet-shares {','.join(f'{s:g}' for s in shares)}: give {len(names)} non-negative "
                             "shares, one per --pantograph type, not all zero")
        shares = [s / sum(shares) for s in shares]
    pantographs = [load_pantograph(n) for n in names]
    with progress(args) as report:
        design = fleet_robust_study(catenary, pantographs, band, shares=shares, spacing=args.second_pantograph_at,
                                    objective=objective, within=within, static_points=int(points[0]),
                                    speed_points=int(points[1]), workers=_dynamic_option(args, "workers"),
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
