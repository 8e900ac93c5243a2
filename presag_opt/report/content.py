"""What a design report says about a line: every number of it, computed once.

:func:`design_report` runs the band's decision pipeline (:func:`presag_opt.pipeline.band.answer_band`:
the Δe rule over the band, the robust design with its tolerance, a validity sweep — a stored study,
or a reduced sweep run for the report — and on request the dynamic robust design) and collects the
inputs with their provenance and every assumed value. Writing it as HTML is
:mod:`presag_opt.report.html`; the decision heading it is the one every command prints for the band.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path

from presag_opt.design.band import CASE_STUDY_BAND, KMH, OperatingBand
from presag_opt.design.recommendation import CASE_STUDY_MODELS
from presag_opt.design.speed_range import STEADY_ARM_UPLIFT_LIMIT
from presag_opt.errors import ModelError
from presag_opt.pipeline.band import CASE_STUDY_PANTOGRAPH, BandAnswer, DynamicOptions, StaticNumerics, answer_band
from presag_opt.robust.installation import InstallationErrors
from presag_opt.system.loader import ModelEntry, load_catenary, model_entries, resolve_model_path
from presag_opt.system.stitch import stitch_summary

QUICK_SWEEP = {"element_length": 1.0, "time_step": 4e-3}
"""Numerics of a report's reduced sweep (coarse: its β* is indicative): element length [m], time step [s]."""

REPORT_OPTIONS = {"validity_sweep": "--study STORE, a full study written by presag sweep",
                  "dynamic_robust": "--dynamic-robust", "installation_monte_carlo": "--dropper-error MM"}
"""The options of ``presag report`` that supply each kind of evidence a report can miss (named in its
decision's "not checked")."""

STATIC_NUMERICS = {"element_length": 0.5, "step": 0.5}
"""Numerics of the report's quasi-static parts, those of every command that decides for a band: the
paper's 0.5 m elements, 0.5 m between elasticity points."""


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
class DesignReport:
    """Everything a design report shows.

    Attributes
    ----------
    answer : BandAnswer
        The band's methods and the decision made from them.
    pantograph : str
        Pantograph model of the dynamic runs.
    inputs : tuple of ModelEntry
        Every number of the model files, with provenance.
    assumptions : tuple of Assumption
        The report's own choices (numerics, loss of the tolerance band, sweep grid).
    quick : bool
        A quick sweep (two pre-sags × speeds × forces): a draft.
    """

    answer: BandAnswer
    pantograph: str
    inputs: tuple[ModelEntry, ...]
    assumptions: tuple[Assumption, ...]
    quick: bool

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
    uplift_limit: float = STEADY_ARM_UPLIFT_LIMIT,
    crew: float | None = None,
    installation_errors: InstallationErrors | None = None,
    dynamic: DynamicOptions | None = None,
    element_length: float = STATIC_NUMERICS["element_length"],
    progress: Callable[[str], None] | None = None,
) -> DesignReport:
    """Compute a design report for a line (default: the paper's case study).

    Parameters
    ----------
    models : sequence of str or Path
        Catenary model files or built-in names; the first is also the one of the robust design and
        of the validity sweep (give the ideal-span model first).
    band : OperatingBand
        Static forces, speeds and α_ae of the line.
    pantograph : str or Path
        Pantograph model of the dynamic runs.
    study : str or Path, optional
        A stored study (``presag sweep``) to read the validity range from; default: a reduced sweep
        run here (a few pre-sags, speeds and static forces on five spans).
    within : float
        Loss of the tolerance intervals. [-]
    quick : bool
        A quick reduced sweep (two pre-sags, speeds and static forces): a draft in seconds.
    uplift_limit : float
        Largest allowed steady-arm uplift. [m]
    crew : float, optional
        The crew's build tolerance of the mid-span pre-sag (default: the assumed one). [m]
    installation_errors : InstallationErrors, optional
        Per-dropper and per-mast errors to derive the crew tolerance from by Monte Carlo. [m]
    dynamic : DynamicOptions, optional
        Also run the dynamic robust design of the first model.
    element_length : float
        Longest element of the static model. [m]
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
    catenaries = [load_catenary(m) for m in models]
    if dynamic is not None:
        from dataclasses import replace

        dynamic = replace(dynamic, pantograph=pantograph)
    answer = answer_band(
        catenaries, band, within=within, uplift_limit=uplift_limit, crew=crew,
        installation_errors=installation_errors, study=study, sweep=None if study is not None else
        ("quick" if quick else "reduced"), sweep_numerics=(QUICK_SWEEP["element_length"], QUICK_SWEEP["time_step"]),
        dynamic=dynamic, numerics=StaticNumerics(element_length=element_length, step=STATIC_NUMERICS["step"]),
        progress=progress)
    inputs = tuple(e for m in models for e in model_entries(m)) + model_entries(pantograph, "pantographs")
    sweep = None if answer.validity is None or study is not None else answer.validity.source
    return DesignReport(
        answer=answer, pantograph=resolve_model_path(pantograph, "pantographs").stem, inputs=inputs,
        assumptions=_assumptions(band, within, sweep, quick, answer) + _stitch_notes(catenaries), quick=quick,
    )


def _stitch_notes(catenaries) -> tuple[Assumption, ...]:
    """One entry per stitched model: what its stitch wire is and that the paper's limit is for simple catenaries."""
    return tuple(
        Assumption(name=f"stitch wires ({c.name})", value=stitch_summary(c),
                   why="the paper's rule and its validity limit β = 0.4 were shown for simple catenaries; this "
                       "report's numbers are this model's own (see docs/stitched.md for the stitched validity study)")
        for c in catenaries if c.stitch_wire is not None
    )


