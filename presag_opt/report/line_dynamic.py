"""The dynamic check of a designed line: the band's worst points simulated on its worst section.

The worst section is the one with the largest static steady-arm uplift estimate among its sized
spans; the worst points of the band are its top speed at the lowest and the highest static force.
The built section (its own form-found geometry, its pre-sag as built) is simulated with
:func:`presag_opt.robust.dynamic_check.dynamic_check`, and the line's decision is made again with
the dynamic uplift of the built pre-sag in place of the static estimate.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable
from dataclasses import dataclass

from presag_opt.design.band import KMH
from presag_opt.design.decision import decide
from presag_opt.design.line import LineDesign
from presag_opt.dynamics.pantograph import load_pantograph
from presag_opt.robust.dynamic_check import DynamicCheck
from presag_opt.robust.dynamic_check import dynamic_check as simulate_designs

CHECK_PANTOGRAPH = "case_study_2mass_friction"
"""Pantograph of the line's dynamic check."""


@dataclass(frozen=True, kw_only=True)
class LineDynamicCheck:
    """A line design with its dynamic check.

    Attributes
    ----------
    design : LineDesign
        The design, its decision made again with the dynamic uplift.
    section : str
        The section simulated.
    check : DynamicCheck
        The runs.
    """

    design: LineDesign
    section: str
    check: DynamicCheck

    @property
    def uplift(self) -> float:
        """Largest steady-arm uplift of the runs. [m]"""
        return max(r.uplift_max for r in self.check.runs)

    def html(self) -> str:
        """The runs as an HTML table with a sentence."""
        from presag_opt.report.html import _table

        limit = self.design.decision.inputs.uplift_limit
        rows = [[f"{r.speed / KMH:.0f}", f"{r.static_force:g}", f"{r.mean_force:.1f}", f"{r.sigma_over_mean:.3f}",
                 f"{r.uplift_max * 1e3:.1f}", f"{r.loss_of_contact * 100:.2f}"] for r in self.check.runs]
        return (f"<p>Section {self.section} as built (largest static uplift estimate), at the band's top speed and "
                f"its lowest and highest static force; steady-arm uplift limit {limit * 1e3:g} mm.</p>"
                + _table(["speed [km/h]", "F_stat [N]", "F_m [N]", "σ/F_m [-]", "uplift [mm]", "loss of contact [%]"],
                         rows, {0, 1, 2, 3, 4, 5}))


def dynamic_check(design: LineDesign, pantograph: str = CHECK_PANTOGRAPH,
                  progress: Callable[[str], None] | None = None) -> LineDynamicCheck:
    """Simulate the band's worst points on the line's worst section and decide again.

    Parameters
    ----------
    design : LineDesign
        The designed line.
    pantograph : str
        Pantograph model name or file.
    progress : callable, optional
        Called with a short message before the runs.
    """
    worst = max(design.sections, key=lambda sec: max(s.static_uplift for s in sec.spans if s.sized))
    band = design.band
    check = simulate_designs(
        worst.catenary, {"built": worst.catenary}, pantograph=load_pantograph(pantograph),
        static_forces=sorted({band.static_force_low, band.static_force_high}), speeds=[band.speed_high],
        aero_coefficient=band.aero_coefficient, reference_span=design.nominal_span_length, progress=progress,
    )
    uplift = max(r.uplift_max for r in check.runs)
    inputs = design.decision.inputs
    candidates = tuple(dataclasses.replace(c, uplift=uplift, uplift_dynamic=True) for c in inputs.candidates)
    kept = tuple(n for n in inputs.not_checked if "dynamic steady-arm uplift" not in n)
    decision = decide(dataclasses.replace(inputs, candidates=candidates, not_checked=kept + (
        f"the dynamic uplift is that of section {worst.section} at the band's top speed only",)))
    return LineDynamicCheck(design=dataclasses.replace(design, decision=decision), section=worst.section, check=check)
