"""``presag tolerance --monte-carlo``: the installation tolerance as a line crew makes it.

Independent errors of each dropper's length and of each mast's contact-wire (registration) and
messenger-wire support heights, drawn many times; the distribution of the design's worst case
(quasi-static: waviness R over the F_m band; ``--dynamic``: σ/F_m, F_m − 3σ and the steady-arm uplift
over the band's grid of static forces × speeds) with percentiles and their confidence intervals; or
(``--find-dropper-tolerance``) the largest per-dropper error whose P95 stays within ``--within`` of
the error-free design, beside the pre-sag interval of ``presag tolerance``. The options are
registered on ``presag tolerance`` by :mod:`presag_opt.cli.robust`.
"""

from __future__ import annotations

import argparse
import math

from presag_opt.cli.common import output_folder, print_json, report_failures, table
from presag_opt.cli.decision_options import workers_of
from presag_opt.errors import ModelError
from presag_opt.jobs.options import (
    DYNAMIC_MONTE_CARLO_SAMPLES,
    MAX_INSTALLATION_ERROR_MM,
    MAX_MONTE_CARLO_SAMPLES,
    MONTE_CARLO_SAMPLES,
)


def add_options(p: argparse.ArgumentParser) -> None:
    """The Monte Carlo options of ``presag tolerance``."""
    g = p.add_argument_group(
        "installation errors by Monte Carlo (--monte-carlo)",
        "independent errors of every dropper length and every mast's contact-wire and messenger-wire support height; "
        "the distribution of the design's worst case (P50, P90, P95, P99 with 95 % order-statistic intervals)",
    )
    g.add_argument("--monte-carlo", action="store_true", help="the tolerance from random installation errors")
    g.add_argument("--dropper-error", metavar="MM", default=None,
                   help="size of each dropper's length error in mm: σ (normal) or t of ±t (uniform)")
    g.add_argument("--height-error", metavar="MM", default=None,
                   help="size of each mast's contact-wire and messenger-support height errors in mm (default 0)")
    g.add_argument("--distribution", choices=("normal", "uniform"), default="normal",
                   help="normal (size = σ, default) or uniform within ±size")
    g.add_argument("--samples", metavar="N", default=None,
                   help=f"realisations (default {MONTE_CARLO_SAMPLES} quasi-static, "
                   f"{DYNAMIC_MONTE_CARLO_SAMPLES} with --dynamic)")
    g.add_argument("--seed", metavar="N", default="0", help="seed of the random draws (default 0)")
    g.add_argument("--presag-mm", metavar="MM", default=None,
                   help="the design's pre-sag on the reference span in mm (default the robust parabola of the band)")
    g.add_argument("--dynamic", action="store_true",
                   help="simulate every realisation over the band's static forces × speeds (from 50 km/h; 4 × 3 "
                   "points, the case-study pantograph)")
    g.add_argument("--out", metavar="DIR", default=None,
                   help="folder keeping every finished realisation of --dynamic (default: a folder of this Monte Carlo "
                   "in the cache, unless --no-cache): a killed run, started again with the same options, simulates "
                   "only the rest")
    g.add_argument("--find-dropper-tolerance", action="store_true",
                   help="the largest dropper error whose P95 stays within --within of the error-free design")


def _number(args, name: str, unit: str, low: float, high: float, *, integer: bool = False, default=None):
    text = getattr(args, name)
    option = "--" + name.replace("_", "-")
    if text is None:
        return default
    try:
        value = int(text) if integer else float(text)
    except ValueError:
        raise ModelError(f"{option} = {text!r} is not a {'whole ' if integer else ''}number; valid range "
                         f"[{low:g}, {high:g}]{(' ' + unit) if unit else ''}") from None
    if not math.isfinite(value) or not low <= value <= high:
        raise ModelError(f"{option} = {text} {unit} is outside the valid range [{low:g}, {high:g}] {unit}".replace("  ", " "))
    return value


def check_options(args: argparse.Namespace) -> None:
    """Refuse Monte Carlo options without ``--monte-carlo`` (one line, before any work)."""
    if args.monte_carlo:
        return
    for name in ("dropper_error", "height_error", "samples", "presag_mm"):
        if getattr(args, name) is not None:
            raise ModelError(f"--{name.replace('_', '-')} is an option of the Monte Carlo; add --monte-carlo")
    if args.out is not None:
        raise ModelError("--out is an option of the Monte Carlo; add --monte-carlo --dynamic")
    for name in ("dynamic", "find_dropper_tolerance"):
        if getattr(args, name):
            raise ModelError(f"--{name.replace('_', '-')} is an option of the Monte Carlo; add --monte-carlo")
    if args.distribution != "normal" or args.seed != "0":
        raise ModelError("--distribution and --seed are options of the Monte Carlo; add --monte-carlo")


