"""The Newton corrections of one implicit step of :func:`~presag_opt.dynamics.integrator.integrate`.

:class:`NonlinearForce` is what the force callback returns (forces on a few DOFs and their tangent).
:class:`EquationOfMotion` holds M, C, K, the force callbacks and the scheme constants
(:func:`~presag_opt.dynamics.laws.scheme_constants`); :class:`StepTerms` what one step keeps fixed
(predictors, right-hand side). The two solvers of the Newton equation (K_eff + s E T Eᵀ) δ = −R:
:class:`FactorisedSolver` factorises K_eff once and adds the tangent by Woodbury's identity from
cached columns of K_eff⁻¹ (the integrator's ``"fast"`` method; the identity's last step is
:func:`~presag_opt.static.woodbury.woodbury_update`, shared with the statics' tension-only droppers), :class:`ReferenceSolver` assembles
and factorises the full matrix every iteration (``"reference"``).

References
----------
W. W. Hager, "Updating the inverse of a matrix", SIAM Review 31 (1989) 221–239,
doi:10.1137/1031049 (Woodbury identity).
"""

from __future__ import annotations

from collections import OrderedDict
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
from scipy.sparse.linalg import splu

from presag_opt.dynamics.assembly import effective_stiffness, newmark_update
from presag_opt.dynamics.laws import SchemeConstants
from presag_opt.errors import ConvergenceError, ModelError
from presag_opt.static.banded_solver import BandedSolver
from presag_opt.static.woodbury import woodbury_update

COLUMN_CACHE_SIZE = 256
"""Columns of K_eff⁻¹ kept by the fast path: enough for the pantograph DOFs and the wire nodes a
pantograph passes over in many steps, small enough (2 MB per 1000 DOFs) for long models. [-]"""


@dataclass(frozen=True)
class NonlinearForce:
    """Nonlinear internal forces on a few DOFs and their tangent, as returned by the force callback.

    Attributes
    ----------
    dofs : numpy.ndarray
        Global DOF indices (int) the forces act on; repeated indices add up. [-]
    force : numpy.ndarray
        Force on each of ``dofs``, on the left-hand side of the equation of motion. [N]
    stiffness : numpy.ndarray
        ∂force/∂u[dofs], shape (k, k). [N/m]
    damping : numpy.ndarray or None
        ∂force/∂v[dofs], shape (k, k); None when the force does not depend on velocity. [N·s/m]
    """

    dofs: np.ndarray
    force: np.ndarray
    stiffness: np.ndarray
    damping: np.ndarray | None = None

    def __post_init__(self) -> None:
        k = len(self.dofs)
        if np.shape(self.force) != (k,) or np.shape(self.stiffness) != (k, k):
            raise ModelError(
                f"nonlinear force: {k} dofs need force of shape ({k},) and stiffness of shape ({k}, {k}), "
                f"got {np.shape(self.force)} and {np.shape(self.stiffness)}"
            )
        if self.damping is not None and np.shape(self.damping) != (k, k):
            raise ModelError(f"nonlinear force: damping must have shape ({k}, {k}), got {np.shape(self.damping)}")

    def tangent(self, a1: float) -> np.ndarray:
        """Newton tangent ∂force/∂u + a1 ∂force/∂v. [N/m]

        Parameters
        ----------
        a1 : float
            ∂v/∂u of the scheme, γ/(β Δt). [1/s]
        """
        return self.stiffness if self.damping is None else self.stiffness + a1 * self.damping


NO_FORCE = NonlinearForce(dofs=np.zeros(0, dtype=int), force=np.zeros(0), stiffness=np.zeros((0, 0)))
"""A nonlinear force that is zero everywhere."""

NonlinearForceFunction = Callable[[np.ndarray, np.ndarray, float], NonlinearForce]
"""``f(u [m], v [m/s], t [s]) -> NonlinearForce`` over the full DOF vectors."""


