"""Design a surveyed line: per-span pre-sag, a dropper schedule, the design-rule checks, one decision.

:func:`design_line` takes a :class:`~presag_opt.system.survey.Survey` and a base catenary (wires,
tensions, droppers, supports) and designs every tension section on its own (balance weights at both
ends, a mid-point anchor; overlap spans between sections are not modelled). Two passes, each with
the sections in parallel (:func:`presag_opt.processes.worker_pool`):

1. **Sizing.** Form-find each section at the base model's pre-sag, compute the elasticity of every
   span at force levels bracketing the band's F_m, and the quasi-static Δe rule over the band
   (:func:`~presag_opt.design.recommendation.layout_recommendation`; the end spans, whose outer
   support is a termination, are left out of the sizing). The line's S_rel is the mean of the
   sections' range ends (the rule of :func:`~presag_opt.design.recommendation.recommend`), and the
   decision (:mod:`presag_opt.design.decision`) is made from it.
2. **Building.** Form-find each section at the pre-sag to build: S = S_rel·l in every span (Swedish
   practice, rule ``proportional``), or each span's own quasi-static S_rel (rule ``per-span``, the
   mean of its values at the band ends); read the dropper schedule, the steady-arm forces and the
   contact-wire heights off the equilibrium, and check the design rules
   (:mod:`presag_opt.design.line_rules`).

Elasticity values reported per span are those of pass 1 at the band-centre F_m.
"""

from __future__ import annotations

import dataclasses
import os
from collections.abc import Callable
from concurrent.futures import as_completed
from dataclasses import dataclass

import numpy as np

from presag_opt.design.band import OperatingBand, force_levels_for_band
from presag_opt.design.decision import QUASI_STATIC_ROBUST, Candidate, Decision, decide
from presag_opt.design.line_rules import RuleCheck, check_rules
from presag_opt.design.recommendation import (
    LayoutRecommendation,
    layout_recommendation,
    quick_decision,
)
from presag_opt.design.section import SectionElasticity, default_spans, section_curves
from presag_opt.errors import ConvergenceError, ModelError, PresagError, failure_reason
from presag_opt.evaluation_store import Evaluation
from presag_opt.processes import WorkerPolicy, worker_pool
from presag_opt.static.discretisation import StaticSettings
from presag_opt.static.form_finding import form_find
from presag_opt.system.catenary import Catenary
from presag_opt.system.survey import Survey, SurveySection, section_catenary

PRESAG_RULES = ("proportional", "per-span", "robust")
"""Pre-sag rules of a line: S = S_rel·l with the line's S_rel; each span's own quasi-static S_rel; each
span's own quasi-static robust parabola (a ``span_rule`` from :mod:`presag_opt.robust.span_design`)."""

OVERLAP_NOTE = ("overlap spans between tension sections are not modelled: each section is designed on its own, "
                "with balance weights at both ends and a mid-point anchor")


@dataclass(frozen=True, kw_only=True)
class LineOptions:
    """How a line is designed (numerics and the pre-sag rule; the band is separate).

    Attributes
    ----------
    rule : str
        ``proportional`` (S = S_rel·l, Swedish practice), ``per-span`` or ``robust`` (needs a
        ``span_rule`` in :func:`design_line`).
    element_length : float
        Longest element of the static model. [m]
    step : float
        Point spacing of the elasticity curves. [m]
    geometry_tolerance : float
        Largest miss of a form-finding target accepted (the static model's default). [m]
    workers : int
        Processes for the sections. [-]
    """

    rule: str = "proportional"
    element_length: float = 0.5
    step: float = 1.0
    geometry_tolerance: float = 5e-5
    workers: int = 2

    def __post_init__(self) -> None:
        if self.rule not in PRESAG_RULES:
            raise ModelError(f"rule = {self.rule!r} is not one of {', '.join(PRESAG_RULES)}")
        if not 0.05 <= self.element_length <= 2.0:
            raise ModelError(f"element_length = {self.element_length:g} m is outside the valid range [0.05, 2] m")
        if not 0.1 <= self.step <= 5.0:
            raise ModelError(f"step = {self.step:g} m is outside the valid range [0.1, 5] m")
        if not 1e-6 <= self.geometry_tolerance <= 1e-3:
            raise ModelError(f"geometry_tolerance = {self.geometry_tolerance * 1e3:g} mm is outside the valid range "
                             "[0.001, 1] mm")
        if not 1 <= self.workers <= 64:
            raise ModelError(f"workers = {self.workers} is outside the valid range [1, 64]")


