"""The case-study recommendation: S_rel over an operating band for ideal and mixed layouts.

:func:`recommend` runs the paper's case study (ST 9,8/9,8, F_stat 70–140 N, v ≤ 90 km/h,
α_ae = 0.00097 N/(km/h)², ideal and mixed spans) and returns the F_m band, the S_rel range per layout,
their mean as the recommendation, and the speed context. It combines the band
(:mod:`~presag_opt.design.band`), the section elasticity (:mod:`~presag_opt.design.section`) and the
validity checks (:mod:`~presag_opt.design.speed_range`); the paper's own recommendation and the
comparison with it are in :mod:`presag_opt.validation`.

References
----------
Schick, Liu, Stichel, "Validity range of a quasi-static method for adjusting the pre-sag of simple
railway catenary systems", Railway Sciences (2025), doi:10.1108/RS-05-2025-0016: eq. (4)–(5), section 5.2.
"""

from __future__ import annotations

import os
import warnings
from collections.abc import Callable, Sequence
from concurrent.futures import as_completed
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from presag_opt.design.band import (
    CASE_STUDY_BAND,
    OperatingBand,
    check_levels_cover,
    force_levels_for_band,
    mean_force_grid,
)
from presag_opt.design.evidence import DeltaERule
from presag_opt.design.quasi_static import PRESAG_METHODS, check_method
from presag_opt.design.section import (
    SectionElasticity,
    SectionPresag,
    check_elasticity_method,
    section_elasticity,
    tension_label,
)
from presag_opt.design.speed_range import SpeedContext, StaticSteadyArmUplift, speed_context
from presag_opt.errors import ModelError
from presag_opt.processes import WorkerPolicy, worker_pool
from presag_opt.static.discretisation import StaticSettings
from presag_opt.system.catenary import Catenary
from presag_opt.system.loader import load_catenary

CASE_STUDY_MODELS = ("st_9.8_ideal", "st_9.8_mixed")
"""Built-in models of the case study: ST 9,8/9,8 on ideal 60 m spans and on the mixed section."""

CASE_STUDY_SPAN_LENGTH = 60.0
"""Nominal span length the recommendation is stated for. [m]"""


@dataclass(frozen=True, kw_only=True)
class LayoutRecommendation:
    """Quasi-static pre-sag of one section (layout) over a mean-force band.

    Attributes
    ----------
    section : SectionElasticity
        The elasticity curves it rests on.
    method : str
        Variant of the rule used for the range.
    speed : SpeedContext
        Speed band against this contact wire's wave speed.
    mean_forces : ndarray
        F_m from the lowest to the highest computed level, at most 1 N apart. [N]
    presag_rel_mid_mast, presag_rel_delta_e : ndarray
        Section S_rel (mean over spans) at ``mean_forces`` by each variant. [-]
    at_band_low, at_band_high : SectionPresag
        Per-span results at the ends of the F_m band (chosen method).
    presag_rel_range : tuple of float
        Smallest and largest section S_rel over the F_m band (chosen method). [-]
    steady_arm_uplift : StaticSteadyArmUplift
        Static uplift estimate at the top of the band.
    """

    section: SectionElasticity
    method: str
    speed: SpeedContext
    mean_forces: np.ndarray
    presag_rel_mid_mast: np.ndarray
    presag_rel_delta_e: np.ndarray
    at_band_low: SectionPresag
    at_band_high: SectionPresag
    presag_rel_range: tuple[float, float]
    steady_arm_uplift: StaticSteadyArmUplift

    @property
    def catenary_name(self) -> str:
        """System and layout."""
        return self.section.catenary.name

    @property
    def layout_kind(self) -> str:
        """``"ideal"`` or ``"mixed"``."""
        return self.section.layout_kind

    def to_dict(self, nominal_span_length: float, presag_rel: float) -> dict:
        """JSON-ready content in edge units (‰, mm, N).

        Parameters
        ----------
        nominal_span_length : float
            Span length the S range is also stated for. [m]
        presag_rel : float
            Recommended S_rel; each span's pre-sag to build is ``presag_rel`` times its length. [-]
        """
        low, high = self.presag_rel_range
        return {
            "catenary": self.catenary_name,
            "layout": self.layout_kind,
            "tension_kN": tension_label(self.section.catenary),
            "geometry_presag_rel_permille": self.section.catenary.presag_rel * 1e3,
            "force_levels_N": list(self.section.force_levels),
            "elasticity_method": self.section.elasticity_method,
            "presag_rel_range_permille": [low * 1e3, high * 1e3],
            "presag_range_mm_on_nominal_span": [low * nominal_span_length * 1e3, high * nominal_span_length * 1e3],
            "spans": [
                {
                    "span": span + 1,
                    "length_m": length,
                    "presag_rel_at_band_ends_permille": [lo * 1e3, hi * 1e3],
                    "own_presag_at_band_ends_mm": [slo * 1e3, shi * 1e3],
                    "proportional_presag_at_band_ends_mm": [plo * 1e3, phi * 1e3],
                    "recommended_presag_mm": presag_rel * length * 1e3,
                }
                for span, length, lo, hi, slo, shi, plo, phi in zip(
                    self.at_band_low.spans,
                    self.at_band_low.span_lengths,
                    self.at_band_low.presag_rel,
                    self.at_band_high.presag_rel,
                    self.at_band_low.presag,
                    self.at_band_high.presag,
                    self.at_band_low.presag_proportional,
                    self.at_band_high.presag_proportional,
                )
            ],
            "speed": self.speed.to_dict(),
            "steady_arm_uplift": self.steady_arm_uplift.to_dict(),
        }


