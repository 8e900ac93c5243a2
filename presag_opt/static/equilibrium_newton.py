"""Newton's method on the potential energy: the equilibrium of a static model under given parameters.

:func:`newton_equilibrium` minimises the potential (:mod:`presag_opt.static.potential`) from a
starting point, droppers free to go slack, to the force tolerance :func:`force_tolerance`;
:func:`newton_solve` does the same from the terms a previous solve left (:class:`NewtonTerms`), which
is how :meth:`presag_opt.static.equilibrium.EquilibriumState.solve` walks along a loaded span.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from presag_opt.errors import ConvergenceError
from presag_opt.static.banded_solver import Factor
from presag_opt.static.discretisation import StaticSettings
from presag_opt.static.potential import PhysicalParameters

if TYPE_CHECKING:
    from presag_opt.static.equilibrium import StaticModel


ROUND_OFF_FACTOR = 16.0
"""Multiple of machine epsilon in the round-off floor of the force tolerance. [-]"""


def force_tolerance(params: PhysicalParameters, x: np.ndarray, settings: StaticSettings) -> float:
    """Out-of-balance force accepted at equilibrium. [N]

    ``settings.force_tolerance``, but never below the round-off of the nodal forces: an element of
    stiffness k between nodes at coordinates of size |x| cannot balance better than about
    ε·k·|x| (ε machine epsilon); short stiff elements far from the origin reach 1e-4 N.

    Parameters
    ----------
    params : PhysicalParameters
        Parameter values (their axial stiffness).
    x : ndarray
        Coordinates of every DOF. [m]
    settings : StaticSettings
        Numerical settings (``force_tolerance``).
    """
    return max(settings.force_tolerance, round_off_force(params, x))


def round_off_force(params: PhysicalParameters, x: np.ndarray) -> float:
    """The round-off of the nodal forces: no balance can be checked more finely than this. [N]

    :data:`ROUND_OFF_FACTOR` · ε · k_max · x_max (ε machine epsilon, k_max the stiffest axial element,
    x_max the largest coordinate in size).

    Parameters
    ----------
    params : PhysicalParameters
        Parameter values (their axial stiffness).
    x : ndarray
        Coordinates of every DOF. [m]
    """
    return ROUND_OFF_FACTOR * np.finfo(float).eps * float(params.axial_stiffness.max()) * float(np.abs(x).max())


def newton_equilibrium(
    model: StaticModel, params: PhysicalParameters, x0: np.ndarray, settings: StaticSettings
) -> tuple[np.ndarray, int]:
    """Minimise the potential energy by Newton's method with a backtracking line search.

    Slack droppers make the energy only once differentiable; the generalised (semi-smooth) Newton
    step with the current active set converges in a few iterations, and the line search guards the
    steps where the set changes. A factorisation of the tangent stiffness is kept while its steps
    reduce the out-of-balance force a hundredfold or more (:data:`REFACTORISE_RATE`): the converged
    state meets the same force tolerance, and an elasticity curve needs one factorisation per point
    instead of three (its values move by 4e-8 relative, measured on ST 9,8/9,8 at 50–250 N).

    Parameters
    ----------
    model : StaticModel
        The static model.
    params : PhysicalParameters
        Parameter values (loads included).
    x0 : ndarray
        Starting coordinates of every DOF. [m]
    settings : StaticSettings
        Numerical settings (``force_tolerance``, ``max_newton_iterations``).

    Returns
    -------
    x : ndarray
        Equilibrium coordinates. [m]
    iterations : int
        Newton iterations used. [-]

    Raises
    ------
    ConvergenceError
        If the largest out-of-balance force stays above ``settings.force_tolerance``.
    """
    x, iterations, _ = newton_solve(model, params, x0, settings)
    return x, iterations


@dataclass(frozen=True)
class NewtonTerms:
    """What a Newton solve leaves for the next one that starts where it ended.

    Attributes
    ----------
    gradient : ndarray
        Out-of-balance force on the free DOFs at the solution, under its loads. [N]
    factor : Factor or None
        The last factorised tangent stiffness (of an iterate near the solution), or None if the
        solve needed none (it started at equilibrium). [N/m]
    """

    gradient: np.ndarray
    factor: Factor | None


REFACTORISE_RATE = 0.01
"""A Newton step that leaves more than this share of the out-of-balance force makes the next step
use a new factorisation of the tangent stiffness; faster steps keep the old one (the chord method:
each step costs a solve instead of a factorisation, and the iteration still stops only at the force
tolerance). [-]"""


def newton_solve(
    model: StaticModel,
    params: PhysicalParameters,
    x0: np.ndarray,
    settings: StaticSettings,
    terms: NewtonTerms | None = None,
) -> tuple[np.ndarray, int, NewtonTerms]:
    """:func:`newton_equilibrium`, optionally started from the gradient at ``x0`` under ``params`` and a
    factorisation near ``x0`` (``terms``), returning the same at the solution.

    The factorisation is kept while the steps it gives converge fast (:data:`REFACTORISE_RATE`) and
    renewed at the current iterate otherwise, so the solution meets the same force tolerance as
    Newton's method, mostly at the cost of one back-substitution per step.

    Parameters
    ----------
    model : StaticModel
        The static model.
    params : PhysicalParameters
        Parameter values (loads included).
    x0 : ndarray
        Starting coordinates of every DOF. [m]
    settings : StaticSettings
        Numerical settings (``force_tolerance``, ``max_newton_iterations``).
    terms : NewtonTerms, optional
        What the previous solve left (gradient and factorisation near ``x0``); None to start afresh.
    """
    funcs = model.functions
    free = funcs.free_dofs
    x = x0.copy()
    tolerance = force_tolerance(params, x, settings)
    if terms is None:
        grad, factor = funcs.gradient(x, params)[free], None
    else:
        grad, factor = terms.gradient, terms.factor
    residual = np.abs(grad).max(initial=0.0)
    renew = factor is None
    for iteration in range(settings.max_newton_iterations):
        if residual <= tolerance:
            return x, iteration, NewtonTerms(grad, factor)
        if renew:
            factor = _factorise(funcs, x, params, iteration)
        step = -factor.solve(grad)
        alpha, energy = 1.0, None
        while True:
            trial = x.copy()
            trial[free] += alpha * step
            new_grad = funcs.gradient(trial, params)[free]
            new_residual = np.abs(new_grad).max(initial=0.0)
            if new_residual < 0.5 * residual or alpha < 1e-3:
                break
            # Armijo test on the energy, for steps that change the set of slack droppers.
            energy = funcs.energy(x, params) if energy is None else energy
            if funcs.energy(trial, params) - energy <= 1e-4 * alpha * float(grad @ step) + 1e-12 * abs(energy):
                break
            alpha *= 0.5
        renew = new_residual > REFACTORISE_RATE * residual
        x, grad, residual = trial, new_grad, new_residual
    if residual <= tolerance:
        return x, settings.max_newton_iterations, NewtonTerms(grad, factor)
    raise ConvergenceError(
        f"equilibrium did not converge: largest out-of-balance force {residual:.3g} N after "
        f"{settings.max_newton_iterations} Newton iterations (tolerance {tolerance:.3g} N)",
        {"residual_N": residual, "iterations": settings.max_newton_iterations},
    )


def _factorise(funcs, x: np.ndarray, params: PhysicalParameters, iteration: int) -> Factor:
    """Factorisation of the tangent stiffness at ``x``; a singular one raises ConvergenceError."""
    hess, _ = funcs.hessian_values(x, params)
    try:
        return funcs.solver.factorise(hess)
    except RuntimeError as exc:
        raise ConvergenceError(f"equilibrium: singular tangent stiffness ({exc})", {"iteration": iteration}) from None
