"""The decision for a surveyed line: its sizing, one decision, the line built at it, every span checked.

:func:`answer_line` is what ``presag design`` runs, in this order:

1. **Sizing** (:func:`~presag_opt.design.line.size_line`) with the per-span quasi-static robust rule
   always given: the Δe rule of every section, and every sized span's own robust pre-sag and
   tolerance (re-linearised at its own pre-sag, as the robust study does).
2. **Evidence**: the line's Δe rule, the mean of its spans' robust designs, on request a stored
   validity study, the dynamic check of the worst section (the one with the largest static uplift
   estimate) at the band's worst points at the pre-sags the decision may build
   (:func:`line_dynamic_check`), and the dynamic robust design of that section.
3. **The decision**, once (:func:`~presag_opt.design.decision.decide`).
4. **Building** at the decided S_rel (:func:`~presag_opt.design.line.build_line`): the dropper
   schedule, the line as built, and every sized span's built pre-sag against its own tolerance: a
   span is flagged (:func:`span_flag`) where it lies outside it, or closer to an end than the crew's
   build tolerance.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path

from presag_opt.design.band import OperatingBand
from presag_opt.design.decision import Decision, decide
from presag_opt.design.evidence import (
    DynamicUpliftCheck,
    Evidence,
    InstallationTolerance,
    check_uplift_limit,
    crew_tolerance,
)
from presag_opt.design.line import LineOptions, build_line, size_line
from presag_opt.design.line_results import LineDesign, LineSizing, RoundingEffect, SpanDesign
from presag_opt.design.speed_range import STEADY_ARM_UPLIFT_LIMIT, highest_static_force_static
from presag_opt.dynamics.pantograph import Pantograph, load_pantograph
from presag_opt.pipeline.band import CASE_STUDY_PANTOGRAPH, DynamicOptions
from presag_opt.pipeline.validity import ValidityRange, stored_sweep
from presag_opt.robust.dynamic_check import DynamicCheck, dynamic_check, window_settings
from presag_opt.robust.dynamic_design import DynamicObjective
from presag_opt.robust.dynamic_study import DynamicRobustStudy, dynamic_robust_study, simulated_band
from presag_opt.robust.scenarios import Risk
from presag_opt.robust.span_design import RobustSpanRule
from presag_opt.robust.study import robust_study
from presag_opt.robust.tolerance import check_within
from presag_opt.system.catenary import Catenary
from presag_opt.system.survey import Survey

SPAN_FLAGS = ("", "near an end of its own tolerance", "outside its own tolerance")
"""A sized span's built pre-sag: inside its own tolerance with at least the crew's margin; inside, but
closer to an end than the crew's tolerance; outside."""

COUNTED = {SPAN_FLAGS[1]: "near an end of their own tolerance", SPAN_FLAGS[2]: "outside their own tolerance"}
"""The flags as the headline counts them."""


@dataclass(frozen=True, kw_only=True)
class LineDynamicCheck:
    """The worst section simulated at the band's worst points, at the pre-sags the decision may build.

    Attributes
    ----------
    section : str
        The section simulated: the one with the largest static steady-arm uplift estimate.
    reference_span : float
        Span the runs' pre-sags are quoted on (the section's shortest). [m]
    runs : DynamicCheck
        The runs (top speed, lowest and highest static force) at every pre-sag.
    """

    section: str
    reference_span: float
    runs: DynamicCheck

    def evidence(self) -> DynamicUpliftCheck:
        """The check as evidence for a decision: the largest uplift at each simulated pre-sag."""
        by_presag: dict[float, float] = {}
        for run in self.runs.runs:
            key = run.presag / self.reference_span
            by_presag[key] = max(by_presag.get(key, 0.0), run.uplift_max)
        return DynamicUpliftCheck(simulated=tuple(by_presag.items()),
                                  where=f"section {self.section} at the band's top speed")


