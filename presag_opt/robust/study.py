"""The job behind ``presag robust`` and ``presag tolerance``: robust and nominal designs of a section.

:func:`robust_study` form-finds, computes the elasticity, solves the robust design (re-linearised at
its own pre-sag), evaluates the nominal Δe rule and both tolerance bands. The pieces are in the other
modules of :mod:`presag_opt.robust`; the dynamic check of designs is
:mod:`presag_opt.robust.dynamic_check`.
"""

from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np

from presag_opt.design.band import force_levels_for_band
from presag_opt.design.evidence import QuasiStaticRobust
from presag_opt.design.recommendation import presag_rel_range
from presag_opt.design.section import section_elasticity
from presag_opt.display import data_frame, html_summary
from presag_opt.errors import ModelError
from presag_opt.robust.buildability import Buildability
from presag_opt.robust.lp import RobustDesign, evaluate_design, robust_presag
from presag_opt.robust.path import PathModel, build_path_model
from presag_opt.robust.scenarios import ForceScenarios, Risk
from presag_opt.robust.tolerance import ToleranceBand, check_within, tolerance_band
from presag_opt.static.discretisation import StaticSettings
from presag_opt.static.form_finding import form_find


@dataclass(frozen=True, kw_only=True)
class RobustStudy:
    """Robust and nominal designs of one section over a force band, with tolerance bands.

    Attributes
    ----------
    catenary_name : str
        System.
    path : PathModel
        Path model at the final reference geometry.
    scenarios : ForceScenarios
        The forces (and probabilities) designed for. [N]
    robust : RobustDesign
        The design for the chosen shape and risk.
    robust_parabola : RobustDesign
        The minimax parabola (the one the tolerance band refers to).
    nominal : RobustDesign
        The quasi-static Δe rule over the band (the mean of the S_rel range ends, on the model's own
        geometry, as :func:`~presag_opt.design.recommendation.layout_recommendation` finds it; or the
        S_rel given to :func:`robust_study`), evaluated over the band.
    tolerance : ToleranceBand
        S_rel interval of the robust parabola within ``within`` of its worst-case optimum.
    centre_tolerance : ToleranceBand
        The same for the parabola that is optimal for the band centre F_c alone (its ``best``, the
        minimum of R at F_c; not the nominal Δe design, which is quasi-static, not an optimum of R).
    reference_span : float
        Span length the absolute pre-sag is quoted for. [m]
    wall_time : float
        Wall time of the study. [s]
    """

    catenary_name: str
    path: PathModel
    scenarios: ForceScenarios
    robust: RobustDesign
    robust_parabola: RobustDesign
    nominal: RobustDesign
    tolerance: ToleranceBand
    centre_tolerance: ToleranceBand
    reference_span: float
    wall_time: float = 0.0

    def to_dict(self) -> dict:
        """JSON-ready summary in mm, ‰ and N."""
        l_ref = self.reference_span
        weights = self.scenarios.weights
        return {
            "catenary": self.catenary_name,
            "fm_band_N": [float(self.scenarios.forces.min()), float(self.scenarios.forces.max())],
            "shape": self.robust.shape,
            "risk": self.robust.risk,
            "reference_span_m": l_ref,
            "presag_mm": self.robust.presag_rel * l_ref * 1e3,
            "presag_rel_permille": self.robust.presag_rel * 1e3,
            "dropper_depths_mm": (self.robust.depths * 1e3).tolist(),
            "worst_case_waviness_mm": self.robust.worst_case_waviness * 1e3,
            "mean_waviness_mm": self.robust.mean_waviness(weights) * 1e3,
            "objective_mm": self.robust.objective * 1e3,
            "continuous_objective_mm": None if self.robust.continuous_objective is None
            else self.robust.continuous_objective * 1e3,
            "rounding": self.robust.rounding,
            "nominal_presag_mm": self.nominal.presag_rel * l_ref * 1e3,
            "nominal_worst_case_waviness_mm": self.nominal.worst_case_waviness * 1e3,
            "nominal_mean_waviness_mm": self.nominal.mean_waviness(weights) * 1e3,
            "tolerance_mm": [self.tolerance.low * l_ref * 1e3, self.tolerance.high * l_ref * 1e3],
            "tolerance_within": self.tolerance.within,
            "centre_optimum_presag_mm": self.centre_tolerance.best * l_ref * 1e3,
            "centre_optimum_tolerance_mm": [self.centre_tolerance.low * l_ref * 1e3,
                                            self.centre_tolerance.high * l_ref * 1e3],
            "solver_status": self.robust.solver_status,
        }

    def table(self) -> list[dict]:
        """The robust design beside the Δe rule as rows: S on the reference span, S_rel, worst and mean
        waviness over the band."""
        data = self.to_dict()
        return [{"design": name, "S [mm]": data[f"{key}presag_mm"],
                 "S_rel [‰]": data[f"{key}presag_mm"] / data["reference_span_m"],
                 "worst R [mm]": data[f"{key}worst_case_waviness_mm"], "mean R [mm]": data[f"{key}mean_waviness_mm"]}
                for name, key in (("robust", ""), ("Δe rule", "nominal_"))]

    def to_frame(self):
        """:meth:`table` as a pandas DataFrame."""
        return data_frame(self.table())

    def _repr_html_(self) -> str:
        low, high = self.to_dict()["tolerance_mm"]
        return html_summary(f"Robust pre-sag {self.robust.presag_rel * self.reference_span * 1e3:.1f} mm on "
                            f"{self.reference_span:g} m ({self.robust.shape}, {self.robust.risk})",
                            [f"{self.catenary_name}; quasi-static tolerance (worst-case R within "
                             f"{self.tolerance.within * 100:g} %): {low:.1f}–{high:.1f} mm"], self.table())

    def evidence(self) -> QuasiStaticRobust:
        """The robust parabola and its tolerance as evidence for a decision (:mod:`presag_opt.design.evidence`)."""
        return QuasiStaticRobust(presag_rel=self.robust_parabola.presag_rel,
                                 tolerance=(self.tolerance.low, self.tolerance.high), within=self.tolerance.within)


