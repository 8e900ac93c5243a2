"""The decision for an operating band: every method that answers "which pre-sag?", gathered once.

:func:`answer_band` is what ``presag recommend``, ``presag robust`` (with or without ``--dynamic``)
and ``presag report`` run: the quasi-static Δe rule over the band for every model
(:func:`~presag_opt.design.recommendation.recommend`), the quasi-static robust design of the first
model with its tolerance (:func:`~presag_opt.robust.study.robust_study`, its nominal design the same
Δe number), and on request a validity sweep (a stored study, or a reduced sweep run here), the dynamic
robust design by simulation (:func:`~presag_opt.robust.dynamic_study.dynamic_robust_study`, started
from the same quasi-static study) and the crew's build tolerance by Monte Carlo of per-dropper errors
(:func:`~presag_opt.robust.monte_carlo.installation_tolerance`). Each method returns its record; the
records go into one :class:`~presag_opt.design.evidence.Evidence` and
:func:`~presag_opt.design.decision.decide` runs once.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path

from presag_opt.design.band import CASE_STUDY_BAND, OperatingBand
from presag_opt.design.decision import Decision, decide
from presag_opt.design.evidence import Evidence, check_uplift_limit, crew_tolerance
from presag_opt.design.recommendation import CASE_STUDY_MODELS, CASE_STUDY_SPAN_LENGTH, Recommendation, recommend
from presag_opt.design.speed_range import STEADY_ARM_UPLIFT_LIMIT, highest_static_force_static
from presag_opt.display import data_frame, html_summary
from presag_opt.dynamics.pantograph import Pantograph, load_pantograph
from presag_opt.dynamics.settings import SimulationSettings
from presag_opt.errors import ModelError
from presag_opt.pipeline.validity import ValidityRange, reduced_sweep, stored_sweep
from presag_opt.robust.buildability import Buildability
from presag_opt.robust.dynamic_design import DynamicObjective
from presag_opt.robust.dynamic_study import DynamicRobustStudy, dynamic_robust_study, simulated_band
from presag_opt.robust.installation import InstallationErrors
from presag_opt.robust.monte_carlo import MonteCarloResult, QuasiStaticMonteCarlo, installation_tolerance
from presag_opt.robust.operating_grid import OperatingGrid
from presag_opt.robust.scenarios import ForceScenarios, Risk
from presag_opt.robust.study import RobustStudy, robust_study
from presag_opt.robust.tolerance import check_within
from presag_opt.static.discretisation import StaticSettings
from presag_opt.system.catenary import Catenary
from presag_opt.system.loader import load_catenary

CASE_STUDY_PANTOGRAPH = "case_study_2mass_friction"
"""Pantograph of the case study's dynamic runs (dynamic robust design, validity sweep)."""

JOB_OPTIONS = {"validity_sweep": "study=STORE, a study written by presag sweep",
               "dynamic_robust": "dynamic_robust=True, or the job dynamic_robust_design",
               "dynamic_check": "design_line(..., dynamic_check=True)",
               "installation_monte_carlo": "dropper_error_mm=MM"}
"""The keyword of the Python jobs (:mod:`presag_opt.jobs`) that supplies each kind of evidence a decision
can miss, as a notebook shows it."""

SWEEPS = ("reduced", "quick")
"""Reduced sweeps a decision can run for itself: a few pre-sags × speeds × forces, or two of each."""


@dataclass(frozen=True, kw_only=True)
class StaticNumerics:
    """Numerics of the quasi-static methods (shared by the Δe rule and the robust design).

    Attributes
    ----------
    element_length : float
        Longest element of the static model. [m]
    step : float
        Point spacing of the elasticity curves. [m]
    elasticity_method : {"active-set", "newton"}
        Method of the nonlinear elasticity.
    force_levels : tuple of float or None
        Elasticity force levels (default: 50 N steps bracketing the F_m band). [N]
    """

    element_length: float = 0.5
    step: float = 0.5
    elasticity_method: str = "active-set"
    force_levels: tuple[float, ...] | None = None

    @property
    def settings(self) -> StaticSettings:
        """The static model's settings."""
        return StaticSettings(element_length=self.element_length)


@dataclass(frozen=True, kw_only=True)
class DynamicOptions:
    """How the dynamic robust design of a band is run.

    Attributes
    ----------
    pantograph : str, Path or Pantograph
        Pantograph model (name, file or object).
    objective : str
        Loss at each operating point: ``sigma-over-fm`` or ``sigma``.
    risk : Risk or None
        Risk measure over the grid (default: worst case).
    static_points, speed_points : int
        Grid points along each axis of the band. [-]
    workers : int
        Processes that simulate pre-sags side by side. [-]
    settings : SimulationSettings or None
        Numerical settings of the runs (default: automatic numerics).
    """

    pantograph: str | Path | Pantograph = CASE_STUDY_PANTOGRAPH
    objective: str = "sigma-over-fm"
    risk: Risk | None = None
    static_points: int = 4
    speed_points: int = 3
    workers: int = 2
    settings: SimulationSettings | None = None


