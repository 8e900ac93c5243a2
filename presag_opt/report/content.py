"""What a design report says about a line: every number of it, computed once.

:func:`design_report` runs the recommendation over the operating band, the robust design with its
tolerance band, and the validity study (a stored one, or a reduced sweep run for the report), and
collects the inputs with their provenance and every assumed value. Writing it as HTML is
:mod:`presag_opt.report.html`.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import xarray as xr

from presag_opt.design.band import CASE_STUDY_BAND, KMH, OperatingBand
from presag_opt.design.decision import (
    DELTA_E_RULE,
    QUASI_STATIC_ROBUST,
    Candidate,
    Decision,
    DecisionInputs,
    decide,
)
from presag_opt.design.recommendation import CASE_STUDY_MODELS, CASE_STUDY_SPAN_LENGTH, Recommendation, recommend
from presag_opt.design.speed_range import QUASI_STATIC_BETA_LIMIT
from presag_opt.dynamics.pantograph import load_pantograph
from presag_opt.errors import ModelError
from presag_opt.robust.study import RobustStudy, robust_study
from presag_opt.static.discretisation import StaticSettings
from presag_opt.studies.definition import load_study
from presag_opt.studies.reduced import reduced_study, run_in_process
from presag_opt.studies.store import open_store
from presag_opt.studies.validity_analysis import validity_analysis
from presag_opt.studies.validity_results import ValidityResult
from presag_opt.system.loader import ModelEntry, load_catenary, model_entries, resolve_model_path
from presag_opt.system.stitch import stitch_summary

CASE_STUDY_PANTOGRAPH = "case_study_2mass_friction"
"""Pantograph of the case study's dynamic runs."""

BASE_STUDY = "paper_grid_st98"
"""Study whose numerics, analysis window and uplift limit a reduced sweep starts from."""

SWEEP_BETAS = (0.2, 0.3, 0.4, 0.5, 0.6)
"""Speed ratios of a report's reduced sweep, besides the top speed of the band. [-]"""

SWEEP_PRESAG_FACTORS = (0.5, 1.0, 1.5)
"""Pre-sags of a report's reduced sweep, as multiples of the recommended one. [-]"""

QUICK = {"element_length": 1.0, "step": 1.0, "time_step": 4e-3}
"""Numerics of a quick (draft) report: element length [m], elasticity point spacing [m], time step [s]."""

FULL = {"element_length": 0.5, "step": 0.5, "time_step": 2e-3}
"""Numerics of a report: the paper's 0.5 m elements and 2 ms, 0.5 m point spacing."""


@dataclass(frozen=True, kw_only=True)
class Assumption:
    """A value the report rests on that is a choice rather than data.

    Attributes
    ----------
    name : str
        What it is.
    value : str
        The value with its unit.
    why : str
        Where it comes from or why it was chosen.
    """

    name: str
    value: str
    why: str


@dataclass(frozen=True, kw_only=True)
class ValidityRange:
    """The speed range in which the quasi-static pre-sag holds for the line, and where it was read.

    Attributes
    ----------
    source : str
        The stored study file, or a description of the reduced sweep run for the report.
    dataset : xarray.Dataset
        The study's statistics.
    result : ValidityResult
        Its analysis.
    line_wave_speed : float
        Contact-wire wave speed of the line the report is for. [m/s]
    """

    source: str
    dataset: xr.Dataset
    result: ValidityResult
    line_wave_speed: float

    @property
    def wave_speed(self) -> float:
        """Contact-wire wave speed of the studied line, v/β of the study's runs. [m/s]"""
        return float(self.dataset["speed"].values[0] / self.dataset["beta"].values[0, 0])

    @property
    def warnings(self) -> tuple[str, ...]:
        """Set when the study is of another contact wire than the report's line."""
        if abs(self.wave_speed / self.line_wave_speed - 1.0) <= 0.01:
            return ()
        return (f"the validity study {self.dataset.attrs.get('study_name', '')!r} is of a contact wire with wave "
                f"speed {self.wave_speed / KMH:.0f} km/h, this line's is {self.line_wave_speed / KMH:.0f} km/h: its "
                "speeds do not carry over (compare speed ratios β)",)

    @property
    def limit_speed(self) -> float | None:
        """β*·c_CW of the studied line, the speed up to which the Δe rule holds there (None if not found). [m/s]"""
        return None if self.result.beta_limit is None else self.result.beta_limit * self.wave_speed

    @property
    def paper_limit_speed(self) -> float:
        """The paper's β = 0.4 as a speed on the report's line. [m/s]"""
        return QUASI_STATIC_BETA_LIMIT * self.line_wave_speed

    def text(self) -> str:
        """β* and its speed in words, or why the grid gives no limit."""
        res = self.result
        if res.beta_limit is not None:
            return (f"β* = {res.beta_limit:.2f} ± {res.beta_limit_uncertainty:.2f}: the Δe rule holds up to about "
                    f"{self.limit_speed / KMH:.0f} km/h")
        holding = [v for v in res.per_beta if v.holds]
        if not holding:
            return "the Δe rule holds at no speed of this grid: no limit can be read"
        top = holding[-1]
        return (f"the Δe rule holds up to the highest speed of this grid, {top.speed / KMH:.0f} km/h "
                f"(β = {top.beta:.2f}): the limit lies above it")

    def uplift_up_to(self, speed: float) -> float:
        """Largest steady-arm uplift of the runs at or below a speed (NaN if none). [m]

        Parameters
        ----------
        speed : float
            Highest speed of the runs taken. [m/s]
        """
        speeds = self.dataset["speed"].values
        inside = speeds <= speed * (1 + 1e-9)
        values = self.dataset["uplift_max"].values[:, inside, :]
        return float(np.nanmax(values)) if values.size and np.isfinite(values).any() else math.nan


