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
import scipy.linalg as sla
import scipy.sparse as sp

from presag_opt.dynamics import kernel
from presag_opt.dynamics.pantograph import Pantograph
from presag_opt.dynamics.simulate import (
    RunPlan,
    SimulationSettings,
    plan_run,
    recorded_droppers,
    static_contact,
)
from presag_opt.dynamics.statistics import ContactForceStatistics, contact_force_statistics
from presag_opt.dynamics.structure import StructuralModel, structural_model
from presag_opt.errors import ConvergenceError, ModelError
from presag_opt.static.equilibrium import EquilibriumState
from presag_opt.static.linalg import BandedSolver
from presag_opt.system.quantity import quantity, validate_fields

BATCH_SIZE = 16
"""Runs advanced together by one call of the compiled kernel: enough to vectorise across runs, few
enough that a run's working arrays (about 14 × n_dofs doubles) stay in the processor's cache. [-]"""

CHUNK_STEPS = 250
"""Time steps per call of the compiled kernel: Ctrl-C is honoured between calls. [-]"""


@dataclass(frozen=True, kw_only=True)
class OperatingPoint:
    """One operating point of a batch.

    Attributes
    ----------
    speed : float
        Train speed. [m/s]
    static_force : float
        Static uplift force of each pantograph. [N]
    aero_coefficient : float
        Aerodynamic uplift coefficient α_ae of F_m = F_stat + α_ae v². [N/(m/s)²]
    """

    speed: float = quantity("speed", 0.0, 600.0, display="km/h", low_open=True)
    static_force: float = quantity("force", 0.0, 500.0, low_open=True)
    aero_coefficient: float = quantity("aero_coefficient", 0.0, 0.01, display="N/(km/h)^2", default=0.0)

    def __post_init__(self) -> None:
        validate_fields(self)


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
    newton_iterations : int
        Newton corrections over the whole run. [-]
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
    newton_iterations: int
    error: str | None = None
    time: np.ndarray | None = None
    contact_force: np.ndarray | None = None

    @property
    def ok(self) -> bool:
        """Whether the run finished."""
        return self.error is None

    def to_dict(self) -> dict:
        """Headline numbers with units in the key names, as the single-run ``--json`` output."""
        p = self.point
        out = {
            "speed_kmh": p.speed * 3.6,
            "static_force_N": p.static_force,
            "aero_force_N": p.aero_coefficient * p.speed**2,
            "beta": self.speed_ratio,
            "doppler_factor": self.doppler_factor,
        }
        if not self.ok:
            return {**out, "error": self.error}
        out.update(self.statistics[0].to_dict())
        out["uplift_max_mm"] = self.uplift_max * 1e3
        out["slack_droppers_max"] = self.slack_droppers_max
        if len(self.statistics) > 1:
            out["pantographs"] = [s.to_dict() for s in self.statistics]
        return out


@dataclass(frozen=True, kw_only=True)
class BatchResult:
    """Result of :func:`simulate_many`.

    Attributes
    ----------
    catenary_name : str
        Name of the catenary.
    runs : tuple of RunOutcome
        One per operating point, in the order given.
    wall_time : float
        Wall-clock time of the whole batch. [s]
    settings : SimulationSettings
        Settings used.
    """

    catenary_name: str
    runs: tuple[RunOutcome, ...]
    wall_time: float
    settings: SimulationSettings

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
    progress: Callable[[int], None] | None = None,
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
        Called with the number of runs just finished.

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
    shared = _SharedSystem.build(model, plans[0].pantographs, settings)
    dt = settings.integrator.time_step
    order = sorted(range(len(points)), key=lambda i: -plans[i].step_count(dt))
    outcomes: list[RunOutcome | None] = [None] * len(points)
    for first in range(0, len(order), BATCH_SIZE):
        members = order[first : first + BATCH_SIZE]
        for i, outcome in zip(members, _run_batch(state, model, shared, [plans[i] for i in members], settings,
                                                  keep_histories)):
            outcomes[i] = outcome
        if progress is not None:
            progress(len(members))
    return BatchResult(
        catenary_name=state.catenary.name,
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
            state.catenary, pantograph, speed=point.speed, static_force=point.static_force,
            aero_coefficient=point.aero_coefficient, spacings=spacings, settings=settings,
        )
    except ModelError as exc:
        raise ModelError(
            f"operating point {point.speed * 3.6:g} km/h, {point.static_force:g} N: {exc}"
        ) from None


