"""Where a quasi-static pre-sag holds: the speed band against the wave speed, the steady-arm uplift.

Holds :func:`speed_context` (wave speed, β = v/c_CW, Doppler factor and the paper's validity
statement of the band) and the static steady-arm uplift estimate against the case study's limit. The
wave-speed formulas themselves are in :mod:`presag_opt.speed`; the validity limit and its one
sentence in :mod:`presag_opt.design.validity_limit`; the dynamic uplift comes from
:mod:`presag_opt.dynamics`.

References
----------
Schick, Liu, Stichel, "Validity range of a quasi-static method for adjusting the pre-sag of simple
railway catenary systems", Railway Sciences (2025), doi:10.1108/RS-05-2025-0016: sections 5.2 and 6
(validity β ≤ 0.4, steady-arm uplift limit 83.5 mm).
"""

from __future__ import annotations

from dataclasses import dataclass

from presag_opt.contact_force import mean_force
from presag_opt.design.validity_limit import PAPER_LIMIT, ValidityStatement, validity_statement
from presag_opt.speed import doppler_factor, speed_ratio
from presag_opt.system.components import Wire
from presag_opt.units import KMH

QUASI_STATIC_BETA_LIMIT = PAPER_LIMIT
"""Speed ratio β = v/c_CW up to which the paper finds the quasi-static rule valid (the high end of its
limit; :mod:`presag_opt.design.validity_limit` holds the whole statement). [-]"""

STEADY_ARM_UPLIFT_LIMIT = 0.0835
"""Largest allowed steady-arm uplift of the case study (arms without uplift stop). [m]"""


@dataclass(frozen=True, kw_only=True)
class SpeedContext:
    """Where a speed band lies against the contact wire's wave speed.

    Attributes
    ----------
    wave_speed : float
        Contact-wire wave speed c_CW = sqrt(T_CW/ρ_CW). [m/s]
    speed_low, speed_high : float
        Speed band. [m/s]
    beta_low, beta_max : float
        Speed ratio β = v/c_CW at the ends of the band. [-]
    doppler_factor_min : float
        Doppler factor (c − v)/(c + v) at the highest speed (its smallest value). [-]
    validity : ValidityStatement
        The band against the paper's validity limit (a decision restates it with a validity sweep
        where one was read).

    References
    ----------
    Schick, Liu, Stichel (2025), doi:10.1108/RS-05-2025-0016, sections 5.2 and 6 (valid up to 40 %
    of c_CW).
    """

    wave_speed: float
    speed_low: float
    speed_high: float
    beta_low: float
    beta_max: float
    doppler_factor_min: float
    validity: ValidityStatement

    def to_dict(self) -> dict:
        """JSON-ready content (m/s and km/h)."""
        return {
            "wave_speed_m_per_s": self.wave_speed,
            "speed_kmh": [self.speed_low / KMH, self.speed_high / KMH],
            "beta_low": self.beta_low,
            "beta_max": self.beta_max,
            "doppler_factor_min": self.doppler_factor_min,
            "validity": self.validity.to_dict(),
        }


def speed_context(contact_wire: Wire, speed_low: float, speed_high: float) -> SpeedContext:
    """Wave speed, speed ratios, Doppler factor and the paper's validity statement for a band.

    Parameters
    ----------
    contact_wire : Wire
        The contact wire (tension and mass per metre).
    speed_low, speed_high : float
        Speed band. [m/s]

    Returns
    -------
    SpeedContext

    Raises
    ------
    ModelError
        If a speed is negative or at or above the wave speed.

    References
    ----------
    Schick, Liu, Stichel (2025), doi:10.1108/RS-05-2025-0016, sections 5.2 and 6.
    """
    c = contact_wire.wave_speed
    beta_low = speed_ratio(speed_low, c)
    beta_max = speed_ratio(speed_high, c)
    return SpeedContext(
        wave_speed=c,
        speed_low=float(speed_low),
        speed_high=float(speed_high),
        beta_low=beta_low,
        beta_max=beta_max,
        doppler_factor_min=doppler_factor(speed_high, c),
        validity=validity_statement(c, speed_high),
    )


@dataclass(frozen=True, kw_only=True)
class StaticSteadyArmUplift:
    """Static estimate of the steady-arm uplift, F_m · e at the support, against a limit.

    A *static* estimate only: the dynamic uplift at the steady arm under a passing pantograph is
    larger; the dynamic simulation reports that one.

    Attributes
    ----------
    mean_force : float
        F_m used (the top of the band). [N]
    support_elasticity : float
        Largest contact-wire elasticity at a support of the analysed spans at F_m. [m/N]
    limit : float
        Allowed uplift. [m]
    """

    mean_force: float
    support_elasticity: float
    limit: float = STEADY_ARM_UPLIFT_LIMIT

    @property
    def uplift(self) -> float:
        """F_m · e_support. [m]"""
        return self.mean_force * self.support_elasticity

    @property
    def within_limit(self) -> bool:
        """Whether the static estimate is within the limit."""
        return self.uplift <= self.limit

    def to_dict(self) -> dict:
        """JSON-ready content (mm)."""
        return {
            "kind": "static estimate F_m*e_mast (dynamic uplift is larger)",
            "mean_force_N": self.mean_force,
            "support_elasticity_mm_per_N": self.support_elasticity * 1e3,
            "uplift_mm": self.uplift * 1e3,
            "limit_mm": self.limit * 1e3,
            "within_limit": self.within_limit,
        }


def highest_static_force_static(support_elasticity: float, limit: float, aero_coefficient: float,
                                speed_high: float) -> float:
    """Highest static force whose static uplift estimate keeps the limit at the top speed. [N]

    F_m·e_mast ≤ limit with F_m = F_stat + α_ae·v², so F_stat ≤ limit/e_mast − α_ae·v².

    Parameters
    ----------
    support_elasticity : float
        Largest elasticity at a steady arm. [m/N]
    limit : float
        Steady-arm uplift limit. [m]
    aero_coefficient : float
        α_ae. [N s²/m²]
    speed_high : float
        Highest speed of the band. [m/s]
    """
    # F_m = F_stat + α_ae v² solved for F_stat at the largest F_m the limit allows
    return limit / support_elasticity - mean_force(0.0, speed_high, aero_coefficient)
