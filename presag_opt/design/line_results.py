"""The results of a line design: each span and dropper as built, each section, the line.

Filled by :func:`presag_opt.design.line.design_line`; written out by
:mod:`presag_opt.report.line_report`. Edge units appear only there; here everything is SI.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from presag_opt.design.band import OperatingBand
from presag_opt.design.evidence import DeltaERule, QuasiStaticRobust
from presag_opt.design.line_rules import RuleCheck
from presag_opt.design.recommendation import LayoutRecommendation
from presag_opt.design.section import SectionElasticity
from presag_opt.elasticity import ElasticityCurve
from presag_opt.evaluation_store import Evaluation
from presag_opt.system.catenary import Catenary
from presag_opt.system.survey import Survey

if TYPE_CHECKING:
    from presag_opt.design.line import LineOptions
    from presag_opt.static.discretisation import StaticSettings
    from presag_opt.system.survey import SurveySection


@dataclass(frozen=True, kw_only=True)
class RoundingEffect:
    """What rounding the cut lengths to the crew's step does to one section, by quasi-static Monte Carlo.

    Every dropper's cut length gets an independent error uniform in ±step/2 (the rounding error of a
    length that does not fall on the step); the section's design is its sized spans' quasi-static robust
    parabolas, on the path model the span rule sized them with.

    Attributes
    ----------
    step : float
        The cutting step. [m]
    waviness_exact : float
        Worst-case path waviness over the F_m band of the exact schedule. [m]
    waviness_p95 : float
        Its P95 over the rounded builds. [m]
    waviness_p95_ci : tuple of float
        The 95 % order-statistic interval of that P95. [m]
    presag_error_p95 : float
        P95 of the largest mid-span pre-sag error over the sized spans from rounding alone. [m]
    samples : int
        Realisations. [-]
    seed : int
        Seed of the draws. [-]
    """

    step: float
    waviness_exact: float
    waviness_p95: float
    waviness_p95_ci: tuple[float, float]
    presag_error_p95: float
    samples: int
    seed: int


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
    rounding : RoundingEffect or None
        The effect of rounding the cut lengths to the crew's step (None: not rounded).
    """

    presag: np.ndarray
    tolerance: np.ndarray
    presag_rel: float
    presag_rel_tolerance: tuple[float, float]
    method: str
    rounding: RoundingEffect | None = None


@dataclass(frozen=True, kw_only=True)
class SectionSizing:
    """Pass 1 of one section.

    Attributes
    ----------
    catenary : Catenary
        The section's model at the base model's pre-sag.
    recommendation : LayoutRecommendation
        The quasi-static Δe rule over the band, from the sized (inner) spans.
    elasticity : SectionElasticity
        The elasticity curves of every span (the end spans too).
    span_presags : SpanPresags or None
        The span rule's pre-sags and tolerances (given a span rule), else None.
    """

    catenary: Catenary
    recommendation: LayoutRecommendation
    elasticity: SectionElasticity
    span_presags: SpanPresags | None = None