@dataclass(frozen=True)
class _SharedSystem:
    """What every run of a batch shares, in the kernel's banded DOF order (see kernel notes)."""

    order: np.ndarray  # banded position -> model DOF
    position: np.ndarray  # model DOF -> banded position
    scalars: np.ndarray
    arrays: tuple
    analysed_supports: np.ndarray
    head_dofs: np.ndarray

    @classmethod
    def build(cls, model: StructuralModel, pantographs: tuple[Pantograph, ...], settings: SimulationSettings):
        integ = settings.integrator
        alpha = integ.hht_alpha if integ.scheme == "hht" else 0.0
        beta, gamma, dt = (1.0 - alpha) ** 2 / 4.0, 0.5 - alpha, integ.time_step
        s, a0, a1 = 1.0 + alpha, 1.0 / (beta * dt**2), gamma / (beta * dt)
        effective = (a0 * model.mass + s * (model.stiffness + a1 * model.damping)).tocsc()
        effective.sort_indices()
        ordering = BandedSolver.for_pattern(effective)
        order = ordering.permutation
        position = np.empty_like(order)
        position[order] = np.arange(len(order))
        try:
            factor = sla.cholesky_banded(_lower_band(effective, order, ordering.bandwidth), lower=True,
                                         check_finite=False)
        except np.linalg.LinAlgError:
            raise ModelError("the effective matrix a0 M + s (K + a1 C) is not positive definite: check the model") from None
        # The kernel reads a row's band entries together: store the bands row by row.
        factor_band = np.ascontiguousarray(factor.T)
        stiffness_band = np.ascontiguousarray(_lower_band(model.stiffness.tocsc(), order, ordering.bandwidth).T)

        n = model.n_dofs
        sizes = [p.n_dofs for p in pantographs]
        offsets = np.concatenate([[0], np.cumsum(sizes)[:-1]]).astype(int)
        pmass = sp.block_diag([p.mass_matrix() for p in pantographs]).toarray()
        pdamping = sp.block_diag([p.damping_matrix() for p in pantographs]).toarray()
        pstiffness = sp.block_diag([p.stiffness_matrix() for p in pantographs]).toarray()
        pinverse = np.linalg.inv(a0 * pmass + s * (pstiffness + a1 * pdamping))
        friction_dofs, friction_levels = [], []
        for p, offset in zip(pantographs, offsets):
            for i, stage in enumerate(p.stages):
                if stage.friction > 0.0:
                    lower = n + offset + i + 1 if i + 1 < p.n_dofs else -1
                    friction_dofs.append((n + offset + i, lower))
                    friction_levels.append(stage.friction)
        head_dofs = n + offsets

        d = model.droppers
        dropper_dofs = position[d.dofs]
        cw_height = np.zeros(n)
        cw_height[position[model.cw_z]] = model.cw_height
        scalars = np.array([
            model.rayleigh_alpha, model.rayleigh_beta, dt, alpha, beta, gamma, integ.tolerance,
            integ.max_iterations, settings.friction.velocity,
        ])
        arrays = (
            stiffness_band, factor_band, model.mass.diagonal()[order].copy(), pmass.diagonal().copy(), pdamping,
            pstiffness, pinverse, None, None, head_dofs.astype(np.int64), np.array([p.contact.stiffness for p in pantographs]),
            np.array(friction_dofs, dtype=np.int64).reshape(-1, 2), np.array(friction_levels, dtype=float),
            dropper_dofs.astype(np.int64), d.gradient.copy(), d.axial_stiffness.astype(float).copy(),
            d.preload.astype(float).copy(), None, None, cw_height,
        )
        return cls(order, position, scalars, arrays, np.zeros(0, dtype=np.int64), head_dofs)


