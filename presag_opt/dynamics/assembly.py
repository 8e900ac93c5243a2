"""How the laws enter a time step's equations, written once for both engines.

The laws themselves are :mod:`presag_opt.dynamics.laws`; this module holds the arithmetic around
them that each engine used to write for itself: the step's matrix K_eff, the Newmark predictor and
update, the penetration of a pantograph head into the contact wire, and the contributions of the
contact (on the wire's two nodes and the head) and of a slack dropper (on its six DOFs) as force and
tangent on small fixed-size arrays. The functions are plain Python on numbers, or on NumPy arrays where
the operations broadcast, with no call to another function (K_eff, on matrices, is not compiled): the single-run engine
(:mod:`presag_opt.dynamics.integrator`, :mod:`presag_opt.dynamics.simulate`) calls them as they
are, and the batch kernel (:mod:`presag_opt.dynamics.batch`) compiles the same functions inline with
numba. The written order of each operation is the order every engine rounds in; the C sweeps
(``native/sweeps.c``) repeat the predictor and update of the catenary's DOFs in that order, and the
tests hold them to the last bit.

Newmark kinematics (see :func:`~presag_opt.dynamics.laws.scheme_constants` for the constants)
    ũ = u_n + Δt v_n + Δt² (1/2 − β) a_n,  ṽ = v_n + Δt (1 − γ) a_n;  for δ = u_(n+1) − ũ:
    a_(n+1) = a0 δ,  v_(n+1) = ṽ + γ Δt a_(n+1).
Contact
    The penetration of the head into the chord between the two contact-wire nodes under it,
    g = z_head − (w1 z1 + w2 z2); with the gradient (−w1, −w2, 1) of g over (node 1, node 2, head),
    the contact force f_c on the three DOFs is f_c ∂g and its tangent k_t ∂g ∂gᵀ.

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


def contact_contribution(force, tangent, weight_1, weight_2, dof_force, dof_tangent):
    """The contact's force [N] and tangent [N/m] on (node 1, node 2, head), written into
    ``dof_force`` (3) and ``dof_tangent`` (3 × 3).

    Parameters
    ----------
    force : float
        Contact force f_c (:func:`~presag_opt.dynamics.laws.contact_force`). [N]
    tangent : float
        Its derivative by the penetration (:func:`~presag_opt.dynamics.laws.contact_tangent`). [N/m]
    weight_1, weight_2 : float
        Shape-function weights of the two contact-wire nodes. [-]
    dof_force : ndarray, shape (3,)
        Receives f_c ∂g. [N]
    dof_tangent : ndarray, shape (3, 3)
        Receives k_t ∂g ∂gᵀ. [N/m]
    """
    gradient = (-weight_1, -weight_2, 1.0)
    for i in range(3):
        dof_force[i] = gradient[i] * force
        row = tangent * gradient[i]
        for j in range(3):
            dof_tangent[i, j] = row * gradient[j]


def slack_dropper_contribution(axial, stiffness, gradient, dof_force, dof_tangent):
    """The force [N] and tangent [N/m] on a slack dropper's six DOFs that remove the axial part of
    its linear contribution, written into ``dof_force`` (6) and ``dof_tangent`` (6 × 6).

    Parameters
    ----------
    axial : float
        The dropper's axial force N (:func:`~presag_opt.dynamics.laws.dropper_axial_force`), below
        zero. [N]
    stiffness : float
        What removes the axial stiffness from the tangent: −k for ∂f/∂u, −k (1 + a1 β_R) for the
        Newton tangent ∂f/∂u + a1 ∂f/∂v of a time step. [N/m]
    gradient : ndarray, shape (6,)
        The stretch's gradient B = [−e, e] over the dropper's six DOFs. [-]
    dof_force : ndarray, shape (6,)
        Receives −N B. [N]
    dof_tangent : ndarray, shape (6, 6)
        Receives ``stiffness`` B Bᵀ. [N/m]
    """
    for i in range(6):
        dof_force[i] = -axial * gradient[i]
        row = stiffness * gradient[i]
        for j in range(6):
            dof_tangent[i, j] = row * gradient[j]