@dataclass(frozen=True, kw_only=True)
class SpanPresags:
    """A section's pre-sag per span from a span rule (e.g. the per-span robust rule).

    Attributes
    ----------
    presag : ndarray
        Mid-span pre-sag of every span, below the line between its supports. [m]
    tolerance : ndarray, shape (n_spans, 2)
        Installation tolerance interval of each span's mid-span pre-sag (NaN where the span took
        the section's mean, e.g. an end span). [m]
    presag_rel : float
        The section's representative S_rel: the mean of its sized spans'. [-]
    presag_rel_tolerance : tuple of float
        The mean of the sized spans' tolerance ends in S_rel. [-]
    method : str
        What produced it (shown with the decision).
    """

    presag: np.ndarray
    tolerance: np.ndarray
    presag_rel: float
    presag_rel_tolerance: tuple[float, float]
    method: str


@dataclass(frozen=True, kw_only=True)
class SectionSizing:
    """Pass 1 of one section.

    Attributes
    ----------
    recommendation : LayoutRecommendation
        The quasi-static Δe rule over the band, from the sized (inner) spans.
    elasticity : SectionElasticity
        The elasticity curves of every span (the end spans too, for the span table).
    span_presags : SpanPresags or None
        The span rule's pre-sags (rule ``robust``), else None.
    """

    recommendation: LayoutRecommendation
    elasticity: SectionElasticity
    span_presags: SpanPresags | None = None


@dataclass(frozen=True, kw_only=True)
class SpanDesign:
    """One span as designed (a row of ``spans.csv``).

    Attributes
    ----------
    section : str
        Section id.
    span : int
        Span number within the section, from 1. [-]
    from_mast, to_mast : str
        Mast ids.
    chainage : float
        Chainage of ``from_mast``. [m]
    length : float
        Span length. [m]
    presag : float
        Pre-sag built at mid-span, below the line between the supports. [m]
    e_mid, e_mast, delta_e : float
        Elasticity at mid-span, at ``from_mast`` and Δe = e_max − e_min at the band-centre F_m. [m/N]
    steady_arm_force : float
        Axial force of the steady arm at ``from_mast`` in the built state: + tension (pull-off),
        − compression (push-off). [N]
    static_uplift : float
        Static uplift estimate at ``from_mast``: F_m at the top of the band times e_mast there. [m]
    sized : bool
        Whether the span took part in sizing the pre-sag (not the section's end spans).
    tolerance : tuple of float or None
        Installation tolerance interval of ``presag`` from the span rule (rule ``robust``), else
        None. [m]
    """

    section: str
    span: int
    from_mast: str
    to_mast: str
    chainage: float
    length: float
    presag: float
    e_mid: float
    e_mast: float
    delta_e: float
    steady_arm_force: float
    static_uplift: float
    sized: bool
    tolerance: tuple[float, float] | None = None


@dataclass(frozen=True, kw_only=True)
class DropperDesign:
    """One dropper as built (a row of ``droppers.csv``).

    Attributes
    ----------
    section, from_mast, to_mast : str
        Section and mast ids.
    span, dropper : int
        Span within the section and dropper within the span, both from 1. [-]
    position : float
        Distance from ``from_mast``. [m]
    length : float
        Unstretched length between the messenger and contact-wire clamp points (cut length). [m]
    contact_wire_height : float
        Contact-wire height above the rail at the dropper in the built equilibrium. [m]
    presag : float
        Depth of the contact wire below the straight line between its supports there. [m]
    stitch : bool
        A stitch dropper: it hangs from the stitch wire, not from the messenger wire (its cut length is
        between the stitch-wire and contact-wire clamp points).
    """

    section: str
    span: int
    from_mast: str
    to_mast: str
    dropper: int
    position: float
    length: float
    contact_wire_height: float
    presag: float
    stitch: bool = False


@dataclass(frozen=True, kw_only=True)
class SectionDesign:
    """One tension section designed.

    Attributes
    ----------
    section : str
        Section id.
    catenary : Catenary
        The section's model at the built pre-sag.
    sizing : SectionSizing
        Pass 1: the elasticity and the quasi-static Δe rule over the band.
    spans : tuple of SpanDesign
    droppers : tuple of DropperDesign
    rules : tuple of RuleCheck
        Design-rule checks of the section.
    """

    section: str
    catenary: Catenary
    sizing: SectionSizing
    spans: tuple[SpanDesign, ...]
    droppers: tuple[DropperDesign, ...]
    rules: tuple[RuleCheck, ...]


