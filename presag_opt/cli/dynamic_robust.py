"""``--dynamic-robust`` of ``presag recommend`` and ``presag design``: the dynamic robust design run in the
decision (:mod:`presag_opt.robust.dynamic_decision`), its cost announced on standard error first."""

from __future__ import annotations

import argparse


def add_dynamic_robust_option(p: argparse.ArgumentParser, where: str) -> None:
    """Add ``--dynamic-robust`` (shared by ``presag design`` and ``presag recommend``).

    Parameters
    ----------
    p : argparse.ArgumentParser
        The sub-command's parser.
    where : str
        What the command simulates, for the help text.
    """
    p.add_argument("--dynamic-robust", action="store_true",
                   help=f"also run the dynamic robust design of the band (as presag robust --dynamic) on {where} and "
                        "decide with it: the decision is then final where the dynamic design decides; minutes "
                        "(about a minute for the case study on an idle 2-core machine)")


def dynamic_robust(args: argparse.Namespace, decision, catenary, band, where: str, report):
    """Announce the cost on stderr, then run :func:`presag_opt.robust.dynamic_decision.dynamic_robust_decision`.

    Parameters
    ----------
    args : argparse.Namespace
        The command's options (``--quiet``).
    decision : Decision
        The decision without the dynamic robust design.
    catenary : Catenary
        The system simulated.
    band : OperatingBand
        Static forces, speeds and α_ae. [N], [m/s]
    where : str
        What is simulated, named in the output.
    report : callable or None
        Progress callback (standard error).
    """
    import sys

    from presag_opt.dynamics.pantograph import load_pantograph
    from presag_opt.report.line_dynamic import CHECK_PANTOGRAPH
    from presag_opt.robust.dynamic_decision import dynamic_cost, dynamic_robust_decision, simulated_band
    from presag_opt.units import KMH

    pantograph = load_pantograph(CHECK_PANTOGRAPH)
    simulated = simulated_band(band)
    cost = dynamic_cost(catenary, pantograph, simulated, workers=2)
    if not getattr(args, "quiet", False):
        print(f"\npresag: the dynamic robust design of {where} at {simulated.speed_low / KMH:.0f}–"
              f"{simulated.speed_high / KMH:.0f} km/h: {cost.describe()}, plus its quasi-static robust design "
              "(about a minute for the case study on an idle 2-core machine)", file=sys.stderr, flush=True)
    return dynamic_robust_decision(decision, catenary, pantograph, band, where=where, workers=2, progress=report)


def dynamic_robust_summary(result) -> dict:
    """JSON summary of a :class:`~presag_opt.robust.dynamic_decision.DynamicDecision` (mm, N, s).

    Parameters
    ----------
    result : DynamicDecision
        The decision made with the dynamic robust design.
    """
    data = result.study.to_dict()
    keep = ("presag_mm", "presag_rel_permille", "tolerance_mm", "uplift_max_mm", "reference_span_m", "runs_used",
            "wall_time_s", "static_force_N", "speed_kmh")
    return {"where": result.where, **{k: data[k] for k in keep if k in data}}