@dataclass(frozen=True, kw_only=True)
class DesignReport:
    """Everything a design report shows.

    Attributes
    ----------
    models : tuple of str
        Catenary models as given (names or files).
    pantograph : str
        Pantograph model of the dynamic runs.
    band : OperatingBand
        Forces and speeds the line serves.
    recommendation : Recommendation
        Quasi-static pre-sag over the band, every layout.
    robust : RobustStudy
        Robust (minimax) and nominal designs of the first model, tolerance band.
    validity : ValidityRange
        The validity study of the first model.
    inputs : tuple of ModelEntry
        Every number of the model files, with provenance.
    assumptions : tuple of Assumption
        The report's own choices (numerics, loss of the tolerance band, sweep grid).
    quick : bool
        Coarse numerics (a draft).
    decision : Decision
        What to build, from everything above (:func:`report_decision`); it heads the report.
    """

    models: tuple[str, ...]
    pantograph: str
    band: OperatingBand
    recommendation: Recommendation
    robust: RobustStudy
    validity: ValidityRange
    inputs: tuple[ModelEntry, ...]
    assumptions: tuple[Assumption, ...]
    quick: bool
    decision: Decision

    @property
    def assumed_inputs(self) -> tuple[ModelEntry, ...]:
        """The model-file numbers tagged ``assumed``."""
        return tuple(e for e in self.inputs if e.source == "assumed")


def design_report(
    models: Sequence[str | Path] = CASE_STUDY_MODELS,
    *,
    band: OperatingBand = CASE_STUDY_BAND,
    pantograph: str | Path = CASE_STUDY_PANTOGRAPH,
    study: str | Path | None = None,
    within: float = 0.10,
    quick: bool = False,
    progress: Callable[[str], None] | None = None,
) -> DesignReport:
    """Compute a design report for a line (default: the paper's case study).

    Parameters
    ----------
    models : sequence of str or Path
        Catenary model files or built-in names; the first is also the one of the robust design and
        of the validity study (give the ideal-span model first).
    band : OperatingBand
        Static forces, speeds and α_ae of the line.
    pantograph : str or Path
        Pantograph model of the dynamic runs.
    study : str or Path, optional
        A stored study (``presag sweep``) to read the validity range from; default: a reduced sweep
        run here (a few pre-sags, speeds and static forces on five spans).
    within : float
        Loss of the tolerance band. [-]
    quick : bool
        Coarse numerics (1 m elements, 4 ms, a 2 × 2 × 2 sweep): a draft in seconds.
    progress : callable, optional
        Called with a short message before each expensive step.

    Raises
    ------
    ModelError
        Bad input (unknown model, a band the rule cannot serve, an unreadable study store).
    """
    models = tuple(str(m) for m in models)
    if not models:
        raise ModelError("models is empty; give at least one catenary model")
    numerics = QUICK if quick else FULL
    catenaries = [load_catenary(m) for m in models]
    panto = load_pantograph(pantograph)
    dataset = open_store(study) if study is not None else None  # unreadable stores fail before any work
    settings = StaticSettings(element_length=numerics["element_length"])
    if progress:
        progress("recommendation over the band")
    recommendation = recommend(models=catenaries, band=band, step=numerics["step"], settings=settings,
                               nominal_span_length=_reference_span(catenaries[0]))
    low, high = recommendation.mean_force_band
    robust = robust_study(catenaries[0], (low, high), within=within, settings=settings, progress=progress)
    sweep_note = None
    if dataset is None:
        grid = _sweep_grid(catenaries[0], band, recommendation, quick)
        definition = reduced_study(load_study(BASE_STUDY), catenary=catenaries[0], pantograph=panto,
                                   aero_coefficient=band.aero_coefficient, element_length=numerics["element_length"],
                                   time_step=numerics["time_step"], **grid)
        dataset = run_in_process(definition, progress=progress)
        sweep_note = definition.description
    validity = ValidityRange(
        source=str(study) if study is not None else f"reduced sweep run for this report: {sweep_note}",
        dataset=dataset, result=validity_analysis(dataset), line_wave_speed=catenaries[0].contact_wire.wave_speed)
    inputs = tuple(e for m in models for e in model_entries(m)) + model_entries(pantograph, "pantographs")
    return DesignReport(
        models=models, pantograph=resolve_model_path(pantograph, "pantographs").stem, band=band,
        recommendation=recommendation, robust=robust, validity=validity, inputs=inputs,
        assumptions=_assumptions(band, numerics, within, sweep_note, quick) + _stitch_notes(catenaries), quick=quick,
        decision=report_decision(recommendation, robust, validity, band),
    )