@dataclass(frozen=True, kw_only=True)
class LineDesign:
    """A surveyed line designed.

    Attributes
    ----------
    survey : Survey
        The input.
    base_name : str
        The system model used.
    band : OperatingBand
        Forces and speeds.
    options : LineOptions
    presag_rel : float
        The line's S_rel (mean of the sections' range ends). [-]
    decision : Decision
        What to build and why.
    sections : tuple of SectionDesign
    notes : tuple of str
        What is not modelled or checked.
    failures : tuple of Evaluation
        The sections that could not be designed, each with its masts and the one-line reason (the
        stage, sizing or building, in front of it); the line's pre-sag rests on the others.
    """

    survey: Survey
    base_name: str
    band: OperatingBand
    options: LineOptions
    presag_rel: float
    decision: Decision
    sections: tuple[SectionDesign, ...]
    notes: tuple[str, ...]
    failures: tuple[Evaluation, ...] = ()

    def failure_summary(self) -> str:
        """One line: how many sections failed, the first one's reason and what the rest rests on ("" if none)."""
        if not self.failures:
            return ""
        first = self.failures[0]
        total = len(self.failures) + len(self.sections)
        return (f"{len(self.failures)} of {total} sections could not be designed (first: section "
                f"{first.inputs['section']}, {first.failure}); the pre-sag and the outputs are those of the other "
                f"{len(self.sections)}")

    @property
    def spans(self) -> tuple[SpanDesign, ...]:
        """Every span of every section, in track order."""
        return tuple(s for sec in self.sections for s in sec.spans)

    @property
    def droppers(self) -> tuple[DropperDesign, ...]:
        """Every dropper, in track order."""
        return tuple(d for sec in self.sections for d in sec.droppers)

    @property
    def rules(self) -> tuple[RuleCheck, ...]:
        """Every design-rule check."""
        return tuple(r for sec in self.sections for r in sec.rules)

    @property
    def nominal_span_length(self) -> float:
        """Mean span length of the line (to 0.1 m), the span the decision is quoted on. [m]"""
        return round(float(np.mean([s.length for s in self.spans])), 1)


def design_line(
    survey: Survey,
    base: Catenary,
    band: OperatingBand,
    options: LineOptions | None = None,
    progress: Callable[[str], None] | None = None,
    span_rule: Callable[..., SpanPresags] | None = None,
) -> LineDesign:
    """Design every tension section of a surveyed line (see the module docstring).

    Parameters
    ----------
    survey : Survey
        Masts, sections and their geometry.
    base : Catenary
        System whose wires, tensions, droppers and supports are used; the survey replaces its
        layout and mast geometry.
    band : OperatingBand
        Static forces, speeds and α_ae.
    options : LineOptions, optional
        Pre-sag rule and numerics.
    progress : callable, optional
        Called with a short message as sections finish.
    span_rule : callable, optional
        The pre-sag of every span for rule ``robust``: called as ``span_rule(state, elasticity,
        sized_spans, band, settings)`` on each section's sizing pass and returning a
        :class:`SpanPresags` (:class:`presag_opt.robust.span_design.RobustSpanRule`; the design
        layer does not import the robust one). Picklable, as it runs in the worker processes.

    Raises
    ------
    ModelError
        Rule ``robust`` without a ``span_rule``, or a span rule given for another rule; every section
        failing (the first one's error: a section the base system cannot be built on, e.g. a span too
        short for its dropper rule, droppers shorter than the shortest buildable one). A line where only
        some sections fail is designed without them (:attr:`LineDesign.failures`).
    ConvergenceError
        Every section failing, the first for a solver that did not converge.
    """
    options = options or LineOptions()
    if not isinstance(survey, Survey):
        raise ModelError(f"survey must be a Survey, not {type(survey).__name__}")
    if (options.rule == "robust") != (span_rule is not None):
        raise ModelError("rule 'robust' needs a span_rule (presag_opt.robust.span_design.RobustSpanRule), and "
                         f"only it takes one (rule = {options.rule!r}, span_rule {'given' if span_rule else 'missing'})")
    sections = survey.sections()
    catenaries = [section_catenary(base, s, label=f"{survey.source}, section {s.section}") for s in sections]
    low, high = band.mean_force_band()
    levels = force_levels_for_band(low, high)
    settings = StaticSettings(element_length=options.element_length, geometry_tolerance=options.geometry_tolerance)
    failures: list[Evaluation] = []
    sized = _kept(_in_parallel(_size_section, [(c, levels, band, options.step, settings, span_rule)
                                               for c in catenaries], options.workers, "sizing", progress),
                  sections, "sizing", failures)
    sizing = [s for s in sized if s is not None]
    layouts = [s.recommendation for s in sizing]
    presag_rel = float(np.mean([end for lay in layouts for end in lay.presag_rel_range]))
    decision = _with_rule(quick_decision(layouts, presag_rel, band), sizing)
    jobs = [(c, sec, size, presag_rel, options.rule, band, settings, survey.working_width)
            for c, sec, size in zip(catenaries, sections, sized) if size is not None]
    built = _kept(_in_parallel(_build_section, jobs, options.workers, "building", progress),
                  [job[1] for job in jobs], "building", failures)
    notes = (OVERLAP_NOTE,
             "elasticity per span is that of the sizing pass (the base model's pre-sag) at the band-centre F_m",
             "the steady-arm uplift is a static estimate unless a dynamic check is run")
    return LineDesign(survey=survey, base_name=base.name, band=band, options=options, presag_rel=presag_rel,
                      decision=decision, sections=tuple(b for b in built if b is not None), notes=notes,
                      failures=tuple(failures))


