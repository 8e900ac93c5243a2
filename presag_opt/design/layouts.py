"""How the span layout changes the quasi-static pre-sag: mixed against ideal spans, curved track.

- :func:`mixed_versus_ideal`: the S_rel range over an operating band on ideal and on mixed spans,
  for several variants of the assumptions (dropper rule, span list), to see whether "mixed spans
  need more relative pre-sag than ideal ones" depends on them.
- :func:`curve_effects`: one curve radius for a whole section, several radii: the steady-arm pull,
  the elasticity at the supports and the recommended pre-sag.

Both only combine :func:`~presag_opt.design.recommendation.recommend`,
:func:`~presag_opt.design.section.section_elasticity` and the form-finding.

References
----------
Schick, Liu, Stichel, "Validity range of a quasi-static method for adjusting the pre-sag of simple
railway catenary systems", Railway Sciences (2025), doi:10.1108/RS-05-2025-0016: section 5.2 (ideal
0.68–1.35 ‰, mixed 0.82–1.62 ‰).
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass

import numpy as np

from presag_opt.design.band import CASE_STUDY_BAND, OperatingBand, force_levels_for_band
from presag_opt.design.recommendation import Recommendation, layout_recommendation, recommend
from presag_opt.design.section import section_elasticity
from presag_opt.errors import ModelError
from presag_opt.static.discretisation import StaticSettings
from presag_opt.static.form_finding import form_find
from presag_opt.system.catenary import Catenary, SpanLayout


@dataclass(frozen=True, kw_only=True)
class MixedFinding:
    """S_rel over an operating band on ideal and on mixed spans, for one variant of the assumptions.

    Attributes
    ----------
    label : str
        What the variant changes.
    ideal_range, mixed_range : tuple of float
        Smallest and largest section S_rel over the F_m band (Δe rule). [-]
    """

    label: str
    ideal_range: tuple[float, float]
    mixed_range: tuple[float, float]

    @classmethod
    def from_recommendation(cls, label: str, recommendation: Recommendation) -> MixedFinding:
        """The finding of a recommendation over one ideal and one mixed layout.

        Raises
        ------
        ModelError
            If the recommendation does not have exactly one layout of each kind.
        """
        by_kind = {lay.layout_kind: lay.presag_rel_range for lay in recommendation.layouts}
        if sorted(lay.layout_kind for lay in recommendation.layouts) != ["ideal", "mixed"]:
            raise ModelError(f"variant {label!r}: give one ideal and one mixed layout")
        return cls(label=label, ideal_range=by_kind["ideal"], mixed_range=by_kind["mixed"])

    @property
    def ratio(self) -> float:
        """Mean of the mixed range over the mean of the ideal range. [-]"""
        return float(np.mean(self.mixed_range) / np.mean(self.ideal_range))

    @property
    def mixed_needs_less(self) -> bool:
        """Whether the mixed spans need less relative pre-sag than the ideal ones."""
        return self.ratio < 1.0


def mixed_versus_ideal(
    variants: Mapping[str, tuple[Catenary, Catenary]],
    *,
    band: OperatingBand = CASE_STUDY_BAND,
    step: float = 0.5,
    settings: StaticSettings | None = None,
    progress: Callable[[str], None] | None = None,
) -> tuple[MixedFinding, ...]:
    """The S_rel range on ideal and on mixed spans for each variant of the assumptions.

    Parameters
    ----------
    variants : mapping
        Label -> (ideal catenary, mixed catenary).
    band : OperatingBand
        Forces and speeds (default: the case study).
    step : float
        Point spacing of the elasticity curves. [m]
    settings : StaticSettings, optional
        Numerical settings of the static model.
    progress : callable, optional
        Called with a short message before each variant.
    """
    if not variants:
        raise ModelError("variants is empty; give at least one (ideal, mixed) pair")
    out = []
    for label, (ideal, mixed) in variants.items():
        if progress:
            progress(f"mixed against ideal: {label}")
        result = recommend(models=[ideal, mixed], band=band, step=step, settings=settings)
        out.append(MixedFinding.from_recommendation(label, result))
    return tuple(out)


@dataclass(frozen=True, kw_only=True)
class CurveEffect:
    """A section built on one curve radius: steady-arm pull, elasticity and quasi-static pre-sag.

    Attributes
    ----------
    radius : float
        Curve radius of every span; 0 for straight track. [m]
    steady_arm_pull : float
        Mean tensile force of the steady arms between the end spans (the masts of the sized spans). [N]
    steady_arm_pull_range : tuple of float
        Smallest and largest of those forces: with the alternating stagger of straight track kept on a
        curve, the stagger and curve kinks add at one mast and partly cancel at the next. [N]
    e_mast, e_mid : float
        Mean over the analysed spans of the elasticity at the supports and at mid-span, at the
        centre of the F_m band. [m/N]
    presag_rel_range : tuple of float
        Smallest and largest section S_rel over the F_m band (Δe rule). [-]
    """

    radius: float
    steady_arm_pull: float
    steady_arm_pull_range: tuple[float, float]
    e_mast: float
    e_mid: float
    presag_rel_range: tuple[float, float]

    @property
    def presag_rel(self) -> float:
        """Mean of the range ends, the recommendation's rule. [-]"""
        return float(np.mean(self.presag_rel_range))


def curve_effects(
    catenary: Catenary,
    radii: Sequence[float],
    *,
    band: OperatingBand = CASE_STUDY_BAND,
    step: float = 0.5,
    settings: StaticSettings | None = None,
    progress: Callable[[str], None] | None = None,
) -> tuple[CurveEffect, ...]:
    """Build a section on each curve radius in turn and size its pre-sag over an operating band.

    Parameters
    ----------
    catenary : Catenary
        The section (steady-arm supports, pin messenger supports); its radii are replaced.
    radii : sequence of float
        Curve radius applied to every span; 0 for straight track, else at least 100 m in size. [m]
    band : OperatingBand
        Forces and speeds (default: the case study).
    step : float
        Point spacing of the elasticity curves. [m]
    settings : StaticSettings, optional
        Numerical settings of the static model.
    progress : callable, optional
        Called with a short message before each radius.
    """
    low, high = band.mean_force_band()
    levels = force_levels_for_band(low, high)
    out = []
    for radius in radii:
        if progress:
            progress(f"curve radius {radius:g} m")
        layout = SpanLayout(span_lengths=catenary.layout.span_lengths,
                            curve_radii=(float(radius),) * catenary.layout.n_spans, label=catenary.layout.label)
        state = form_find(catenary.with_layout(layout), settings)
        section = section_elasticity(state, force_levels=levels, step=step)
        curves = section.curves_at(0.5 * (low + high))
        result = layout_recommendation(section, band)
        pulls = state.steady_arm_forces()[1:-1]
        out.append(CurveEffect(
            radius=float(radius),
            steady_arm_pull=float(np.mean(pulls)),
            steady_arm_pull_range=(float(pulls.min()), float(pulls.max())),
            e_mast=float(np.mean([0.5 * (c.elasticity[0] + c.elasticity[-1]) for c in curves])),
            e_mid=float(np.mean([c.e_mid for c in curves])),
            presag_rel_range=result.presag_rel_range,
        ))
    return tuple(out)