def presag_rel_range(section: SectionElasticity, low: float, high: float, method: str = "delta-e") -> tuple[float, float]:
    """Smallest and largest section S_rel (mean over its spans) over an F_m band: the range the rule
    gives, on F_m at most 1 N apart with the band's ends and every force level. [-]

    Parameters
    ----------
    section : SectionElasticity
        Curves whose force levels bracket the band.
    low, high : float
        The F_m band. [N]
    method : {"delta-e", "mid-mast"}
        Variant of the rule.
    """
    levels = section.force_levels
    check_levels_cover(levels, low, high)
    mean_forces = mean_force_grid(levels[0], levels[-1], [low, high, *levels])
    return _range_over_band(mean_forces, section.presag_rel_curve(mean_forces, method), low, high)


def _range_over_band(mean_forces: np.ndarray, presag_rel: np.ndarray, low: float, high: float) -> tuple[float, float]:
    """Smallest and largest S_rel [-] of a curve over F_m [N] at the forces inside [low, high] [N]."""
    values = presag_rel[(mean_forces >= low) & (mean_forces <= high)]
    return (float(values.min()), float(values.max()))


def layout_recommendation(
    section: SectionElasticity, band: OperatingBand, method: str = "delta-e", speed: SpeedContext | None = None
) -> LayoutRecommendation:
    """Quasi-static pre-sag of a section over the F_m band of an operating band.

    Parameters
    ----------
    section : SectionElasticity
        Curves whose force levels bracket the band's F_m range.
    band : OperatingBand
        Forces and speeds.
    method : {"delta-e", "mid-mast"}
        Variant of the rule for the range.
    speed : SpeedContext, optional
        The band's speed context for this contact wire, if already computed.

    Raises
    ------
    ModelError
        If the levels do not bracket the F_m band, or a speed is at or above the wave speed.
    """
    check_method(method)
    low, high = band.mean_force_band()
    levels = section.force_levels
    check_levels_cover(levels, low, high)
    if speed is None:
        speed = speed_context(section.catenary.contact_wire, band.speed_low, band.speed_high)
    mean_forces = mean_force_grid(levels[0], levels[-1], [low, high, *levels])
    curves = section.presag_rel_curves(mean_forces, PRESAG_METHODS)
    at_high = section.presag(high, method)
    return LayoutRecommendation(
        section=section,
        method=method,
        speed=speed,
        mean_forces=mean_forces,
        presag_rel_mid_mast=curves["mid-mast"],
        presag_rel_delta_e=curves["delta-e"],
        at_band_low=section.presag(low, method),
        at_band_high=at_high,
        presag_rel_range=_range_over_band(mean_forces, curves[method], low, high),
        steady_arm_uplift=StaticSteadyArmUplift(
            mean_force=high, support_elasticity=float(at_high.support_elasticity.max())
        ),
    )


