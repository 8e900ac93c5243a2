"""Elasticity curves as results: one span at one force level, and a study of several levels.

Summary values follow the paper's notation: e_mid at mid-span, e_mast at the supports (mean of the
span's two ends), e_max, e_min, Δe = e_max − e_min, and the uniformity
u = (e_max − e_min)/(e_max + e_min) (Schick, Liu & Stichel 2025, doi:10.1108/RS-05-2025-0016,
section 4.1, eq. (5)).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True, kw_only=True)
class ElasticityCurve:
    """Elasticity along one span.

    Attributes
    ----------
    span : int
        Span index, from 0. [-]
    span_length : float
        Length of the span. [m]
    force : float or None
        Force of a nonlinear curve; None for the linear (tangent-stiffness) curve. [N]
    position : ndarray
        Distance from the span's first mast. [m]
    elasticity : ndarray
        Uplift per unit force at each position. [m/N]
    slack_droppers : ndarray of int or None
        Number of slack droppers in the section with the force at each position (nonlinear only). [-]
    """

    span: int
    span_length: float
    force: float | None
    position: np.ndarray
    elasticity: np.ndarray
    slack_droppers: np.ndarray | None = None

    def at(self, position: float | np.ndarray) -> float | np.ndarray:
        """Elasticity interpolated at positions from the span's first mast. [m/N]

        Parameters
        ----------
        position : float or ndarray
            Distance from the span's first mast. [m]
        """
        return np.interp(position, self.position, self.elasticity)

    @property
    def e_mid(self) -> float:
        """Elasticity at mid-span. [m/N]"""
        return float(self.at(0.5 * self.span_length))

    @property
    def e_mast(self) -> float:
        """Elasticity at the supports: mean of the span's two ends. [m/N]"""
        return float(0.5 * (self.elasticity[0] + self.elasticity[-1]))

    @property
    def e_max(self) -> float:
        """Largest elasticity along the span. [m/N]"""
        return float(self.elasticity.max())

    @property
    def e_min(self) -> float:
        """Smallest elasticity along the span. [m/N]"""
        return float(self.elasticity.min())

    @property
    def delta_e(self) -> float:
        """Δe = e_max − e_min. [m/N]"""
        return self.e_max - self.e_min

    @property
    def uniformity(self) -> float:
        """u = (e_max − e_min)/(e_max + e_min). [-]"""
        return self.delta_e / (self.e_max + self.e_min)

    def summary_mm_per_N(self) -> dict[str, float | None]:
        """Summary values in mm/N (and the force in N), for tables and JSON."""
        return {
            "force_N": self.force,
            "e_mid_mm_per_N": self.e_mid * 1e3,
            "e_mast_mm_per_N": self.e_mast * 1e3,
            "e_max_mm_per_N": self.e_max * 1e3,
            "e_min_mm_per_N": self.e_min * 1e3,
            "delta_e_mm_per_N": self.delta_e * 1e3,
            "uniformity": self.uniformity,
        }

@dataclass(frozen=True, kw_only=True)
class ElasticityStudy:
    """Elasticity curves of one span at several force levels (and optionally the linear curve).

    Attributes
    ----------
    catenary_name : str
        Name of the system.
    span : int
        Span index, from 0. [-]
    curves : tuple of ElasticityCurve
        Nonlinear curves by increasing force, then the linear curve if computed.
    warnings : tuple of str
        Curves outside the model's physical validity (see :func:`uplift_warnings`).
    """

    catenary_name: str
    span: int
    curves: tuple[ElasticityCurve, ...]
    warnings: tuple[str, ...] = ()

    @property
    def nonlinear(self) -> tuple[ElasticityCurve, ...]:
        """Curves at force levels, by increasing force."""
        return tuple(c for c in self.curves if c.force is not None)

    @property
    def linear(self) -> ElasticityCurve | None:
        """The tangent-stiffness curve, if computed."""
        return next((c for c in self.curves if c.force is None), None)

    def to_dict(self) -> dict:
        """JSON-ready content: positions in m, elasticities in mm/N."""
        first = self.curves[0]
        return {
            "catenary": self.catenary_name,
            "span": self.span + 1,
            "span_length_m": first.span_length,
            "x_m": first.position.tolist(),
            "curves": [
                {
                    **c.summary_mm_per_N(),
                    "x_m": c.position.tolist(),
                    "elasticity_mm_per_N": (c.elasticity * 1e3).tolist(),
                    **({"slack_droppers": c.slack_droppers.tolist()} if c.slack_droppers is not None else {}),
                }
                for c in self.curves
            ],
            "warnings": list(self.warnings),
        }
