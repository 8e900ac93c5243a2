"""Dynamic check of the quasi-static robust designs against the nominal Δe design (case study), the
per-dropper profile beside the parabola of the same linear program.

Run: python research/robust_dynamic.py
Designs from ``presag robust --shape per-dropper`` (ST 9,8/9,8 ideal, F_m 70–148 N, minimax, 5 mm
construction step): its per-dropper profile (built into every span, :func:`design_catenary`), the
minimax parabola of the same path model, and the nominal Δe rule at the band centre. Each is
form-found to its own geometry and simulated with the case-study pantograph and analysis window for
F_stat 70, 105, 140 N at 50, 70, 90 km/h (β < 0.4) and at 160 and 200 km/h (β ≈ 0.46 and 0.58, beyond
the quasi-static regime), one batch per design.
"""

from __future__ import annotations

import time

from presag_opt.design import CASE_STUDY_BAND
from presag_opt.dynamics.case import load_case
from presag_opt.robust import design_catenary, dynamic_check, robust_study

KMH = 1 / 3.6


def main() -> None:
    start = time.perf_counter()
    case = load_case("case_study_st98")
    catenary = case.catenary
    study = robust_study(catenary, (70.0, 148.0), shape="per-dropper")
    profile = design_catenary(catenary, study.path, study.robust.depths)
    designs = {"per-dropper": profile, "parabola": study.robust_parabola.presag_rel, "nominal": study.nominal.presag_rel}
    print("per-dropper depths of the central span [mm]: " + ", ".join(f"{d * 1e3:.0f}" for d in study.robust.depths))
    print(f"quasi-static worst R: per-dropper {study.robust.worst_case_waviness * 1e3:.2f} mm, parabola "
          f"{study.robust_parabola.worst_case_waviness * 1e3:.2f} mm, nominal {study.nominal.worst_case_waviness * 1e3:.2f} mm")
    print({k: f"{(v.presag_rel if hasattr(v, 'presag_rel') else v) * 60e3:.1f} mm" for k, v in designs.items()})
    check = dynamic_check(
        catenary, designs, pantograph=case.pantograph,
        static_forces=(70.0, 105.0, 140.0), speeds=tuple(v * KMH for v in (50, 70, 90, 160, 200)),
        aero_coefficient=CASE_STUDY_BAND.aero_coefficient, reference_span=60.0, settings=case.settings,
        progress=lambda m: print("…", m, flush=True),
    )
    print("\nrun table: design, F_stat [N], v [km/h], beta, F_m [N], sigma/F_m, uplift [mm], loss of contact [%]")
    for r in check.runs:
        print(f"{r.design:12s} {r.static_force:5.0f} {r.speed * 3.6:5.0f} {r.beta:5.2f} {r.mean_force:7.1f} "
              f"{r.sigma_over_mean:7.4f} {r.uplift_max * 1e3:6.1f} {r.loss_of_contact * 100:5.1f}")
    print("\nsummary:")
    for row in check.summary():
        print(row)
    print(f"\ntotal {time.perf_counter() - start:.0f} s")


if __name__ == "__main__":
    main()
