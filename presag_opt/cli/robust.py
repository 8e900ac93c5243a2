"""``presag robust`` and ``presag tolerance``."""

from __future__ import annotations

import argparse

from presag_opt.cli.common import add_json_flag, band, model_help, output_path, print_json, progress, table
from presag_opt.errors import ModelError
from presag_opt.system.loader import load_catenary

DEFAULT_MODEL = "st_9.8_ideal"
CASE_STUDY_FM_BAND = "70:148"


def register(subparsers: argparse._SubParsersAction) -> None:
    """Add the robust-design sub-commands."""
    for name, helptext in (
        ("robust", "pre-sag that minimises the waviness over a band of mean contact forces"),
        ("tolerance", "installation tolerance: the pre-sag interval within a loss of the robust optimum"),
    ):
        p = subparsers.add_parser(name, help=helptext, description=f"{helptext[0].upper()}{helptext[1:]}.")
        p.add_argument("model", nargs="?", default=DEFAULT_MODEL, help=model_help("catenaries", DEFAULT_MODEL))
        p.add_argument("--fm-band", default=CASE_STUDY_FM_BAND, metavar="N:N",
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
            p.add_argument("--step-mm", metavar="MM", type=float, default=5.0,
                           help="construction step of per-dropper heights in mm (default 5)")
            p.add_argument("--asymmetric", action="store_true", help="allow per-dropper profiles that are not symmetric")
        p.set_defaults(handler=robust_command if name == "robust" else tolerance_command)


def parse_within(text: str) -> float:
    """``10`` or ``10%`` (percent) -> 0.1; the range is the API's to check."""
    try:
        return float(text.removesuffix("%")) / 100.0
    except ValueError:
        raise ModelError(f"--within = {text!r}: write a percentage such as 10 (or 10%)") from None


def _study(args: argparse.Namespace, **kwargs):
    from presag_opt.robust import robust_study  # cvxpy is imported only when a robust command runs

    try:
        fm_band = band(args.fm_band)
    except argparse.ArgumentTypeError as exc:
        raise ModelError(f"--fm-band {exc}") from None
    within = parse_within(args.within)
    plot = output_path(args.plot) if args.plot else None
    catenary = load_catenary(args.model)
    with progress(args) as report:
        study = robust_study(catenary, fm_band, within=within, progress=report, **kwargs)
    return study, plot


def robust_command(args: argparse.Namespace) -> int:
    from presag_opt.robust import Buildability, Risk

    risk = Risk.parse(args.risk)
    build = Buildability(step=args.step_mm * 1e-3, symmetric=not args.asymmetric) if args.shape == "per-dropper" else None
    study, plot = _study(args, shape=args.shape, risk=risk, buildability=build)
    _plot(args, study, plot)
    data = study.to_dict()
    if args.json:
        print_json(data)
        return 0
    print(f"Robust pre-sag: {study.catenary_name}, F_m {data['fm_band_N'][0]:g}–{data['fm_band_N'][1]:g} N, "
          f"{data['shape']}, {data['risk']}")
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
    return 0


def tolerance_command(args: argparse.Namespace) -> int:
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
