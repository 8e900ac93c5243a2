"""Woodbury's identity: a solve with a factorised matrix plus a low-rank update, one NumPy function.

For (A + U C V) w = r with A factorised, x = A⁻¹ r and the columns Z = A⁻¹ U known, the solution is
w = x − Z y, with y the solution of a small system whose matrix, the capacitance, has the size of
the update's rank. :func:`woodbury_update` is that last step; its callers form the capacitance in
the form their update allows:

- the single-run integrator's Newton correction
  (:meth:`presag_opt.dynamics.step_solvers.FactorisedSolver.correction`), A = K_eff, U = E, V = Eᵀ,
  C = T the nonlinear forces' tangent (possibly singular): capacitance I + T Z_SS, right-hand side
  T x_S;
- the tension-only droppers of the linearised structure
  (:meth:`presag_opt.static.linearised.TensionOnlyStructure.slack_set`), A = K, U = G_S, V = G_Sᵀ,
  C = −D_S (the slack droppers' stiffnesses, removed): the textbook capacitance C⁻¹ + V A⁻¹ U =
  G_SᵀK⁻¹G_S − D_S⁻¹, right-hand side G_Sᵀ x, and the update applied to the droppers' stretches.

The batch kernel's correction (:mod:`presag_opt.dynamics.batch.woodbury`) is the first of these
written for numba; its module notes say why it is not this function compiled.

References
----------
W. W. Hager, "Updating the inverse of a matrix", SIAM Review 31 (1989) 221–239,
doi:10.1137/1031049.
"""

from __future__ import annotations

import numpy as np

from presag_opt.errors import ConvergenceError


def woodbury_update(
    x: np.ndarray, influence: np.ndarray, capacitance: np.ndarray, rhs: np.ndarray, *, singular: str
) -> tuple[np.ndarray, np.ndarray]:
    """w = x − Z y with y = capacitance⁻¹ rhs (the last step of Woodbury's identity).

    Parameters
    ----------
    x : ndarray, shape (n,)
        Solution without the update, A⁻¹ r (or a linear map of it). [unit of w]
    influence : ndarray, shape (n, k)
        Z = A⁻¹ U (or the same map of it), one column per entry of the update. [unit of w per unit of y]
    capacitance : ndarray, shape (k, k)
        The small system's matrix. [unit of rhs per unit of y]
    rhs : ndarray, shape (k,)
        Its right-hand side. [unit of y times that of the capacitance]
    singular : str
        The one-line message of the :class:`~presag_opt.errors.ConvergenceError` raised when the
        capacitance is singular.

    Returns
    -------
    w : ndarray, shape (n,)
        The updated solution. [unit of x]
    y : ndarray, shape (k,)
        The small system's solution. [unit of rhs over that of the capacitance]

    Raises
    ------
    ConvergenceError
        If the capacitance is singular.
    """
    try:
        y = np.linalg.solve(capacitance, rhs)
    except np.linalg.LinAlgError:
        raise ConvergenceError(singular) from None
    return x - influence @ y, y