@dataclass(frozen=True, kw_only=True)
class LineAnswer:
    """A surveyed line designed, checked, and the one decision made from it.

    Attributes
    ----------
    design : LineDesign
        The line as built.
    check : LineDynamicCheck or None
        The dynamic check of the worst section, if run.
    dynamic : DynamicRobustStudy or None
        The dynamic robust design of the worst section, if run.
    validity : ValidityRange or None
        The stored validity study, if read.
    decision : Decision
        What to build and why.
    """

    design: LineDesign
    check: LineDynamicCheck | None
    dynamic: DynamicRobustStudy | None
    validity: ValidityRange | None
    decision: Decision

    def flag(self, span: SpanDesign) -> str:
        """The span's flag with the decision's crew tolerance (:func:`span_flag`)."""
        return span_flag(span, self.decision.evidence.installation.half_width)

    def flagged(self) -> dict[str, list[SpanDesign]]:
        """The flagged sized spans by flag."""
        out: dict[str, list[SpanDesign]] = {flag: [] for flag in SPAN_FLAGS[1:]}
        for span in self.design.spans:
            flag = self.flag(span)
            if flag:
                out[flag].append(span)
        return out

    def headline(self) -> str:
        """The decision's headline for the line with the flagged spans counted: S_rel × span length under
        rule ``proportional``; under a per-span rule, the range of the pre-sags built (each span its own)."""
        spans = self.design.spans
        lengths = [s.length for s in spans]
        checked = sum(1 for s in spans if s.tolerance is not None)
        counts = "; ".join(f"{len(flagged)} of {checked} sized spans {COUNTED[flag]}"
                           for flag, flagged in self.flagged().items() if flagged)
        built = None
        if self.design.options.rule != "proportional":
            rule, ends = {
                "robust": ("its own quasi-static robust pre-sag", "the end spans at their section's mean"),
                "per-span": ("its own Δe-rule pre-sag",
                             f"the end spans at the line's S_rel {self.decision.presag_rel * 1e3:.2f} ‰"),
            }[self.design.options.rule]
            low, high = min(s.presag for s in spans), max(s.presag for s in spans)
            built = f"each sized span {rule}, {low * 1e3:.1f}–{high * 1e3:.1f} mm as built ({ends})"
        headline = self.decision.headline(lengths, built)
        return headline + (f" — {counts} (spans.csv)" if counts else "")

    def advice(self) -> str:
        """What to do about flagged spans ("" when none is flagged or each span already has its own design)."""
        if not any(self.flagged().values()) or self.design.options.rule == "robust":
            return ""
        return ("one pre-sag for the whole line leaves these spans near or beyond an end of their own tolerance; "
                "rule robust (--rule robust) builds each sized span at its own quasi-static robust pre-sag, inside "
                "its own tolerance")

    def lines(self, options: dict[str, str]) -> list[str]:
        """The decision as printed for the line (see :meth:`presag_opt.design.decision.Decision.lines`).

        Parameters
        ----------
        options : dict of str to str
            Evidence name to the option of the running command that supplies it.
        """
        return [self.headline(), *self.decision.lines(options, [s.length for s in self.design.spans])[1:]]


def span_flag(span: SpanDesign, crew: float) -> str:
    """How a span's built pre-sag sits in its own tolerance (one of :data:`SPAN_FLAGS`).

    Parameters
    ----------
    span : SpanDesign
        A span as built (without a tolerance of its own, e.g. an end span, it is not flagged).
    crew : float
        The crew's build tolerance. [m]
    """
    margins = span.margins()
    if margins is None:
        return SPAN_FLAGS[0]
    smallest = min(margins)
    return SPAN_FLAGS[2] if smallest < 0 else SPAN_FLAGS[1] if smallest < crew else SPAN_FLAGS[0]


def with_rounding(crew: InstallationTolerance,
                  rounding: Sequence[tuple[str, RoundingEffect]]) -> InstallationTolerance:
    """The crew tolerance a decision uses when the cut lengths are rounded: never below what rounding alone
    causes (the largest P95 mid-span pre-sag error of the sections' rounding Monte Carlo).

    The crew's figure (or the assumed one) stands where it is at least that; otherwise rounding sets the
    tolerance, and its source says so.

    Parameters
    ----------
    crew : InstallationTolerance
        The crew's tolerance as set or assumed.
    rounding : sequence of (str, RoundingEffect)
        Each section's rounding effect (:meth:`~presag_opt.design.line_results.LineSizing.rounding`).
    """
    if not rounding:
        return crew
    section, worst = max(rounding, key=lambda item: item[1].presag_error_p95)
    if crew.half_width >= worst.presag_error_p95:
        return crew
    step = worst.step * 1e3
    return InstallationTolerance(
        half_width=worst.presag_error_p95, kind="monte-carlo",
        source=f"P95 of the mid-span pre-sag error from rounding the cut lengths to {step:g} mm (uniform ±{step / 2:g} "
               f"mm on every dropper, {worst.samples} Monte Carlo builds, section {section}), more than the crew's "
               f"±{crew.half_width * 1e3:.1f} mm ({crew.source})")


