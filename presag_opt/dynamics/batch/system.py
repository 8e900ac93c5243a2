"""The arrays of a batch for the compiled kernel: what all runs share, and each run's start and path.

:class:`BatchSystem` holds what every run of :func:`~presag_opt.dynamics.batch.simulate_many` shares
for one catenary, pantograph train and time step: the degrees of freedom in banded (reverse
Cuthill–McKee) order, the row-wise bands of K and of the Cholesky factor of
K_eff = a0 M + s (K + a1 C), the pantographs' small matrices, friction elements and droppers.
:func:`integrate_batch` adds what one batch of runs needs (start states, contact paths, the columns
of K_eff⁻¹ at every DOF a nonlinear force can reach) and runs :mod:`presag_opt.dynamics.batch.kernel`.
The interface (operating points, outcomes, statistics) is :mod:`presag_opt.dynamics.batch`.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, replace
from typing import NamedTuple

import numpy as np
import scipy.sparse as sp

from presag_opt.dynamics.assembly import effective_stiffness
from presag_opt.dynamics.batch import kernel
from presag_opt.dynamics.batch.band_rows import BandRows, lower_rows, symmetric_rows, upper_rows
from presag_opt.dynamics.batch.compilation import compile_kernel
from presag_opt.dynamics.batch.kernel_data import (
    Records,
    Runs,
    RunState,
    Scalars,
    Scratch,
    Shared,
    Work,
    make_scratch,
    make_work,
    swept_array,
)
from presag_opt.dynamics.laws import scheme_constants, suspension_elements
from presag_opt.dynamics.pantograph import Pantograph
from presag_opt.dynamics.results import analysed_supports
from presag_opt.dynamics.run_plan import RunPlan, recorded_droppers, static_contact
from presag_opt.dynamics.settings import SimulationSettings
from presag_opt.dynamics.structure import StructuralModel
from presag_opt.errors import ModelError
from presag_opt.native import sweeps as native_sweeps
from presag_opt.native.banded_numba import banded_cholesky_solve
from presag_opt.static.banded_solver import BandedSolver
from presag_opt.static.equilibrium import EquilibriumState

CHUNK_STEPS = 250
"""Time steps per call of the compiled kernel: Ctrl-C is honoured between calls. [-]"""

INFLUENCE_BLOCK = 64
"""Unit right-hand sides solved together when the columns of K_eff⁻¹ are formed. [-]"""


@dataclass(frozen=True)
class BatchSystem:
    """What every run of a batch shares (see the module notes).

    Attributes
    ----------
    model : StructuralModel
        The catenary's structural model.
    order : ndarray of int
        Model DOF at each banded position. [-]
    position : ndarray of int
        Banded position of each model DOF. [-]
    scalars : Scalars
        The kernel's numbers (scheme constants, Rayleigh coefficients, Newton and friction settings).
    fixed : dict
        The kernel's shared arrays that do not depend on the batch, by name (fields of
        :class:`~presag_opt.dynamics.batch.kernel_data.Shared`).
    """

    model: StructuralModel
    order: np.ndarray
    position: np.ndarray
    scalars: Scalars
    fixed: dict

    @classmethod
    def build(
        cls, model: StructuralModel, pantographs: tuple[Pantograph, ...], settings: SimulationSettings
    ) -> BatchSystem:
        """Order, factorise and lay out the shared system.

        Parameters
        ----------
        model : StructuralModel
            The catenary.
        pantographs : tuple of Pantograph
            The train, front to rear.
        settings : SimulationSettings
            Time step, scheme, tolerances and friction regularisation.

        Raises
        ------
        ModelError
            If K_eff is not positive definite.
        """
        integ = settings.integrator
        scheme = scheme_constants(integ)
        effective = effective_stiffness(model.mass, model.damping, model.stiffness, scheme).tocsc()
        effective.sort_indices()
        ordering = BandedSolver.for_pattern(effective)
        factor = ordering.factorise(effective.data)
        if not factor.positive_definite:
            raise ModelError("the effective matrix a0 M + s (K + a1 C) is not positive definite: check the model")
        order = ordering.permutation
        position = np.empty_like(order)
        position[order] = np.arange(len(order))

        n = model.n_dofs
        offsets = np.concatenate([[0], np.cumsum([p.n_dofs for p in pantographs])[:-1]]).astype(np.int64)
        mass = sp.block_diag([p.mass_matrix() for p in pantographs]).toarray()
        damping = sp.block_diag([p.damping_matrix() for p in pantographs]).toarray()
        stiffness = sp.block_diag([p.stiffness_matrix() for p in pantographs]).toarray()
        friction_dofs, friction_levels = [], []
        for p, offset in zip(pantographs, offsets):
            for stage, (upper, lower) in zip(p.stages, suspension_elements(p.n_dofs)):
                if stage.friction > 0.0:  # element between a stage and the stage below (or the car body)
                    friction_dofs.append((n + offset + upper, n + offset + lower if lower >= 0 else -1))
                    friction_levels.append(stage.friction)
        d = model.droppers
        stiffness_band = np.ascontiguousarray(_lower_band(model.stiffness.tocsc(), order, ordering.bandwidth).T)
        factor_band = np.ascontiguousarray(factor.cholesky.T)
        fixed = {
            # The kernel reads a row's band entries together: the bands are stored row by row.
            "stiffness_band": stiffness_band,
            "factor_band": factor_band,
            "stiffness_rows": symmetric_rows(stiffness_band),
            "lower_rows": lower_rows(factor_band),
            "upper_rows": upper_rows(factor_band),
            "mass": model.mass.diagonal()[order].copy(),
            "pantograph_mass": mass.diagonal().copy(),
            "pantograph_damping": damping,
            "pantograph_stiffness": stiffness,
            "pantograph_inverse": np.linalg.inv(effective_stiffness(mass, damping, stiffness, scheme)),
            "head_dof": n + offsets,
            "contact_stiffness": np.array([p.contact.stiffness for p in pantographs]),
            "friction_dofs": np.array(friction_dofs, dtype=np.int64).reshape(-1, 2),
            "friction_levels": np.array(friction_levels, dtype=float),
            "dropper_dofs": position[d.dofs].astype(np.int64),
            "dropper_gradient": np.ascontiguousarray(d.gradient, dtype=float),
            "dropper_stiffness": np.asarray(d.axial_stiffness, dtype=float).copy(),
        }
        scalars = Scalars(
            scheme=scheme, rayleigh_alpha=float(model.rayleigh_alpha), rayleigh_beta=float(model.rayleigh_beta),
            tolerance=float(integ.tolerance), max_iterations=int(integ.max_iterations),
            friction_velocity=float(settings.friction.velocity),
        )
        return cls(model, order, position, scalars, fixed)


@dataclass(frozen=True)
class StaticLine:
    """The static line a run starts from, on the structure its batch shares.

    A run of :func:`integrate_batch` moves about the shared structure's equilibrium with the shared
    stiffness, mass and damping; its contact wire lies at ``cw_height`` and its droppers carry
    ``dropper_preload``. For a catenary simulated on its own structure these are the structure's own
    (:meth:`own`); an installed line (the design built with installation errors) shares the design's
    structure and brings its own heights and preloads (:meth:`installed`).

    Attributes
    ----------
    state : EquilibriumState
        The line's equilibrium (the stations of its contact-wire nodes).
    cw_height : ndarray
        Static height of each contact-wire node, along-track order. [m]
    dropper_preload : ndarray
        Static tension of each dropper, along-track order (zero in a slack one, as the state gives it). [N]
    """

    state: EquilibriumState
    cw_height: np.ndarray
    dropper_preload: np.ndarray

    @classmethod
    def own(cls, model: StructuralModel) -> StaticLine:
        """The structure's own line: its equilibrium, heights and preloads."""
        return cls(model.state, model.cw_height, model.droppers.preload)

    @classmethod
    def installed(cls, model: StructuralModel, state: EquilibriumState) -> StaticLine:
        """Another equilibrium of the same discretisation (an installed line) on ``model``.

        Parameters
        ----------
        model : StructuralModel
            The shared structure.
        state : EquilibriumState
            The line's equilibrium: same nodes, elements and droppers as ``model.state``.

        Raises
        ------
        ModelError
            If ``state`` is not a line of the same discretisation.
        """
        disc, own = state.discretisation, model.state.discretisation
        if (len(disc.cw_nodes) != len(own.cw_nodes) or not np.array_equal(disc.cw_nodes, own.cw_nodes)
                or not np.array_equal(disc.dropper_elements, own.dropper_elements)):
            raise ModelError("static line: the installed line has another discretisation than the shared structure")
        return cls(state, state.positions[disc.cw_nodes, 2].copy(), state.dropper_forces())


