"""Benchmark of the dynamic simulator (issue 4). Run: python benchmarks/bench_dynamics.py [--repeat N] [--quick]

Measures, on this machine, median wall times of
- the case study (ST 9,8/9,8, 10 ideal spans, 2-mass pantograph with friction, 120 N) at 90 km/h,
  the paper's 0.5 m / 2 ms, HHT-α −0.005 and average-acceleration Newmark; target < 5 s;
- the EN 50318-style reference case at 250 km/h; target < 10 s;
  (both from a form-found state, as a parametric study reuses it; form-finding is timed apart);
- the integrator's fast path against its plain reference path on the same EN 50318 run: σ
  agreement (target within 1 %) and the speed ratio;
and prints the validation figures quoted in the closing note:
- the EN 50318-style statistics at 250 and 300 km/h beside the published reference ranges, as
  shipped (automatic numerics; exit status 1 unless all 16 are inside) and at the paper's 0.5 m, 2 ms;
- σ convergence from 2 to 1 ms and from 0.5 to 0.25 m elements on the case study at 90 and 180 km/h
  (target: changes below 3 %).
``--quick`` skips the reference path and the fine discretisations (about 30 s instead of 5 min).
"""

from __future__ import annotations

import argparse
import dataclasses
import os
import statistics
import sys
import time

from presag_opt.dynamics.case import load_case
from presag_opt.dynamics.integrator import IntegratorSettings
from presag_opt.static.discretisation import StaticSettings
from presag_opt.static.form_finding import form_find
from presag_opt.validation import en50318_verdicts


def timed(fn, repeat: int):
    """Median wall time [s], median CPU time of this process [s] and the last result."""
    wall, cpu, result = [], [], None
    for _ in range(repeat):
        start, start_cpu = time.perf_counter(), time.process_time()
        result = fn()
        wall.append(time.perf_counter() - start)
        cpu.append(time.process_time() - start_cpu)
    return statistics.median(wall), statistics.median(cpu), result


def with_numerics(settings, *, element_length=None, time_step=None, method=None, scheme=None):
    """Settings with another element length [m], time step [s], solution method or scheme."""
    integrator = settings.integrator
    if time_step is not None:
        integrator = dataclasses.replace(integrator, time_step=time_step)
    if method is not None:
        integrator = dataclasses.replace(integrator, method=method)
    if scheme is not None:
        integrator = IntegratorSettings(time_step=integrator.time_step, scheme=scheme, method=integrator.method)
    static = settings.static if element_length is None else StaticSettings(element_length=element_length)
    return dataclasses.replace(settings, integrator=integrator, static=static, numerics="fixed")


