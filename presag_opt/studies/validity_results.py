"""Named results of a study's validity analysis: minima over F_m, optimal-S bands, β verdicts, β*.

The criteria that fill them are in :mod:`presag_opt.studies.validity_analysis`; each class names its
units.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass, field

from presag_opt.units import KMH


@dataclass(frozen=True, kw_only=True)
class Minimum:
    """Minimum of a spline through grid values.

    Attributes
    ----------
    location : float or None
        Where the minimum lies, if it is distinct (else None). [unit of the abscissa]
    value : float
        The smallest spline value (at an end if the minimum is not interior). [unit of the ordinate]
    distinct : bool
        Interior, with a rise of at least :data:`~presag_opt.studies.validity_analysis.DISTINCT_RISE` to both ends.
    """

    location: float | None
    value: float
    distinct: bool


@dataclass(frozen=True, kw_only=True)
class ForceOptimum:
    """Fig. 6 and 8: optimal F_m of one pre-sag at one β.

    Attributes
    ----------
    presag : float
        S. [m]
    speed : float
        v. [m/s]
    beta : float
        β. [-]
    ratio : Minimum
        Minimum of σ/F_m over F_m (location in N, value in -).
    sigma : Minimum
        Minimum of σ over F_m (location and value in N).
    """

    presag: float
    speed: float
    beta: float
    ratio: Minimum
    sigma: Minimum


@dataclass(frozen=True, kw_only=True)
class PresagBand:
    """Fig. 7: dynamically optimal and near-optimal S at one β and static force, beside the rules.

    Attributes
    ----------
    static_force : float
        F_stat. [N]
    mean_force : float
        Nominal F_m = F_stat + α_ae v². [N]
    optimal : float or None
        S at the minimum of σ, if strictly inside the S grid. [m]
    band_low, band_high : float
        Near-optimal band of S (σ within the margin of its minimum). [m]
    open_low, open_high : bool
        The band reaches that end of the S grid (it may extend beyond).
    benefit : bool
        σ varies by more than the margin over the S grid.
    presag_delta_e, presag_mid_mast : float
        Self-consistent quasi-static pre-sag of the Δe and mid/mast rules (NaN if unavailable). [m]
    """

    static_force: float
    mean_force: float
    optimal: float | None
    band_low: float
    band_high: float
    open_low: bool
    open_high: bool
    benefit: bool
    presag_delta_e: float
    presag_mid_mast: float

    @property
    def rule_inside(self) -> bool:
        """The Δe rule lies in the near-optimal band (an open end extends the band indefinitely)."""
        s = self.presag_delta_e
        if not math.isfinite(s):
            return False
        return (self.open_low or s >= self.band_low) and (self.open_high or s <= self.band_high)


@dataclass(frozen=True, kw_only=True)
class BetaVerdict:
    """Whether the Δe rule holds at one β.

    Attributes
    ----------
    speed : float
        v. [m/s]
    beta : float
        β. [-]
    bands : tuple of PresagBand
        One per static force.
    holds : bool
        See the module notes.
    """

    speed: float
    beta: float
    bands: tuple[PresagBand, ...]
    holds: bool


@dataclass(frozen=True, kw_only=True)
class PowerFit:
    """S_dyn − S_stat = k·β^a.

    Attributes
    ----------
    k : float
        Coefficient. [m]
    a : float
        Exponent. [-]
    r2 : float
        Coefficient of determination of the correction. [-]
    points : int
        Optima used. [-]
    """

    k: float
    a: float
    r2: float
    points: int


@dataclass(frozen=True, kw_only=True)
class UpliftCheck:
    """Largest steady-arm uplift of the grid against its limit.

    Attributes
    ----------
    maximum : float
        Largest uplift over the finished runs. [m]
    limit : float
        Allowed uplift. [m]
    presag, speed, static_force : float
        Where the maximum occurs. [m], [m/s], [N]
    """

    maximum: float
    limit: float
    presag: float
    speed: float
    static_force: float

    @property
    def within_limit(self) -> bool:
        """Whether the largest uplift is at most the limit."""
        return self.maximum <= self.limit


@dataclass(frozen=True, kw_only=True)
class ValidityResult:
    """Result of :func:`validity_analysis`.

    Attributes
    ----------
    beta_limit : float or None
        β*, or None if the rule holds at every β of the grid or already fails at the lowest. [-]
    beta_limit_uncertainty : float or None
        Half the β interval β* lies in. [-]
    criterion : str
        How β* was read, in words, including whether σ/F_m had distinct minima.
    fit : PowerFit or None
        Fit of eq. 7; None when the optima cannot support one (:attr:`no_fit_reason` says why).
    per_beta : tuple of BetaVerdict
        Fig. 7 per β, increasing.
    force_optima : tuple of ForceOptimum
        Fig. 6/8 per S and β.
    uplift : UpliftCheck or None
        None if no run finished.
    no_fit_reason : str
        Why there is no fit (empty with a fit): too few optima, no correction to fit, an exponent at
        its bound, or r² below :data:`~presag_opt.studies.validity_analysis.FIT_MIN_R2`.
    settings : dict
        The criteria's thresholds the analysis used (name -> value, each dimensionless) and
        ``pantograph``, the pantograph whose statistics were read (``leading`` or ``trailing``). [-]
    """

    beta_limit: float | None
    beta_limit_uncertainty: float | None
    criterion: str
    fit: PowerFit | None
    per_beta: tuple[BetaVerdict, ...]
    force_optima: tuple[ForceOptimum, ...]
    uplift: UpliftCheck | None
    no_fit_reason: str = ""
    settings: dict = field(default_factory=dict)

    def to_dict(self) -> dict:
        """JSON-ready summary; pre-sag in mm, speed in km/h (the units are in the key names)."""
        mm = 1e3

        def band(b: PresagBand) -> dict:
            return {
                "static_force_N": b.static_force, "F_m_N": b.mean_force,
                "presag_delta_e_mm": b.presag_delta_e * mm, "presag_mid_mast_mm": b.presag_mid_mast * mm,
                "presag_optimal_mm": None if b.optimal is None else b.optimal * mm,
                "band_mm": [b.band_low * mm, b.band_high * mm], "band_open": [b.open_low, b.open_high],
                "benefit": b.benefit, "rule_inside": b.rule_inside,
            }

        def minimum(m: Minimum) -> dict:
            return {"F_m_N": m.location, "value": m.value, "distinct": m.distinct}

        return {
            "beta_limit": self.beta_limit,
            "beta_limit_uncertainty": self.beta_limit_uncertainty,
            "criterion": self.criterion,
            "fit": None if self.fit is None else {**asdict(self.fit), "k_mm": self.fit.k * mm},
            "no_fit_reason": self.no_fit_reason,
            "per_beta": [{"beta": v.beta, "speed_kmh": v.speed / KMH, "holds": v.holds,
                          "bands": [band(b) for b in v.bands]} for v in self.per_beta],
            "force_optima": [{"presag_mm": o.presag * mm, "beta": o.beta, "speed_kmh": o.speed / KMH,
                              "sigma_over_F_m": minimum(o.ratio), "sigma": minimum(o.sigma)}
                             for o in self.force_optima],
            "uplift": None if self.uplift is None else {
                "max_mm": self.uplift.maximum * mm, "limit_mm": self.uplift.limit * mm,
                "within_limit": self.uplift.within_limit, "presag_mm": self.uplift.presag * mm,
                "speed_kmh": self.uplift.speed / KMH, "static_force_N": self.uplift.static_force,
            },
            "settings": dict(self.settings),
        }
