"""Many operating points on one form-found catenary: the batch entry point of the simulator.

:func:`simulate_many` runs a list of :class:`OperatingPoint` (speed, static force, aerodynamic
coefficient) under one :class:`~presag_opt.static.equilibrium.EquilibriumState` and returns one
:class:`RunOutcome` per point, in the order given. The runs share what does not depend on the
operating point: the structural model, the banded factorisation of the effective matrix for the
shared time step, and the columns of its inverse at every DOF a nonlinear force can act on. The
time stepping is compiled (:mod:`presag_opt.dynamics.batch.kernel`) and advances all runs of a batch
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

import numpy as np

from presag_opt.dynamics.batch.kernel_data import STATUS_NOT_FINITE, STATUS_OK, Records
from presag_opt.dynamics.batch.system import BatchSystem, StaticLine, integrate_batch
from presag_opt.dynamics.pantograph import Pantograph
from presag_opt.dynamics.results import BatchResult, RunOutcome
from presag_opt.dynamics.run_plan import RunPlan, plan_run, route, run_warnings
from presag_opt.dynamics.settings import OperatingPoint, SimulationSettings
from presag_opt.dynamics.statistics import (
    contact_force_statistics,
)
from presag_opt.dynamics.structure import structural_model
from presag_opt.errors import ConvergenceError, ModelError
from presag_opt.static.equilibrium import EquilibriumState
from presag_opt.units import KMH

BATCH_SIZE = 16
"""Runs advanced together by the compiled kernel: enough to vectorise across runs and to hide the
latency of the banded substitutions, few enough that the working arrays (about 14 × n_dofs doubles
per run) stay close to the processor. [-]"""


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
    return _simulate(state, None, pantograph, points, spacings, settings, keep_histories, progress)[0]


def simulate_installed(
    design: EquilibriumState,
    installed: Sequence[EquilibriumState],
    pantograph: Pantograph | Sequence[Pantograph],
    points: Sequence[OperatingPoint],
    *,
    spacings: Sequence[float] | None = None,
    settings: SimulationSettings | None = None,
    keep_histories: bool = False,
    progress: Callable[[str], None] | None = None,
) -> tuple[BatchResult, ...]:
    """Run every operating point on each of several installed lines of one design, together.

    The installed lines (the design built with installation errors and re-solved,
    :func:`~presag_opt.robust.realisation.installed_state`) share the design's structure: its
    stiffness, mass, damping, the factorised effective matrix, the influence columns and the dropper
    directions; each run brings its own line's static contact-wire heights and dropper preloads
    (:class:`~presag_opt.dynamics.batch.system.StaticLine`). The runs of all lines that share a time
    step fill the batches together, and the shared matrices are formed once. What the shared
    structure leaves out is the change of the tangent stiffness with the installation errors: a
    second-order effect for errors of millimetres (the tests bound it).

    Parameters
    ----------
    design : EquilibriumState
        The form-found design: the shared structure, and the route, sections and wave speed of every run.
    installed : sequence of EquilibriumState
        The installed lines: equilibria of the same discretisation as ``design``; at least one.
    pantograph : Pantograph or sequence of Pantograph
        As in :func:`~presag_opt.dynamics.simulate.simulate`.
    points : sequence of OperatingPoint
        The operating points, run on every line; at least one.
    spacings : sequence of float, optional
        Distances between consecutive pantographs, front to rear. [m]
    settings : SimulationSettings, optional
        Numerical settings and analysis window shared by all runs.
    keep_histories : bool
        Keep each run's record times and raw contact forces.
    progress : callable, optional
        Called with a short message (``"32/96 runs"``, the runs of all lines) as each group finishes.

    Returns
    -------
    tuple of BatchResult
        One per installed line, in order, each with one outcome per point.

    Raises
    ------
    ModelError
        As :func:`simulate_many`; and an empty list of lines or a line of another discretisation.
    """
    installed = list(installed)
    if not installed:
        raise ModelError("installed lines: the list is empty; give at least one")
    return _simulate(design, installed, pantograph, points, spacings, settings, keep_histories, progress)


def _simulate(
    state: EquilibriumState,
    installed: list[EquilibriumState] | None,
    pantograph: Pantograph | Sequence[Pantograph],
    points: Sequence[OperatingPoint],
    spacings: Sequence[float] | None,
    settings: SimulationSettings | None,
    keep_histories: bool,
    progress: Callable[[str], None] | None,
) -> tuple[BatchResult, ...]:
    """Every point on every line (the structure's own when ``installed`` is None), batched by time step."""
    started = wallclock.perf_counter()
    settings = settings or SimulationSettings()
    points = list(points)
    if not points:
        raise ModelError("operating points: the list is empty; give at least one (speed, static force)")
    plans = [_plan(state, pantograph, p, spacings, settings) for p in points]
    model = structural_model(state, settings=settings.structure)
    lines = [StaticLine.own(model)] if installed is None else [StaticLine.installed(model, s) for s in installed]
    outcomes: dict[tuple[int, int], RunOutcome] = {}
    total = len(lines) * len(points)
    # Runs that share a time step share a system (with automatic numerics the step follows the speed).
    steps = sorted({p.settings.integrator.time_step for p in plans}, reverse=True)
    for time_step in steps:
        group = [(line, i) for line in range(len(lines)) for i, p in enumerate(plans)
                 if p.settings.integrator.time_step == time_step]
        group_settings = plans[group[0][1]].settings
        system = BatchSystem.build(model, plans[group[0][1]].pantographs, group_settings)
        group.sort(key=lambda job: -plans[job[1]].step_count(time_step))
        for first in range(0, len(group), BATCH_SIZE):
            members = group[first : first + BATCH_SIZE]
            batch_started = wallclock.perf_counter()
            records = integrate_batch(state, system, [plans[i] for _, i in members], group_settings,
                                      [lines[line] for line, _ in members], progress)
            share = (wallclock.perf_counter() - batch_started) / len(members)
            for b, (line, i) in enumerate(members):
                outcomes[line, i] = _outcome(state, points[i], plans[i], b, records, keep_histories, share)
            if progress is not None:
                progress(f"{len(outcomes)}/{total} runs")
    wall_time = wallclock.perf_counter() - started
    return tuple(
        BatchResult(
            catenary_name=route(state)[0],
            pantograph_names=tuple(p.name for p in plans[0].pantographs),
            runs=tuple(outcomes[line, i] for i in range(len(points))),
            wall_time=wall_time,
            settings=settings,
        )
        for line in range(len(lines))
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
            f"operating point {point.speed / KMH:g} km/h, {point.static_force:g} N: {exc}"
        ) from None


def _outcome(
    state: EquilibriumState, point: OperatingPoint, plan: RunPlan, b: int, records: Records,
    keep_histories: bool, wall_time: float,
) -> RunOutcome:
    """Run ``b`` of a batch's records as an outcome: its statistics, or why it stopped."""
    settings = plan.settings
    dt = settings.integrator.time_step
    common = dict(point=point, speed_ratio=plan.speed_ratio, doppler_factor=plan.doppler_factor,
                  wave_speed=plan.wave_speed, analysed_spans=plan.analysed_spans,
                  analysed_section=plan.analysed_section, newton_iterations=int(records.iterations[b]),
                  wall_time=wall_time, time_step=dt, warnings=run_warnings(state, plan),
                  offsets=tuple(float(x) for x in plan.operation.offsets))
    failed = dict(statistics=(), uplift_max=float("nan"), slack_droppers_max=0, **common)
    if records.status[b] != STATUS_OK:
        step = int(records.fail_step[b])
        what = ("a non-finite residual" if records.status[b] == STATUS_NOT_FINITE else
                f"residual {records.fail_residual[b]:.3g} N after {settings.integrator.max_iterations} corrections")
        return RunOutcome(error=f"Newton iteration did not converge in step {step} (t = {step * dt:.6g} s): {what}",
                          **failed)
    n_steps = plan.step_count(dt)
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
