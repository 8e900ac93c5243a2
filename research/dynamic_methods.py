"""Where each pre-sag method holds (issue 10): the Δe rule, the quasi-static robust design and the
dynamic robust design, compared by simulation on the case-study catenary.

Run: python research/dynamic_methods.py [--workers N] [--parts case,beta,high] [--out FILE.json]

ST 9,8/9,8 ideal spans, the case-study pantograph and analysis window (``case_study_st98``),
F_stat 70–140 N, α_ae 0.00097 N/(km/h)², worst case of σ/F_m, uplift limit 83.5 mm, 4 × 3 points
per band. Each band is one ``presag robust --dynamic`` study (:func:`dynamic_robust_study`).

case   F_stat 70–140 N × 50–90 km/h: the dynamic robust S beside the quasi-static robust S of the
       paper's F_m band 70–148 N (55.8 mm), the Δe rule at its centre (61.4 mm) and the paper's 67 mm,
       each simulated on the same grid: worst-case and mean σ/F_m, largest steady-arm uplift.
beta   speed bands β ± 0.05 around β = 0.15, 0.30, 0.45 and 0.60: the three methods with their cost
       and the recommendation.
high   a band above the quasi-static validity limit, 120–180 km/h.

A band where no pre-sag keeps the steady-arm uplift limit is reported with the reason, and then
studied again without the limit (1000 mm) so that the methods can still be compared there.
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import time

from presag_opt.design.band import KMH, OperatingBand
from presag_opt.design.speed_range import STEADY_ARM_UPLIFT_LIMIT
from presag_opt.dynamics.case import load_case
from presag_opt.errors import ConvergenceError, ModelError
from presag_opt.robust import BandEvaluator, DynamicObjective, OperatingGrid, dynamic_robust_study

FORCES = (70.0, 140.0)
AERO = 0.00097 / KMH**2
POINTS = (4, 3)
CASE_SPEEDS = (50.0, 90.0)
PUBLISHED = {"quasi-static robust, F_m 70–148 N": 55.8, "Δe rule at 109 N": 61.4, "paper's recommendation": 67.0}
"""Pre-sags of the case study [mm]: this project's quasi-static robust design and Δe rule for the paper's
F_m band, and the paper's recommended 1.12 ‰ on 60 m."""
BETAS = (0.15, 0.30, 0.45, 0.60)
HIGH_SPEEDS = (120.0, 180.0)
NO_LIMIT = 1.0
"""The largest uplift limit a DynamicObjective takes, 1000 mm: no limit in effect. [m]"""


def band(speeds_kmh) -> OperatingBand:
    return OperatingBand(static_force_low=FORCES[0], static_force_high=FORCES[1], speed_low=speeds_kmh[0] * KMH,
                         speed_high=speeds_kmh[1] * KMH, aero_coefficient=AERO)


def study_band(case, speeds_kmh, workers: int, uplift_limit: float = STEADY_ARM_UPLIFT_LIMIT) -> dict:
    """One band's dynamic robust study as JSON-ready data, or the reason there is no design (and,
    when it is the uplift limit, the study without it)."""
    started = time.perf_counter()
    print(f"\n== F_stat {FORCES[0]:g}–{FORCES[1]:g} N × {speeds_kmh[0]:.0f}–{speeds_kmh[1]:.0f} km/h, uplift limit "
          f"{uplift_limit * 1e3:g} mm; load average {os.getloadavg()[0]:.2f}", flush=True)
    try:
        study = dynamic_robust_study(case.catenary, case.pantograph, band(speeds_kmh), static_points=POINTS[0],
                                     speed_points=POINTS[1], settings=case.settings, workers=workers,
                                     objective=DynamicObjective(uplift_limit=uplift_limit))
    except (ModelError, ConvergenceError) as exc:
        print(f"no design: {exc}", flush=True)
        failed = {"speed_kmh": list(speeds_kmh), "error": str(exc), "wall_time_s": time.perf_counter() - started}
        if "steady-arm uplift" in str(exc) and uplift_limit < NO_LIMIT:
            failed["without_uplift_limit"] = study_band(case, speeds_kmh, workers, NO_LIMIT)
        return failed
    data = study.to_dict()
    print(f"β {data['beta'][0]:.2f}–{data['beta'][1]:.2f}; {data['runs_used']} runs, {data['wall_time_s']:.0f} s")
    for m in data["methods"]:
        print(f"  {m['method']:24s} S {m['presag_mm']:6.1f} mm  worst σ/F_m {m['worst_case_objective']:.4f}  mean "
              f"{m['mean_objective']:.4f}  uplift {m['uplift_max_mm']:5.1f} mm  cost {m['cost_s']:5.0f} s  "
              f"within 10 %: {'yes' if m['within_tolerance'] else 'no'}")
    print(f"  tolerance {data['tolerance_mm'][0]:.1f}–{data['tolerance_mm'][1]:.1f} mm")
    print(f"  recommendation: {data['recommendation']['method']}: {data['recommendation']['reason']}", flush=True)
    return data


