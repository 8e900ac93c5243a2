"""Many operating points on one form-found catenary: the batch entry point of the simulator.

:func:`simulate_many` runs a list of :class:`OperatingPoint` (speed, static force, aerodynamic
coefficient) under one :class:`~presag_opt.static.equilibrium.EquilibriumState` and returns one
:class:`RunOutcome` per point, in the order given. The runs share what does not depend on the
operating point: the structural model, the banded factorisation of the effective matrix for the
shared time step, and the columns of its inverse at every DOF a nonlinear force can act on. The
time stepping is compiled (:mod:`presag_opt.dynamics.kernel`) and advances all runs of a batch
together, the batch index innermost.

Each run is what :func:`~presag_opt.dynamics.simulate.simulate` computes for the same point, with
the same model, start, duration, Newton iteration and statistics (the tests hold the two paths
together); :func:`simulate` stays the plain reference. A run's result does not depend on the other
runs of its batch; a run that fails (Newton iteration not converging) is reported with its reason
and the others finish unaffected. Only what the statistics need is recorded: the contact force of
every pantograph, the largest steady-arm uplift and the most slack droppers at once.
"""

from __future__ import annotations

import time as wallclock
from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np

from presag_opt.dynamics import batch_newton
from presag_opt.dynamics.batch_system import BatchRecords, BatchSystem, integrate_batch
from presag_opt.dynamics.pantograph import Pantograph
from presag_opt.dynamics.run_plan import RunPlan, plan_run, route, run_warnings
from presag_opt.dynamics.settings import OperatingPoint, SimulationSettings
from presag_opt.dynamics.statistics import (
    ContactForceStatistics,
    contact_force_statistics,
)
from presag_opt.dynamics.structure import structural_model
from presag_opt.errors import ConvergenceError, ModelError
from presag_opt.static.equilibrium import EquilibriumState

BATCH_SIZE = 16
"""Runs advanced together by the compiled kernel: enough to vectorise across runs and to hide the
latency of the banded substitutions, few enough that the working arrays (about 14 × n_dofs doubles
per run) stay close to the processor. [-]"""


@dataclass(frozen=True, kw_only=True)
class RunOutcome:
    """Result of one run of a batch: its statistics, or the reason it failed.

    Attributes
    ----------
    point : OperatingPoint
        The operating point.
    statistics : tuple of ContactForceStatistics
        Contact-force statistics of each pantograph, front to rear; empty if the run failed.
    uplift_max : float
        Largest contact-wire uplift at a steady arm / support of the analysed section; NaN if the
        run failed. [m]
    slack_droppers_max : int
        Most droppers of the analysed section slack at the same time. [-]
    speed_ratio : float
        β = v / c. [-]
    doppler_factor : float
        (c − v)/(c + v). [-]
    wave_speed : float
        Contact-wire wave speed. [m/s]
    analysed_spans : tuple of int
        Spans (from 0) of the analysed section. [-]
    analysed_section : tuple of float
        Stations where the analysed section starts and ends. [m]
    newton_iterations : int
        Newton corrections over the whole run. [-]
    wall_time : float
        The run's share of the wall-clock time of the kernel call it ran in (that call's time
        divided by its runs). [s]
    time_step : float
        The run's time step. [s]
    warnings : tuple of str
        One line per numerical setting that under-resolves the run.
    error : str or None
        Why the run failed (one line), None if it finished.
    time : ndarray or None
        Record times, kept with ``keep_histories``. [s]
    contact_force : ndarray or None
        Raw contact force of each pantograph, shape (n_times, n_pantographs), kept with
        ``keep_histories``. [N]
    """

    point: OperatingPoint
    statistics: tuple[ContactForceStatistics, ...]
    uplift_max: float
    slack_droppers_max: int
    speed_ratio: float
    doppler_factor: float
    wave_speed: float
    analysed_spans: tuple[int, ...]
    analysed_section: tuple[float, float]
    newton_iterations: int
    wall_time: float
    time_step: float
    warnings: tuple[str, ...] = ()
    error: str | None = None
    time: np.ndarray | None = None
    contact_force: np.ndarray | None = None

    @property
    def ok(self) -> bool:
        """Whether the run finished."""
        return self.error is None

    def to_dict(self, *, catenary: str, pantograph: str) -> dict:
        """Headline numbers with units in the key names: the keys of the single-run ``--json`` output.

        Parameters
        ----------
        catenary : str
            Catenary name.
        pantograph : str
            Name of the leading pantograph.
        """
        p = self.point
        out = {
            "catenary": catenary,
            "pantograph": pantograph,
            "speed_kmh": p.speed * 3.6,
            "static_force_N": p.static_force,
            "aero_force_N": p.aero_coefficient * p.speed**2,
        }
        if self.ok:
            out.update(self.statistics[0].to_dict())
            out["uplift_max_mm"] = self.uplift_max * 1e3
        out.update({
            "beta": self.speed_ratio,
            "doppler_factor": self.doppler_factor,
            "wave_speed_kmh": self.wave_speed * 3.6,
            "analysed_spans": [s + 1 for s in self.analysed_spans],
            "analysed_section_m": list(self.analysed_section),
        })
        if self.ok:
            out["slack_droppers_max"] = self.slack_droppers_max
        out["time_step_ms"] = self.time_step * 1e3
        out["wall_time_s"] = self.wall_time
        out["warnings"] = list(self.warnings)
        if not self.ok:
            out["error"] = self.error
        elif len(self.statistics) > 1:
            out["pantographs"] = [s.to_dict() for s in self.statistics]
        return out