class KernelArguments(NamedTuple):
    """What a batch hands the kernel: the C sweeps (or None for numba's), the arrays by name
    (:mod:`~presag_opt.dynamics.batch.kernel_data`) and the batch's last record."""

    c_sweeps: object
    scalars: Scalars
    shared: Shared
    runs: Runs
    state: RunState
    out: Records
    work: Work
    scratch: Scratch
    longest: int


def integrate_batch(
    state: EquilibriumState, system: BatchSystem, plans: list[RunPlan], settings: SimulationSettings,
    lines: list[StaticLine] | None = None, progress: Callable[[str], None] | None = None,
) -> Records:
    """Integrate one batch of runs on a shared system: what the kernel recorded of each run.

    Parameters
    ----------
    state : EquilibriumState
        The form-found catenary of the shared structure.
    system : BatchSystem
        Its shared arrays.
    plans : list of RunPlan
        The runs, sorted by step count, longest first (the kernel's active runs form a prefix).
    settings : SimulationSettings
        As for :meth:`BatchSystem.build`.
    lines : list of StaticLine, optional
        Each run's static line; default the structure's own for every run.
    progress : callable, optional
        Told when the kernel is compiled for its first use (:func:`~presag_opt.dynamics.batch.compilation.compile_kernel`).

    Returns
    -------
    Records
        The kernel's records, indexed by run in the order of ``plans``.
    """
    c_sweeps, scalars, shared, runs, run_state, out, work, scratch, longest = kernel_arguments(
        state, system, plans, settings, lines)
    compile_kernel(c_sweeps, scalars, shared, runs, run_state, out, work, scratch, progress)
    kernel.initialise(scalars, shared, runs, run_state, out, scratch)
    for first in range(1, longest + 1, CHUNK_STEPS):
        kernel.advance(first, min(first + CHUNK_STEPS - 1, longest), c_sweeps, scalars, shared, runs,
                       run_state, out, work, scratch)
    return out


