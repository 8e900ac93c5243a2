"""The paper's Fig. 5b study: the pre-sag from one elasticity curve against interpolated curves.

Holds :func:`single_curve_error` and its result. The paper's published errors are in
:mod:`presag_opt.validation.paper`; the interpolation it is measured against is
:func:`presag_opt.design.quasi_static.interpolate_elasticity`.

References
----------
Schick, Liu, Stichel, "Validity range of a quasi-static method for adjusting the pre-sag of simple
railway catenary systems", Railway Sciences (2025), doi:10.1108/RS-05-2025-0016: section 5.1, Fig. 5b.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from presag_opt.design.band import mean_force_grid
from presag_opt.design.quasi_static import check_method, elasticity_difference
from presag_opt.design.section import SectionElasticity
from presag_opt.errors import ModelError
from presag_opt.validation.paper import SINGLE_CURVE_MAX_FORCE


@dataclass(frozen=True, kw_only=True)
class SingleCurveError:
    """Error of sizing the pre-sag from one elasticity curve instead of the interpolated ones.

    Attributes
    ----------
    catenary_name : str
        System and layout.
    geometry_presag : float
        Mid-span pre-sag of the first analysed span in the geometry the curves were computed at. [m]
    reference_force : float
        Force of the single curve. [N]
    method : str
        Variant of the rule.
    mean_forces : ndarray
        F_m. [N]
    presag_interpolated : ndarray
        Section S (mean S_rel times the first analysed span's length) from interpolated curves. [m]
    presag_single_curve : ndarray
        The same from the ``reference_force`` curve alone. [m]

    References
    ----------
    Schick, Liu, Stichel (2025), doi:10.1108/RS-05-2025-0016, section 5.1 and Fig. 5b.
    """

    catenary_name: str
    geometry_presag: float
    reference_force: float
    method: str
    mean_forces: np.ndarray
    presag_interpolated: np.ndarray
    presag_single_curve: np.ndarray

    @property
    def relative_error(self) -> np.ndarray:
        """(S_single − S_interpolated) / S_interpolated; positive when one curve overestimates. [-]"""
        return self.presag_single_curve / self.presag_interpolated - 1.0

    def error_at(self, mean_force: float) -> float:
        """Relative error at one F_m (linear between grid points). [-]

        Parameters
        ----------
        mean_force : float
            Mean contact force F_m. [N]
        """
        if not self.mean_forces[0] <= mean_force <= self.mean_forces[-1]:
            raise ModelError(
                f"mean force = {mean_force:g} N is outside the studied range "
                f"[{self.mean_forces[0]:g}, {self.mean_forces[-1]:g}] N"
            )
        return float(np.interp(mean_force, self.mean_forces, self.relative_error))


def single_curve_error(
    section: SectionElasticity,
    *,
    reference_force: float = 100.0,
    max_force: float = SINGLE_CURVE_MAX_FORCE,
    method: str = "delta-e",
) -> SingleCurveError:
    """The paper's Fig. 5b study: pre-sag from one curve against the interpolated curves.

    Parameters
    ----------
    section : SectionElasticity
        Curves at levels that include ``reference_force`` and reach ``max_force``.
    reference_force : float
        Force of the single curve (the paper: 100 N). [N]
    max_force : float
        Largest F_m studied (the paper: 179 N). [N]
    method : {"delta-e", "mid-mast"}
        Variant of the rule (Fig. 5b uses Δe).

    Returns
    -------
    SingleCurveError
        Over F_m from the lowest level to ``max_force``.
    """
    check_method(method)
    levels = section.force_levels
    if not any(math.isclose(reference_force, f) for f in levels):
        raise ModelError(f"reference_force = {reference_force:g} N is not one of the computed levels {list(levels)} N")
    if not levels[0] < max_force <= levels[-1]:
        raise ModelError(
            f"max_force = {max_force:g} N is outside the computed force levels ({levels[0]:g}, {levels[-1]:g}] N"
        )
    mean_forces = mean_force_grid(levels[0], max_force, levels)
    reference = section.curves_at(reference_force)
    lengths = section.span_lengths
    diff_single = np.array([elasticity_difference(c, method) for c in reference])
    # The same arithmetic as SectionPresag.presag_rel_mean, (F·Δe)/l averaged, so that at the
    # reference force both sides are the same number to the last bit.
    single = np.array([np.mean(f * diff_single / lengths) for f in mean_forces]) * lengths[0]
    interpolated = section.presag_rel_curve(mean_forces, method) * lengths[0]
    return SingleCurveError(
        catenary_name=section.catenary.name,
        geometry_presag=section.catenary.presag_of_span(section.spans[0]),
        reference_force=float(reference_force),
        method=method,
        mean_forces=mean_forces,
        presag_interpolated=interpolated,
        presag_single_curve=single,
    )
