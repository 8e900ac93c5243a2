"""Where a quasi-static pre-sag holds: the speed band against the wave speed, the steady-arm uplift.

Holds :func:`speed_context` (wave speed, β = v/c_CW, Doppler factor, validity β ≤ 0.4) and the static
steady-arm uplift estimate against the case study's limit. The wave-speed formulas themselves are in
:mod:`presag_opt.speed`; the dynamic uplift comes from :mod:`presag_opt.dynamics`.

References
----------
Schick, Liu, Stichel, "Validity range of a quasi-static method for adjusting the pre-sag of simple
railway catenary systems", Railway Sciences (2025), doi:10.1108/RS-05-2025-0016: sections 5.2 and 6
(validity β ≤ 0.4, steady-arm uplift limit 83.5 mm).
"""

from __future__ import annotations

from dataclasses import dataclass

from presag_opt.design.band import KMH
from presag_opt.speed import doppler_factor, speed_ratio
from presag_opt.system.components import Wire

QUASI_STATIC_BETA_LIMIT = 0.4
"""Speed ratio β = v/c_CW up to which the quasi-static rule matches dynamic simulation. [-]"""

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
    beta_limit : float
        Validity limit of the quasi-static rule. [-]
    warnings : tuple of str
        Set when the band crosses or lies beyond the limit.

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
    beta_limit: float
    warnings: tuple[str, ...] = ()

    @property
    def quasi_static_valid(self) -> bool:
        """Whether the whole band lies within β ≤ beta_limit."""
        return self.beta_max <= self.beta_limit

    @property
    def limit_speed(self) -> float:
        """Speed at which β reaches the limit. [m/s]"""
        return self.beta_limit * self.wave_speed

    def to_dict(self) -> dict:
        """JSON-ready content (m/s and km/h)."""
        return {
            "wave_speed_m_per_s": self.wave_speed,
            "speed_kmh": [self.speed_low / KMH, self.speed_high / KMH],
            "beta_low": self.beta_low,
            "beta_max": self.beta_max,
            "doppler_factor_min": self.doppler_factor_min,
            "beta_limit": self.beta_limit,
            "limit_speed_kmh": self.limit_speed / KMH,
            "quasi_static_valid": self.quasi_static_valid,
        }


def speed_context(
    contact_wire: Wire, speed_low: float, speed_high: float, beta_limit: float = QUASI_STATIC_BETA_LIMIT
) -> SpeedContext:
    """Wave speed, speed ratios, Doppler factor and validity of the quasi-static rule for a band.

    When the band crosses ``beta_limit`` or lies above it, the result's ``warnings`` say so
    (:func:`~presag_opt.design.recommendation.recommend` passes them on as :class:`UserWarning`).

    Parameters
    ----------
    contact_wire : Wire
        The contact wire (tension and mass per metre).
    speed_low, speed_high : float
        Speed band. [m/s]
    beta_limit : float
        Validity limit of the quasi-static rule. [-]

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
    notes = []
    if beta_low > beta_limit:
        notes.append(
            f"the whole speed band ({speed_low / KMH:g}–{speed_high / KMH:g} km/h, β = {beta_low:.2f}–{beta_max:.2f}) "
            f"lies above β = {beta_limit:g}: the quasi-static pre-sag rule does not hold there"
        )
    elif beta_max > beta_limit:
        notes.append(
            f"the speed band crosses β = {beta_limit:g} at {beta_limit * c / KMH:.0f} km/h (β_max = {beta_max:.2f}): "
            "the quasi-static pre-sag rule holds only below that speed"
        )
    return SpeedContext(
        wave_speed=c,
        speed_low=float(speed_low),
        speed_high=float(speed_high),
        beta_low=beta_low,
        beta_max=beta_max,
        doppler_factor_min=doppler_factor(speed_high, c),
        beta_limit=beta_limit,
        warnings=tuple(notes),
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