def robust_study(
    catenary,
    fm_band: tuple[float, float],
    *,
    shape: str = "parabola",
    risk: Risk | None = None,
    buildability: Buildability | None = None,
    within: float = 0.10,
    scenarios: ForceScenarios | None = None,
    relinearise: bool = True,
    settings: StaticSettings | None = None,
    nominal_presag_rel: float | None = None,
    progress=None,
) -> RobustStudy:
    """Design the pre-sag of a section for a band of mean contact forces.

    Steps: form-find the model's geometry; compute the elasticity curves of the analysed spans at
    force levels bracketing the band (active-set method); solve the minimax parabola; then, as the
    paper finds the elasticity is best taken near the optimal pre-sag (its Fig. 5b: 16 % error at
    179 N from the 30 mm geometry, 2 % from 70 mm), form-find again at that pre-sag, recompute the
    curves and solve again (``relinearise``); finally the requested shape and risk, the nominal Δe
    rule over the band and both tolerance bands on the final geometry.

    Parameters
    ----------
    catenary : Catenary
        System model (its pre-sag is the first reference geometry).
    fm_band : (float, float)
        Mean contact force band. [N]
    shape : {"parabola", "per-dropper"}
        See :func:`robust_presag`.
    risk : Risk, optional
        See :func:`robust_presag`.
    buildability : Buildability, optional
        See :func:`robust_presag`.
    within : float
        Tolerance-band loss. [-]
    scenarios : ForceScenarios, optional
        Defaults to 17 equally likely forces over the band.
    relinearise : bool
        Recompute geometry and elasticity at the first robust pre-sag.
    settings : StaticSettings, optional
        Numerical settings of the static model (default: 0.5 m elements).
    nominal_presag_rel : float, optional
        S_rel of the Δe rule to evaluate as the nominal design (a decision passes the one its
        recommendation found, so that one rule has one number); default: the rule over ``fm_band`` on
        the model's own geometry. [-]
    progress : callable, optional
        Called with a short message before each expensive step.
    """
    started = time.perf_counter()
    low, high = fm_band
    scenarios = scenarios or ForceScenarios.band(low, high)
    check_within(within)  # before the form-finding, not after it
    risk = risk or Risk()
    levels = force_levels_for_band(min(low, scenarios.forces.min()), max(high, scenarios.forces.max()))

    def path_at(cat):
        if progress:
            progress(f"{cat.name}: form-finding at S_rel = {cat.presag_rel * 1e3:.3f} ‰")
        state = form_find(cat, settings)
        if progress:
            progress(f"{cat.name}: elasticity at {', '.join(f'{f:g}' for f in levels)} N")
        return build_path_model(state, section_elasticity(state, force_levels=levels, elasticity_method="active-set"))

    path = path_at(catenary)
    if nominal_presag_rel is None:
        nominal_presag_rel = layout_recommendation_rel(path.section, fm_band)
    if relinearise:
        first = robust_presag(path, scenarios)
        path = path_at(_within_model_range(catenary, first, fm_band))
    parabola = robust_presag(path, scenarios)
    _within_model_range(catenary, parabola, fm_band)
    design = parabola if (shape == "parabola" and risk.measure == "minimax") else robust_presag(
        path, scenarios, shape=shape, risk=risk, buildability=buildability
    )
    centre = 0.5 * (low + high)
    nominal = evaluate_design(path, path.parabola_depths(nominal_presag_rel), scenarios, shape="parabola", risk=risk,
                              presag_rel=nominal_presag_rel, risk_label="nominal")
    single = ForceScenarios(forces=np.array([centre]), weights=np.array([1.0]))
    lengths = catenary.layout.span_lengths
    reference = lengths[path.spans[0]] if len(set(lengths)) == 1 else max(lengths)
    return RobustStudy(
        catenary_name=catenary.name,
        path=path,
        scenarios=scenarios,
        robust=design,
        robust_parabola=parabola,
        nominal=nominal,
        tolerance=tolerance_band(path, scenarios, within),
        centre_tolerance=tolerance_band(path, single, within),
        reference_span=float(reference),
        wall_time=time.perf_counter() - started,
    )


def layout_recommendation_rel(section, fm_band: tuple[float, float]) -> float:
    """The Δe rule's S_rel over an F_m band on a section: the mean of its range ends (one definition
    with :func:`~presag_opt.design.recommendation.layout_recommendation`). [-]

    Parameters
    ----------
    section : SectionElasticity
        Curves whose force levels bracket the band.
    fm_band : (float, float)
        The F_m band. [N]
    """
    return float(np.mean(presag_rel_range(section, *fm_band)))


def _within_model_range(catenary, design: RobustDesign, fm_band: tuple[float, float]):
    """The catenary at a design's pre-sag, or a ModelError when that pre-sag is outside the model's
    range (0–5 ‰): the elasticity was computed at another geometry and the design cannot be built
    from a model file, so the result is refused rather than reported."""
    try:
        return catenary.with_presag(design.presag_rel)
    except ModelError:
        longest = max(catenary.layout.span_lengths)
        raise ModelError(
            f"the robust pre-sag for F_m {fm_band[0]:g}–{fm_band[1]:g} N is S_rel = {design.presag_rel * 1e3:.2f} ‰ "
            f"({design.presag_rel * longest * 1e3:.0f} mm on {longest:g} m), outside the model's valid range "
            "0–5 ‰; narrow the force band"
        ) from None