@dataclass(frozen=True, kw_only=True)
class Recommendation:
    """A pre-sag recommendation over an operating band for one or more layouts.

    Attributes
    ----------
    band : OperatingBand
        Forces and speeds.
    mean_force_band : tuple of float
        F_m at the low and the high end of the band. [N]
    method : str
        Variant of the quasi-static rule.
    layouts : tuple of LayoutRecommendation
        One per section (e.g. ideal and mixed spans).
    presag_rel : float
        Recommended relative pre-sag: the mean of the layouts' S_rel range ends, as in the paper
        (0.68–1.35 and 0.82–1.62 ‰ → 1.12 ‰). [-]
    nominal_span_length : float
        Span length the absolute pre-sag is stated for. [m]
    warnings : tuple of str
        Validity and uplift warnings.
    recomputed : Recommendation or None
        The same study with the elasticity recomputed at the recommended pre-sag geometry.

    References
    ----------
    Schick, Liu, Stichel (2025), doi:10.1108/RS-05-2025-0016, section 5.2 (case-study recommendation).
    """

    band: OperatingBand
    mean_force_band: tuple[float, float]
    method: str
    layouts: tuple[LayoutRecommendation, ...]
    presag_rel: float
    nominal_span_length: float
    warnings: tuple[str, ...] = ()
    recomputed: Recommendation | None = None

    @property
    def presag(self) -> float:
        """Recommended pre-sag on a span of the nominal length. [m]"""
        return self.presag_rel * self.nominal_span_length

    @property
    def presag_rel_range(self) -> tuple[float, float]:
        """Envelope of the layouts' S_rel ranges. [-]"""
        return (min(lay.presag_rel_range[0] for lay in self.layouts), max(lay.presag_rel_range[1] for lay in self.layouts))

    @property
    def beta_max(self) -> float:
        """Largest speed ratio over the layouts' contact wires. [-]"""
        return max(lay.speed.beta_max for lay in self.layouts)

    @property
    def static_uplift(self) -> StaticSteadyArmUplift:
        """The layouts' largest static steady-arm uplift estimate (at the top of the band)."""
        return max(self.layouts, key=lambda lay: lay.steady_arm_uplift.uplift).steady_arm_uplift

    def evidence(self) -> DeltaERule:
        """The Δe rule as evidence for a decision (:mod:`presag_opt.design.evidence`)."""
        uplift = self.static_uplift
        return DeltaERule(presag_rel=self.presag_rel, presag_rel_range=self.presag_rel_range,
                          static_uplift=uplift.uplift, support_elasticity=uplift.support_elasticity)

    def to_dict(self) -> dict:
        """JSON-ready content in edge units (mm, ‰, N, km/h)."""
        low, high = self.presag_rel_range
        out = {
            "presag_mm": self.presag * 1e3,
            "presag_rel_permille": self.presag_rel * 1e3,
            "presag_rel_range_permille": [low * 1e3, high * 1e3],
            "fm_band_N": list(self.mean_force_band),
            "beta_max": self.beta_max,
            "method": self.method,
            "nominal_span_length_m": self.nominal_span_length,
            "band": self.band.to_dict(),
            "layouts": [lay.to_dict(self.nominal_span_length, self.presag_rel) for lay in self.layouts],
            "warnings": list(self.warnings),
        }
        if self.recomputed is not None:
            out["recomputed_at_recommended_geometry"] = self.recomputed.to_dict()
        return out


def _as_catenary(model: str | Path | Catenary) -> Catenary:
    return model if isinstance(model, Catenary) else load_catenary(model)


def _layout_job(catenary, levels, step, elasticity_method, settings, band, method, speed, progress=None):
    """One layout of :func:`recommend` (a top-level function so that a process pool can run it)."""
    section = section_elasticity(
        catenary, force_levels=levels, step=step, elasticity_method=elasticity_method, settings=settings,
        progress=progress,
    )
    return layout_recommendation(section, band, method, speed)