@dataclass(frozen=True, kw_only=True)
class BandAnswer:
    """Everything computed for a band, and the one decision made from it.

    Attributes
    ----------
    models : tuple of str
        The catenary models (names as given).
    band : OperatingBand
        Static forces, speeds and α_ae. [N], [m/s]
    recommendation : Recommendation
        The quasi-static Δe rule over the band, every model.
    robust : RobustStudy
        The quasi-static robust design of the first model.
    validity : ValidityRange or None
        The validity sweep, if one was read or run.
    dynamic : DynamicRobustStudy or None
        The dynamic robust design of the first model, if run.
    monte_carlo : MonteCarloResult or None
        The quasi-static Monte Carlo of the installation errors, if run (the crew tolerance then
        comes from it).
    decision : Decision
        What to build, and why.
    """

    models: tuple[str, ...]
    band: OperatingBand
    recommendation: Recommendation
    robust: RobustStudy
    validity: ValidityRange | None
    dynamic: DynamicRobustStudy | None
    monte_carlo: MonteCarloResult | None
    decision: Decision

    def table(self, name: str = "answers") -> list[dict]:
        """A table as rows: ``answers`` (every method's S, uplift and margin: the decision's table) or
        ``layouts`` (the Δe rule per layout: S_rel range, S range on the reference span, static uplift).

        Parameters
        ----------
        name : {"answers", "layouts"}
            The table.
        """
        if name == "answers":
            return self.decision.table()
        if name != "layouts":
            raise ModelError(f"table = {name!r} is not one of answers, layouts")
        span = self.decision.reference_span
        return [{"layout": lay.layout_kind, "system": lay.catenary_name, "spans": len(lay.section.spans),
                 "S_rel low [‰]": lay.presag_rel_range[0] * 1e3, "S_rel high [‰]": lay.presag_rel_range[1] * 1e3,
                 f"S low on {span:g} m [mm]": lay.presag_rel_range[0] * span * 1e3,
                 f"S high on {span:g} m [mm]": lay.presag_rel_range[1] * span * 1e3,
                 "static uplift [mm]": lay.steady_arm_uplift.uplift * 1e3}
                for lay in self.recommendation.layouts]

    def to_frame(self, name: str = "answers"):
        """:meth:`table` as a pandas DataFrame.

        Parameters
        ----------
        name : {"answers", "layouts"}
            The table.
        """
        return data_frame(self.table(name))

    def _repr_html_(self) -> str:
        return html_summary(self.decision.headline(), self.decision.lines(JOB_OPTIONS)[1:], self.table())


def reference_span(catenary: Catenary) -> float:
    """The span length a band's pre-sag is quoted on: the spans of an ideal section, else the case
    study's 60 m. [m]

    Parameters
    ----------
    catenary : Catenary
        The first model of the band.
    """
    lengths = set(catenary.layout.span_lengths)
    return lengths.pop() if len(lengths) == 1 else CASE_STUDY_SPAN_LENGTH


