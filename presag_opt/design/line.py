"""Design a surveyed line: per-span pre-sag, a dropper schedule, the design-rule checks, per-span tolerances.

:func:`design_line` takes a :class:`~presag_opt.system.survey.Survey` and a base catenary (wires,
tensions, droppers, supports) and designs every tension section on its own (balance weights at both
ends, a mid-point anchor; overlap spans between sections are not modelled). Two passes, each with
the sections in parallel (:func:`presag_opt.processes.worker_pool`):

1. **Sizing.** Form-find each section at the base model's pre-sag, compute the elasticity of every
   span at force levels bracketing the band's F_m, and the quasi-static Δe rule over the band
   (:func:`~presag_opt.design.recommendation.layout_recommendation`; the end spans, whose outer
   support is a termination, are left out of the sizing). The line's S_rel is the mean of the
   sections' range ends (the rule of :func:`~presag_opt.design.recommendation.recommend`).
2. **Building.** Form-find each section at the pre-sag to build: S = S_rel·l in every span (Swedish
   practice, rule ``proportional``), each span's own quasi-static S_rel (rule ``per-span``, the
   mean of its values at the band ends), or each span's quasi-static robust parabola (rule
   ``robust``); read the dropper schedule, the steady-arm forces and the contact-wire heights off the
   equilibrium, compute the elasticity of every span as built, check the design rules
   (:mod:`presag_opt.design.line_rules`) and, given a span rule, every sized span's own quasi-static
   tolerance interval on the built geometry (the check of the built pre-sag, whatever the rule).

The decision for the whole line is made by :func:`presag_opt.pipeline.line.answer_line` from this
sizing's records (:meth:`~presag_opt.design.line_results.LineSizing.delta_e` and
:meth:`~presag_opt.design.line_results.LineSizing.quasi_static_robust`). Elasticity
values reported per span are those of the line as built, at the band-centre F_m.
"""

from __future__ import annotations

import os
from collections.abc import Callable
from concurrent.futures import as_completed
from dataclasses import dataclass

import numpy as np

from presag_opt.design.band import OperatingBand, force_levels_for_band
from presag_opt.design.line_droppers import section_droppers
from presag_opt.design.line_results import (
    LineDesign,
    LineSizing,
    SectionDesign,
    SectionSizing,
    SpanDesign,
)
from presag_opt.design.line_rules import check_rules, span_gradients
from presag_opt.design.recommendation import layout_recommendation
from presag_opt.design.section import SectionElasticity, default_spans, section_curves
from presag_opt.design.speed_range import StaticSteadyArmUplift
from presag_opt.design.survey_terms import in_survey_terms
from presag_opt.errors import ConvergenceError, ModelError, PresagError, failure_reason
from presag_opt.evaluation_store import Evaluation
from presag_opt.processes import WorkerPolicy, worker_pool
from presag_opt.static.discretisation import StaticSettings
from presag_opt.static.form_finding import form_find
from presag_opt.system.catenary import Catenary
from presag_opt.system.dropper_type import DropperType, check_step, load_dropper_type
from presag_opt.system.survey import Survey, SurveySection, section_catenary

PRESAG_RULES = ("proportional", "per-span", "robust")
"""Pre-sag rules of a line: S = S_rel·l with the line's S_rel; each span's own quasi-static S_rel; each
span's own quasi-static robust parabola (a ``span_rule`` from :mod:`presag_opt.robust.span_design`)."""

