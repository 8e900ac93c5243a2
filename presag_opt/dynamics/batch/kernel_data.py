"""The arrays of the batch kernel, by name: what its compiled functions read and write.

The compiled kernel (:mod:`presag_opt.dynamics.batch.kernel`, :mod:`presag_opt.dynamics.batch.newton_step` and
its parts) takes these named tuples, which numba passes in nopython mode like plain tuples (a field is read as
``shared.head_dof``, at no cost). Each tuple is documented here once; the kernel's functions take
them under one name each (``scalars``: :class:`Scalars`, the batch's constants; ``shared``:
:class:`Shared`, what every run shares; ``runs``: :class:`Runs`, what differs between runs;
``state``: :class:`RunState`; ``out``: :class:`Records`, the records being written; ``work``:
:class:`Work`, the sweeps' per-step arrays; ``scratch``: :class:`Scratch`, the arrays of the run being
iterated) and their docstrings refer here for them. :func:`~presag_opt.dynamics.batch.system.integrate_batch` fills
them; :func:`make_work` and :func:`make_scratch` allocate the working arrays of one batch. A run's
status in :class:`Records` is one of :data:`STATUS_RUNNING`, :data:`STATUS_OK`,
:data:`STATUS_NOT_CONVERGED` and :data:`STATUS_NOT_FINITE`.

Extended DOF numbering: the catenary's DOFs in banded (reverse Cuthill–McKee) order, 0 … n − 1, then
the pantographs' DOFs, n … n + n_p − 1. Arrays with a run dimension are indexed [DOF, run] for the
catenary (run innermost; padded to whole blocks of lanes for the compiled sweeps) and [DOF, run] or
[run, …] as noted.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from presag_opt.dynamics.batch.band_rows import BandRows
from presag_opt.dynamics.laws import SchemeConstants

STATUS_RUNNING = -1
"""``Records.status`` of a run still going. [-]"""
STATUS_OK = 0
"""``Records.status`` of a run that reached its last step. [-]"""
STATUS_NOT_CONVERGED = 1
"""``Records.status`` of a run whose Newton iteration did not converge in the corrections allowed. [-]"""
STATUS_NOT_FINITE = 2
"""``Records.status`` of a run whose residual became infinite or NaN. [-]"""
PIECE_SIZE = 6
"""Most DOFs one force contribution acts on (a dropper's six; a contact's three). [-]"""

SWEPT_ARRAYS = ("u", "v", "q", "r", "delta", "linear")
"""The [DOF, lane] arrays the sweeps read and write row by row (:class:`RunState` and :class:`Work`),
in the order of their places in a 4 KiB page (:func:`swept_array`). [-]"""

PAGE_BYTES = 4096
"""The span of addresses within which a load is compared with earlier stores by their low bits (a 4 KiB page). [B]"""

SWEPT_ARRAY_STAGGER = 704
"""Distance between the starts of consecutive :data:`SWEPT_ARRAYS` within a :data:`PAGE_BYTES` page: eleven
64-byte cache lines, so that the six spread evenly over the page (576 bytes or more apart). [B]"""


class Scalars(NamedTuple):
    """The numbers all runs of a batch share.

    Attributes
    ----------
    scheme : SchemeConstants
        The time step and the HHT-α constants.
    rayleigh_alpha : float
        Mass-proportional Rayleigh coefficient α_R. [1/s]
    rayleigh_beta : float
        Stiffness-proportional Rayleigh coefficient β_R. [s]
    tolerance : float
        Newton tolerance relative to the step's largest force term. [-]
    max_iterations : int
        Newton corrections allowed per step. [-]
    friction_velocity : float
        Friction regularisation velocity v_reg. [m/s]
    """

    scheme: SchemeConstants
    rayleigh_alpha: float
    rayleigh_beta: float
    tolerance: float
    max_iterations: int
    friction_velocity: float


class Shared(NamedTuple):
    """The arrays all runs of a batch share (C order, as ``sweeps.c`` reads them).

    Bands are stored by rows, band[j, k] = A[j + k, j]: ``stiffness_band`` K [N/m] and
    ``factor_band`` the Cholesky factor L of K_eff [sqrt(N/m)]; the sweeps read their nonzero
    off-diagonal entries by rows (:mod:`presag_opt.dynamics.batch.band_rows`): ``stiffness_rows`` of K,
    ``lower_rows`` of L and ``upper_rows`` of Lᵀ, and the diagonals from the bands; ``mass`` the lumped masses [kg];
    ``pantograph_mass``, ``_damping``, ``_stiffness`` and ``_inverse`` the pantographs' M [kg],
    C [N·s/m], K [N/m] and K_eff⁻¹ [m/N]; ``column_of`` the row of ``columns`` (K_eff⁻¹ e_j [m/N])
    of each DOF, −1 if none; ``head_dof`` and ``contact_stiffness`` [N/m] of each head;
    ``friction_dofs`` (upper DOF, lower DOF or −1 for the car body) and ``friction_levels`` [N];
    ``dropper_dofs`` (6 each), ``dropper_gradient`` [-], ``dropper_stiffness`` [N/m],
    ``dropper_recorded``; ``support_dofs`` of the analysed section; ``stretch_influence`` each dropper's
    stretch per unit force at each column [m/N]; ``candidate_index`` each row's place among the rows
    a nonlinear force can reach (−1 if none) and ``candidate_rows`` their list; ``support_row``
    whether a row is a support of the analysed section.
    """

    stiffness_band: np.ndarray
    factor_band: np.ndarray
    stiffness_rows: BandRows
    lower_rows: BandRows
    upper_rows: BandRows
    mass: np.ndarray
    pantograph_mass: np.ndarray
    pantograph_damping: np.ndarray
    pantograph_stiffness: np.ndarray
    pantograph_inverse: np.ndarray
    column_of: np.ndarray
    columns: np.ndarray
    head_dof: np.ndarray
    contact_stiffness: np.ndarray
    friction_dofs: np.ndarray
    friction_levels: np.ndarray
    dropper_dofs: np.ndarray
    dropper_gradient: np.ndarray
    dropper_stiffness: np.ndarray
    dropper_recorded: np.ndarray
    support_dofs: np.ndarray
    stretch_influence: np.ndarray
    candidate_index: np.ndarray
    candidate_rows: np.ndarray
    support_row: np.ndarray


class Runs(NamedTuple):
    """Each run's length and contact path: ``n_steps`` [-]; per (run, head, record) the two
    contact-wire DOFs under the head ``path_nodes``, their shape weights ``path_weights`` [-] and the
    element's compliance ``path_compliance`` [m/N]; ``head_height`` at rest per (run, head) [m];
    ``uplift`` the mean uplift force per run [N]; the run's static line: ``cw_height`` the static
    height per (run, DOF), read at the contact-wire DOFs [m], and ``dropper_preload`` per (run,
    dropper) [N] (runs of several installed lines on one shared structure differ in these alone)."""

    n_steps: np.ndarray
    path_nodes: np.ndarray
    path_weights: np.ndarray
    path_compliance: np.ndarray
    head_height: np.ndarray
    uplift: np.ndarray
    cw_height: np.ndarray
    dropper_preload: np.ndarray


class RunState(NamedTuple):
    """The runs' state between steps. Catenary, [DOF, lane]: the next step's predictors u = ũ [m],
    v = ṽ [m/s], q = ũ + β_R ṽ [m] and r = α r_n [N] (the right-hand side); pantographs,
    [DOF, run]: displacement [m], velocity [m/s], acceleration [m/s²] and internal force r [N]."""

    u: np.ndarray
    v: np.ndarray
    q: np.ndarray
    r: np.ndarray
    pantograph_u: np.ndarray
    pantograph_v: np.ndarray
    pantograph_a: np.ndarray
    pantograph_r: np.ndarray


class Records(NamedTuple):
    """What the kernel records per run: ``contact_force`` [N] per (run, head, record),
    ``uplift_max`` [m], ``slack_max`` [-], ``status``, ``fail_step``, ``fail_residual`` [N] and
    ``iterations`` [-]; what :func:`~presag_opt.dynamics.batch.system.integrate_batch` returns."""

    contact_force: np.ndarray
    uplift_max: np.ndarray
    slack_max: np.ndarray
    status: np.ndarray
    fail_step: np.ndarray
    fail_residual: np.ndarray
    iterations: np.ndarray


class Work(NamedTuple):
    """Per-step arrays of a batch: ``delta`` δ [m] and ``linear`` = C ṽ + K ũ [N] (DOF, lane); on
    the candidate rows ``g`` = rhs − s (C ṽ + K ũ) [N] (row, lane); per lane the force
    ``scale`` and the ``first_residual`` at the predictor [N]; per run the count, columns and
    coefficients s φ [N] of φ's catenary part (``phi_count``, ``phi_column``,
    ``phi_coefficient``)."""

    delta: np.ndarray
    g: np.ndarray
    linear: np.ndarray
    scale: np.ndarray
    first_residual: np.ndarray
    phi_count: np.ndarray
    phi_column: np.ndarray
    phi_coefficient: np.ndarray


class PantographStep(NamedTuple):
    """One run's pantograph quantities of a step: predictors ũ [m], ṽ [m/s]; right-hand side α r_n
    plus the uplift on the heads, C ṽ + K ũ, g = rhs − s (C ṽ + K ũ) [N]; δ_lin = K_eff⁻¹ g [m]."""

    u_pred: np.ndarray
    v_pred: np.ndarray
    rhs: np.ndarray
    linear: np.ndarray
    g: np.ndarray
    delta_lin: np.ndarray


class DropperStep(NamedTuple):
    """One run's dropper stretches of a step: at the predictor [m], its rate [m/s], and the stretch
    δ_lin adds [m]."""

    stretch: np.ndarray
    rate: np.ndarray
    linear: np.ndarray


class Scratch(NamedTuple):
    """Scratch arrays of one run's Newton iteration, allocated once per batch: the nonlinear set
    (``set_dofs``, forces ``set_force`` [N], dense ``tangent`` [N/m], each DOF's ``position`` in the
    set or −1), each head's ``contact_now`` [N], the set positions ``piece_dofs``, forces
    ``piece_force`` [N] and tangent ``piece_tangent`` [N/m] of one contribution (up to six DOFs); the
    full displacement ``u_of`` [m] and velocity ``v_of`` [m/s] at the DOFs the forces read; each
    dropper's ``stretch`` [m] and ``rate`` [m/s]; the current φ (``phi_dofs``, ``phi`` [N]) and the
    ``residual`` on the set [N]; the run's :class:`PantographStep` and :class:`DropperStep` of the
    step (``pantograph``, ``droppers``); the Woodbury correction's target x_S (``target`` [m]) and
    solution (``correction`` [N]), its capacitance matrix (``capacitance``, by columns, the leading
    count² entries used [-]) and LAPACK's ``pivots`` and integer arguments (``lapack_integers``: the
    order, one, info). The kernel's parts allocate nothing: every array they fill is one of these."""

    set_dofs: np.ndarray
    set_force: np.ndarray
    tangent: np.ndarray
    position: np.ndarray
    contact_now: np.ndarray
    piece_dofs: np.ndarray
    piece_force: np.ndarray
    piece_tangent: np.ndarray
    u_of: np.ndarray
    v_of: np.ndarray
    stretch: np.ndarray
    rate: np.ndarray
    phi_dofs: np.ndarray
    phi: np.ndarray
    residual: np.ndarray
    pantograph: PantographStep
    droppers: DropperStep
    target: np.ndarray
    correction: np.ndarray
    capacitance: np.ndarray
    pivots: np.ndarray
    lapack_integers: np.ndarray