@dataclass
class EquationOfMotion:
    """The equation of motion and the scheme constants.

    Attributes
    ----------
    mass : scipy.sparse.csr_matrix
        Mass matrix M. [kg]
    damping : scipy.sparse.csr_matrix
        Damping matrix C. [N·s/m]
    stiffness : scipy.sparse.csr_matrix
        Stiffness matrix K. [N/m]
    external_force : callable
        ``f(t [s])``: external force on every DOF at time t [N].
    nonlinear_force : callable
        The nonlinear force callback (:data:`NonlinearForceFunction`).
    c : SchemeConstants
        Constants of the time-stepping scheme.
    """

    mass: sp.csr_matrix
    damping: sp.csr_matrix
    stiffness: sp.csr_matrix
    external_force: Callable[[float], np.ndarray]
    nonlinear_force: NonlinearForceFunction
    c: SchemeConstants

    def effective_matrix(self) -> sp.csc_matrix:
        """K_eff = a0 M + s (K + a1 C). [N/m]"""
        return effective_stiffness(self.mass, self.damping, self.stiffness, self.c).tocsc()

    def inertia(self, a: np.ndarray) -> np.ndarray:
        """M a; elementwise for a lumped (diagonal) mass matrix. [N]

        Parameters
        ----------
        a : ndarray
            Acceleration of every DOF. [m/s²]
        """
        diagonal = self.__dict__.get("_mass_diagonal")
        if diagonal is None:
            is_diagonal = self.mass.nnz == np.count_nonzero(self.mass.diagonal()) and sp.triu(self.mass, 1).nnz == 0 \
                and sp.tril(self.mass, -1).nnz == 0
            diagonal = self.mass.diagonal() if is_diagonal else False
            self.__dict__["_mass_diagonal"] = diagonal
        return diagonal * a if diagonal is not False else self.mass @ a

    def internal_force(self, u: np.ndarray, v: np.ndarray, nl: NonlinearForce) -> np.ndarray:
        """r = C v + K u + f_nl. [N]

        Parameters
        ----------
        u : ndarray
            Displacement of every DOF. [m]
        v : ndarray
            Velocity of every DOF. [m/s]
        nl : NonlinearForce
            The nonlinear forces at ``u`` and ``v``.
        """
        r = self.damping @ v + self.stiffness @ u
        np.add.at(r, nl.dofs, nl.force)
        return r


@dataclass
class StepTerms:
    """Quantities fixed during one step: predictors, external force and the right-hand side.

    Attributes
    ----------
    time : float
        Time at the end of the step, t_(n+1). [s]
    u_pred : ndarray
        Displacement predictor ũ of every DOF. [m]
    v_pred : ndarray
        Velocity predictor ṽ of every DOF. [m/s]
    forcing : ndarray
        External force on every DOF at ``time``. [N]
    rhs : ndarray
        Right-hand side of the step's equation (the HHT-α mix of forces). [N]
    """

    time: float
    u_pred: np.ndarray
    v_pred: np.ndarray
    forcing: np.ndarray
    rhs: np.ndarray

    def kinematics(self, u: np.ndarray, c: SchemeConstants) -> tuple[np.ndarray, np.ndarray]:
        """Acceleration and velocity that go with the displacement ``u``. [m/s²], [m/s]

        Parameters
        ----------
        u : ndarray
            Displacement of every DOF at the end of the step. [m]
        c : SchemeConstants
            Constants of the time-stepping scheme.
        """
        return newmark_update(u - self.u_pred, self.v_pred, c)


def full_residual(system: EquationOfMotion, step: StepTerms, u: np.ndarray, nl: NonlinearForce) -> tuple[np.ndarray, float]:
    """Residual R(u) and the size of the largest force term in it. [N], [N]

    Parameters
    ----------
    system : EquationOfMotion
        The equation of motion.
    step : StepTerms
        What the step keeps fixed.
    u : ndarray
        Displacement of every DOF (the iterate). [m]
    nl : NonlinearForce
        The nonlinear forces at ``u``.
    """
    c = system.c
    a, v = step.kinematics(u, c)
    inertia = system.inertia(a)
    internal = c.s * system.internal_force(u, v, nl)
    scale = max(norm(inertia), norm(internal), norm(step.rhs))
    return inertia + internal - step.rhs, scale


def norm(x: np.ndarray) -> float:
    """Largest absolute entry (0 for an empty vector). [as x]

    Parameters
    ----------
    x : ndarray
        A vector, such as a residual [N] or a correction [m]; the result has its unit.
    """
    return float(np.max(np.abs(x))) if x.size else 0.0


SPARSE_RIGHT_HAND_SIDE = 32
"""A right-hand side with at most this many nonzeros is solved from cached K_eff⁻¹ columns. [-]"""