END_SPAN_NOTE = "end span, not sized: its outer support is the termination; it takes the section's S_rel"
"""Why an end span of a section is not sized (and has no tolerance interval of its own)."""

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
    round_step : float
        The crew's cutting step the cut lengths are rounded to (0: exact). [m]
    dropper_type : DropperType, optional
        The dropper type's allowances (default: the built-in one,
        :data:`~presag_opt.system.dropper_type.DEFAULT_DROPPER_TYPE`).
    """

    rule: str = "proportional"
    element_length: float = 0.5
    step: float = 1.0
    geometry_tolerance: float = 5e-5
    workers: int = 2
    round_step: float = 0.0
    dropper_type: DropperType | None = None

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
        check_step(self.round_step)
        if not 1 <= self.workers <= 64:
            raise ModelError(f"workers = {self.workers} is outside the valid range [1, 64]")


def size_line(
    survey: Survey,
    base: Catenary,
    band: OperatingBand,
    options: LineOptions | None = None,
    progress: Callable[[str], None] | None = None,
    span_rule=None,
) -> LineSizing:
    """Pass 1: size every tension section of a surveyed line on the base model's geometry.

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
    span_rule : RobustSpanRule, optional
        The per-span quasi-static robust rule (:class:`presag_opt.robust.span_design.RobustSpanRule`;
        the design layer does not import the robust one), called as ``span_rule(state, elasticity,
        sized_spans, band, settings)`` on each section: every sized span's own robust pre-sag and
        tolerance (the pre-sags of rule ``robust``, and the tolerance each span's built pre-sag is
        checked against under every rule). Picklable, as it runs in the worker processes.

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
    if options.rule == "robust" and span_rule is None:
        raise ModelError("rule 'robust' needs a span_rule (presag_opt.robust.span_design.RobustSpanRule)")
    sections = survey.sections()
    catenaries = [section_catenary(base, s, label=f"{survey.source}, section {s.section}") for s in sections]
    low, high = band.mean_force_band()
    levels = force_levels_for_band(low, high)
    settings = StaticSettings(element_length=options.element_length, geometry_tolerance=options.geometry_tolerance)
    failures: list[Evaluation] = []
    sized = _kept(_in_parallel(_size_section, [(c, levels, band, options.step, settings, span_rule)
                                               for c in catenaries], options.workers, "sizing", progress),
                  sections, "sizing", failures)
    kept = [(sec, size) for sec, size in zip(sections, sized, strict=True) if size is not None]
    return LineSizing(survey=survey, base_name=base.name, band=band, options=options,
                      sections=tuple(sec for sec, _ in kept), sizing=tuple(size for _, size in kept),
                      levels=tuple(levels), settings=settings, failures=tuple(failures))


def build_line(sizing: LineSizing, presag_rel: float, progress: Callable[[str], None] | None = None) -> LineDesign:
    """Pass 2: build every section at its pre-sags and read the line as built.

    Parameters
    ----------
    sizing : LineSizing
        Pass 1 (:func:`size_line`).
    presag_rel : float
        The S_rel to build: in every span under rule ``proportional`` (the decision's), in the end
        spans under rule ``per-span``. [-]
    progress : callable, optional
        Called with a short message as sections finish.
    """
    options = sizing.options
    dropper_type = options.dropper_type or load_dropper_type()
    jobs = [(size.catenary, sec, size, presag_rel, options.rule, sizing.band, sizing.settings,
             sizing.survey.working_width, sizing.levels, options.step, dropper_type, options.round_step)
            for sec, size in zip(sizing.sections, sizing.sizing)]
    failures = list(sizing.failures)
    built = _kept(_in_parallel(_build_section, jobs, options.workers, "building", progress),
                  list(sizing.sections), "building", failures)
    notes = (OVERLAP_NOTE, "elasticity per span is that of the line as built, at the band-centre F_m")
    return LineDesign(survey=sizing.survey, base_name=sizing.base_name, band=sizing.band, options=options,
                      presag_rel=presag_rel, sections=tuple(b for b in built if b is not None), notes=notes,
                      failures=tuple(failures))


def design_line(
    survey: Survey,
    base: Catenary,
    band: OperatingBand,
    options: LineOptions | None = None,
    progress: Callable[[str], None] | None = None,
    span_rule=None,
) -> LineDesign:
    """Size and build a surveyed line at the Δe rule's S_rel, without a decision (:func:`size_line`,
    :func:`build_line`; the decision for a line is :func:`presag_opt.pipeline.line.answer_line`).

    Parameters
    ----------
    survey : Survey
        Masts, sections and their geometry.
    base : Catenary
        The system model.
    band : OperatingBand
        Static forces, speeds and α_ae.
    options : LineOptions, optional
        Pre-sag rule and numerics.
    progress : callable, optional
        Called with a short message as sections finish.
    span_rule : RobustSpanRule, optional
        See :func:`size_line`.
    """
    sizing = size_line(survey, base, band, options, progress, span_rule)
    return build_line(sizing, sizing.presag_rel, progress)