@dataclass(frozen=True, kw_only=True)
class BatchResult:
    """Result of :func:`simulate_many`.

    Attributes
    ----------
    catenary_name : str
        Name of the catenary.
    pantograph_names : tuple of str
        Pantograph models, front to rear.
    runs : tuple of RunOutcome
        One per operating point, in the order given.
    wall_time : float
        Wall-clock time of the whole batch. [s]
    settings : SimulationSettings
        Settings used.
    """

    catenary_name: str
    pantograph_names: tuple[str, ...]
    runs: tuple[RunOutcome, ...]
    wall_time: float
    settings: SimulationSettings

    def to_dict(self) -> dict:
        """All runs as the ``--json`` output of ``presag simulate`` with several operating points."""
        keys = dict(catenary=self.catenary_name, pantograph=self.pantograph_names[0])
        return {
            "catenary": self.catenary_name,
            "pantographs": list(self.pantograph_names),
            "wall_time_s": self.wall_time,
            "failed_runs": len(self.failed),
            "runs": [r.to_dict(**keys) for r in self.runs],
        }

    @property
    def failed(self) -> tuple[RunOutcome, ...]:
        """The runs that did not finish."""
        return tuple(r for r in self.runs if not r.ok)


def simulate_many(
    state: EquilibriumState,
    pantograph: Pantograph | Sequence[Pantograph],
    points: Sequence[OperatingPoint],
    *,
    spacings: Sequence[float] | None = None,
    settings: SimulationSettings | None = None,
    keep_histories: bool = False,
    progress: Callable[[str], None] | None = None,
) -> BatchResult:
    """Run many operating points on one form-found catenary.

    Parameters
    ----------
    state : EquilibriumState
        The form-found catenary shared by all runs.
    pantograph : Pantograph or sequence of Pantograph
        As in :func:`~presag_opt.dynamics.simulate.simulate`.
    points : sequence of OperatingPoint
        The operating points; at least one.
    spacings : sequence of float, optional
        Distances between consecutive pantographs, front to rear, for every run. [m]
    settings : SimulationSettings, optional
        Numerical settings and analysis window shared by all runs (``integrator.method`` is not
        used: the batch has its own solver).
    keep_histories : bool
        Keep each run's record times and raw contact forces.
    progress : callable, optional
        Called with a short message (``"32/96 runs"``) as each group of runs finishes.

    Returns
    -------
    BatchResult
        One outcome per point, in order.

    Raises
    ------
    ModelError
        Before any run starts: an empty list of points, or a point that :func:`plan_run` refuses
        (speed at or above the wave speed, a time step too large for the contact stiffness, a
        section too short). The message names the point.
    """
    started = wallclock.perf_counter()
    settings = settings or SimulationSettings()
    points = list(points)
    if not points:
        raise ModelError("operating points: the list is empty; give at least one (speed, static force)")
    plans = [_plan(state, pantograph, p, spacings, settings) for p in points]
    model = structural_model(state, settings=settings.structure)
    outcomes: list[RunOutcome | None] = [None] * len(points)
    # Runs that share a time step share a system (with automatic numerics the step follows the speed).
    steps = sorted({p.settings.integrator.time_step for p in plans}, reverse=True)
    for time_step in steps:
        group = [i for i, p in enumerate(plans) if p.settings.integrator.time_step == time_step]
        group_settings = plans[group[0]].settings
        system = BatchSystem.build(model, plans[group[0]].pantographs, group_settings)
        group.sort(key=lambda i: -plans[i].step_count(time_step))
        for first in range(0, len(group), BATCH_SIZE):
            members = group[first : first + BATCH_SIZE]
            batch_started = wallclock.perf_counter()
            records = integrate_batch(state, system, [plans[i] for i in members], group_settings)
            share = (wallclock.perf_counter() - batch_started) / len(members)
            for b, i in enumerate(members):
                outcomes[i] = _outcome(state, points[i], plans[i], b, records, keep_histories, share)
            if progress is not None:
                progress(f"{sum(o is not None for o in outcomes)}/{len(points)} runs")
    return BatchResult(
        catenary_name=route(state)[0],
        pantograph_names=tuple(p.name for p in plans[0].pantographs),
        runs=tuple(outcomes),
        wall_time=wallclock.perf_counter() - started,
        settings=settings,
    )