def recommend(
    *,
    models: Sequence[str | Path | Catenary] = CASE_STUDY_MODELS,
    band: OperatingBand = CASE_STUDY_BAND,
    method: str = "delta-e",
    force_levels: Sequence[float] | None = None,
    step: float = 0.5,
    elasticity_method: str = "active-set",
    nominal_span_length: float = CASE_STUDY_SPAN_LENGTH,
    recompute_at_recommended: bool = False,
    settings: StaticSettings | None = None,
    progress: Callable[[str], None] | None = None,
) -> Recommendation:
    """Recommend a relative pre-sag for a line from its operating band (the paper's case study).

    For each model: form-find once at its pre-sag geometry, compute the elasticity curves of its
    spans at force levels that bracket the F_m band, and find the range of the section's S_rel over
    the band. The recommendation is the mean of all range ends (the paper's "mean value").

    Parameters
    ----------
    models : sequence of str, Path or Catenary
        Built-in model names, model files or catenaries (default: ST 9,8/9,8 ideal and mixed).
    band : OperatingBand
        F_stat range, speed range and α_ae (default: the case study).
    method : {"delta-e", "mid-mast"}
        Variant of the quasi-static rule (default Δe, the one the paper's recommendation uses).
    force_levels : sequence of float, optional
        Elasticity force levels [N]; default: 50 N steps bracketing the F_m band
        (:func:`force_levels_for_band`).
    step : float
        Point spacing of the elasticity curves. [m]
    elasticity_method : {"active-set", "newton"}
        Method of the nonlinear elasticity (active-set: fast, for whole sections).
    nominal_span_length : float
        Span length the absolute recommendation is stated for. [m]
    recompute_at_recommended : bool
        Also recompute everything at the recommended pre-sag geometry (``recomputed``).
    settings : StaticSettings, optional
        Numerical settings of the static model.
    progress : callable, optional
        Called with a short message before each expensive step.

    Returns
    -------
    Recommendation

    Raises
    ------
    ModelError
        Bad input (unknown method or model, force levels that do not cover the band, a speed at
        or above the wave speed).

    References
    ----------
    Schick, Liu, Stichel (2025), doi:10.1108/RS-05-2025-0016, eq. (4)–(5), section 5.2.
    """
    check_method(method)
    if not isinstance(band, OperatingBand):
        raise ModelError(f"band must be an OperatingBand, not {type(band).__name__}")
    if not 5.0 <= nominal_span_length <= 120.0:
        raise ModelError(f"nominal_span_length = {nominal_span_length:g} m is outside the valid range [5, 120] m")
    if not models:
        raise ModelError("models is empty; give at least one catenary model")
    check_elasticity_method(elasticity_method)
    catenaries = [_as_catenary(m) for m in models]
    low, high = band.mean_force_band()
    levels = tuple(sorted(force_levels)) if force_levels is not None else force_levels_for_band(low, high)
    check_levels_cover(levels, low, high)
    # Speed errors (v >= c_CW) surface before any expensive form-finding.
    speeds = [speed_context(c.contact_wire, band.speed_low, band.speed_high) for c in catenaries]

    def study(geometries: Sequence[Catenary]) -> tuple[LayoutRecommendation, ...]:
        jobs = [(c, levels, step, elasticity_method, settings, band, method, speed) for c, speed in zip(geometries, speeds)]
        workers = min(len(jobs), os.cpu_count() or 1)
        if workers < 2:
            return tuple(_layout_job(*job, progress=progress) for job in jobs)
        # The layouts are independent: one process each (fork start, so nothing is re-imported).
        if progress:
            for c in geometries:
                progress(f"{c.name}: form-finding and elasticity (in parallel)")
        with worker_pool(workers, WorkerPolicy.FAST_START) as pool:
            futures = [pool.submit(_layout_job, *job) for job in jobs]
            for done, _ in enumerate(as_completed(futures), start=1):
                if progress:
                    progress(f"layouts done: {done}/{len(jobs)}")
            return tuple(f.result() for f in futures)

    def recommended_rel(layouts: Sequence[LayoutRecommendation]) -> float:
        return float(np.mean([end for lay in layouts for end in lay.presag_rel_range]))

    layouts = study(catenaries)
    presag_rel = recommended_rel(layouts)
    notes = [
        f"{lay.catenary_name}: static steady-arm uplift estimate {lay.steady_arm_uplift.uplift * 1e3:.1f} mm "
        f"at F_m = {high:.0f} N exceeds the limit {lay.steady_arm_uplift.limit * 1e3:g} mm"
        for lay in layouts
        if not lay.steady_arm_uplift.within_limit
    ]
    notes = list(dict.fromkeys(notes))
    for note in notes:
        warnings.warn(note, UserWarning, stacklevel=2)
    common = dict(band=band, mean_force_band=(low, high), method=method, nominal_span_length=nominal_span_length)
    recomputed = None
    if recompute_at_recommended:
        again = study([c.with_presag(presag_rel) for c in catenaries])
        recomputed = Recommendation(layouts=again, presag_rel=recommended_rel(again), **common)
    return Recommendation(layouts=layouts, presag_rel=presag_rel, warnings=tuple(notes), recomputed=recomputed, **common)