def _kept(results: list, sections: list[SurveySection], stage: str, failures: list[Evaluation]) -> list:
    """The sections' results with each failed one (an error in its place) recorded in ``failures`` and
    set to None; every one failing raises the first error."""
    errors = [r for r in results if isinstance(r, PresagError)]
    if errors and len(errors) == len(results):
        raise errors[0]
    for section, result in zip(sections, results, strict=True):
        if isinstance(result, PresagError):
            first, last = section.masts[0], section.masts[-1]
            failures.append(Evaluation(index=len(failures), failure=f"{stage}: {failure_reason(result)}", inputs={
                "section": section.section, "from_mast": first.mast, "to_mast": last.mast,
                "chainage_m": [first.chainage, last.chainage]}))
    return [None if isinstance(r, PresagError) else r for r in results]


def _named(job: Callable, *args):
    """``job(*args)`` with the section's name in front of an error's message (the first argument is its catenary)."""
    try:
        return job(*args)
    except ConvergenceError as exc:
        raise ConvergenceError(f"{args[0].layout.label}: {exc}", exc.stats) from exc
    except ModelError as exc:
        raise ModelError(f"{args[0].layout.label}: {exc}") from exc


def _in_parallel(job: Callable, arguments: list[tuple], workers: int, stage: str,
                 progress: Callable[[str], None] | None) -> list:
    """Run ``job(*args)`` for every section, in worker processes where there are several; a section
    whose job raises one of the package's errors gives that error in its place (the others go on)."""
    workers = min(workers, len(arguments), os.cpu_count() or 1)
    if workers < 2:
        out = []
        for i, args in enumerate(arguments, start=1):
            try:
                out.append(_named(job, *args))
            except PresagError as exc:
                out.append(exc)
            if progress:
                progress(f"{stage}: section {i}/{len(arguments)} done")
        return out
    with worker_pool(workers, WorkerPolicy.FAST_START) as pool:
        futures = [pool.submit(_named, job, *args) for args in arguments]
        for done, _ in enumerate(as_completed(futures), start=1):
            if progress:
                progress(f"{stage}: sections done {done}/{len(arguments)}")
        return [f.exception() if isinstance(f.exception(), PresagError) else f.result() for f in futures]


def _with_rule(decision: Decision, sizing: list[SectionSizing]) -> Decision:
    """The decision made again with the span rule's answer beside the Δe rule: the mean of the sections'
    S_rel and tolerance ends, with the same static uplift estimate (F_m·e_mast does not depend on S)."""
    rules = [s.span_presags for s in sizing if s.span_presags is not None]
    if not rules:
        return decision
    inputs = decision.inputs
    robust = Candidate(method=QUASI_STATIC_ROBUST, presag_rel=float(np.mean([r.presag_rel for r in rules])),
                       tolerance=(float(np.mean([r.presag_rel_tolerance[0] for r in rules])),
                                  float(np.mean([r.presag_rel_tolerance[1] for r in rules]))),
                       uplift=inputs.candidates[0].uplift, uplift_dynamic=inputs.candidates[0].uplift_dynamic)
    kept = tuple(n for n in inputs.not_checked if not n.startswith("the quasi-static robust design"))
    return decide(dataclasses.replace(inputs, candidates=inputs.candidates + (robust,), not_checked=kept + (
        f"the robust design is per span ({rules[0].method}); its S_rel is the mean of the sized spans'",)))