def _plan(
    state: EquilibriumState,
    pantograph: Pantograph | Sequence[Pantograph],
    point: OperatingPoint,
    spacings: Sequence[float] | None,
    settings: SimulationSettings,
) -> RunPlan:
    try:
        return plan_run(
            state, pantograph, speed=point.speed, static_force=point.static_force,
            aero_coefficient=point.aero_coefficient, spacings=spacings, settings=settings,
        )
    except ModelError as exc:
        raise ModelError(
            f"operating point {point.speed * 3.6:g} km/h, {point.static_force:g} N: {exc}"
        ) from None


def _outcome(
    state: EquilibriumState, point: OperatingPoint, plan: RunPlan, b: int, records: BatchRecords,
    keep_histories: bool, wall_time: float,
) -> RunOutcome:
    """Run ``b`` of a batch's records as an outcome: its statistics, or why it stopped."""
    settings = plan.settings
    dt = settings.integrator.time_step
    common = dict(point=point, speed_ratio=plan.speed_ratio, doppler_factor=plan.doppler_factor,
                  wave_speed=plan.wave_speed, analysed_spans=plan.analysed_spans,
                  analysed_section=plan.analysed_section, newton_iterations=int(records.iterations[b]),
                  wall_time=wall_time, time_step=dt, warnings=run_warnings(state, plan))
    failed = dict(statistics=(), uplift_max=float("nan"), slack_droppers_max=0, **common)
    if records.status[b] != batch_newton.STATUS_OK:
        step = int(records.fail_step[b])
        what = ("a non-finite residual" if records.status[b] == batch_newton.STATUS_NOT_FINITE else
                f"residual {records.fail_residual[b]:.3g} N after {settings.integrator.max_iterations} corrections")
        return RunOutcome(error=f"Newton iteration did not converge in step {step} (t = {step * dt:.6g} s): {what}",
                          **failed)
    n_steps = int(records.n_steps[b])
    time = dt * np.arange(n_steps + 1)
    forces = records.contact_force[b, :, : n_steps + 1].T.copy()
    try:
        statistics = tuple(
            contact_force_statistics(time, forces[:, i], window_start=plan.window(i)[0],
                                     window_end=plan.window(i)[1], cutoff=settings.cutoff_frequency)
            for i in range(len(plan.pantographs))
        )
    except (ModelError, ConvergenceError) as exc:
        return RunOutcome(error=str(exc).splitlines()[0], **failed)
    return RunOutcome(
        statistics=statistics,
        uplift_max=float(records.uplift_max[b]),
        slack_droppers_max=int(records.slack_max[b]),
        time=time if keep_histories else None,
        contact_force=forces if keep_histories else None,
        **common,
    )