def _assumptions(band: OperatingBand, within: float, sweep: str | None, quick: bool,
                 answer: BandAnswer) -> tuple[Assumption, ...]:
    crew = answer.decision.evidence.installation
    out = [
        Assumption(name="aerodynamic uplift coefficient α_ae", value=f"{band.aero_coefficient * KMH**2:g} N/(km/h)²",
                   why="part of the operating band as given; the case study's value turns F_stat 70–140 N at up "
                       "to 90 km/h into the paper's F_m band 70–148 N"),
        Assumption(name="quasi-static rule", value="Δe = e_max − e_min",
                   why="the variant behind the paper's case-study recommendation"),
        Assumption(name="Δe rule's pre-sag", value="mean of the layouts' S_rel range ends",
                   why="the paper's 'mean value' of the ideal and mixed ranges"),
        Assumption(name="spans sized in a mixed section", value="all but the two end spans",
                   why="the end spans' outer support is the termination, not a steady arm"),
        Assumption(name="tolerance interval loss", value=f"{within * 100:g} %",
                   why="the worst case over the band may exceed its optimum by this share inside a tolerance interval"),
        Assumption(name="crew's build tolerance", value=f"±{crew.half_width * 1e3:.1f} mm on the mid-span pre-sag",
                   why=crew.source),
        Assumption(name="force scenarios of the robust design", value="17 equally likely F_m over the band",
                   why="the band is sampled evenly; the minimax design depends only on its ends in practice"),
        Assumption(name="static numerics", value=f"{answer.robust.path.state.discretisation.settings.element_length:g} m elements, "
                   f"{STATIC_NUMERICS['step']:g} m between elasticity points",
                   why="the paper's 0.5 m; the same numerics as every command that decides for a band"),
        Assumption(name="validity criterion", value="β where the Δe rule leaves the band of S within 5 % of the "
                   "σ optimum", why="see the study's criterion text; the paper puts the limit at β = 0.4"),
    ]
    if sweep is not None:
        out.append(Assumption(name="reduced validity sweep", value=sweep,
                              why=f"{QUICK_SWEEP['element_length']:g} m elements and {QUICK_SWEEP['time_step'] * 1e3:g} "
                                  "ms on five central spans" + (", two points per axis (--quick)" if quick else "")
                                  + ": its β* may lower the paper's limit, not raise it; a full study (presag sweep) "
                                  "gives the numbers to quote"))
    return tuple(out)
