"""``presag sensitivity``: global sensitivity of one output of a case to its assumed inputs (Morris, Sobol)."""

from __future__ import annotations

import argparse
import sys

from presag_opt.cli.common import (
    add_json_flag,
    output_folder,
    print_json,
    progress,
    report_failures,
    table,
)
from presag_opt.cli.decision_options import add_workers_option, workers_of
from presag_opt.jobs.studies import SENSITIVITY_CASE


def register(subparsers: argparse._SubParsersAction) -> None:
    """Add the ``sensitivity`` sub-command."""
    p = subparsers.add_parser(
        "sensitivity",
        help="global sensitivity of a result to the assumed inputs (Morris screening, Sobol indices)",
        description=(
            "Vary the assumed numbers of a case's model files jointly over their plausible ranges (declared "
            "beside each value as range = [low, high], else value ± 20 %) and rank them by their effect on one "
            "output: Morris elementary effects (mu*, sigma) to screen, Sobol indices (S1, ST with bootstrap "
            "confidence intervals) to quantify. Outputs: recommendation, robust (quasi-static); "
            "dynamic:V1,V2 (sigma and sigma/F_m at those km/h), minima:V (do the sigma/F_m minima move with S), "
            "validity:V1,V2,... (beta*), run as reduced studies (5 spans, 1 m, 4 ms); dynamic-robust (the dynamic "
            "robust pre-sag of presag robust --dynamic over F_stat 70-140 N x 50-90 km/h and its tolerance, each "
            "sample one design at screening numerics)."
        ),
    )
    p.add_argument("case", nargs="?", default=SENSITIVITY_CASE, help=f"case file or built-in name (default {SENSITIVITY_CASE})")
    p.add_argument("--quantity", dest="output", required=True, metavar="QUANTITY",
                   help="the result whose sensitivity is analysed: recommendation | robust | dynamic-robust | "
                        "dynamic:V1,V2 | minima:V | validity:V1,V2,... (speeds in km/h)")
    p.add_argument("--method", choices=["morris", "sobol", "spread"], default="morris",
                   help="morris (screen), sobol (S1, ST) or spread (the output's mean and spread only)")
    p.add_argument("--inputs", metavar="NAME,...", default=None,
                   help="dotted input names (as presag sweep), default: every assumed input the output depends on")
    p.add_argument("--range", metavar="NAME=LOW:HIGH", action="append", default=[], dest="ranges",
                   help="range of an input in its model-file unit (adds the input); repeatable")
    p.add_argument("--samples", metavar="N", type=int, default=None,
                   help="Morris trajectories (default 10) or Sobol base sample, a power of two (default 64)")
    p.add_argument("--seed", metavar="N", type=int, default=0, help="seed of the design and bootstrap (default 0)")
    add_workers_option(p, scheduler=True)
    p.add_argument("--scheduler", metavar="ADDRESS", default=None,
                   help="Dask distributed scheduler to run the evaluations on (e.g. tcp://host:8786)")
    p.add_argument("--out", metavar="STORE", default=None,
                   help="folder of the resumable stores (default: a folder of the analysis in the cache, "
                        "unless --no-cache); a killed analysis run again computes only the evaluations not kept")
    p.add_argument("--plot", metavar="DIR", default=None, help="save the Morris or Sobol figures into this folder")
    add_json_flag(p)
    p.set_defaults(handler=sensitivity_command)


def sensitivity_command(args: argparse.Namespace) -> int:
    """Handler of ``presag sensitivity``."""
    from presag_opt.jobs import sensitivity_study

    workers = workers_of(args)
    plot = output_folder(args.plot, "--plot") if args.plot else None
    out = output_folder(args.out, "--out") if args.out else None

    def announce(text: str) -> None:
        print(f"presag sensitivity: {text}", file=sys.stderr, flush=True)

    inputs = [n.strip() for n in args.inputs.split(",") if n.strip()] if args.inputs else None
    with progress(args) as report:
        result = sensitivity_study(
            args.case, quantity=args.output, method=args.method, inputs=inputs, ranges=args.ranges,
            samples=args.samples, seed=args.seed, workers=workers, scheduler=args.scheduler, out=out,
            announce=announce, progress=report)
    paths = save_sensitivity_figures(result, plot) if plot and result.method != "spread" else []
    if args.json:
        print_json(result.to_dict())
        return report_failures("sensitivity", result.failure_summary())
    print(f"{result.case}: {result.method} sensitivity of {result.output} over {len(result.inputs)} inputs, "
          f"{result.evaluations} evaluations in {result.seconds:.0f} s (seed {result.seed}"
          + (f"; {result.resolution}" if result.resolution else "") + ")")
    solver = result.solver
    if solver.get("form_findings"):
        print(f"form-findings: {solver['form_findings']} solved ({solver['cached']} from the cache), iterations "
              f"median {solver['iterations']['q50']:.0f}, largest {solver['iterations']['q100']:.0f}; "
              f"{solver['restarts']} restart(s)")
    unit = {"morris": "trajectories", "sobol": "base samples"}.get(result.method, "points")
    for t in result.indices:
        used = f"; {t.samples} of {t.samples + t.dropped} {unit}" if t.dropped else ""
        print(f"\n{t.output} [{t.unit}]: mean {t.mean:.4g}, std {t.std:.3g}{used}")
        if t.method == "spread":
            continue
        if t.morris:
            print(table(["input", "mu*", "± (95 %)", "sigma", "mu*/max"],
                        [(e.name, e.mu_star, e.mu_star_conf, e.sigma, e.relative) for e in t.morris],
                        ["{}", "{:.4g}", "{:.2g}", "{:.4g}", "{:.2f}"]))
        else:
            print(table(["input", "S1", "± (95 %)", "ST", "± (95 %)"],
                        [(s.name, s.first, s.first_conf, s.total, s.total_conf) for s in t.sobol],
                        ["{}", "{:.3f}", "{:.3f}", "{:.3f}", "{:.3f}"]))
    if paths:
        print("\nPlots saved: " + ", ".join(str(p) for p in paths))
    return report_failures("sensitivity", result.failure_summary())


def save_sensitivity_figures(result, folder):
    """The figures of a result (imports matplotlib only when asked).

    Parameters
    ----------
    result : SensitivityResult
        The result to draw.
    folder : str or Path
        Folder the figures are written into.

    Returns
    -------
    list of Path
        The figures written.
    """
    from presag_opt.sensitivity.plots import save_sensitivity_plots

    return save_sensitivity_plots(result, folder)