def _kept(results: list, sections: list[SurveySection], stage: str, failures: list[Evaluation]) -> list:
    """The sections' results with each failed one (an error in its place, in the survey's terms:
    :func:`~presag_opt.design.survey_terms.in_survey_terms`) recorded in ``failures`` and set to None;
    every one failing raises the first error."""
    results = [in_survey_terms(r, sec) if isinstance(r, PresagError) else r
               for r, sec in zip(results, sections, strict=True)]
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
    return SectionSizing(catenary=catenary, recommendation=layout_recommendation(sized, band), elasticity=everything,
                         span_presags=rule)


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
                   rule: str, band: OperatingBand, settings: StaticSettings, working_width: float, levels,
                   step: float, dropper_type: DropperType, round_step: float) -> SectionDesign:
    """Pass 2 of one section: form-find at the pre-sag to build; elasticity as built; spans (each sized
    one with its own tolerance from the span rule, where there is one), droppers, rule checks."""
    presag = _span_presags(catenary, sizing, presag_rel, rule)
    lengths = np.asarray(catenary.layout.span_lengths)
    if rule == "proportional":
        built_model = catenary.with_presag(presag_rel)
    else:
        depths = [4.0 * s * (x / l) * (1.0 - x / l)
                  for s, l, x in ((s, l, catenary.droppers.positions_in_span(l)) for s, l in zip(presag, lengths))]
        built_model = catenary.with_presag_profile(depths)
    state = form_find(built_model, settings)
    as_built = section_curves(state, levels, step)
    ids = [m.mast for m in section.masts]
    centre = 0.5 * sum(band.mean_force_band())
    top = band.mean_force_band()[1]
    # the static uplift is that of the top of the band: F_m,top times the (secant) elasticity at F_m,top,
    # the decision's estimate, here at each steady arm of the line as built
    curves, at_top = (dict(zip(as_built.spans, c)) for c in as_built.curves_at_forces((centre, top)))
    arm = state.steady_arm_forces()
    inner = _sized_spans(catenary)
    own = sizing.span_presags
    gradients, changes = span_gradients(section)

    def span_design(s: int) -> SpanDesign:
        termination = s == 0  # from_mast of the first span is the section's termination
        checked = own is not None and s in inner and not np.isnan(own.tolerance[s]).any()
        return SpanDesign(
            section=section.section, span=s + 1, from_mast=ids[s], to_mast=ids[s + 1],
            chainage=section.masts[s].chainage, length=float(lengths[s]), presag=float(presag[s]),
            e_mid=curves[s].e_mid, e_mast=float(curves[s].elasticity[0]), delta_e=curves[s].delta_e,
            steady_arm_force=None if termination or not len(arm) else float(arm[s]),
            static_uplift=None if termination else StaticSteadyArmUplift(
                mean_force=top, support_elasticity=float(at_top[s].elasticity[0])).uplift, sized=s in inner,
            tolerance=(float(own.tolerance[s, 0]), float(own.tolerance[s, 1])) if checked else None,
            robust_presag=float(own.presag[s]) if checked else None,
            note="" if s in inner else END_SPAN_NOTE, uniformity=curves[s].uniformity, curve=curves[s],
            gradient=float(gradients[s]), gradient_change=None if s == 0 else float(changes[s - 1]))

    spans = tuple(span_design(s) for s in range(len(lengths)))
    droppers = section_droppers(state, built_model, section, dropper_type, round_step)
    rules = check_rules(section, built_model, droppers, band, working_width)
    return SectionDesign(section=section.section, catenary=built_model, sizing=sizing, spans=spans,
                         droppers=tuple(droppers), rules=rules)