def report_decision(recommendation: Recommendation, robust: RobustStudy, validity: ValidityRange,
                    band: OperatingBand) -> Decision:
    """The decision of a report (:mod:`presag_opt.design.decision`) from what the report computed.

    Candidates: the Δe rule (the recommendation) and the quasi-static robust design (with its
    tolerance interval). Their steady-arm uplift is the validity sweep's largest over its static
    forces and the speeds up to the band's top, at the swept pre-sags next to the candidate's (the
    larger of the two that bracket it: an uplift limit is checked on the safe side, not
    interpolated); β* comes from the sweep. The highest static force that keeps the uplift
    limit is the largest of the sweep's static forces up to which (from the lowest) some swept
    pre-sag keeps it; None if not even the lowest does. Whether any swept pre-sag keeps the limit over
    the whole band decides if the band is uplift-bound.

    Parameters
    ----------
    recommendation : Recommendation
        The quasi-static recommendation.
    robust : RobustStudy
        The quasi-static robust design of the first model.
    validity : ValidityRange
        The validity study (dynamic sweep).
    band : OperatingBand
        Forces and speeds.
    """
    data = validity.dataset
    limit = float(data.attrs["uplift_limit"])
    l_ref = robust.reference_span
    inside = data["speed"].values <= band.speed_high * (1 + 1e-9)
    uplift = data["uplift_max"].values[:, inside, :]  # (presag, speed, static force)
    per_presag_force = np.nanmax(uplift, axis=1) if uplift.size and np.isfinite(uplift).any() else None
    presag_rel = data["presag"].values / l_ref

    def swept_uplift(s_rel: float) -> float | None:
        if per_presag_force is None:
            return None
        swept, values = presag_rel, np.nanmax(per_presag_force, axis=1)
        same = np.isclose(swept, s_rel, rtol=1e-6, atol=0.0)
        if same.any():
            return float(values[same].max())
        below, above = swept < s_rel, swept > s_rel
        nearest = [np.flatnonzero(below)[np.argmax(swept[below])]] if below.any() else []
        nearest += [np.flatnonzero(above)[np.argmin(swept[above])]] if above.any() else []
        return float(values[nearest].max())

    highest, feasible = None, None
    if per_presag_force is not None:
        # the band cut at each swept static force: is there a swept S whose uplift keeps the limit up to it?
        forces = data["static_force"].values
        order = np.argsort(forces)
        up_to = np.fmax.accumulate(per_presag_force[:, order], axis=1)  # (presag, band top)
        keeps = np.nanmin(up_to, axis=0) <= limit
        highest = float(forces[order][keeps].max()) if keeps.any() else None
        feasible = bool(keeps[-1])
    tol = robust.tolerance
    dynamic = per_presag_force is not None
    candidates = (
        Candidate(method=DELTA_E_RULE, presag_rel=recommendation.presag_rel, uplift=swept_uplift(recommendation.presag_rel),
                  uplift_dynamic=dynamic),
        Candidate(method=QUASI_STATIC_ROBUST, presag_rel=robust.robust_parabola.presag_rel, tolerance=(tol.low, tol.high),
                  uplift=swept_uplift(robust.robust_parabola.presag_rel), uplift_dynamic=dynamic),
    )
    result = validity.result
    limit_beta, limit_source = result.beta_limit, ""
    uncertainty = result.beta_limit_uncertainty if result.beta_limit is not None else 0.0
    if limit_beta is None and result.per_beta:
        held = [v for v in result.per_beta if v.holds]
        if not held:  # the rule holds at none of the study's speeds: trusted nowhere at or above its lowest β
            limit_beta = min(v.beta for v in result.per_beta)
            limit_source = f"the lowest β of the validity sweep, {limit_beta:.2f}, at which the Δe rule already fails"
            uncertainty = 1e-6  # trusted only below it
        else:  # it holds at every speed of the grid: trusted up to its highest
            limit_beta = max(v.beta for v in held)
            limit_source = f"the highest β of the validity sweep, {limit_beta:.2f}, up to which the Δe rule holds"
    return decide(DecisionInputs(
        candidates=candidates,
        beta_max=recommendation.beta_max,
        beta_limit=limit_beta,
        beta_limit_source=limit_source,
        beta_limit_uncertainty=uncertainty,
        uplift_limit=limit,
        highest_static_force=highest,
        lowest_static_force_checked=float(data["static_force"].values.min()),
        some_presag_keeps_uplift=feasible,
        not_checked=("the dynamic robust design and its dynamic tolerance (presag robust --dynamic)",)
        + (() if result.beta_limit is not None else (f"the validity limit: {validity.text()}",)),
    ))


