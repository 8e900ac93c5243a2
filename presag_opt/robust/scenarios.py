"""What a robust design serves and how its losses are weighed: force scenarios and risk measures.

Holds :class:`ForceScenarios` (mean contact forces with probabilities, from a band or from an
operating band of static forces and speeds) and :class:`Risk` (minimax, mean, CVaR), including the
exact value of a risk measure over scenario losses. Their linear-programming form is in
:mod:`presag_opt.robust.lp`.

References
----------
R. T. Rockafellar, S. Uryasev, "Optimization of conditional value-at-risk", Journal of Risk 2(3)
(2000) 21–41.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from presag_opt.design.band import OperatingBand, mean_contact_force
from presag_opt.errors import ModelError

MAX_MEAN_FORCE = 1000.0
"""Highest mean contact force of a design band (the elasticity is computed up to this and beyond). [N]"""

@dataclass(frozen=True, kw_only=True)
class ForceScenarios:
    """Mean contact forces the design must serve, with probabilities.

    Attributes
    ----------
    forces : ndarray
        Mean contact forces F_m. [N]
    weights : ndarray
        Probability of each force (sums to 1). [-]
    """

    forces: np.ndarray
    weights: np.ndarray

    def __post_init__(self) -> None:
        forces = np.asarray(self.forces, dtype=float)
        weights = np.asarray(self.weights, dtype=float)
        if forces.ndim != 1 or len(forces) == 0 or forces.shape != weights.shape:
            raise ModelError("force scenarios: give one weight per force, at least one force")
        if not np.all(np.isfinite(forces)) or np.any(forces <= 0.0):
            raise ModelError(f"force scenarios: forces {forces.min():g}…{forces.max():g} N must be positive")
        if np.any(weights < 0.0) or not math.isclose(weights.sum(), 1.0, rel_tol=1e-9):
            raise ModelError("force scenarios: weights must be non-negative and sum to 1")
        object.__setattr__(self, "forces", forces)
        object.__setattr__(self, "weights", weights)

    @classmethod
    def band(cls, low: float, high: float, count: int = 17) -> ForceScenarios:
        """Evenly spaced forces over [low, high], equally likely.

        Parameters
        ----------
        low, high : float
            The F_m band. [N]
        count : int
            Number of forces (the minimax design is exact at them; 17 puts them < 5 N apart on
            the case study's 70–148 N band). [-]
        """
        if not (math.isfinite(low) and math.isfinite(high)) or not 0.0 < low < high <= MAX_MEAN_FORCE:
            raise ModelError(
                f"F_m band = [{low:g}, {high:g}] N is empty, inverted or too high; valid 0 < low < high <= "
                f"{MAX_MEAN_FORCE:g} N"
            )
        if not 2 <= count <= 200:
            raise ModelError(f"count = {count} is outside the valid range [2, 200]")
        forces = np.linspace(low, high, count)
        return cls(forces=forces, weights=np.full(count, 1.0 / count))

    @classmethod
    def from_operating_band(cls, band: OperatingBand, static_points: int = 8, speed_points: int = 8) -> ForceScenarios:
        """F_m = F_stat + α_ae v² for F_stat and v uniform and independent over the band.

        A tensor grid of midpoints (``static_points`` × ``speed_points`` equally likely cells);
        forces closer than 0.01 N are merged.

        Parameters
        ----------
        band : OperatingBand
            Ranges of static force and speed, and the aerodynamic coefficient.
        static_points : int
            Midpoints across the static-force range. [-]
        speed_points : int
            Midpoints across the speed range. [-]
        """
        f_stat = band.static_force_low + (np.arange(static_points) + 0.5) / static_points * (
            band.static_force_high - band.static_force_low
        )
        speed = band.speed_low + (np.arange(speed_points) + 0.5) / speed_points * (band.speed_high - band.speed_low)
        forces = np.array([mean_contact_force(f, v, band.aero_coefficient) for f in f_stat for v in speed])
        rounded, inverse = np.unique(np.round(forces, 2), return_inverse=True)
        weights = np.bincount(inverse, minlength=len(rounded)) / len(forces)
        return cls(forces=rounded, weights=weights)


@dataclass(frozen=True, kw_only=True)
class Risk:
    """How the scenarios' waviness is aggregated.

    Attributes
    ----------
    measure : {"minimax", "mean", "cvar"}
        Worst case, expected value, or conditional value-at-risk.
    level : float
        CVaR level α (mean of the worst 1 − α share); unused otherwise. [-]
    """

    measure: str = "minimax"
    level: float = 0.9

    def __post_init__(self) -> None:
        if self.measure not in ("minimax", "mean", "cvar"):
            raise ModelError(f"risk = {self.measure!r} is not one of minimax, mean, cvar:LEVEL")
        if not 0.0 <= self.level < 1.0:
            raise ModelError(f"risk level = {self.level:g} is outside the valid range [0, 1)")

    @classmethod
    def parse(cls, text: str) -> Risk:
        """``minimax``, ``mean`` or ``cvar:0.9``."""
        if text.startswith("cvar"):
            _, _, level = text.partition(":")
            try:
                value = float(level or 0.9)
            except ValueError:
                raise ModelError(f"risk = {text!r}: write cvar:LEVEL with LEVEL in [0, 1), e.g. cvar:0.9") from None
            return cls(measure="cvar", level=value)
        return cls(measure=text)

    def value(self, losses: np.ndarray, weights: np.ndarray) -> float:
        """The risk measure of scenario losses, evaluated exactly (the linear program's objective).

        Parameters
        ----------
        losses : ndarray
            Loss of each scenario, here the waviness R. [m]
        weights : ndarray
            Probability of each scenario. [-]

        Returns
        -------
        float
            Worst loss, expected loss or CVaR. [m]
        """
        if self.measure == "minimax":
            return float(losses.max())
        if self.measure == "mean":
            return float(weights @ losses)
        # CVaR of a discrete distribution: min over η of η + E[(L − η)+]/(1 − α), attained at a loss value.
        return float(min(eta + weights @ np.maximum(losses - eta, 0.0) / (1.0 - self.level) for eta in losses))

    @property
    def label(self) -> str:
        """``minimax``, ``mean`` or ``cvar:0.90``."""
        return f"cvar:{self.level:.2f}" if self.measure == "cvar" else self.measure
