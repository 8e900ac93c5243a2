"""The physical laws of the dynamic model and the constants of its time scheme, each written once.

Every engine uses these functions: the single-run path (:mod:`presag_opt.dynamics.simulate`,
:mod:`presag_opt.dynamics.pantograph`, :mod:`presag_opt.dynamics.structure`,
:mod:`presag_opt.dynamics.integrator`) calls them as plain Python, on numbers or on NumPy arrays;
the batch kernel (:mod:`presag_opt.dynamics.batch.forces`) compiles the same functions with numba
(as kernel parts) and calls them on numbers. This module imports no numba, so the single-run path stays
numba-free. The written order of every operation is the order the engines round in: a change here
changes every engine, and nothing else defines these laws.

Contact
    Penalty spring k_c between the pantograph head and the contact wire, in series with the
    compliance h t (1 − t)/T of the wire element under the head (the point-load deflection of a
    tensioned element that the linear shape functions leave out): k = 1/(1/k_c + c). The force is
    k × penetration while the head penetrates the chord between the element's nodes, zero in a gap.
Dry friction
    Regularised Coulomb friction of a pantograph stage's suspension, F = F0 tanh(Δv / v_reg), on the
    velocity Δv of the stage relative to the stage below (the car body for the lowest stage).
Droppers (tension only)
    The axial force of a linearised dropper, N = N0 + k e + β_R k ė, from its stretch e and rate ė
    (its share of the stiffness-proportional Rayleigh damping included) is
    :func:`~presag_opt.static.linearised.dropper_axial_force`, the law the static active set uses
    too; a dropper is slack where N < 0 (:func:`~presag_opt.static.linearised.dropper_slack`), and
    its tension is max(N, 0) (:func:`dropper_tension`).
Pantograph stages
    Stage i hangs on a spring, a damper and a friction element to stage i + 1, the lowest stage on
    the car body (fixed): :func:`suspension_elements` lists them, once for the pantograph's matrices
    and for the batch's friction elements.
Time scheme
    HHT-α (Newmark's average acceleration for α = 0): γ = 1/2 − α, β = (1 − α)²/4, and the
    constants the step uses (:func:`scheme_constants`).

References
----------
H. M. Hilber, T. J. R. Hughes, R. L. Taylor, Earthq. Eng. Struct. Dyn. 5 (1977) 283–292,
doi:10.1002/eqe.4290050306 (HHT-α). Schick, Liu, Stichel, Railway Sciences (2025),
doi:10.1108/RS-05-2025-0016, section 2 (penalty contact, tension-only droppers).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from presag_opt.static.linearised import dropper_axial_force, dropper_slack

__all__ = [
    "SchemeConstants",
    "contact_force",
    "contact_stiffness",
    "contact_tangent",
    "dropper_axial_force",
    "dropper_slack",
    "dropper_tension",
    "friction",
    "head_height_in_contact",
    "scheme_constants",
    "suspension_elements",
]


def contact_stiffness(penalty_stiffness, element_compliance):
    """Contact stiffness of the penalty spring in series with the wire element, 1/(1/k_c + c). [N/m]

    Parameters
    ----------
    penalty_stiffness : float
        Penalty (contact) stiffness k_c. [N/m]
    element_compliance : float
        Point-load deflection per unit force of the wire element under the head. [m/N]
    """
    return 1.0 / (1.0 / penalty_stiffness + element_compliance)


def contact_force(stiffness, penetration):
    r"""Compressive contact force: stiffness × penetration in contact, zero in a gap. [N]

    Parameters
    ----------
    stiffness : float
        Contact stiffness (:func:`contact_stiffness`). [N/m]
    penetration : float
        Head height minus the height of the wire's chord at the contact point. [m]

    Notes
    -----
    A unilateral penalty law: the penalty spring k_c in series with the compliance c of the wire
    element under the head (:func:`contact_stiffness`), active only while the head penetrates:

    .. math::

        F_c = \frac{\langle \delta \rangle}{1/k_c + c}, \qquad
        \langle \delta \rangle = \max(\delta, 0).

    Examples
    --------
    A 50 kN/m penalty spring on a wire element of 1e-5 m/N, penetrated by 2 mm, and in a gap:

    >>> from presag_opt.dynamics.laws import contact_force, contact_stiffness
    >>> k = contact_stiffness(50_000.0, 1e-5)
    >>> print(f"{k:.0f} N/m: {contact_force(k, 2e-3):.1f} N in contact, {contact_force(k, -1e-3):.1f} N in a gap")
    33333 N/m: 66.7 N in contact, 0.0 N in a gap
    """
    return stiffness * penetration if penetration > 0.0 else 0.0


def head_height_in_contact(chord_height, penalty_stiffness, element_compliance, force):
    """Height of a head that presses the wire with the contact force ``force``: the chord's height
    plus the penetration F (c + 1/k_c) that :func:`contact_force` turns into F (its inverse). [m]

    Parameters
    ----------
    chord_height : float
        Height of the wire element's chord at the contact point. [m]
    penalty_stiffness : float
        Penalty (contact) stiffness k_c. [N/m]
    element_compliance : float
        Point-load deflection per unit force of the wire element under the head, c. [m/N]
    force : float
        Contact force F, positive. [N]
    """
    return chord_height + element_compliance * force + force / penalty_stiffness


def contact_tangent(stiffness, penetration):
    """Derivative of :func:`contact_force` with respect to the penetration. [N/m]

    Parameters
    ----------
    stiffness : float
        Contact stiffness. [N/m]
    penetration : float
        As for :func:`contact_force`. [m]
    """
    return stiffness if penetration > 0.0 else 0.0


def friction(level, relative_velocity, regularisation_velocity, factor):
    r"""Regularised Coulomb friction F0 tanh(Δv / v_reg) and ``factor`` times its slope ∂F/∂Δv.

    Works on numbers and on arrays of elements alike.

    Parameters
    ----------
    level : float or ndarray
        Friction force level F0. [N]
    relative_velocity : float or ndarray
        Velocity of the stage relative to the stage below (or the car body). [m/s]
    regularisation_velocity : float
        v_reg. [m/s]
    factor : float
        Multiplies the slope, and is applied first: 1 gives ∂F/∂Δv [N·s/m]; the Newton tangent of a
        time step a1 ∂F/∂Δv [N/m], with a1 = γ/(β Δt) [1/s].

    Returns
    -------
    force : float or ndarray
        Friction force, with the sign of the relative motion it resists. [N]
    slope : float or ndarray
        factor · F0/v_reg · (1 − tanh²(Δv / v_reg)). [N·s/m times the unit of ``factor``]

    Notes
    -----
    Coulomb friction of level F0, regularised over v_reg so that the Newton iteration of an implicit
    step sees a smooth law:

    .. math::

        F_f = F_0 \tanh\!\left(\frac{\Delta v}{v_{reg}}\right), \qquad
        \frac{\partial F_f}{\partial \Delta v} = \frac{F_0}{v_{reg}}
        \left(1 - \tanh^2\frac{\Delta v}{v_{reg}}\right).

    Examples
    --------
    >>> from presag_opt.dynamics.laws import friction
    >>> force, slope = friction(10.0, 0.5, 0.01, 1.0)
    >>> round(float(force), 6), round(float(slope), 6)
    (10.0, 0.0)
    """
    th = np.tanh(relative_velocity / regularisation_velocity)
    return level * th, factor * level / regularisation_velocity * (1.0 - th * th)


def dropper_tension(axial):
    r"""Tensile force of a tension-only dropper: max(N, 0). [N]

    Parameters
    ----------
    axial : float or ndarray
        Axial force of the linearised dropper (:func:`dropper_axial_force`). [N]

    Notes
    -----
    The linearised dropper's axial force from its stretch e and rate ė (the Rayleigh share β_R of
    its stiffness as damping) carries tension only:

    .. math::

        N = N_0 + k\,e + \beta_R k\,\dot e, \qquad T = \max(N, 0).

    Examples
    --------
    >>> from presag_opt.dynamics.laws import dropper_tension
    >>> dropper_tension([120.0, -5.0]).tolist()
    [120.0, 0.0]
    """
    return np.maximum(axial, 0.0)


def suspension_elements(n_stages: int) -> tuple[tuple[int, int], ...]:
    """The suspension elements of a pantograph: (stage, stage below), −1 for the car body.

    Parameters
    ----------
    n_stages : int
        Stages (masses), head first. [-]
    """
    return tuple((i, i + 1 if i + 1 < n_stages else -1) for i in range(n_stages))


class SchemeConstants(NamedTuple):
    """The constants of one HHT-α / Newmark time step.

    Attributes
    ----------
    time_step : float
        Δt. [s]
    alpha : float
        HHT α; 0 for Newmark's average acceleration. [-]
    beta : float
        Newmark β = (1 − α)²/4. [-]
    gamma : float
        Newmark γ = 1/2 − α. [-]
    s : float
        1 + α. [-]
    a0 : float
        ∂a/∂u = 1/(β Δt²). [1/s²]
    a1 : float
        ∂v/∂u = γ/(β Δt). [1/s]
    velocity_predictor : float
        Δt (1 − γ): ṽ = v_n + Δt (1 − γ) a_n. [s]
    displacement_predictor : float
        Δt² (1/2 − β): ũ = u_n + Δt v_n + Δt² (1/2 − β) a_n. [s²]
    velocity_update : float
        γ Δt: v_(n+1) = ṽ + γ Δt a_(n+1). [s]
    """

    time_step: float
    alpha: float
    beta: float
    gamma: float
    s: float
    a0: float
    a1: float
    velocity_predictor: float
    displacement_predictor: float
    velocity_update: float


def scheme_constants(settings) -> SchemeConstants:
    r"""The HHT-α / Newmark constants of an integrator's settings.

    Parameters
    ----------
    settings : IntegratorSettings
        Its ``scheme`` ("newmark": α = 0; "hht": ``hht_alpha``) and ``time_step`` [s].

    Returns
    -------
    SchemeConstants

    Notes
    -----
    HHT-α takes the equation of motion at a weighted instant of the step, with Newmark's update of
    the displacement and velocity; α ∈ [−1/3, 0] damps the highest frequencies (α = 0 is Newmark's
    average acceleration, without numerical damping):

    .. math::

        M a_{n+1} + (1 + \alpha)\left(C v_{n+1} + f(u_{n+1})\right) - \alpha \left(C v_n + f(u_n)\right)
        = (1 + \alpha) F_{n+1} - \alpha F_n,

        u_{n+1} = u_n + \Delta t\, v_n + \Delta t^2 \left[(\tfrac12 - \beta) a_n + \beta a_{n+1}\right], \qquad
        v_{n+1} = v_n + \Delta t \left[(1 - \gamma) a_n + \gamma a_{n+1}\right],

    with :math:`\gamma = 1/2 - \alpha` and :math:`\beta = (1 - \alpha)^2/4`.

    Examples
    --------
    >>> from presag_opt.dynamics.integrator import IntegratorSettings
    >>> from presag_opt.dynamics.laws import scheme_constants
    >>> c = scheme_constants(IntegratorSettings(scheme="hht", hht_alpha=-0.005, time_step=2e-3))
    >>> round(c.gamma, 4), round(c.beta, 6)
    (0.505, 0.252506)
    """
    alpha = settings.hht_alpha if settings.scheme == "hht" else 0.0
    dt = settings.time_step
    beta = (1.0 - alpha) ** 2 / 4.0
    gamma = 0.5 - alpha
    return SchemeConstants(
        time_step=dt,
        alpha=alpha,
        beta=beta,
        gamma=gamma,
        s=1.0 + alpha,
        a0=1.0 / (beta * dt**2),
        a1=gamma / (beta * dt),
        velocity_predictor=dt * (1.0 - gamma),
        displacement_predictor=dt**2 * (0.5 - beta),
        velocity_update=gamma * dt,
    )
