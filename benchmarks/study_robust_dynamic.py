"""Dynamic check of the robust pre-sag against the nominal Δe design (case study).

Run: python benchmarks/study_robust_dynamic.py
Designs from `presag robust` defaults (ST 9,8/9,8 ideal, F_m 70–148 N); each simulated with the
case-study pantograph for F_stat 70, 105, 140 N at 30, 60, 90 km/h (β < 0.4) and at 160 and
200 km/h (β ≈ 0.46 and 0.58, beyond the quasi-static regime).
"""

from __future__ import annotations

import time

from presag_opt.dynamics.pantograph import load_pantograph
from presag_opt.design import CASE_STUDY_BAND
from presag_opt.robust import dynamic_check, robust_study
from presag_opt.system.loader import load_catenary

KMH = 1 / 3.6


def main() -> None:
    start = time.perf_counter()
    catenary = load_catenary("st_9.8_ideal")
    study = robust_study(catenary, (70.0, 148.0))
    designs = {"robust": study.robust_parabola.presag_rel, "nominal": study.nominal.presag_rel}
    print({k: f"{v * 60e3:.1f} mm" for k, v in designs.items()})
    check = dynamic_check(
        catenary, designs, pantograph=load_pantograph("case_study_2mass_friction"),
        static_forces=(70.0, 105.0, 140.0), speeds=tuple(v * KMH for v in (30, 60, 90, 160, 200)),
        aero_coefficient=CASE_STUDY_BAND.aero_coefficient, reference_span=60.0,
        progress=lambda m: print("…", m, flush=True),
    )
    print("\nrun table: design, F_stat [N], v [km/h], beta, F_m [N], sigma/F_m, uplift [mm], loss of contact [%]")
    for r in check.runs:
        print(f"{r.design:8s} {r.static_force:5.0f} {r.speed * 3.6:5.0f} {r.beta:5.2f} {r.mean_force:7.1f} "
              f"{r.sigma_over_mean:7.3f} {r.uplift_max * 1e3:6.1f} {r.loss_of_contact * 100:5.1f}")
    print("\nsummary:")
    for row in check.summary():
        print(row)
    print(f"\ntotal {time.perf_counter() - start:.0f} s")


if __name__ == "__main__":
    main()