def line_dynamic_check(sizing: LineSizing, presags: Sequence[float], pantograph: Pantograph,
                       progress: Callable[[str], None] | None = None) -> LineDynamicCheck:
    """Simulate the band's worst points (top speed, lowest and highest static force) on the worst section
    at each of the given pre-sags.

    Parameters
    ----------
    sizing : LineSizing
        The sized line (:meth:`~presag_opt.design.line_results.LineSizing.worst_section`).
    presags : sequence of float
        The S_rel to simulate (e.g. the ends of the quasi-static tolerance and the Δe rule). [-]
    pantograph : Pantograph
        The pantograph.
    progress : callable, optional
        Called with a short message before each pre-sag's runs.
    """
    worst = sizing.worst_section()
    catenary = sizing.sizing[worst].catenary
    band = sizing.band
    span = min(catenary.layout.span_lengths)
    designs = {f"{s * span * 1e3:.1f} mm": s for s in sorted(set(presags))}
    runs = dynamic_check(catenary, designs, pantograph=pantograph,
                         static_forces=sorted({band.static_force_low, band.static_force_high}),
                         speeds=[band.speed_high], aero_coefficient=band.aero_coefficient, reference_span=span,
                         settings=window_settings(catenary), progress=progress)
    return LineDynamicCheck(section=sizing.sections[worst].section, reference_span=span, runs=runs)


def answer_line(
    survey: Survey,
    base: Catenary,
    band: OperatingBand,
    *,
    options: LineOptions | None = None,
    within: float = 0.10,
    uplift_limit: float = STEADY_ARM_UPLIFT_LIMIT,
    crew: float | None = None,
    study: str | Path | None = None,
    check: bool = False,
    dynamic: DynamicOptions | None = None,
    progress: Callable[[str], None] | None = None,
) -> LineAnswer:
    """Design a surveyed line, check it, and decide once (see the module docstring).

    Parameters
    ----------
    survey : Survey
        Masts, sections and their geometry.
    base : Catenary
        The system (wires, tensions, droppers, supports).
    band : OperatingBand
        Static forces, speeds and α_ae. [N], [m/s]
    options : LineOptions, optional
        Pre-sag rule and numerics.
    within : float
        Allowed loss of the tolerance intervals. [-]
    uplift_limit : float
        Largest allowed steady-arm uplift. [m]
    crew : float, optional
        The crew's build tolerance of the mid-span pre-sag (default: the assumed one). [m]
    study : str or Path, optional
        A stored validity study to read.
    check : bool
        Simulate the built worst section at the band's worst points.
    dynamic : DynamicOptions, optional
        Run the dynamic robust design of the worst section.
    progress : callable, optional
        Called with a short message as the work goes on.
    """
    options = options or LineOptions()
    installation = crew_tolerance(crew)
    check_within(within)
    check_uplift_limit(uplift_limit)
    pantograph = None
    if check or dynamic is not None:
        source = CASE_STUDY_PANTOGRAPH if dynamic is None else dynamic.pantograph
        pantograph = source if isinstance(source, Pantograph) else load_pantograph(source)
    # a stored study is read before any form-finding: a missing or foreign store fails at once
    validity = None if study is None else stored_sweep(study, band, base.contact_wire.wave_speed)
    sizing = size_line(survey, base, band, options, progress=progress,
                       span_rule=RobustSpanRule(within=within, round_step=options.round_step))
    installation = with_rounding(installation, sizing.rounding())
    delta_e = sizing.delta_e()
    quasi = sizing.quasi_static_robust(within)
    worst = sizing.sizing[sizing.worst_section()].catenary
    line_check = None
    if check:
        line_check = line_dynamic_check(sizing, [*quasi.tolerance, quasi.presag_rel, delta_e.presag_rel], pantograph,
                                        progress)
    study_dynamic = None
    if dynamic is not None:
        section = worst.with_presag(delta_e.presag_rel)
        if progress:
            progress(f"dynamic robust design of section {sizing.sections[sizing.worst_section()].section}")
        robust = robust_study(section, band.mean_force_band(), within=within, settings=sizing.settings,
                              nominal_presag_rel=delta_e.presag_rel, progress=progress)
        objective = DynamicObjective(loss=dynamic.objective, risk=dynamic.risk or Risk(), uplift_limit=uplift_limit)
        study_dynamic = dynamic_robust_study(section, pantograph, simulated_band(band), objective=objective,
                                             within=within, static_points=dynamic.static_points,
                                             speed_points=dynamic.speed_points, settings=dynamic.settings,
                                             workers=dynamic.workers, quasi=robust, progress=progress)
    evidence = Evidence(
        wave_speed=base.contact_wire.wave_speed, speed_high=band.speed_high, uplift_limit=uplift_limit,
        reference_span=min(sizing.sized_span_lengths), static_force_floor=band.static_force_low,
        static_force_estimate=highest_static_force_static(delta_e.support_elasticity, uplift_limit,
                                                          band.aero_coefficient, band.speed_high),
        delta_e=delta_e, quasi_static_robust=quasi,
        validity_sweep=None if validity is None else validity.record,
        dynamic_check=None if line_check is None else line_check.evidence(),
        dynamic_robust=None if study_dynamic is None else study_dynamic.evidence(),
        installation=installation, scope="line",
    )
    decision = decide(evidence)
    design = build_line(sizing, decision.presag_rel, progress)
    return LineAnswer(design=design, check=line_check, dynamic=study_dynamic, validity=validity, decision=decision)
