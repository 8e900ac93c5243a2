"""``presag robust`` and ``presag tolerance``."""

from __future__ import annotations

import argparse
import sys

from presag_opt.cli.common import add_json_flag, print_json, table
from presag_opt.errors import ModelError
from presag_opt.system.loader import builtin_model_names, load_catenary

DEFAULT_MODEL = "st_9.8_ideal"
CASE_STUDY_FM_BAND = "70:148"


def register(subparsers: argparse._SubParsersAction) -> None:
    """Add the robust-design sub-commands."""
    models = ", ".join(builtin_model_names())
    for name, helptext in (
        ("robust", "pre-sag that minimises the waviness over a band of mean contact forces"),
        ("tolerance", "installation tolerance: the pre-sag interval within a loss of the robust optimum"),
    ):
        p = subparsers.add_parser(name, help=helptext, description=f"{helptext[0].upper()}{helptext[1:]}. "
                                  f"Built-in models: {models}.")
        p.add_argument("model", nargs="?", default=DEFAULT_MODEL, help=f"model file or built-in name (default {DEFAULT_MODEL})")
        p.add_argument("--fm-band", default=CASE_STUDY_FM_BAND, metavar="LOW:HIGH",
                       help=f"mean contact force band in N (default {CASE_STUDY_FM_BAND}, the case study)")
        p.add_argument("--within", default="10%", help="allowed loss for the tolerance band, e.g. 10%% (default)")
        p.add_argument("--plot", metavar="FILE", default=None, help="save R against S over the band (PNG, PDF, SVG)")
        add_json_flag(p)
        if name == "robust":
            p.add_argument("--shape", choices=("parabola", "per-dropper"), default="parabola")
            p.add_argument("--risk", default="minimax", help="minimax (default), mean, or cvar:LEVEL such as cvar:0.9")
            p.add_argument("--step-mm", type=float, default=5.0, help="construction step of per-dropper heights in mm (default 5)")
            p.add_argument("--asymmetric", action="store_true", help="allow per-dropper profiles that are not symmetric")
        p.set_defaults(handler=robust_command if name == "robust" else tolerance_command)


def parse_band(text: str) -> tuple[float, float]:
    """``70:148`` -> (70.0, 148.0), checked."""
    try:
        low, high = (float(v) for v in text.split(":"))
    except ValueError:
        raise ModelError(f"--fm-band = {text!r}: write LOW:HIGH in N, e.g. 70:148") from None
    if not (0.0 < low < high <= 1000.0):
        raise ModelError(f"--fm-band = {text} N is empty or inverted; valid: 0 < LOW < HIGH <= 1000 N")
    return low, high


def parse_within(text: str) -> float:
    """``10%`` or ``0.1`` -> 0.1."""
    try:
        value = float(text[:-1]) / 100.0 if text.endswith("%") else float(text)
    except ValueError:
        raise ModelError(f"--within = {text!r}: write a percentage such as 10%") from None
    if not 0.0 < value <= 2.0:
        raise ModelError(f"--within = {text} is outside the valid range (0, 200] %")
    return value


def _study(args: argparse.Namespace, **kwargs):
    from presag_opt.robust import robust_study  # cvxpy is imported only when a robust command runs

    band = parse_band(args.fm_band)
    within = parse_within(args.within)
    catenary = load_catenary(args.model)
    progress = None if args.json else (lambda msg: print(f"… {msg}", file=sys.stderr))
    return robust_study(catenary, band, within=within, progress=progress, **kwargs)


def robust_command(args: argparse.Namespace) -> int:
    from presag_opt.robust import Buildability, Risk

    risk = Risk.parse(args.risk)
    build = Buildability(step=args.step_mm * 1e-3, symmetric=not args.asymmetric) if args.shape == "per-dropper" else None
    study = _study(args, shape=args.shape, risk=risk, buildability=build)
    _plot(args, study)
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
    study = _study(args)
    _plot(args, study)
    data = study.to_dict()
    if args.json:
        print_json({k: data[k] for k in ("catenary", "fm_band_N", "reference_span_m", "presag_mm", "worst_case_waviness_mm",
                                         "tolerance_mm", "tolerance_within", "nominal_presag_mm",
                                         "nominal_worst_case_waviness_mm", "nominal_tolerance_mm")})
        return 0
    (low, high), (nlow, nhigh) = data["tolerance_mm"], data["nominal_tolerance_mm"]
    print(f"Installation tolerance: {study.catenary_name}, F_m {data['fm_band_N'][0]:g}–{data['fm_band_N'][1]:g} N, "
          f"within {data['tolerance_within'] * 100:g} % of the optimum")
    print(table(["design", "S [mm]", "tolerance [mm]", "width [mm]"], [
        ("robust over the band", data["presag_mm"], f"{low:.1f}–{high:.1f}", high - low),
        ("for the band centre only", study.nominal_tolerance.best * data["reference_span_m"] * 1e3,
         f"{nlow:.1f}–{nhigh:.1f}", nhigh - nlow),
    ], ["{}", "{:.1f}", "{}", "{:.1f}"]))
    return 0


def _plot(args: argparse.Namespace, study) -> None:
    if args.plot:
        from presag_opt.plotting import plot_waviness

        plot_waviness(study, args.plot)
        if not args.json:
            print(f"Plot saved to {args.plot}")