def en50318_table(case, settings, label: str) -> int:
    """Run the EN 50318-style case at both published speeds (one form-finding per element length the
    settings give each speed) and print every statistic against its range; returns the count inside."""
    print(f"-- {label}")
    inside = 0
    for speed in (250, 300):
        plan = case.plan(speed / 3.6, settings)
        started = time.perf_counter()
        state = form_find(case.catenary, plan.settings.static)
        result = case.run(speed / 3.6, state=state, settings=settings)
        wall = time.perf_counter() - started
        stats = result.to_dict()
        verdicts = en50318_verdicts(speed, stats)
        inside += sum(v.inside for v in verdicts)
        cells = [
            f"{v.statistic} {v.value:.1f} [{v.low:g}, {v.high:g}]" + ("" if v.inside else " (out)")
            for v in verdicts
        ]
        print(f"{speed} km/h (β = {stats['beta']:.3f}, {plan.settings.static.element_length:g} m, "
              f"{plan.settings.integrator.time_step * 1e3:g} ms, {wall:.1f} s wall incl. form-finding): "
              + "; ".join(cells))
    return inside


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--quick", action="store_true")
    args = parser.parse_args()
    r = args.repeat

    study = load_case("case_study_st98")
    en = load_case("en50318_2002")
    t_ff_st, _, st_state = timed(lambda: form_find(study.catenary, study.settings.static), 1)
    t_ff_en, _, en_state = timed(lambda: form_find(en.catenary, en.settings.static), 1)
    print(f"== form-finding (once per geometry): ST 9,8/9,8 {t_ff_st:.2f} s, EN 50318 {t_ff_en:.2f} s, "
          f"free DOFs {len(st_state.model.functions.free_dofs)} / {len(en_state.model.functions.free_dofs)}")

    print(f"\n== wall time (and CPU time of this process), median of {r} runs, from a form-found state; "
          f"load average {os.getloadavg()[0]:.1f} on {os.cpu_count()} cores")
    paper = with_numerics(study.settings, element_length=0.5, time_step=2e-3)  # the paper's fixed numerics
    for label, settings in (("HHT-α -0.005 (default)", paper), ("Newmark", with_numerics(paper, scheme="newmark"))):
        t, cpu, run = timed(lambda s=settings: study.run(25.0, state=st_state, settings=s), r)
        print(f"case study 90 km/h, {label}: {t:.2f} s, CPU {cpu:.2f} s (target < 5 s); "
              f"stepping {run.stepping_time:.2f} s, "
              f"{len(run.newton_iterations)} steps, {run.newton_iterations.mean():.2f} Newton corrections/step, "
              f"σ = {run.statistics.std_force:.3f} N")
    en_paper = with_numerics(en.settings, element_length=0.5, time_step=2e-3)
    t_en, cpu_en, fast = timed(lambda: en.run(250 / 3.6, state=en_state, settings=en_paper), r)
    print(f"EN 50318 250 km/h: {t_en:.2f} s, CPU {cpu_en:.2f} s (target < 10 s); stepping {fast.stepping_time:.2f} s, "
          f"{len(fast.newton_iterations)} steps, {fast.newton_iterations.mean():.2f} corrections/step")

    if not args.quick:
        reference_settings = with_numerics(en_paper, method="reference")
        t_ref, cpu_ref, reference = timed(lambda: en.run(250 / 3.6, state=en_state, settings=reference_settings), 1)
        s_fast, s_ref = fast.statistics.std_force, reference.statistics.std_force
        print(f"fast vs reference path, same EN 50318 run: σ {s_fast:.6f} / {s_ref:.6f} N "
              f"(difference {abs(s_fast / s_ref - 1) * 100:.2e} %, target < 1 %); "
              f"wall {t_en:.2f} / {t_ref:.1f} s, CPU {cpu_en:.2f} / {cpu_ref:.1f} s "
              f"-> fast path {cpu_ref / cpu_en:.0f}x faster")

    print("\n== EN 50318-style reference case against the published ranges")
    shipped = en50318_table(en, en.settings, "as shipped: automatic numerics")
    print(f"as shipped: {shipped} of 16 statistics inside the published ranges "
          f"({'met' if shipped == 16 else 'NOT MET'})")
    if not args.quick:
        en50318_table(en, en_paper, "the paper's 0.5 m, 2 ms")

    if not args.quick:
        print("\n== σ convergence, case study (target: < 3 % change)")
        fine_state = form_find(study.catenary, StaticSettings(element_length=0.25))
        for speed in (90, 180):
            v = speed / 3.6
            base = study.run(v, state=st_state, settings=paper).statistics.std_force
            step_settings = with_numerics(paper, time_step=1e-3)
            step = study.run(v, state=st_state, settings=step_settings).statistics.std_force
            mesh_settings = with_numerics(paper, element_length=0.25)
            mesh = study.run(v, state=fine_state, settings=mesh_settings).statistics.std_force
            print(f"{speed} km/h: σ {base:.3f} N; dt 1 ms {step:.3f} N ({(step / base - 1) * 100:+.2f} %); "
                  f"0.25 m {mesh:.3f} N ({(mesh / base - 1) * 100:+.2f} %)")
    return 0 if shipped == 16 else 1


if __name__ == "__main__":
    sys.exit(main())