def _size_section(catenary: Catenary, levels, band: OperatingBand, step: float,
                  settings: StaticSettings, span_rule=None) -> SectionSizing:
    """Pass 1 of one section: elasticity of every span, the Δe rule over the band from the inner spans, and
    the span rule's pre-sags where there is one."""
    state = form_find(catenary, settings)
    everything = section_curves(state, levels, step)
    inner = set(_sized_spans(catenary))
    sized = SectionElasticity(catenary=everything.catenary,
                              studies=tuple(s for s in everything.studies if s.span in inner),
                              force_levels=everything.force_levels, elasticity_method=everything.elasticity_method,
                              step=everything.step)
    rule = None if span_rule is None else span_rule(state, everything, sorted(inner), band, settings)
    return SectionSizing(recommendation=layout_recommendation(sized, band), elasticity=everything, span_presags=rule)


def _sized_spans(catenary: Catenary) -> tuple[int, ...]:
    """Spans that size the pre-sag: all but the two end spans (also on a section of equal spans)."""
    n = catenary.layout.n_spans
    return tuple(range(1, n - 1)) if n > 3 else default_spans(catenary)


def _span_presags(catenary: Catenary, sizing: SectionSizing, presag_rel: float, rule: str) -> np.ndarray:
    """Mid-span pre-sag to build in every span. [m]"""
    lengths = np.asarray(catenary.layout.span_lengths)
    if rule == "proportional":
        return presag_rel * lengths
    if rule == "robust":
        return np.asarray(sizing.span_presags.presag, dtype=float)
    rec = sizing.recommendation
    own = dict(zip(rec.at_band_low.spans, 0.5 * (rec.at_band_low.presag_rel + rec.at_band_high.presag_rel)))
    return np.array([own.get(s, presag_rel) for s in range(len(lengths))]) * lengths


def _build_section(catenary: Catenary, section: SurveySection, sizing: SectionSizing, presag_rel: float,
                   rule: str, band: OperatingBand, settings: StaticSettings, working_width: float) -> SectionDesign:
    """Pass 2 of one section: form-find at the pre-sag to build; spans, droppers, rule checks."""
    presag = _span_presags(catenary, sizing, presag_rel, rule)
    lengths = np.asarray(catenary.layout.span_lengths)
    if rule == "proportional":
        built_model = catenary.with_presag(presag_rel)
    else:
        depths = [4.0 * s * (x / l) * (1.0 - x / l)
                  for s, l, x in ((s, l, catenary.droppers.positions_in_span(l)) for s, l in zip(presag, lengths))]
        built_model = catenary.with_presag_profile(depths)
    state = form_find(built_model, settings)
    disc = state.discretisation
    ids = [m.mast for m in section.masts]
    centre = 0.5 * sum(band.mean_force_band())
    top = band.mean_force_band()[1]
    curves = dict(zip(sizing.elasticity.spans, sizing.elasticity.curves_at(centre)))
    arm = state.steady_arm_forces()
    inner = set(_sized_spans(catenary))
    tolerance = (None if sizing.span_presags is None else
                 [None if np.isnan(t).any() else (float(t[0]), float(t[1])) for t in sizing.span_presags.tolerance])
    spans = tuple(
        SpanDesign(section=section.section, span=s + 1, from_mast=ids[s], to_mast=ids[s + 1],
                   chainage=section.masts[s].chainage, length=float(lengths[s]), presag=float(presag[s]),
                   e_mid=curves[s].e_mid, e_mast=float(curves[s].elasticity[0]), delta_e=curves[s].delta_e,
                   steady_arm_force=float(arm[s]) if len(arm) else 0.0,
                   static_uplift=top * float(curves[s].elasticity[0]), sized=s in inner,
                   tolerance=None if tolerance is None else tolerance[s])
        for s in range(len(lengths))
    )
    cut = state.params.unstretched_length[disc.dropper_elements]
    cw_nodes = disc.axial.node_a[disc.dropper_elements]
    droppers, count = [], {}
    stitch = disc.stitch_dropper if disc.stitch_dropper is not None else np.zeros(len(cut), dtype=bool)
    for span, x, length, node, on_stitch in zip(disc.dropper_span, disc.dropper_position, cut, cw_nodes, stitch):
        count[span] = count.get(span, 0) + 1
        droppers.append(DropperDesign(
            section=section.section, span=int(span) + 1, from_mast=ids[span], to_mast=ids[span + 1],
            dropper=count[span], position=float(x), length=float(length),
            contact_wire_height=float(state.positions[node, 2]),
            presag=float(built_model.presag_depth(int(span), np.array([x]))[0]), stitch=bool(on_stitch)))
    rules = check_rules(section, built_model, droppers, band, working_width)
    return SectionDesign(section=section.section, catenary=built_model, sizing=sizing, spans=spans,
                         droppers=tuple(droppers), rules=rules)
