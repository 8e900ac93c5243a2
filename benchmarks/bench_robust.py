"""Benchmark of the robust design (issue: robust pre-sag). Run: python benchmarks/bench_robust.py

Targets, measured after the elasticity curves exist, as medians of 3 runs: robust parabolic S (a
re-solve) < 1 s; per-dropper profile of the 31-span mixed section < 10 s. A missed target ends with
a ``NOT MET`` line and exit status 1. Also prints the case-study comparison quoted in the note (one
run of the full study, timed once).
"""

from __future__ import annotations

import sys
import time

import numpy as np
from _targets import MIN_REPEAT, Targets, median_time

from presag_opt.design import CASE_STUDY_BAND, force_levels_for_band, section_elasticity
from presag_opt.robust import ForceScenarios, Risk, build_path_model, robust_presag, robust_study
from presag_opt.static.form_finding import form_find
from presag_opt.system.loader import load_catenary


def path_for(name, band):
    state = form_find(load_catenary(name))
    start = time.perf_counter()
    section = section_elasticity(state, force_levels=force_levels_for_band(*band), elasticity_method="active-set")
    path = build_path_model(state, section)
    return path, time.perf_counter() - start


def once(fn):
    """Wall time of one call (the first solve includes the cvxpy compilation, so it is not repeated). [s]"""
    start = time.perf_counter()
    result = fn()
    return time.perf_counter() - start, result


def main() -> int:
    targets = Targets()
    band = CASE_STUDY_BAND.mean_force_band()
    scenarios = ForceScenarios.band(*band)
    for name in ("st_9.8_ideal", "st_9.8_mixed"):
        path, prep = path_for(name, band)
        print(f"== {name}: {len(path.spans)} analysed spans, {len(path.dropper_span)} droppers; curves + "
              f"sensitivity {prep:.2f} s")
        first, _ = once(lambda: robust_presag(path, scenarios))
        t_par, par = median_time(lambda: robust_presag(path, scenarios), MIN_REPEAT)
        print(f"parabola minimax: first solve (with cvxpy compilation) {first:.3f} s, re-solve median {t_par:.3f} s; "
              f"S_rel {par.presag_rel * 1e3:.3f} ‰, worst R {par.worst_case_waviness * 1e3:.2f} mm")
        targets.below(f"{name}: robust parabola re-solve", t_par, 1.0)
        t_cvar, cvar = median_time(lambda: robust_presag(path, ForceScenarios.from_operating_band(CASE_STUDY_BAND),
                                                         risk=Risk.parse("cvar:0.9")), MIN_REPEAT)
        print(f"parabola CVaR 0.9: median {t_cvar:.3f} s; S_rel {cvar.presag_rel * 1e3:.3f} ‰")
        t_pd, prof = median_time(lambda: robust_presag(path, scenarios, shape="per-dropper"), MIN_REPEAT)
        print(f"per-dropper minimax: median {t_pd:.2f} s; worst R "
              f"{prof.worst_case_waviness * 1e3:.2f} mm (continuous {prof.continuous_objective * 1e3:.2f} mm, "
              f"rounding {prof.rounding})")
        if name == "st_9.8_mixed":
            targets.below("per-dropper profile, mixed section", t_pd, 10.0)

    print("\n== case study, full study (2 form-findings, curves, LPs)")
    t, study = once(lambda: robust_study(load_catenary("st_9.8_ideal"), band))
    d = study.to_dict()
    print(f"{t:.1f} s: robust S {d['presag_mm']:.1f} mm, worst R {d['worst_case_waviness_mm']:.2f} mm, mean "
          f"{d['mean_waviness_mm']:.2f} mm; nominal Δe S {d['nominal_presag_mm']:.1f} mm, worst R "
          f"{d['nominal_worst_case_waviness_mm']:.2f} mm, mean {d['nominal_mean_waviness_mm']:.2f} mm; "
          f"improvement {100 * (1 - d['worst_case_waviness_mm'] / d['nominal_worst_case_waviness_mm']):.0f} %")
    print(f"tolerance (10 %): {d['tolerance_mm'][0]:.1f}–{d['tolerance_mm'][1]:.1f} mm; optimum for the band centre "
          f"only: S {d['centre_optimum_presag_mm']:.1f} mm, {d['centre_optimum_tolerance_mm'][0]:.1f}–"
          f"{d['centre_optimum_tolerance_mm'][1]:.1f} mm")
    grid = np.linspace(0, 2.5e-3, 2501)
    worst = [study.path.waviness(study.path.parabola_depths(s), study.scenarios.forces).max() for s in grid]
    print(f"brute-force scan: best worst-case R {min(worst) * 1e3:.3f} mm at {grid[int(np.argmin(worst))] * 60e3:.2f} mm; "
          f"LP {study.robust_parabola.worst_case_waviness * 1e3:.3f} mm")
    return targets.exit_status()


if __name__ == "__main__":
    sys.exit(main())
