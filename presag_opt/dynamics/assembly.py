"""How the laws enter a time step's equations, written once for both engines.

The laws themselves are :mod:`presag_opt.dynamics.laws`; this module holds the arithmetic around
them that each engine used to write for itself: the step's matrix K_eff, the Newmark predictor and
update, the penetration of a pantograph head into the contact wire, and how each nonlinear force
(contact, friction, slack dropper) adds its force and tangent to the few DOFs it acts on
(:func:`force_contribution`, on small fixed-size arrays). The functions are plain Python on numbers, or on NumPy arrays where
the operations broadcast, with no call to another function (K_eff, on matrices, is not compiled): the single-run engine
(:mod:`presag_opt.dynamics.integrator`, :mod:`presag_opt.dynamics.simulate`) calls them as they
are, and the batch kernel (:mod:`presag_opt.dynamics.batch`) compiles the same functions with
numba. The written order of each operation is the order every engine rounds in; the C sweeps
(``native/sweeps.c``) repeat the predictor and update of the catenary's DOFs in that order, and the
tests hold them to the last bit.

Newmark kinematics (see :func:`~presag_opt.dynamics.laws.scheme_constants` for the constants)
    ũ = u_n + Δt v_n + Δt² (1/2 − β) a_n,  ṽ = v_n + Δt (1 − γ) a_n;  for δ = u_(n+1) − ũ:
    a_(n+1) = a0 δ,  v_(n+1) = ṽ + γ Δt a_(n+1).
Nonlinear forces
    Each acts along a scalar measure g of a few DOFs: the penetration of the head into the chord
    between the two contact-wire nodes under it, g = z_head − (w1 z1 + w2 z2), with gradient
    (−w1, −w2, 1) over (node 1, node 2, head); a pantograph stage's velocity relative to the stage
    below, (1, −1); a dropper's stretch, B = [−e, e] over its six DOFs. A force f along g with
    tangent k gives f ∂g on the DOFs and k ∂g ∂gᵀ in the Newton matrix.

References
----------
N. M. Newmark, J. Eng. Mech. Div. ASCE 85 (1959) 67–94. Schick, Liu, Stichel, Railway Sciences
(2025), doi:10.1108/RS-05-2025-0016, section 2 (penalty contact).
"""

from __future__ import annotations


def effective_stiffness(mass, damping, stiffness, scheme):
    """The step's constant matrix K_eff = a0 M + s (K + a1 C) [N/m], of sparse or dense matrices
    (every engine's, the catenary's and the pantographs'; not compiled).

    Parameters
    ----------
    mass, damping, stiffness : sparse matrix or ndarray
        M [kg], C [N·s/m] and K [N/m].
    scheme : SchemeConstants
        The time step and the scheme's constants.
    """
    return scheme.a0 * mass + scheme.s * (stiffness + scheme.a1 * damping)


def newmark_predictor(displacement, velocity, acceleration, scheme):
    """The step's predictors ũ [m] and ṽ [m/s] from the state at its start.

    Parameters
    ----------
    displacement, velocity, acceleration : float or ndarray
        u_n [m], v_n [m/s] and a_n [m/s²].
    scheme : SchemeConstants
        The time step and the scheme's constants (:func:`~presag_opt.dynamics.laws.scheme_constants`).
    """
    return (displacement + scheme.time_step * velocity + scheme.displacement_predictor * acceleration,
            velocity + scheme.velocity_predictor * acceleration)


def newmark_update(delta, velocity_predictor, scheme):
    """Acceleration [m/s²] and velocity [m/s] at the step's end from δ = u_(n+1) − ũ.

    Parameters
    ----------
    delta : float or ndarray
        Displacement from the predictor, δ. [m]
    velocity_predictor : float or ndarray
        ṽ. [m/s]
    scheme : SchemeConstants
        The time step and the scheme's constants.
    """
    acceleration = scheme.a0 * delta
    return acceleration, velocity_predictor + scheme.velocity_update * acceleration


def head_penetration(head_height, head_displacement, weight_1, height_1, displacement_1, weight_2, height_2,
                     displacement_2):
    """Penetration of a pantograph head into the chord of the contact-wire element under it [m]
    (positive: in contact).

    Parameters
    ----------
    head_height, head_displacement : float
        The head's height at rest [m] and its displacement [m].
    weight_1, weight_2 : float
        Linear shape-function weights of the element's two nodes at the contact point. [-]
    height_1, height_2 : float
        The nodes' static heights. [m]
    displacement_1, displacement_2 : float
        The nodes' vertical displacements. [m]
    """
    wire = weight_1 * (height_1 + displacement_1) + weight_2 * (height_2 + displacement_2)
    return head_height + head_displacement - wire


def force_contribution(force, tangent, gradient, dof_force, dof_tangent):
    """A nonlinear force along a scalar measure g of a few DOFs (a penetration, a relative velocity, a
    dropper's stretch): the force f ∂g [N] and the tangent k ∂g ∂gᵀ [N/m] on those DOFs, written into
    ``dof_force`` and ``dof_tangent``. Every nonlinear force of the dynamic model enters both engines'
    equations through this one function.

    Parameters
    ----------
    force : float
        The force along g, f (the contact force, a friction force, minus a slack dropper's axial
        force). [N]
    tangent : float
        Its Newton tangent k along g (∂f/∂g, or a1 ∂f/∂ġ for friction). [N/m]
    gradient : tuple or ndarray of float
        ∂g over the DOFs, one entry each: (−w1, −w2, 1) for a head's penetration of the wire between
        two nodes, (1, −1) for a stage's velocity relative to the stage below, B = [−e, e] for a
        dropper's stretch. [-]
    dof_force : ndarray
        Receives f ∂g (as many entries as ``gradient``). [N]
    dof_tangent : ndarray
        Receives k ∂g ∂gᵀ (square, as many rows as ``gradient``). [N/m]
    """
    for i in range(len(gradient)):
        dof_force[i] = gradient[i] * force
        row = tangent * gradient[i]
        for j in range(len(gradient)):
            dof_tangent[i, j] = row * gradient[j]
