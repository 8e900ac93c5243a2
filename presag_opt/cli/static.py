"""``presag form-find``, ``presag elasticity`` and ``presag cache``."""

from __future__ import annotations

import argparse
import os

from presag_opt.cli.common import (
    add_json_flag,
    add_plot_option,
    float_list,
    form_find_for,
    model_help,
    plot_folder,
    positive_float,
    print_json,
    progress,
    progress_enabled,
    table,
)
from presag_opt.cli.decision_options import add_element_length_option
from presag_opt.elasticity import DEFAULT_FORCES, elasticity_study
from presag_opt.errors import ModelError
from presag_opt.runtime import NO_CACHE_ENV, default_cache_directory
from presag_opt.static import cache
from presag_opt.static.discretisation import StaticSettings
from presag_opt.system.loader import builtin_model_names, load_catenary

DEFAULT_MODEL = "st_9.8_ideal"


def register(subparsers: argparse._SubParsersAction) -> None:
    """Add the static-model sub-commands."""
    models = ", ".join(builtin_model_names())
    p = subparsers.add_parser(
        "form-find",
        help="form-find a catenary and print its dropper schedule",
        description=f"Form-find a catenary and print its dropper schedule. Built-in models: {models}.",
    )
    p.add_argument("model", nargs="?", default=DEFAULT_MODEL, help=model_help("catenaries", DEFAULT_MODEL))
    p.add_argument("--span", metavar="NUMBER", type=int, default=None, help="print only this span (counted from 1)")
    add_element_length_option(p)
    add_json_flag(p)
    p.set_defaults(handler=form_find_command)

    p = subparsers.add_parser(
        "elasticity",
        help="elasticity curves of a span",
        description=f"Elasticity of a span at force levels (re-solved equilibria). Built-in models: {models}.",
    )
    p.add_argument("model", nargs="?", default=DEFAULT_MODEL, help=model_help("catenaries", DEFAULT_MODEL))
    p.add_argument("--span", metavar="NUMBER", type=int, default=None,
                   help="span counted from 1 (default: the central span)")
    p.add_argument("--forces", metavar="N,N,...", type=float_list, default=list(DEFAULT_FORCES),
                   help="force levels in N, a list A,B,C (default 50,100,150,200)")
    p.add_argument("--step", metavar="M", type=positive_float, default=0.5,
                   help="point spacing of the nonlinear curves in m (default 0.5)")
    p.add_argument("--linear", action="store_true", help="add the linear (tangent stiffness) curve, every 0.1 m")
    p.add_argument("--presag", metavar="MM", type=positive_float, default=None,
                   help="override the model's pre-sag: mid-span pre-sag of the longest span in mm")
    add_plot_option(p, "the curves")
    add_element_length_option(p)
    add_json_flag(p)
    p.set_defaults(handler=elasticity_command)

    p = subparsers.add_parser(
        "cache",
        help="show or clear the cache of form-found states and of the finished evaluations of long analyses",
        description="Form-found states are cached in $XDG_CACHE_HOME/presag_opt (default ~/.cache/presag_opt), "
        "keyed by the model's values, the settings, the package version and the code; the finished evaluations "
        "of long analyses (presag sensitivity, presag tolerance --monte-carlo --dynamic) are kept in its "
        f"'evaluations' folder, one folder per analysis; --no-cache or {NO_CACHE_ENV}=1 turns both off.",
    )
    p.add_argument("--clear", action="store_true", help="delete the cached states and the kept evaluations")
    p.set_defaults(handler=cache_command)


def span_index(args: argparse.Namespace, n_spans: int) -> int | None:
    """The 0-based span from ``--span`` (1-based), checked.

    Parameters
    ----------
    args : argparse.Namespace
        Parsed options of the sub-command.
    n_spans : int
        Number of spans of the section. [-]
    """
    if args.span is None:
        return None
    if not 1 <= args.span <= n_spans:
        raise ModelError(f"--span = {args.span} is outside the valid range [1, {n_spans}]")
    return args.span - 1