def set_size(shared: Shared) -> int:
    """Largest nonlinear set of a run: two wire nodes and the head per pantograph, the pantograph
    DOFs twice (friction), six DOFs per dropper, and one spare. [-]"""
    return 3 * len(shared.head_dof) + 2 * len(shared.pantograph_mass) + 6 * len(shared.dropper_stiffness) + 1


def make_scratch(shared: Shared) -> Scratch:
    """The scratch arrays of the per-run Newton solve of a batch."""
    n = len(shared.mass)
    n_p = len(shared.pantograph_mass)
    n_d = len(shared.dropper_stiffness)
    size = set_size(shared)
    return Scratch(
        set_dofs=np.empty(size, dtype=np.int64),
        set_force=np.empty(size),
        tangent=np.empty((size, size)),
        position=np.full(n + n_p, -1, dtype=np.int64),
        contact_now=np.zeros(len(shared.head_dof)),
        piece_dofs=np.empty(PIECE_SIZE, dtype=np.int64),
        piece_force=np.empty(PIECE_SIZE),
        piece_tangent=np.empty((PIECE_SIZE, PIECE_SIZE)),
        u_of=np.zeros(n + n_p),
        v_of=np.zeros(n + n_p),
        stretch=np.zeros(n_d),
        rate=np.zeros(n_d),
        phi_dofs=np.empty(size, dtype=np.int64),
        phi=np.empty(size),
        residual=np.empty(size),
        pantograph=PantographStep(*(np.empty(n_p) for _ in PantographStep._fields)),
        droppers=DropperStep(*(np.empty(n_d) for _ in DropperStep._fields)),
        target=np.empty(size),
        correction=np.empty(size),
        capacitance=np.empty(size * size),
        pivots=np.empty(size, dtype=np.int32),
        lapack_integers=np.empty(3, dtype=np.int32),
    )


