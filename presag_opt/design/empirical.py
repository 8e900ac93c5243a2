"""The empirical pre-sag rule (eq. 1–3): e_mid = l / (k (T_CW + T_MW)), S = F_stat (e_mid − e_mast).

Holds the rule and :class:`EmpiricalPresag`, including the rounding the paper's Table 1 is printed
with. The paper's printed Table 1 itself, and the comparison with it, live in
:mod:`presag_opt.validation`; the quasi-static rule in :mod:`presag_opt.design.quasi_static`.

Table 1 rounding convention
---------------------------
The paper's Table 1 rounds S to whole millimetres *before* dividing by l for S_rel (to 0.01 ‰): on
ST 9,8/9,8 the low end S = 140 N · 0.5 · 0.7653 mm/N = 53.57 mm is printed as 54 mm and 0.90 ‰
(= 54/60), whereas 53.57/60 would print as 0.89 ‰. This convention reproduces all eight printed
pre-sag numbers of Table 1 (74–104 mm, 1.23–1.73 ‰; 54–75 mm, 0.90–1.25 ‰) and e_mid to three
decimals (1.056, 0.765 mm/N); :meth:`EmpiricalPresag.printed` applies it (half-up rounding).

References
----------
Schick, Liu, Stichel, "Validity range of a quasi-static method for adjusting the pre-sag of simple
railway catenary systems", Railway Sciences (2025), doi:10.1108/RS-05-2025-0016: eq. (1)–(3), Table 1.
"""

from __future__ import annotations

from dataclasses import dataclass
from decimal import ROUND_HALF_UP, Decimal

from presag_opt.system.quantity import quantity, validate_fields

EMPIRICAL_K = 4.0
"""Factor k of the empirical mid-span elasticity for simple catenaries (eq. 1). [-]"""

E_MAST_RATIOS = (0.5, 0.3)
"""e_mast / e_mid assumed by the empirical rule: 0.5 gives the low, 0.3 the high pre-sag. [-]"""


def mid_span_elasticity_empirical(
    span_length: float, contact_wire_tension: float, messenger_wire_tension: float, k: float = EMPIRICAL_K
) -> float:
    """Empirical mid-span elasticity e_mid = l / (k (T_CW + T_MW)).

    Parameters
    ----------
    span_length : float
        Span length l. [m]
    contact_wire_tension : float
        Contact-wire tension T_CW. [N]
    messenger_wire_tension : float
        Messenger-wire tension T_MW. [N]
    k : float
        Empirical factor, about 4 for simple catenaries. [-]

    Returns
    -------
    float
        e_mid. [m/N]

    References
    ----------
    Schick, Liu, Stichel (2025), doi:10.1108/RS-05-2025-0016, eq. (1).
    """
    return span_length / (k * (contact_wire_tension + messenger_wire_tension))


def _round_half_up(value: float, decimals: int) -> float:
    return float(Decimal(repr(value)).quantize(Decimal(1).scaleb(-decimals), rounding=ROUND_HALF_UP))


@dataclass(frozen=True, kw_only=True)
class EmpiricalPresag:
    """The empirical pre-sag rule for one system and span (validated inputs, derived results).

    Attributes
    ----------
    span_length : float
        Span length l. [m]
    contact_wire_tension : float
        T_CW. [N]
    messenger_wire_tension : float
        T_MW. [N]
    static_force : float
        Static contact force F_stat. [N]
    k : float
        Factor of eq. (1). [-]
    e_mast_ratios : tuple of float
        e_mast / e_mid for the low and the high end of the pre-sag range. [-]

    References
    ----------
    Schick, Liu, Stichel (2025), doi:10.1108/RS-05-2025-0016, eq. (1)–(3), Table 1.
    """

    span_length: float = quantity("length", 5.0, 120.0)
    contact_wire_tension: float = quantity("force", 0.5, 60.0, display="kN")
    messenger_wire_tension: float = quantity("force", 0.5, 60.0, display="kN")
    static_force: float = quantity("force", 0.0, 1000.0, low_open=True)
    k: float = quantity("ratio", 0.0, 20.0, low_open=True, default=EMPIRICAL_K)
    e_mast_ratios: tuple[float, ...] = quantity("ratio", 0.0, 1.0, high_open=True, default=E_MAST_RATIOS)

    def __post_init__(self) -> None:
        validate_fields(self)
        object.__setattr__(self, "e_mast_ratios", tuple(float(r) for r in self.e_mast_ratios))

    @property
    def e_mid(self) -> float:
        """Empirical mid-span elasticity (eq. 1). [m/N]"""
        return mid_span_elasticity_empirical(
            self.span_length, self.contact_wire_tension, self.messenger_wire_tension, self.k
        )

    @property
    def e_mast(self) -> tuple[float, ...]:
        """Assumed elasticity at the mast, one per ratio. [m/N]"""
        return tuple(r * self.e_mid for r in self.e_mast_ratios)

    @property
    def presag(self) -> tuple[float, ...]:
        """S = F_stat (e_mid − e_mast), one per ratio (eq. 2). [m]"""
        return tuple(self.static_force * (self.e_mid - e) for e in self.e_mast)

    @property
    def presag_rel(self) -> tuple[float, ...]:
        """S_rel = S / l, one per ratio (eq. 3). [-]"""
        return tuple(s / self.span_length for s in self.presag)

    def printed(self) -> dict[str, float | tuple[float, ...]]:
        """The values as the paper's Table 1 prints them.

        e_mid to 0.001 mm/N; S to whole mm; S_rel from the *rounded* S, to 0.01 ‰ (half-up
        rounding throughout). See the module notes for why S is rounded first.

        Returns
        -------
        dict
            ``e_mid_mm_per_N`` [mm/N], ``presag_mm`` (tuple) [mm], ``presag_rel_permille`` (tuple) [‰].
        """
        presag_mm = tuple(_round_half_up(s * 1e3, 0) for s in self.presag)
        return {
            "e_mid_mm_per_N": _round_half_up(self.e_mid * 1e3, 3),
            "presag_mm": presag_mm,
            "presag_rel_permille": tuple(_round_half_up(s / self.span_length, 2) for s in presag_mm),
        }

    def to_dict(self) -> dict:
        """JSON-ready content in edge units (kN, mm, mm/N, ‰)."""
        return {
            "span_length_m": self.span_length,
            "tension_kN": [self.contact_wire_tension / 1e3, self.messenger_wire_tension / 1e3],
            "static_force_N": self.static_force,
            "k": self.k,
            "e_mast_ratios": list(self.e_mast_ratios),
            "e_mid_mm_per_N": self.e_mid * 1e3,
            "e_mast_mm_per_N": [e * 1e3 for e in self.e_mast],
            "presag_mm": [s * 1e3 for s in self.presag],
            "presag_rel_permille": [s * 1e3 for s in self.presag_rel],
            "printed_as_table1": self.printed(),
        }