class FactorisedSolver:
    """Newton corrections with K_eff factorised once and the tangent added by Woodbury's identity."""

    def __init__(self, system: EquationOfMotion):
        self._system = system
        # K_eff is symmetric positive definite and, ordered along the track, banded: the shared
        # RCM + banded Cholesky solver (SuperLU if it is not positive definite).
        matrix = sp.csc_matrix(system.effective_matrix())
        matrix.sort_indices()
        try:
            self._lu = BandedSolver.for_pattern(matrix).factorise(matrix.data)
        except RuntimeError:
            raise ModelError("the effective matrix a0 M + s (K + a1 C) is singular: check the model") from None
        self._size = matrix.shape[0]
        self._columns: OrderedDict[int, np.ndarray] = OrderedDict()

    def correction(self, rhs: np.ndarray, dofs: np.ndarray, tangent: np.ndarray) -> np.ndarray:
        """Solve (K_eff + E T Eᵀ) δ = rhs, with T = s·tangent on ``dofs``. [m]

        Parameters
        ----------
        rhs : ndarray
            Right-hand side on every DOF (−R, the negative residual). [N]
        dofs : ndarray of int
            DOFs the nonlinear forces act on (E). [-]
        tangent : ndarray, shape (len(dofs), len(dofs))
            Tangent of the nonlinear forces, :meth:`NonlinearForce.tangent`. [N/m]
        """
        loaded = np.flatnonzero(rhs)
        if len(loaded) <= SPARSE_RIGHT_HAND_SIDE:
            # After a step's first correction the residual lives on the nonlinear DOFs only.
            x = self._inverse_columns(loaded) @ rhs[loaded]
        else:
            x = self._lu.solve(rhs)
        if len(dofs) == 0:
            return x
        z = self._inverse_columns(dofs)
        t = self._system.c.s * tangent
        return woodbury_update(x, z, np.eye(len(dofs)) + t @ z[dofs, :], t @ x[dofs],
                               singular="singular Newton matrix: the nonlinear tangent cancels K_eff")[0]

    def next_residual(
        self,
        step: StepTerms,
        u: np.ndarray,
        old: NonlinearForce,
        new: NonlinearForce,
        tangent: np.ndarray,
        delta: np.ndarray,
    ) -> np.ndarray:
        """Residual after a correction: the exact linear part cancels, so only f_nl's change is left.

        R(u + δ) = R(u) + K_eff δ + s (f_nl,new - f_nl,old) and the correction made
        K_eff δ = -R(u) - s T δ[dofs], so R(u + δ) = s (f_nl,new - f_nl,old - T δ[dofs]).

        Parameters
        ----------
        step : StepTerms
            What the step keeps fixed.
        u : ndarray
            Displacement of every DOF after the correction. [m]
        old : NonlinearForce
            The nonlinear forces before the correction.
        new : NonlinearForce
            The nonlinear forces at ``u``.
        tangent : ndarray, shape (len(old.dofs), len(old.dofs))
            The tangent the correction was solved with. [N/m]
        delta : ndarray
            The correction δ of every DOF. [m]
        """
        r = np.zeros_like(u)
        np.add.at(r, new.dofs, new.force)
        np.add.at(r, old.dofs, -old.force - tangent @ delta[old.dofs])
        return self._system.c.s * r

    def _inverse_columns(self, dofs: np.ndarray) -> np.ndarray:
        """Columns K_eff⁻¹ e_j for j in ``dofs``, computed once and kept while recently used. [m/N]"""
        missing = [int(j) for j in dict.fromkeys(dofs.tolist()) if j not in self._columns]
        if missing:
            unit = np.zeros((self._size, len(missing)))
            unit[missing, range(len(missing))] = 1.0
            for j, column in zip(missing, self._lu.solve(unit).T):
                self._columns[j] = column
        for j in dofs.tolist():
            self._columns.move_to_end(j)
        while len(self._columns) > COLUMN_CACHE_SIZE:
            self._columns.popitem(last=False)
        return np.column_stack([self._columns[j] for j in dofs.tolist()])


class ReferenceSolver:
    """Newton corrections by assembling and factorising the full Newton matrix every iteration."""

    def __init__(self, system: EquationOfMotion):
        self._system = system

    def correction(self, rhs: np.ndarray, dofs: np.ndarray, tangent: np.ndarray) -> np.ndarray:
        """Solve (K_eff + s E T Eᵀ) δ = rhs by a fresh sparse LU factorisation. [m]

        Parameters
        ----------
        rhs : ndarray
            Right-hand side on every DOF (−R, the negative residual). [N]
        dofs : ndarray of int
            DOFs the nonlinear forces act on (E). [-]
        tangent : ndarray, shape (len(dofs), len(dofs))
            Tangent of the nonlinear forces, :meth:`NonlinearForce.tangent`. [N/m]
        """
        n = len(rhs)
        rows, cols = np.meshgrid(dofs, dofs, indexing="ij")
        update = sp.coo_matrix((self._system.c.s * tangent.ravel(), (rows.ravel(), cols.ravel())), shape=(n, n))
        try:
            return splu((self._system.effective_matrix() + update).tocsc()).solve(rhs)
        except RuntimeError as exc:
            raise ConvergenceError(f"singular Newton matrix ({exc})") from None

    def next_residual(
        self,
        step: StepTerms,
        u: np.ndarray,
        old: NonlinearForce,
        new: NonlinearForce,
        tangent: np.ndarray,
        delta: np.ndarray,
    ) -> np.ndarray:
        """Full residual at the new iterate. [N]

        Parameters
        ----------
        step : StepTerms
            What the step keeps fixed.
        u : ndarray
            Displacement of every DOF after the correction. [m]
        old : NonlinearForce
            The nonlinear forces before the correction.
        new : NonlinearForce
            The nonlinear forces at ``u``.
        tangent : ndarray, shape (len(old.dofs), len(old.dofs))
            The tangent the correction was solved with. [N/m]
        delta : ndarray
            The correction δ of every DOF. [m]
        """
        return full_residual(self._system, step, u, new)[0]