def _lower_band(matrix: sp.csc_matrix, order: np.ndarray, bandwidth: int) -> np.ndarray:
    """Lower band of a symmetric matrix in the given order: band[k, j] = A[j + k, j]."""
    permuted = sp.coo_matrix(matrix[order][:, order])
    lower = (permuted.row >= permuted.col) & (permuted.data != 0.0)  # stored zeros may lie outside the band
    band = np.zeros((bandwidth + 1, matrix.shape[0]))
    np.add.at(band, (permuted.row[lower] - permuted.col[lower], permuted.col[lower]), permuted.data[lower])
    return band


def _influence_columns(factor_band: np.ndarray, dofs: np.ndarray) -> np.ndarray:
    """Columns K_eff⁻¹ e_j for the banded positions ``dofs``, as rows of an array. [m/N]"""
    n = factor_band.shape[0]
    out = np.empty((len(dofs), n))
    for start in range(0, len(dofs), 64):
        block = dofs[start : start + 64]
        unit = np.zeros((n, len(block)))
        unit[block, np.arange(len(block))] = 1.0
        kernel.band_cholesky_solve(factor_band, unit, len(block))
        out[start : start + len(block)] = unit.T
    return out


def _run_batch(
    state: EquilibriumState,
    model: StructuralModel,
    shared: _SharedSystem,
    plans: list[RunPlan],
    settings: SimulationSettings,
    keep_histories: bool,
) -> list[RunOutcome]:
    """Integrate one batch (runs sorted longest first) and turn its records into outcomes."""
    dt = settings.integrator.time_step
    n = model.n_dofs
    n_runs, n_pan = len(plans), len(plans[0].pantographs)
    n_steps = np.array([p.step_count(dt) for p in plans], dtype=np.int64)
    longest = int(n_steps.max())
    path_nodes = np.zeros((n_runs, n_pan, longest + 1, 2), dtype=np.int64)
    path_weights = np.zeros((n_runs, n_pan, longest + 1, 2))
    path_compliance = np.zeros((n_runs, n_pan, longest + 1))
    head_height = np.zeros((n_runs, n_pan))
    u = np.zeros((n, n_runs))
    for b, plan in enumerate(plans):
        times = dt * np.arange(n_steps[b] + 1)
        u0, paths = static_contact(state, model, plan, times)
        u[:, b] = u0[shared.order]
        for p, path in enumerate(paths):
            path_nodes[b, p, : n_steps[b] + 1] = shared.position[model.cw_z[path.nodes]]
            path_weights[b, p, : n_steps[b] + 1] = path.weights
            path_compliance[b, p, : n_steps[b] + 1] = path.compliance
            head_height[b, p] = path.head_height
    candidates = np.unique(np.concatenate([path_nodes.ravel(), shared.arrays[13].ravel()]))
    column_of = np.full(n, -1, dtype=np.int64)
    column_of[candidates] = np.arange(len(candidates))
    columns = _influence_columns(shared.arrays[1], candidates)
    recorded = np.zeros(len(model.droppers), dtype=np.bool_)
    recorded[recorded_droppers(model, plans[0].analysed_section, settings)] = True
    supports = np.flatnonzero(
        (model.state.discretisation.mast_station >= plans[0].analysed_section[0] - 1e-9)
        & (model.state.discretisation.mast_station <= plans[0].analysed_section[1] + 1e-9)
    )
    dropper_dofs, dropper_gradient = shared.arrays[13], shared.arrays[14]
    stretch_influence = np.einsum("cdk,dk->cd", columns[:, dropper_dofs], dropper_gradient)
    arrays = list(shared.arrays)
    arrays[7], arrays[8] = column_of, columns
    arrays[17], arrays[18] = recorded, shared.position[model.support_z[supports]].astype(np.int64)
    is_candidate = np.zeros(n, dtype=np.bool_)
    is_candidate[candidates] = True
    arrays = tuple(arrays) + (np.ascontiguousarray(stretch_influence), is_candidate, candidates.astype(np.int64))
    n_p = shared.arrays[3].shape[0]
    uplift = np.array([p.operation.uplift_force for p in plans])
    runs = (n_steps, path_nodes, path_weights, path_compliance, head_height, uplift)
    run_state = (u, np.zeros((n, n_runs)), np.zeros((n, n_runs)), np.zeros((n, n_runs)),
                 np.zeros((n_p, n_runs)), np.zeros((n_p, n_runs)), np.zeros((n_p, n_runs)), np.zeros((n_p, n_runs)))
    out = (
        np.zeros((n_runs, n_pan, longest + 1)), np.zeros(n_runs), np.zeros(n_runs, dtype=np.int64),
        np.zeros(n_runs, dtype=np.int64), np.zeros(n_runs, dtype=np.int64), np.zeros(n_runs), np.zeros(n_runs, dtype=np.int64),
    )
    scratch = kernel.make_scratch(arrays)
    size = len(scratch[1])
    work = (
        np.zeros((n, n_runs)), np.zeros((n, n_runs)), np.zeros((n, n_runs)), np.zeros((n, n_runs)), np.zeros(n_runs),
        np.zeros(n_runs, dtype=np.int64), np.zeros((n_runs, size), dtype=np.int64), np.zeros((n_runs, size)),
        np.zeros(n_runs, dtype=np.int64), np.zeros((n_runs, size), dtype=np.int64), np.zeros((n_runs, size)),
        np.zeros((n, n_runs)), np.zeros((n, n_runs)), np.zeros(n_runs), np.zeros(n_runs, dtype=np.bool_),
    )
    kernel.initialise(shared.scalars, arrays, runs, run_state, out, scratch)
    for first in range(1, longest + 1, CHUNK_STEPS):
        kernel.advance(first, min(first + CHUNK_STEPS - 1, longest), shared.scalars, arrays, runs, run_state, out,
                       work, scratch)
    return [_outcome(plan, b, n_steps[b], dt, out, settings, keep_histories) for b, plan in enumerate(plans)]