def _stitch_notes(catenaries) -> tuple[Assumption, ...]:
    """One entry per stitched model: what its stitch wire is and that the paper's limit is for simple catenaries."""
    return tuple(
        Assumption(name=f"stitch wires ({c.name})", value=stitch_summary(c),
                   why="the paper's rule and its validity limit β = 0.4 were shown for simple catenaries; this "
                       "report's numbers are this model's own (see docs/stitched.md for the stitched validity study)")
        for c in catenaries if c.stitch_wire is not None
    )


def _reference_span(catenary) -> float:
    """The span length pre-sag is quoted on: the spans of an ideal section, else the case study's 60 m. [m]"""
    lengths = set(catenary.layout.span_lengths)
    return lengths.pop() if len(lengths) == 1 else CASE_STUDY_SPAN_LENGTH


def _sweep_grid(catenary, band: OperatingBand, recommendation: Recommendation, quick: bool) -> dict:
    """Pre-sags around the recommendation, speeds from the band's top to β = 0.5, the band's forces."""
    c_kmh = catenary.contact_wire.wave_speed / KMH
    top = band.speed_high / KMH
    speeds = sorted({round(top)} | {10 * round(b * c_kmh / 10) for b in SWEEP_BETAS})
    speeds = [v for v in speeds if 0 < v < 0.9 * c_kmh]
    presag = recommendation.presag_rel * max(catenary.layout.span_lengths)
    factors = SWEEP_PRESAG_FACTORS
    forces = [band.static_force_low, 0.5 * (band.static_force_low + band.static_force_high), band.static_force_high]
    if quick:
        speeds, factors, forces = [round(top), speeds[-1]], (factors[0], factors[-1]), [forces[0], forces[-1]]
    return {
        "presags": tuple(round(f * presag, 3) for f in factors),
        "speeds": tuple(v * KMH for v in sorted(set(speeds))),
        "static_forces": tuple(sorted(set(forces))),
    }


def _assumptions(band: OperatingBand, numerics: dict, within: float, sweep: str | None,
                 quick: bool) -> tuple[Assumption, ...]:
    out = [
        Assumption(name="aerodynamic uplift coefficient α_ae", value=f"{band.aero_coefficient * KMH**2:g} N/(km/h)²",
                   why="part of the operating band as given; the case study's value turns F_stat 70–140 N at up "
                       "to 90 km/h into the paper's F_m band 70–148 N"),
        Assumption(name="quasi-static rule", value="Δe = e_max − e_min",
                   why="the variant behind the paper's case-study recommendation"),
        Assumption(name="recommended pre-sag", value="mean of the layouts' S_rel range ends",
                   why="the paper's 'mean value' of the ideal and mixed ranges"),
        Assumption(name="spans sized in a mixed section", value="all but the two end spans",
                   why="the end spans' outer support is the termination, not a steady arm"),
        Assumption(name="tolerance band loss", value=f"{within * 100:g} %",
                   why="worst-case waviness over the F_m band may exceed the robust optimum by this share"),
        Assumption(name="force scenarios of the robust design", value="17 equally likely F_m over the band",
                   why="the band is sampled evenly; the minimax design depends only on its ends in practice"),
        Assumption(name="static numerics", value=f"{numerics['element_length']:g} m elements, "
                   f"{numerics['step']:g} m between elasticity points",
                   why="the paper's 0.5 m" if not quick else "coarse: a draft report (--quick)"),
        Assumption(name="validity criterion", value="β where the Δe rule leaves the band of S within 5 % of the "
                   "σ optimum", why="see the study's criterion text; the paper puts the limit at β = 0.4"),
    ]
    if sweep is not None:
        out.append(Assumption(name="reduced validity sweep", value=sweep,
                              why="five central spans with one lead-in span; a full study (presag sweep) gives the "
                                  "numbers to quote"))
    return tuple(out)