@dataclass(frozen=True, kw_only=True)
class LineSizing:
    """Pass 1 of a line: every section sized on the base model's geometry, before the pre-sag is chosen.

    Attributes
    ----------
    survey : Survey
        The input.
    base_name : str
        The system model used.
    band : OperatingBand
        Forces and speeds.
    options : LineOptions
        Pre-sag rule and numerics.
    sections : tuple of SurveySection
        The survey's tension sections that were sized.
    sizing : tuple of SectionSizing
        Each of them sized.
    levels : tuple of float
        The elasticity force levels. [N]
    settings : StaticSettings
        The static model's settings.
    failures : tuple of Evaluation
        The sections that could not be sized, each with its masts and the one-line reason.
    """

    survey: Survey
    base_name: str
    band: OperatingBand
    options: LineOptions
    sections: tuple[SurveySection, ...]
    sizing: tuple[SectionSizing, ...]
    levels: tuple[float, ...]
    settings: StaticSettings
    failures: tuple[Evaluation, ...] = ()

    @property
    def presag_rel(self) -> float:
        """The line's S_rel by the Δe rule: the mean of the sections' range ends. [-]"""
        return float(np.mean([end for s in self.sizing for end in s.recommendation.presag_rel_range]))

    @property
    def sized_span_lengths(self) -> tuple[float, ...]:
        """Lengths of the spans that size the pre-sag, every section. [m]"""
        return tuple(float(s.recommendation.at_band_low.span_lengths[i])
                     for s in self.sizing for i in range(len(s.recommendation.at_band_low.spans)))

    def rounding(self) -> tuple[tuple[str, RoundingEffect], ...]:
        """(section, its :class:`RoundingEffect`) of every section (empty where the cut lengths are exact)."""
        return rounding_by_section(self.sections, self.sizing)

    def worst_section(self) -> int:
        """Index of the section with the largest static steady-arm uplift estimate of its sized spans."""
        return int(np.argmax([s.recommendation.steady_arm_uplift.uplift for s in self.sizing]))

    def delta_e(self) -> DeltaERule:
        """The line's Δe rule as evidence (:mod:`presag_opt.design.evidence`): its S_rel, the envelope of
        the sections' ranges and their largest static uplift estimate."""
        layouts = [s.recommendation for s in self.sizing]
        worst = layouts[self.worst_section()].steady_arm_uplift
        return DeltaERule(presag_rel=self.presag_rel,
                          presag_rel_range=(min(lay.presag_rel_range[0] for lay in layouts),
                                            max(lay.presag_rel_range[1] for lay in layouts)),
                          static_uplift=worst.uplift, support_elasticity=worst.support_elasticity)

    def quasi_static_robust(self, within: float) -> QuasiStaticRobust | None:
        """The sized spans' own quasi-static robust designs as one record: the mean of their S_rel and of
        their tolerance ends (None without a span rule).

        Parameters
        ----------
        within : float
            The allowed loss their intervals were computed with. [-]
        """
        rel, low, high = [], [], []
        for s in self.sizing:
            if s.span_presags is None:
                continue
            lengths = np.asarray(s.catenary.layout.span_lengths)
            sized = ~np.isnan(s.span_presags.tolerance[:, 0])
            rel += list(s.span_presags.presag[sized] / lengths[sized])
            low += list(s.span_presags.tolerance[sized, 0] / lengths[sized])
            high += list(s.span_presags.tolerance[sized, 1] / lengths[sized])
        if not rel:
            return None
        return QuasiStaticRobust(presag_rel=float(np.mean(rel)), tolerance=(float(np.mean(low)), float(np.mean(high))),
                                 within=within)


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
        Elasticity at mid-span, at ``from_mast`` and Δe = e_max − e_min at the band-centre F_m, on
        the line as built. [m/N]
    steady_arm_force : float or None
        Axial force of the steady arm at ``from_mast`` in the built state: + tension (pull-off),
        − compression (push-off); None where ``from_mast`` is the section's termination. [N]
    static_uplift : float or None
        Static uplift estimate at ``from_mast``: F_m at the top of the band times the elasticity there at
        that force, on the line as built (the decision's estimate, mast by mast); None where ``from_mast``
        is the termination (it has no steady arm to lift). [m]
    sized : bool
        Whether the span took part in sizing the pre-sag (not the section's end spans).
    tolerance : tuple of float or None
        The span's own quasi-static tolerance interval of its mid-span pre-sag (the per-span robust
        rule's, given one; None for an end span). [m]
    robust_presag : float or None
        The span's own quasi-static robust pre-sag (with ``tolerance``). [m]
    note : str
        Why the span is not sized or checked (empty for a sized span).
    uniformity : float
        (e_max − e_min)/(e_max + e_min) along the span as built, at the band-centre F_m. [-]
    curve : ElasticityCurve or None
        The elasticity e(x) along the span as built, at the band-centre F_m.
    gradient : float
        Contact-wire gradient between the span's masts, (h_to − h_from)/l, + rising. [-]
    gradient_change : float or None
        Change of gradient from the section's previous span (None for its first span). [-]
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
    steady_arm_force: float | None
    static_uplift: float | None
    sized: bool
    tolerance: tuple[float, float] | None = None
    robust_presag: float | None = None
    note: str = ""
    uniformity: float = 0.0
    curve: ElasticityCurve | None = None
    gradient: float = 0.0
    gradient_change: float | None = None

    def margins(self) -> tuple[float, float] | None:
        """Distance of the built pre-sag above the low and below the high end of its own tolerance
        (negative: outside); None without one. [m]"""
        if self.tolerance is None:
            return None
        return (self.presag - self.tolerance[0], self.tolerance[1] - self.presag)


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
        Unstretched length between the messenger and contact-wire clamp points (clamp to clamp). [m]
    contact_wire_height : float
        Contact-wire height above the rail at the dropper in the built equilibrium. [m]
    presag : float
        Depth of the contact wire below the straight line between its supports there. [m]
    stitch : bool
        A stitch dropper: it hangs from the stitch wire, not from the messenger wire (its clamp-to-clamp
        length is between the stitch-wire and contact-wire clamp points).
    chainage : float
        Absolute chainage of the dropper. [m]
    messenger_height : float
        Height of the wire it hangs from (messenger or stitch wire) above the rail there, built. [m]
    lateral : float
        Lateral position of the contact wire at the dropper from the track centre line, + to the left. [m]
    cut_length : float
        The length to cut: ``length`` plus the dropper type's terminal and loop allowances, rounded to
        the crew's step (:meth:`presag_opt.system.dropper_type.DropperType.cut_length`). [m]
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
    chainage: float = 0.0
    messenger_height: float = 0.0
    lateral: float = 0.0
    cut_length: float = 0.0

    @property
    def id(self) -> str:
        """The dropper's id on a crew's sheet: section/from–to/number, e.g. ``S1/M3-M4/5``."""
        return f"{self.section}/{self.from_mast}-{self.to_mast}/{self.dropper}"


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
        The S_rel the line is built with: in every span under rule ``proportional``, in the end spans
        under rule ``per-span`` (:func:`presag_opt.design.line.build_line`). [-]
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

    def rounding(self) -> tuple[tuple[str, RoundingEffect], ...]:
        """(section, its :class:`RoundingEffect`) of every section (empty where the cut lengths are exact)."""
        return rounding_by_section(self.sections, [sec.sizing for sec in self.sections])


def rounding_by_section(sections, sizing) -> tuple[tuple[str, RoundingEffect], ...]:
    """(section id, rounding effect) of the sections whose sizing carries one.

    Parameters
    ----------
    sections : sequence
        Objects with a ``section`` id (survey sections or designed ones).
    sizing : sequence of SectionSizing
        Their sizing, in the same order.
    """
    return tuple((sec.section, size.span_presags.rounding) for sec, size in zip(sections, sizing, strict=True)
                 if size.span_presags is not None and size.span_presags.rounding is not None)
