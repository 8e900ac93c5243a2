"""Time `design_line` on a made-up 5 km line: 100 spans in 4 tension sections (no dynamic check).

Run: ``python benchmarks/bench_line_design.py [--workers N]``. Prints the wall time of the design
(both passes, sections in parallel) and of writing the outputs. The line: ST 9,8/9,8 wires on
spans of 45–55 m, two curves (R 800 m and −1200 m) with the wire registered to the outside, and a
bridge lowering the contact wire by 0.2 m at two masts.
"""

from __future__ import annotations

import argparse
import sys
import tempfile
import time

from presag_opt.design.band import CASE_STUDY_BAND
from presag_opt.design.line import LineOptions, design_line
from presag_opt.report.line_report import write_line_outputs
from presag_opt.system.loader import load_catenary
from presag_opt.system.survey import Survey, SurveyMast


def five_km_survey(spans_per_section: int = 25, sections: int = 4) -> Survey:
    """A 5 km line: 4 × 25 spans of 45–55 m, two curves and a bridge. [m]"""
    masts, chainage, k = [], 0.0, 0
    for sec in range(sections):
        for i in range(spans_per_section + 1):
            if sec and i == 0:
                chainage += 50.0  # the overlap span to the previous section (not modelled)
            radius = 800.0 if 30 <= k < 45 else -1200.0 if 70 <= k < 85 else 0.0
            stagger = -0.25 if radius > 0 else 0.25 if radius < 0 else (0.3 if k % 2 == 0 else -0.3)
            height = 5.3 if k in (55, 56) else 5.5  # a bridge
            masts.append(SurveyMast(mast=f"M{k + 1}", chainage=chainage, stagger=stagger, contact_wire_height=height,
                                    system_height=1.2 if k not in (55, 56) else 1.0, curve_radius=radius,
                                    steady_arm="pull-off", section=f"S{sec + 1}", row=f"mast {k + 1}"))
            chainage += 45.0 + 10.0 * ((k * 7) % 11) / 10.0 if i < spans_per_section else 0.0
            k += 1
    return Survey(masts=tuple(masts), source="five_km_line")


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--workers", type=int, default=2)
    args = parser.parse_args()
    survey = five_km_survey()
    base = load_catenary("st_9.8_mixed")
    start = time.perf_counter()
    design = design_line(survey, base, CASE_STUDY_BAND, LineOptions(workers=args.workers),
                         progress=lambda m: print(f"  {time.perf_counter() - start:6.1f} s  {m}", file=sys.stderr))
    designed = time.perf_counter() - start
    with tempfile.TemporaryDirectory() as folder:
        write_line_outputs(design, folder, xlsx=True)
    total = time.perf_counter() - start
    print(f"{survey.length / 1e3:.2f} km, {len(design.sections)} sections, {len(design.spans)} spans, "
          f"{len(design.droppers)} droppers: designed in {designed:.1f} s, outputs written at {total:.1f} s "
          f"(workers {args.workers})")
    print("\n".join(design.decision.lines(design.nominal_span_length)))
    return 0


if __name__ == "__main__":
    sys.exit(main())