def kernel_arguments(state: EquilibriumState, system: BatchSystem, plans: list[RunPlan],
                     settings: SimulationSettings, lines: list[StaticLine] | None = None) -> KernelArguments:
    """The kernel's arguments for one batch of runs (see :func:`integrate_batch` for the parameters):
    every array allocated and filled with the runs' initial state, nothing integrated yet."""
    model = system.model
    dt = settings.integrator.time_step
    n = model.n_dofs
    n_runs, n_pan = len(plans), len(plans[0].pantographs)
    n_steps = np.array([p.step_count(dt) for p in plans], dtype=np.int64)
    longest = int(n_steps.max())
    path_nodes = np.zeros((n_runs, n_pan, longest + 1, 2), dtype=np.int64)
    path_weights = np.zeros((n_runs, n_pan, longest + 1, 2))
    path_compliance = np.zeros((n_runs, n_pan, longest + 1))
    head_height = np.zeros((n_runs, n_pan))
    lines = lines or [StaticLine.own(model)] * n_runs
    cw_height = np.zeros((n_runs, n))
    dropper_preload = np.zeros((n_runs, len(model.droppers)))
    c_sweeps = native_sweeps.sweeps()
    lanes = n_runs if c_sweeps is None else native_sweeps.lanes_for(n_runs)  # run dimension of the swept arrays
    u = swept_array("u", n, lanes)
    for b, (plan, line) in enumerate(zip(plans, lines, strict=True)):
        records = slice(0, n_steps[b] + 1)
        cw_height[b, system.position[model.cw_z]] = line.cw_height
        dropper_preload[b] = line.dropper_preload
        on_structure = model if line.cw_height is model.cw_height else replace(model, cw_height=line.cw_height)
        u0, paths = static_contact(line.state, on_structure, plan, dt * np.arange(n_steps[b] + 1))
        u[:, b] = u0[system.order]
        for p, path in enumerate(paths):
            path_nodes[b, p, records] = system.position[model.cw_z[path.nodes]]
            path_weights[b, p, records] = path.weights
            path_compliance[b, p, records] = path.compliance
            head_height[b, p] = path.head_height

    # Columns of K_eff⁻¹ at every DOF a nonlinear force can reach: the contact path and the droppers.
    fixed = system.fixed
    candidates = np.unique(np.concatenate([path_nodes.ravel(), fixed["dropper_dofs"].ravel()]))
    column_of = np.full(n, -1, dtype=np.int64)
    column_of[candidates] = np.arange(len(candidates))
    columns = _influence_columns(fixed["factor_band"], candidates)
    candidate_index = np.full(n, -1, dtype=np.int64)
    candidate_index[candidates] = np.arange(len(candidates))
    recorded = np.zeros(len(model.droppers), dtype=np.bool_)
    recorded[recorded_droppers(model, plans[0].analysed_section, settings)] = True
    supports = analysed_supports(state.discretisation.mast_station, plans[0].analysed_section)
    support_dofs = system.position[model.support_z[supports]].astype(np.int64)
    support_row = np.zeros(n, dtype=np.bool_)
    support_row[support_dofs] = True
    shared = dict(
        fixed,
        column_of=column_of,
        columns=columns,
        dropper_recorded=recorded,
        support_dofs=support_dofs,
        stretch_influence=np.ascontiguousarray(
            np.einsum("cdk,dk->cd", columns[:, fixed["dropper_dofs"]], fixed["dropper_gradient"])
        ),
        candidate_index=candidate_index,
        candidate_rows=candidates.astype(np.int64),
        support_row=support_row,
    )
    shared = Shared(**{name: shared[name] if isinstance(shared[name], BandRows) else np.ascontiguousarray(shared[name])
                       for name in Shared._fields})  # C order, as sweeps.c
    uplift = np.array([p.operation.uplift_force for p in plans])
    runs = Runs(n_steps=n_steps, path_nodes=path_nodes, path_weights=path_weights, path_compliance=path_compliance,
                head_height=head_height, uplift=uplift, cw_height=cw_height, dropper_preload=dropper_preload)
    n_p = len(fixed["pantograph_mass"])
    run_state = RunState(u, swept_array("v", n, lanes), swept_array("q", n, lanes), swept_array("r", n, lanes),
                         *(np.zeros((n_p, n_runs)) for _ in range(4)))
    out = Records(
        contact_force=np.zeros((n_runs, n_pan, longest + 1)),
        uplift_max=np.zeros(n_runs),
        slack_max=np.zeros(n_runs, dtype=np.int64),
        status=np.zeros(n_runs, dtype=np.int64),
        fail_step=np.zeros(n_runs, dtype=np.int64),
        fail_residual=np.zeros(n_runs),
        iterations=np.zeros(n_runs, dtype=np.int64),
    )
    return KernelArguments(c_sweeps, system.scalars, shared, runs, run_state, out, make_work(shared, n_runs, lanes),
                           make_scratch(shared), longest)


def _lower_band(matrix: sp.csc_matrix, order: np.ndarray, bandwidth: int) -> np.ndarray:
    """Lower band of a symmetric matrix in the given order: band[k, j] = A[j + k, j]."""
    permuted = sp.coo_matrix(matrix[order][:, order])
    lower = (permuted.row >= permuted.col) & (permuted.data != 0.0)  # stored zeros may lie outside the band
    band = np.zeros((bandwidth + 1, matrix.shape[0]))
    np.add.at(band, (permuted.row[lower] - permuted.col[lower], permuted.col[lower]), permuted.data[lower])
    return band


def _influence_columns(factor_band: np.ndarray, dofs: np.ndarray) -> np.ndarray:
    """Columns K_eff⁻¹ e_j for the banded positions ``dofs``, one per row. [m/N]"""
    n = factor_band.shape[0]
    out = np.empty((len(dofs), n))
    for start in range(0, len(dofs), INFLUENCE_BLOCK):
        block = dofs[start : start + INFLUENCE_BLOCK]
        unit = np.zeros((n, len(block)))
        unit[block, np.arange(len(block))] = 1.0
        banded_cholesky_solve(factor_band, unit, len(block))
        out[start : start + len(block)] = unit.T
    return out
