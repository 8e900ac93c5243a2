"""Form-finding over the model's input space (issue: converge wherever the inputs are valid).

Run: python benchmarks/bench_form_finding_fuzz.py [--sets N] [--seed S] [--workers W] [--json FILE]

Draws N input sets (default 600, seed 0; :mod:`presag_opt.sensitivity.form_finding_fuzz`: every assumed
input of ST 9,8/9,8 and ST 7,1/7,1 over the range ``presag sensitivity`` varies it over, 3–8 spans
straight or on a curve of 300–3000 m either hand, alternating or outside stagger, pull-off and
push-off arms, contact-wire height changes up to 0.5 m a span, pre-sag 0–2 ‰), form-finds each at
the default settings (0.5 m elements, 0.05 mm geometry tolerance) in W processes, and prints the
table: the share converged, refused before any solve, refused after the solve and failed, and per
converged solve the quantiles of IPOPT and Newton iterations, passes, restarts and wall time, with
every set that did not converge and its reason. Targets: no set fails; at most 2 % are refused only
after the solve; the median solve takes at most 6 IPOPT iterations and one pass. A missed target
ends with a ``NOT MET`` line and exit status 1.
"""

from __future__ import annotations

import argparse
import json
import sys
from concurrent.futures import ProcessPoolExecutor

from _targets import Targets

from presag_opt.sensitivity.form_finding_fuzz import STATUSES, draw_cases, fuzz_table, solve_case


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sets", type=int, default=600, help="input sets (default 600)")
    parser.add_argument("--seed", type=int, default=0, help="seed of the draw (default 0)")
    parser.add_argument("--workers", type=int, default=1, help="processes (default 1)")
    parser.add_argument("--json", metavar="FILE", default=None, help="also write the table and every outcome as JSON")
    args = parser.parse_args()
    cases = draw_cases(args.sets, args.seed)
    with ProcessPoolExecutor(args.workers) as pool:
        outcomes = []
        for outcome in pool.map(solve_case, cases, chunksize=4):
            outcomes.append(outcome)
            if len(outcomes) % 50 == 0:
                print(f"  {len(outcomes)}/{len(cases)} sets", file=sys.stderr, flush=True)
    table = fuzz_table(outcomes)

    print(f"== form-finding over {table['sets']} input sets (seed {args.seed})")
    for status in STATUSES:
        print(f"  {status:22s} {table['count'][status]:5d}  {table['share'][status] * 100:6.2f} %")
    print("\n  per converged solve   " + "  ".join(f"{q:>7s}" for q in ("q50", "q90", "q99", "q100")))
    for name, values in table["quantiles"].items():
        print(f"  {name:20s}  " + "  ".join(f"{values[q]:7.3g}" for q in ("q50", "q90", "q99", "q100")))
    low, high = table["dropper_guess_error_m"]
    print(f"\n  first-guess dropper length minus form-found: {low * 1e3:+.1f} … {high * 1e3:+.1f} mm")
    for outcome in outcomes:
        if outcome.status != "converged":
            c = outcome.case
            print(f"  set {c.index} {outcome.status}: {c.system}, {len(c.span_lengths)} spans, R = {c.radius:g} m, "
                  f"S_rel {c.presag_rel * 1e3:.2f} ‰: {outcome.reason}")
    if args.json:
        with open(args.json, "w", encoding="utf-8") as handle:
            json.dump({"table": table, "outcomes": [
                {"case": o.case.to_dict(), "status": o.status, "reason": o.reason, "seconds": o.seconds,
                 "dropper_guess_error_m": o.dropper_guess_error,
                 "statistics": o.statistics.to_dict() if o.statistics else None} for o in outcomes]}, handle, indent=1)

    targets = Targets()
    print()
    targets.below("share failed", table["share"]["failed"] * 100, 1e-9, "%")
    targets.below("share refused only after the solve", table["share"]["refused after solving"] * 100, 2.0 + 1e-9, "%")
    targets.below("median IPOPT iterations", table["quantiles"]["ipopt_iterations"]["q50"], 6.0 + 1e-9, "")
    targets.below("median passes", table["quantiles"]["passes"]["q50"], 1.0 + 1e-9, "")
    return targets.exit_status()


if __name__ == "__main__":
    sys.exit(main())
