"""The mean contact force of a pantograph, F_m = F_stat + α_ae v², defined once for the package.

The static uplift force F_stat of the pantograph plus its aerodynamic uplift α_ae v² at train speed v
is the mean contact force the quasi-static rules are evaluated at (:mod:`presag_opt.design`), the
mean uplift force a simulated pantograph presses the wire with (:mod:`presag_opt.dynamics`) and the
nominal force of a study's grid (:mod:`presag_opt.studies`). It sits below all of them. :func:`mean_force`
is the bare formula; :func:`presag_opt.design.band.mean_contact_force` checks its inputs and then calls it.

References
----------
Schick, Liu, Stichel, Railway Sciences (2025), doi:10.1108/RS-05-2025-0016, eq. (4).
"""

from __future__ import annotations


def mean_force(static_force, speed, aero_coefficient):
    r"""Mean contact force F_m = F_stat + α_ae v² (numbers or arrays; no validation here). [N]

    Parameters
    ----------
    static_force : float or ndarray
        Static uplift force F_stat. [N]
    speed : float or ndarray
        Train speed v. [m/s]
    aero_coefficient : float or ndarray
        Aerodynamic uplift coefficient α_ae. [N/(m/s)²]

    Notes
    -----
    The pantograph's static uplift plus its aerodynamic lift, quadratic in the speed (eq. 4):

    .. math::

        F_m = F_{stat} + \alpha_{ae} v^2

    Examples
    --------
    The case study's top of band, 140 N at 90 km/h with α_ae = 0.00097 N/(km/h)²:

    >>> from presag_opt.contact_force import mean_force
    >>> from presag_opt.units import KMH
    >>> round(mean_force(140.0, 90 * KMH, 0.00097 / KMH**2), 3)
    147.857
    """
    return static_force + aero_coefficient * (speed * speed)
