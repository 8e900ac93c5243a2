"""Benchmark of the static model (issue: foundation). Run: python benchmarks/bench_static.py [--repeat N]

Measures, on this machine, median wall times (of N >= 3 runs, default 3) of
- form-finding, 10-span ideal ST 9,8/9,8 and the 31-span mixed section, cold (model built and
  compiled in the call) and warm (CasADi functions cached);
- linear elasticity of one span every 0.1 m (one factorisation);
- the same curve by per-point nonlinear re-solves under 1 N (Newton), same run, and the ratio;
- nonlinear elasticity at 4 force levels × 121 points (Newton), and the active-set method;
and prints the validation figures quoted in the closing note. A missed target ends with a
``NOT MET`` line and exit status 1.
"""

from __future__ import annotations

import argparse
import sys

import numpy as np
from _targets import Targets, median_time

from presag_opt.elasticity import linear_elasticity, nonlinear_elasticity
from presag_opt.static import equilibrium, form_finding
from presag_opt.static.discretisation import CONTACT_WIRE, MESSENGER_WIRE, StaticSettings
from presag_opt.system.loader import load_catenary


def cold_form_find(name: str):
    equilibrium._static_model.cache_clear()
    return form_finding.form_find(load_catenary(name))


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=3, help="runs per median (at least 3)")
    args = parser.parse_args()
    r = args.repeat
    targets = Targets()

    print("== form-finding (median of", r, "runs)")
    for name, target in (("st_9.8_ideal", 2.0), ("st_9.8_mixed", 10.0)):
        cold, state = median_time(lambda: cold_form_find(name), r)
        warm, _ = median_time(lambda: form_finding.form_find(load_catenary(name)), r)
        print(f"{name:14s} cold {cold:6.2f} s  warm {warm:6.2f} s  "
              f"nodes {state.discretisation.n_nodes}, free DOFs {len(state.model.functions.free_dofs)}")
        targets.below(f"form-finding {name}, cold", cold, target)

    state = form_finding.form_find(load_catenary("st_9.8_ideal"))
    print("\n== elasticity, central span of st_9.8_ideal")

    def fresh_linear():
        state._cache.clear()
        return linear_elasticity(state, step=0.1)

    t_lin, lin = median_time(fresh_linear, r)
    t_res, res = median_time(lambda: nonlinear_elasticity(state, 1.0, step=0.1), r)
    print(f"linear, 601 points every 0.1 m: {t_lin:.3f} s; per-point re-solves under 1 N, same points: {t_res:.2f} s")
    targets.below("linear elasticity, 601 points", t_lin, 0.5)
    targets.at_least("re-solve / linear time ratio", t_res / t_lin, 100.0, "x")
    print(f"largest difference between the two: {np.max(np.abs(lin.elasticity[1:-1] / res.elasticity[1:-1] - 1)) * 100:.3f} %")

    def four_levels(method):
        return [nonlinear_elasticity(state, f, step=0.5, method=method) for f in (50.0, 100.0, 150.0, 200.0)]

    t_nl, curves = median_time(lambda: four_levels("newton"), r)
    t_as, fast = median_time(lambda: four_levels("active-set"), r)
    print(f"nonlinear 4 levels x 121 points, Newton: {t_nl:.1f} s; active-set: {t_as:.2f} s")
    targets.below("nonlinear elasticity, 4 levels x 121 points, Newton", t_nl, 20.0)
    for c, f in zip(curves, fast):
        print(f"  F = {c.force:5.0f} N  Newton: e_mid {c.e_mid * 1e3:.3f}, e_mast {c.e_mast * 1e3:.3f}, "
              f"Δe {c.delta_e * 1e3:.3f} mm/N, max slack droppers {c.slack_droppers.max()}; "
              f"active-set Δe {f.delta_e * 1e3:.3f} ({(f.delta_e / c.delta_e - 1) * 100:+.1f} %)")

    print("\n== validation figures")
    cat = state.catenary
    disc = state.discretisation
    lengths = np.asarray(cat.layout.span_lengths)[disc.dropper_span]
    t = disc.dropper_position / lengths
    target = cat.contact_wire_height - 4 * cat.presag_rel * lengths * t * (1 - t)
    miss = np.abs(state.positions[disc.axial.node_a[disc.dropper_elements], 2] - target).max()
    print(f"CW height at droppers: largest miss {miss * 1e3:.4f} mm")
    for group, wire in ((CONTACT_WIRE, cat.contact_wire), (MESSENGER_WIRE, cat.messenger_wire)):
        h = state.horizontal_tension(group)
        print(f"group {group}: horizontal tension {h.min():.2f}…{h.max():.2f} N ({np.abs(h / wire.tension - 1).max() * 100:.4f} % off)")
    central = disc.dropper_span == cat.layout.central_span
    d = state.dropper_lengths()[central]
    print(f"central-span dropper asymmetry {np.abs(d - d[::-1]).max() * 1e3:.4f} mm; min dropper force {state.dropper_forces().min():.1f} N")
    fine = form_finding.form_find(cat, StaticSettings(element_length=0.25))
    lf = linear_elasticity(fine)
    print(f"element 0.5 -> 0.25 m: e_mid {lin.e_mid * 1e3:.4f} -> {lf.e_mid * 1e3:.4f} mm/N "
          f"({(lf.e_mid / lin.e_mid - 1) * 100:+.2f} %), Δe {lin.delta_e * 1e3:.4f} -> {lf.delta_e * 1e3:.4f} "
          f"({(lf.delta_e / lin.delta_e - 1) * 100:+.2f} %)")
    for name in ("st_9.8_ideal", "st_7.1_ideal"):
        c = load_catenary(name)
        s = form_finding.form_find(c)
        e = linear_elasticity(s)
        emp = 60.0 / (4 * (c.contact_wire.tension + c.messenger_wire.tension))
        print(f"{name}: e_mid {e.e_mid * 1e3:.3f} mm/N = {e.e_mid / emp:.3f} x empirical {emp * 1e3:.3f}; "
              f"e_mast/e_mid {e.e_mast / e.e_mid:.2f}; e_max {e.e_max * 1e3:.3f}, e_min {e.e_min * 1e3:.3f}")
    return targets.exit_status()


if __name__ == "__main__":
    sys.exit(main())