def answer_band(
    models: Sequence[str | Path | Catenary] = CASE_STUDY_MODELS,
    band: OperatingBand = CASE_STUDY_BAND,
    *,
    method: str = "delta-e",
    numerics: StaticNumerics | None = None,
    within: float = 0.10,
    shape: str = "parabola",
    risk: Risk | None = None,
    buildability: Buildability | None = None,
    recompute: bool = False,
    uplift_limit: float = STEADY_ARM_UPLIFT_LIMIT,
    crew: float | None = None,
    installation_errors: InstallationErrors | None = None,
    study: str | Path | None = None,
    sweep: str | None = None,
    sweep_numerics: tuple[float, float] = (1.0, 4e-3),
    dynamic: DynamicOptions | None = None,
    span_length: float | None = None,
    progress: Callable[[str], None] | None = None,
) -> BandAnswer:
    """Gather every method's answer for a band and decide once (see the module docstring).

    Parameters
    ----------
    models : sequence of str, Path or Catenary
        Catenary models (built-in names, files or catenaries); the first is also the one of the
        robust designs and of a sweep.
    band : OperatingBand
        Static forces, speeds and α_ae. [N], [m/s]
    method : {"delta-e", "mid-mast"}
        Variant of the quasi-static rule.
    numerics : StaticNumerics, optional
        Numerics of the quasi-static methods.
    within : float
        Allowed loss of the tolerance intervals (quasi-static and dynamic). [-]
    shape : {"parabola", "per-dropper"}
        Shape of the quasi-static robust design (its tolerance is that of the parabola).
    risk : Risk, optional
        Risk measure of the quasi-static robust design (default minimax).
    buildability : Buildability, optional
        Construction limits of a per-dropper design.
    recompute : bool
        Also recompute the Δe rule at its own pre-sag geometry.
    uplift_limit : float
        Largest allowed steady-arm uplift. [m]
    crew : float, optional
        The crew's build tolerance of the mid-span pre-sag (default: the assumed one). [m]
    installation_errors : InstallationErrors, optional
        Per-dropper and per-mast error sizes: the crew tolerance is then the Monte Carlo's P95. [m]
    study : str or Path, optional
        A stored validity study (``presag sweep``) to read.
    sweep : {"reduced", "quick"}, optional
        Run a reduced sweep here instead (not with ``study``).
    sweep_numerics : (float, float)
        Element length [m] and time step [s] of a reduced sweep.
    dynamic : DynamicOptions, optional
        Run the dynamic robust design of the first model (default: not run).
    span_length : float, optional
        Span length pre-sags are quoted on in mm (default :func:`reference_span` of the first model). [m]
    progress : callable, optional
        Called with a short message before each expensive step.

    Raises
    ------
    ModelError
        Bad input, before any work where it can be seen then.
    """
    if sweep is not None and sweep not in SWEEPS:
        raise ModelError(f"sweep = {sweep!r} is not one of {', '.join(SWEEPS)}")
    if sweep is not None and study is not None:
        raise ModelError("give a stored study or a reduced sweep, not both")
    if crew is not None and installation_errors is not None:
        raise ModelError("give the crew tolerance or the installation errors to derive it from, not both")
    check_within(within)
    check_uplift_limit(uplift_limit)
    numerics = numerics or StaticNumerics()
    names = tuple(m.name if isinstance(m, Catenary) else str(m) for m in models)
    catenaries = [m if isinstance(m, Catenary) else load_catenary(m) for m in models]
    if not catenaries:
        raise ModelError("models is empty; give at least one catenary model")
    first = catenaries[0]
    installation = crew_tolerance(crew)  # a bad crew tolerance fails here, before any work
    objective = None
    pantograph = None
    if dynamic is not None:
        objective = DynamicObjective(loss=dynamic.objective, risk=dynamic.risk or Risk(), uplift_limit=uplift_limit)
        pantograph = (dynamic.pantograph if isinstance(dynamic.pantograph, Pantograph)
                      else load_pantograph(dynamic.pantograph))
        # the simulated grid refused before any work (an empty band, a speed the simulator cannot run)
        OperatingGrid.from_band(simulated_band(band), static_points=dynamic.static_points,
                                speed_points=dynamic.speed_points)
    span = reference_span(first) if span_length is None else span_length
    # a stored study is read before any form-finding: a missing or foreign store fails at once
    validity = None if study is None else stored_sweep(study, band, first.contact_wire.wave_speed)
    recommendation = recommend(models=catenaries, band=band, method=method, force_levels=numerics.force_levels,
                               step=numerics.step, elasticity_method=numerics.elasticity_method,
                               nominal_span_length=span, recompute_at_recommended=recompute,
                               settings=numerics.settings, progress=progress)
    delta_e = recommendation.evidence()
    robust = robust_study(first, recommendation.mean_force_band, shape=shape, risk=risk, buildability=buildability,
                          within=within, settings=numerics.settings, nominal_presag_rel=delta_e.presag_rel,
                          progress=progress)
    if sweep is not None:
        validity = reduced_sweep(first, load_pantograph(CASE_STUDY_PANTOGRAPH) if pantograph is None else pantograph,
                                 band, delta_e.presag_rel, quick=sweep == "quick", element_length=sweep_numerics[0],
                                 time_step=sweep_numerics[1], progress=progress)
    monte_carlo = None
    if installation_errors is not None:
        if progress:
            progress("installation errors: linearised response and Monte Carlo")
        mc = QuasiStaticMonteCarlo(robust.path, robust.path.parabola_depths(robust.robust_parabola.presag_rel),
                                   ForceScenarios.band(*recommendation.mean_force_band))
        monte_carlo = mc.run(installation_errors)
        installation = installation_tolerance(mc, installation_errors)
    study_dynamic = None
    if dynamic is not None:
        study_dynamic = dynamic_robust_study(first, pantograph, simulated_band(band), objective=objective, within=within,
                                             static_points=dynamic.static_points, speed_points=dynamic.speed_points,
                                             settings=dynamic.settings, workers=dynamic.workers, quasi=robust,
                                             progress=progress)
    evidence = Evidence(
        wave_speed=min(c.contact_wire.wave_speed for c in catenaries), speed_high=band.speed_high,
        uplift_limit=uplift_limit, reference_span=span, static_force_floor=band.static_force_low,
        static_force_estimate=highest_static_force_static(delta_e.support_elasticity, uplift_limit,
                                                          band.aero_coefficient, band.speed_high),
        delta_e=delta_e, quasi_static_robust=robust.evidence(),
        validity_sweep=None if validity is None else validity.record,
        dynamic_robust=None if study_dynamic is None else study_dynamic.evidence(),
        installation=installation,
    )
    return BandAnswer(models=names, band=band, recommendation=recommendation, robust=robust, validity=validity,
                      dynamic=study_dynamic, monte_carlo=monte_carlo, decision=decide(evidence))

