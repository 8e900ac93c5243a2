"""The per-span quasi-static robust rule of a surveyed line: each span its own minimax parabola.

The quasi-static robust design (:mod:`presag_opt.robust.lp`) finds the parabolic pre-sag that
minimises the worst-case path waviness R over a band of mean contact forces. On a surveyed section
the spans differ (lengths, heights, staggers, steady arms), and a path point feels only the droppers
of its own span (:meth:`~presag_opt.robust.path.PathModel.of_span`), so every span can have its own
minimax parabola and its own tolerance interval (:func:`~presag_opt.robust.tolerance.tolerance_band`).
The depths are measured below each span's support line, the straight line between the contact-wire
heights at its masts, so a height change between masts is not mistaken for waviness.

:class:`RobustSpanRule` is the rule ``robust`` of :func:`presag_opt.design.line.design_line`: it sizes
the spans on the sizing pass's geometry, form-finds again at those pre-sags, recomputes the
elasticity there and sizes again (the elasticity is best taken near the optimal pre-sag, as
:func:`~presag_opt.robust.study.robust_study` does), and gives the section's end spans, whose outer
support is the termination, the mean S_rel of its sized spans. Whatever the rule of the line, the
decision pipeline (:func:`presag_opt.pipeline.line.answer_line`) runs this rule on every section: each
sized span's built pre-sag is checked against its own tolerance interval.

References
----------
Schick, Liu, Stichel, Railway Sciences (2025), doi:10.1108/RS-05-2025-0016, sections 4.1 and 6.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from presag_opt.design.band import OperatingBand
from presag_opt.design.line_results import SpanPresags
from presag_opt.design.section import SectionElasticity, section_elasticity
from presag_opt.errors import ModelError
from presag_opt.robust.cut_rounding import rounding_effect
from presag_opt.robust.path import PathModel, build_path_model
from presag_opt.robust.scenarios import ForceScenarios
from presag_opt.robust.tolerance import check_within, tolerance_band
from presag_opt.static.discretisation import StaticSettings
from presag_opt.static.equilibrium import EquilibriumState
from presag_opt.static.form_finding import form_find
from presag_opt.system.catenary import Catenary
from presag_opt.system.dropper_type import check_step

MAX_PRESAG_REL = 0.005
"""Largest relative pre-sag a model takes (5 ‰); a span's robust pre-sag above it is refused. [-]"""


@dataclass(frozen=True, kw_only=True)
class SpanRobust:
    """The minimax parabola of one span over a force band.

    Attributes
    ----------
    span : int
        Span, from 0. [-]
    presag_rel : float
        Its relative pre-sag S/l. [-]
    tolerance : tuple of float
        S_rel interval whose worst-case waviness stays within ``within`` of the optimum. [-]
    worst_case_waviness : float
        The optimum: the largest peak-to-peak path height over the forces. [m]
    within : float
        Allowed loss of the tolerance interval. [-]
    """

    span: int
    presag_rel: float
    tolerance: tuple[float, float]
    worst_case_waviness: float
    within: float


def span_robust_designs(path: PathModel, scenarios: ForceScenarios, within: float = 0.10,
                        spans: Sequence[int] | None = None) -> tuple[SpanRobust, ...]:
    """The minimax parabola and its tolerance interval of every analysed span on its own.

    Parameters
    ----------
    path : PathModel
        Path model of the section (:func:`~presag_opt.robust.path.build_path_model`).
    scenarios : ForceScenarios
        Mean contact forces designed for. [N]
    within : float
        Allowed relative loss of the tolerance interval, e.g. 0.10. [-]
    spans : sequence of int, optional
        Spans to design, from 0 (default: every analysed span of ``path``). [-]
    """
    out = []
    for span in path.spans if spans is None else spans:
        band = tolerance_band(path.of_span(int(span)), scenarios, within)
        out.append(SpanRobust(span=int(span), presag_rel=band.best, tolerance=(band.low, band.high),
                              worst_case_waviness=band.best_objective, within=within))
    return tuple(out)


