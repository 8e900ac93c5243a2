"""Convergence of σ in element length and time step against the speed ratio: the evidence behind
the automatic numerics (:func:`presag_opt.dynamics.numerics.numerics_for_speed`).

Run: python research/convergence.py [--quick]

For the EN 50318-style case (250, 300 km/h) and the case study (50, 90, 120, 180 km/h) it runs the
batch engine on a ladder of element lengths (time step fixed at the finest value) and of time steps
(element length fixed at the finest value), and prints σ, F_m and the maximum with their change
against the finest discretisation, beside the resolution each setting gives: elements per
wavelength of the shortest wave the analysis keeps, (c − v)/f_c, and steps per period of that wave
as the wire carries it, f_c/(1 − β). ``--quick`` uses two rungs per ladder.
"""

from __future__ import annotations

import argparse

from presag_opt.dynamics.case import load_case
from presag_opt.validation.dynamic_model import convergence_study

CASES = {"en50318_2002": (250.0, 300.0), "case_study_st98": (50.0, 90.0, 120.0, 180.0)}
ELEMENTS = (0.5, 0.4, 0.33, 0.25)
STEPS_MS = (2.0, 1.5, 1.0, 0.5)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="two rungs per ladder")
    args = parser.parse_args()
    elements = (ELEMENTS[0], ELEMENTS[-1]) if args.quick else ELEMENTS
    steps = (STEPS_MS[0], STEPS_MS[-1]) if args.quick else STEPS_MS
    for name, speeds in CASES.items():
        case = load_case(name)
        c = case.catenary.contact_wire.wave_speed
        f_c = case.settings.cutoff_frequency
        ladders = {
            "element length": [(h, steps[-1] * 1e-3) for h in elements],
            "time step": [(elements[-1], dt * 1e-3) for dt in steps],
        }
        for label, ladder in ladders.items():
            print(f"\n{name}: {label} ladder")
            study = convergence_study(case, [v / 3.6 for v in speeds], ladder)
            finest = study.rungs[-1]
            print(f"{'v':>5} {'β':>6} {'h [m]':>6} {'dt [ms]':>7} {'el/λ':>6} {'steps/T':>7} {'σ [N]':>8} "
                  f"{'Δσ':>7} {'ΔF_m':>7} {'Δmax':>7} {'wall [s]':>8}")
            for rung in study.rungs:
                h, dt = rung.element_length, rung.time_step
                for i, v in enumerate(rung.speeds):
                    shortest = (c - v) / f_c
                    print(f"{v * 3.6:5.0f} {v / c:6.3f} {h:6.2f} {dt * 1e3:7.2f} {shortest / h:6.1f} "
                          f"{(1 - v / c) / (f_c * dt):7.1f} {rung.std_force[i]:8.3f} "
                          f"{rung.std_force[i] / finest.std_force[i] - 1:+7.2%} "
                          f"{rung.mean_force[i] / finest.mean_force[i] - 1:+7.2%} "
                          f"{rung.max_force[i] / finest.max_force[i] - 1:+7.2%} {rung.seconds:8.1f}")


if __name__ == "__main__":
    main()