def _outcome(
    plan: RunPlan, b: int, n_steps: int, dt: float, out: tuple, settings: SimulationSettings, keep_histories: bool
) -> RunOutcome:
    contact_force, uplift_max, slack_max, status, fail_step, fail_residual, iterations = out
    point = OperatingPoint(
        speed=plan.operation.speed, static_force=plan.operation.static_force,
        aero_coefficient=plan.operation.aero_coefficient,
    )
    common = dict(point=point, speed_ratio=plan.speed_ratio, doppler_factor=plan.doppler_factor,
                  newton_iterations=int(iterations[b]))
    if status[b] != kernel.STATUS_OK:
        what = "a non-finite residual" if status[b] == kernel.STATUS_NOT_FINITE else (
            f"residual {fail_residual[b]:.3g} N after {settings.integrator.max_iterations} corrections")
        error = (f"Newton iteration did not converge in step {fail_step[b]} (t = {fail_step[b] * dt:.6g} s): {what}")
        return RunOutcome(statistics=(), uplift_max=float("nan"), slack_droppers_max=0, error=error, **common)
    time = dt * np.arange(n_steps + 1)
    forces = contact_force[b, :, : n_steps + 1].T.copy()
    try:
        statistics = tuple(
            contact_force_statistics(time, forces[:, i], window_start=w[0], window_end=w[1],
                                     cutoff=settings.cutoff_frequency)
            for i, w in enumerate(plan.window(i) for i in range(len(plan.pantographs)))
        )
    except (ModelError, ConvergenceError) as exc:
        return RunOutcome(statistics=(), uplift_max=float("nan"), slack_droppers_max=0,
                          error=str(exc).splitlines()[0], **common)
    return RunOutcome(
        statistics=statistics,
        uplift_max=float(uplift_max[b]),
        slack_droppers_max=int(slack_max[b]),
        time=time if keep_histories else None,
        contact_force=forces if keep_histories else None,
        **common,
    )