def swept_array(name: str, n: int, lanes: int) -> np.ndarray:
    """A zeroed, C-ordered [DOF, lane] array of the sweeps that starts at its own place in a 4 KiB page.

    Large arrays from numpy start at one offset within a page (or wherever the allocator's history puts
    them), so row j of one can lie at the same address modulo 4 KiB as row j of another. The processor
    then takes a load of one (u, v, r) for one that may depend on the store just made to the other
    (delta, linear) and waits for it: "4K aliasing". Placed :data:`SWEPT_ARRAY_STAGGER` apart, the
    paper grid's 10-run batch took 2.9–3.1 s against 3.2–3.5 s, and the case-study decision's 12 runs
    3.9–4.2 s against 4.2–4.6 s (side by side on a 2-core AMD EPYC, medians of 3 alternated twice; the
    same numbers to the last bit). All six at a page's start instead (whole cache lines, one offset)
    gained nothing: the gain is the stagger's.

    Parameters
    ----------
    name : str
        One of :data:`SWEPT_ARRAYS`.
    n : int
        Catenary DOFs. [-]
    lanes : int
        Run dimension. [-]
    """
    double = 8
    buffer = np.zeros(n * lanes + 2 * PAGE_BYTES // double)
    to_page = (-buffer.ctypes.data % PAGE_BYTES) // double  # numpy aligns to 16 bytes at least: whole doubles
    start = to_page + (SWEPT_ARRAYS.index(name) * SWEPT_ARRAY_STAGGER % PAGE_BYTES) // double
    return buffer[start:start + n * lanes].reshape(n, lanes)


def make_work(shared: Shared, n_runs: int, lanes: int | None = None) -> Work:
    """The per-step work arrays of a batch; ``lanes`` (default ``n_runs``) is the run dimension of
    the arrays the sweeps read, padded for the compiled sweeps.

    Parameters
    ----------
    shared : Shared
        What the runs of the batch share.
    n_runs : int
        Runs in the batch. [-]
    lanes : int, optional
        Run dimension of the swept arrays, at least ``n_runs`` (:func:`~presag_opt.native.sweeps.lanes_for`). [-]
    """
    lanes = n_runs if lanes is None else lanes
    n = len(shared.mass)
    n_candidates = len(shared.candidate_rows)
    size = set_size(shared)
    return Work(
        delta=swept_array("delta", n, lanes),
        g=np.zeros((n_candidates, lanes)),
        linear=swept_array("linear", n, lanes),
        scale=np.zeros(lanes),
        first_residual=np.zeros(lanes),
        phi_count=np.zeros(n_runs, dtype=np.int64),
        phi_column=np.zeros((n_runs, size), dtype=np.int64),
        phi_coefficient=np.zeros((n_runs, size)),
    )