@dataclass(frozen=True, kw_only=True)
class RobustSpanRule:
    """The per-span quasi-static robust rule (``rule = "robust"`` of a line design).

    Attributes
    ----------
    within : float
        Allowed loss of each span's tolerance interval. [-]
    relinearise : bool
        Size again on the geometry and elasticity at the first pre-sags (as the robust study does).
    round_step : float
        The crew's cutting step: above 0, the effect of rounding every cut length to it on the spans'
        robust designs (:func:`~presag_opt.robust.cut_rounding.rounding_effect`, on the same path model). [m]
    """

    within: float = 0.10
    relinearise: bool = True
    round_step: float = 0.0

    def __post_init__(self) -> None:
        check_within(self.within)
        check_step(self.round_step)

    def __call__(self, state: EquilibriumState, elasticity: SectionElasticity, sized: Sequence[int],
                 band: OperatingBand, settings: StaticSettings | None = None) -> SpanPresags:
        """The pre-sag and tolerance interval of every span of a section.

        Parameters
        ----------
        state : EquilibriumState
            The section form-found at the sizing pre-sag.
        elasticity : SectionElasticity
            Elasticity curves of (at least) the sized spans on ``state``, at force levels covering
            the band's F_m.
        sized : sequence of int
            Spans that take their own pre-sag, from 0; the others get the mean S_rel of these. [-]
        band : OperatingBand
            Static forces, speeds and α_ae (the F_m band is designed for).
        settings : StaticSettings, optional
            Numerics of the form-finding at the first pre-sags.
        """
        scenarios = ForceScenarios.band(*band.mean_force_band())
        catenary = state.catenary
        path = build_path_model(state, _only(elasticity, sized))
        designs = span_robust_designs(path, scenarios, self.within)
        if self.relinearise:
            again = form_find(_profiled(catenary, designs), settings)
            curves = section_elasticity(again, force_levels=elasticity.force_levels, spans=tuple(sized),
                                        step=elasticity.step, elasticity_method=elasticity.elasticity_method)
            path = build_path_model(again, curves)
            designs = span_robust_designs(path, scenarios, self.within)
        rounding = None
        if self.round_step > 0.0:
            rel = _rel_of_every_span(catenary, designs)
            lengths = np.asarray(catenary.layout.span_lengths)[path.dropper_span]
            t = path.dropper_fraction
            depths = rel[path.dropper_span] * lengths * 4.0 * t * (1.0 - t)
            rounding = rounding_effect(path, depths, scenarios, self.round_step)
        return dataclasses.replace(_span_presags(catenary, designs), rounding=rounding)


def _only(elasticity: SectionElasticity, spans: Sequence[int]) -> SectionElasticity:
    """The elasticity of the given spans only."""
    missing = set(spans) - set(elasticity.spans)
    if missing:
        raise ModelError(f"robust rule: no elasticity of span(s) {', '.join(str(s + 1) for s in sorted(missing))}")
    return dataclasses.replace(elasticity, studies=tuple(s for s in elasticity.studies if s.span in set(spans)))


def _checked(catenary: Catenary, designs: Sequence[SpanRobust]) -> None:
    for d in designs:
        if not 0.0 <= d.presag_rel <= MAX_PRESAG_REL:
            length = catenary.layout.span_lengths[d.span]
            raise ModelError(
                f"{catenary.layout.label}: the robust pre-sag of span {d.span + 1} is S_rel = {d.presag_rel * 1e3:.2f} ‰ "
                f"({d.presag_rel * length * 1e3:.0f} mm on {length:g} m), outside the model's valid range 0–5 ‰; "
                "narrow the force band")


def _rel_of_every_span(catenary: Catenary, designs: Sequence[SpanRobust]) -> np.ndarray:
    """S_rel of every span: its own where designed, else the mean of the designed ones. [-]"""
    _checked(catenary, designs)
    own = {d.span: d.presag_rel for d in designs}
    mean = float(np.mean(list(own.values())))
    return np.array([own.get(s, mean) for s in range(catenary.layout.n_spans)])


def _profiled(catenary: Catenary, designs: Sequence[SpanRobust]) -> Catenary:
    """The section with every span's parabola as its dropper profile."""
    rel = _rel_of_every_span(catenary, designs)
    depths = []
    for s, length in enumerate(catenary.layout.span_lengths):
        t = np.asarray(catenary.droppers.positions_in_span(length)) / length
        depths.append(4.0 * rel[s] * length * t * (1.0 - t))
    return catenary.with_presag_profile(depths)


def _span_presags(catenary: Catenary, designs: Sequence[SpanRobust]) -> SpanPresags:
    lengths = np.asarray(catenary.layout.span_lengths, dtype=float)
    rel = _rel_of_every_span(catenary, designs)
    tolerance = np.full((len(lengths), 2), np.nan)
    for d in designs:
        tolerance[d.span] = np.array(d.tolerance) * lengths[d.span]
    lows, highs = zip(*(d.tolerance for d in designs))
    return SpanPresags(
        presag=rel * lengths, tolerance=tolerance,
        presag_rel=float(np.mean([d.presag_rel for d in designs])),
        presag_rel_tolerance=(float(np.mean(lows)), float(np.mean(highs))),
        method="quasi-static robust design, per span",
    )