def form_find_command(args: argparse.Namespace) -> int:
    """Handler of ``presag form-find``."""
    catenary = load_catenary(args.model)
    span = span_index(args, catenary.layout.n_spans)
    state = form_find_for(args, catenary, StaticSettings(element_length=args.element_length))
    rows = [r for r in state.dropper_schedule() if span is None or r.span == span + 1]
    arms = state.steady_arm_forces()
    if args.json:
        print_json({
            "catenary": catenary.name,
            "form_finding": state.form_finding.to_dict(),
            "droppers": [r.__dict__ for r in rows],
            "steady_arms": [
                {"mast": i + 1, "force_N": f, "angle_deg": a}
                for i, (f, a) in enumerate(zip(arms, state.steady_arm_angles() * 180 / 3.141592653589793))
            ],
        })
        return 0
    print(f"Dropper schedule: {catenary.name}")
    print(table(
        ["span", "position [m]", "cut length [mm]", "installed [mm]", "force [N]"],
        [(r.span, r.position_m, r.length_mm, r.installed_length_mm, r.force_N) for r in rows],
        ["{}", "{:.2f}", "{:.0f}", "{:.1f}", "{:.1f}"],
    ))
    if len(arms):
        print(f"\nSteady arms: tension {arms.min():.0f}…{arms.max():.0f} N")
    return 0


def elasticity_command(args: argparse.Namespace) -> int:
    """Handler of ``presag elasticity``."""
    plots = plot_folder(args)
    catenary = load_catenary(args.model)
    if args.presag is not None:
        catenary = catenary.with_presag(args.presag * 1e-3 / max(catenary.layout.span_lengths))
    span = span_index(args, catenary.layout.n_spans)
    progress_enabled(args)  # --quiet with --progress is refused before the work
    state = form_find_for(args, catenary, StaticSettings(element_length=args.element_length))
    with progress(args, total=len(args.forces) + args.linear) as report:
        study = elasticity_study(state, span=span, forces=args.forces, step=args.step, linear=args.linear,
                                 progress=report, workers=os.cpu_count() or 1)
    plot = None
    if plots:
        from presag_opt.plotting import plot_elasticity

        plot = plot_elasticity(study, plots / "elasticity.png")
    if args.json:
        print_json(study.to_dict())
        return 0
    print(f"Elasticity of span {study.span + 1} ({study.curves[0].span_length:g} m): {catenary.name}")
    rows = []
    for curve in study.curves:
        s = curve.summary_mm_per_N()
        rows.append((
            "linear" if curve.force is None else f"{curve.force:g}",
            s["e_mid_mm_per_N"], s["e_mast_mm_per_N"], s["e_max_mm_per_N"], s["e_min_mm_per_N"],
            s["delta_e_mm_per_N"], s["uniformity"],
            None if curve.slack_droppers is None else int(curve.slack_droppers.max()),
        ))
    print(table(
        ["force [N]", "e_mid", "e_mast", "e_max", "e_min", "Δe [mm/N]", "uniformity", "slack droppers (max)"],
        rows,
        ["{}", "{:.3f}", "{:.3f}", "{:.3f}", "{:.3f}", "{:.3f}", "{:.3f}", "{}"],
    ))
    for message in study.warnings:
        print(f"warning: {message}")
    if plot:
        print(f"\nPlot saved to {plot}")
    return 0


def cache_command(args: argparse.Namespace) -> int:
    """Handler of ``presag cache``: where the cache is and what it holds, or ``--clear``."""
    folder = default_cache_directory()
    if args.clear:
        print(f"removed {cache.clear(folder)} cached state(s) and the evaluations of "
              f"{cache.clear_evaluations(folder)} analyses from {folder}")
        return 0
    files = sorted(folder.glob("state-*.npz")) if folder.is_dir() else []
    size = sum(f.stat().st_size for f in files)
    kept = folder / cache.EVALUATIONS
    analyses = [p for p in kept.iterdir() if p.is_dir()] if kept.is_dir() else []
    state = f"off (--no-cache or {NO_CACHE_ENV})" if cache.active_directory() is None else "on"
    print(f"cache {folder}: {len(files)} state(s), {size / 1e6:.1f} MB; the evaluations of {len(analyses)} "
          f"analyses; {state}")
    return 0