def case_part(case, workers: int, uplift_limit: float) -> dict:
    """The case-study band and the published pre-sags simulated on its grid."""
    data = study_band(case, CASE_SPEEDS, workers, uplift_limit)
    if "error" in data:
        return data
    grid = OperatingGrid.from_band(band(CASE_SPEEDS), static_points=POINTS[0], speed_points=POINTS[1])
    evaluator = BandEvaluator(case.catenary, case.pantograph, grid, settings=case.settings, workers=workers)
    objective = DynamicObjective()
    designs = {**PUBLISHED, "dynamic robust": data["presag_mm"]}
    span = evaluator.reference_span
    rows = []
    for (label, presag_mm), evaluation in zip(designs.items(), evaluator.evaluate_many(
            [s * 1e-3 / span for s in designs.values()])):
        stats = evaluation.statistics
        losses = stats.losses("sigma-over-fm")
        rows.append({"design": label, "presag_mm": presag_mm, "worst_sigma_over_Fm": objective.worst_case(stats),
                     "mean_sigma_over_Fm": float(grid.weights @ losses),
                     "uplift_max_mm": float(stats.uplift_max.max() * 1e3),
                     "statistical_min_N": float(stats.statistical_min.min())})
        print(f"  {label:36s} S {presag_mm:6.2f} mm  worst σ/F_m {rows[-1]['worst_sigma_over_Fm']:.4f}  mean "
              f"{rows[-1]['mean_sigma_over_Fm']:.4f}  uplift {rows[-1]['uplift_max_mm']:5.1f} mm", flush=True)
    return {**data, "published_presags": rows}


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--parts", default="case,beta,high")
    parser.add_argument("--betas", default=",".join(f"{b:g}" for b in BETAS), help="centres of the beta bands")
    parser.add_argument("--uplift-limit", type=float, default=STEADY_ARM_UPLIFT_LIMIT * 1e3, help="in mm")
    parser.add_argument("--out", default=None, help="write every number to this JSON file")
    args = parser.parse_args()
    parts = args.parts.split(",")
    case = load_case("case_study_st98")
    wave = case.catenary.contact_wire.wave_speed / KMH
    out = {}
    if "case" in parts:
        out["case"] = case_part(case, args.workers, args.uplift_limit * 1e-3)
    if "beta" in parts:
        out["beta"] = {f"{beta:.2f}": study_band(case, ((beta - 0.05) * wave, (beta + 0.05) * wave), args.workers,
                                                 args.uplift_limit * 1e-3)
                       for beta in map(float, args.betas.split(","))}
    if "high" in parts:
        out["high"] = study_band(case, HIGH_SPEEDS, args.workers, args.uplift_limit * 1e-3)
    if args.out:
        with open(args.out, "w", encoding="utf-8") as fh:
            json.dump(out, fh, indent=2, ensure_ascii=False)
    return 0


if __name__ == "__main__":
    sys.exit(main())