def tolerance_keywords(args: argparse.Namespace) -> dict:
    """The Monte Carlo options as keywords of the ``tolerance`` job (none without ``--monte-carlo``),
    each number checked with its flag named, before any work."""
    if not args.monte_carlo:
        return {}
    dropper = _number(args, "dropper_error", "mm", 0.0, MAX_INSTALLATION_ERROR_MM)
    if args.find_dropper_tolerance:
        if args.dynamic:
            raise ModelError("--find-dropper-tolerance is quasi-static; drop --dynamic")
        if dropper is not None:
            raise ModelError("--find-dropper-tolerance searches the dropper error; drop --dropper-error")
    elif dropper is None:
        raise ModelError("--monte-carlo needs --dropper-error MM (or --find-dropper-tolerance)")
    if args.out is not None and not args.dynamic:
        raise ModelError("--out keeps the realisations of --dynamic (the quasi-static Monte Carlo takes seconds); "
                         "add --dynamic or drop --out")
    return dict(
        dropper_error_mm=dropper,
        height_error_mm=_number(args, "height_error", "mm", 0.0, MAX_INSTALLATION_ERROR_MM, default=0.0),
        samples=_number(args, "samples", "", 1, MAX_MONTE_CARLO_SAMPLES, integer=True),  # None: the job's default
        seed=_number(args, "seed", "", 0, 2**32 - 1, integer=True),
        presag_mm=_number(args, "presag_mm", "mm", 0.0, 1000.0),
        distribution=args.distribution, find_dropper_tolerance=args.find_dropper_tolerance, dynamic=args.dynamic,
        workers=workers_of(args), store=output_folder(args.out) if args.out is not None else None,
    )


def print_answer(args: argparse.Namespace, answer, plot) -> int:
    """Print the Monte Carlo of ``presag tolerance --monte-carlo`` (a table, or ``--json``) and draw its
    histogram.

    Parameters
    ----------
    args : argparse.Namespace
        The parsed command line (``--json``).
    answer : ToleranceAnswer
        The job's answer, with its Monte Carlo.
    plot : Path or None
        Where to draw the histogram of the worst cases (None: no plot).

    Returns
    -------
    int
        Exit status: 0, or the status of a Monte Carlo with failed realisations. [-]
    """
    data = answer.to_dict()
    if plot:
        _plot(answer.worst_cases(), data, plot)
    summary = answer.failure_summary()
    if args.json:
        print_json(data)
        return report_failures("tolerance", summary)
    _print(data)
    if plot:
        print(f"Plot saved to {plot}")
    return report_failures("tolerance", summary)


def _print(data: dict) -> None:
    unit = "" if data["unit"] == "-" else f" [{data['unit']}]"
    fmt = "{:.4f}" if data["unit"] == "-" else "{:.2f}"
    print(f"Installation errors by Monte Carlo: {data['catenary']}, S = {data['presag_mm']:.1f} mm on "
          f"{data['reference_span_m']:g} m, {data['kind']}")
    print(f"errors per dropper {data['dropper_error_mm']:.2f} mm, per mast height {data['height_error_mm']:.2f} mm "
          f"({data['distribution']}: {'σ' if data['distribution'] == 'normal' else '±t'}); {data['samples']} "
          f"realisations" + (f" ({data['samples_used']} finished)" if data.get("failed") else "")
          + f", seed {data['seed']}")
    rows = [("error-free", data["nominal_worst_case"], None, None)]
    rows += [(f"P{k}", data[f"p{k}"]["value"], *data[f"p{k}"]["ci"]) for k in (50, 90, 95, 99)]
    print(table([data["measure"] + unit, "value", "95 % CI low", "95 % CI high"], rows, ["{}", fmt, fmt, fmt]))
    if data["kind"] == "dynamic":
        for key, name in (("smallest_statistical_min_N", "smallest F_m − 3σ [N]"),
                          ("largest_uplift_mm", "largest steady-arm uplift [mm]")):
            part = data[key]
            print(f"{name}: error-free {part['nominal']:.1f}; " + ", ".join(
                f"P{k} {part[f'p{k}']['value']:.1f}" for k in (50, 90, 95, 99)))
        slack = data["slack_droppers_at_rest"]
        if slack["realisations"]:
            print(f"{slack['realisations']} realisations leave droppers slack at rest (at most {slack['most']}); "
                  "they start just taut, without their slack length")
        print(f"simulation: {data['wall_time_s']:.0f} s with {data['workers']} workers")
    if "largest_dropper_error_mm" in data:
        low, high = data["s_interval_mm"]
        print(f"\nLargest dropper error with P{data['held_percentile']} within {data['within'] * 100:g} % of the "
              f"error-free design: {data['largest_dropper_error_mm']:.2f} mm ({data['distribution']}); "
              f"the pre-sag interval within {data['s_interval_within'] * 100:g} %: {low:.1f}–{high:.1f} mm")


def _plot(values, data: dict, path) -> None:
    from presag_opt.style import drawing, new_figure, save_figure

    with drawing():
        fig, ax = new_figure(width=6.4, height=4.0)
        ax.hist(values, bins=min(60, max(10, len(values) // 50)), color="0.7")
        ax.axvline(data["nominal_worst_case"], color="k", label="error-free")
        ax.axvline(data["p95"]["value"], color="C3", linestyle="--", label="P95")
        unit = "" if data["unit"] == "-" else f" [{data['unit']}]"
        ax.set_xlabel(data["measure"] + unit)
        ax.set_ylabel("realisations")
        ax.set_title(f"S = {data['presag_mm']:.1f} mm, dropper {data['dropper_error_mm']:.1f} mm, height "
                     f"{data['height_error_mm']:.1f} mm ({data['distribution']})", fontsize=9)
        ax.legend()
        save_figure(fig, path)
