"""The quasi-static pre-sag rule (eq. 2, 5) and the elasticity curve at a force between levels.

S = F_m (e_mid − e_mast) (``"mid-mast"``) or S = F_m (e_max − e_min) = F_m Δe (``"delta-e"``, the
variant the paper finds to match dynamic simulation for β < 0.4), with the elasticity curve at F_m
interpolated between the two computed force levels closest to F_m (:func:`interpolate_elasticity`).
Computing the curves is left to :mod:`presag_opt.elasticity`, applying the rule to whole sections to
:mod:`presag_opt.design.section`.

Elasticity outside the computed force levels
--------------------------------------------
:func:`interpolate_elasticity` raises :class:`~presag_opt.errors.ModelError` for a force outside the
range of the computed levels instead of extrapolating or clamping. Above the highest level droppers
keep going slack (on ST 9,8/9,8 a second dropper slackens between 150 and 200 N and e_mast rises by
about 20 %), so a clamped curve would misstate S by as much as the effect the rule is meant to
capture. Levels are cheap with the active-set elasticity, so
:func:`~presag_opt.design.recommendation.recommend` always computes levels that bracket the F_m band
(:func:`~presag_opt.design.band.force_levels_for_band`); only a user who supplies levels that do not
cover the band meets the error, and its message names the range to add.

References
----------
Schick, Liu, Stichel, "Validity range of a quasi-static method for adjusting the pre-sag of simple
railway catenary systems", Railway Sciences (2025), doi:10.1108/RS-05-2025-0016: eq. (2), (5), section 4.1.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

from presag_opt.elasticity import ElasticityCurve
from presag_opt.errors import ModelError

PRESAG_METHODS = ("mid-mast", "delta-e")
"""Quasi-static variants: S = F_m (e_mid − e_mast) (eq. 2 with F_m) and S = F_m Δe (eq. 5)."""


def interpolate_elasticity(curves: Sequence[ElasticityCurve], force: float) -> ElasticityCurve:
    """Elasticity curve at a force, interpolated between the two computed levels closest to it.

    Pointwise linear interpolation in force: e(x; F) = (1 − w) e(x; F_a) + w e(x; F_b) with
    F_a ≤ F ≤ F_b neighbouring levels and w = (F − F_a)/(F_b − F_a). At a computed level the curve
    of that level is returned unchanged.

    Parameters
    ----------
    curves : sequence of ElasticityCurve
        Nonlinear curves of one span at distinct force levels, on the same positions.
    force : float
        Force to interpolate at. [N]

    Returns
    -------
    ElasticityCurve
        The curve at ``force`` (``slack_droppers`` is None for an interpolated curve).

    Raises
    ------
    ModelError
        If ``force`` lies outside the range of the levels (no extrapolation: see the module notes),
        or the curves are not nonlinear curves of one span on common positions.

    References
    ----------
    Schick, Liu, Stichel (2025), doi:10.1108/RS-05-2025-0016, section 4.1 (interpolation between the
    two curves with the closest forces).
    """
    return interpolate_elasticities(curves, (force,))[0]


def interpolate_elasticities(curves: Sequence[ElasticityCurve], forces: Sequence[float]) -> tuple[ElasticityCurve, ...]:
    """:func:`interpolate_elasticity` at several forces, the curves checked once.

    Parameters
    ----------
    curves : sequence of ElasticityCurve
        Nonlinear curves of one span at distinct force levels, on the same positions.
    forces : sequence of float
        Forces to interpolate at. [N]

    Returns
    -------
    tuple of ElasticityCurve
        One curve per force, in the order of ``forces``.

    Raises
    ------
    ModelError
        As :func:`interpolate_elasticity`, for the first force outside the levels.

    Examples
    --------
    >>> import numpy as np
    >>> from presag_opt.elasticity import ElasticityCurve
    >>> x = np.array([0.0, 30.0, 60.0])
    >>> at_100 = ElasticityCurve(span=0, span_length=60.0, force=100.0, position=x,
    ...                          elasticity=np.array([0.3, 0.6, 0.3]) * 1e-3)
    >>> at_150 = ElasticityCurve(span=0, span_length=60.0, force=150.0, position=x,
    ...                          elasticity=np.array([0.4, 0.6, 0.4]) * 1e-3)
    >>> [round(c.delta_e * 1e3, 3) for c in interpolate_elasticities([at_150, at_100], [100.0, 125.0, 150.0])]
    [0.3, 0.25, 0.2]
    """
    levels = sorted(curves, key=lambda c: -1.0 if c.force is None else c.force)
    if not levels or any(c.force is None for c in levels):
        raise ModelError("interpolate_elasticity needs nonlinear curves (with a force level), at least one")
    first = levels[0]
    for c in levels[1:]:
        if c.span != first.span or not np.array_equal(c.position, first.position):
            raise ModelError("interpolate_elasticity: curves must belong to one span and share their positions")
    level_forces = np.array([c.force for c in levels])
    if np.any(np.diff(level_forces) <= 0.0):
        raise ModelError(f"interpolate_elasticity: force levels {level_forces.tolist()} N are not distinct")
    return tuple(_interpolated(levels, level_forces, float(force)) for force in forces)


def _interpolated(levels: list[ElasticityCurve], forces: np.ndarray, force: float) -> ElasticityCurve:
    """The curve at ``force`` from checked ``levels`` (sorted, distinct, common positions) at ``forces``."""
    for c in levels:
        if math.isclose(force, c.force, rel_tol=1e-12, abs_tol=1e-12):
            return c
    if not forces[0] < force < forces[-1]:
        raise ModelError(
            f"mean force = {force:g} N is outside the computed force levels [{forces[0]:g}, {forces[-1]:g}] N; "
            "add a level beyond it (elasticity is not extrapolated)"
        )
    upper = int(np.searchsorted(forces, force))
    a, b = levels[upper - 1], levels[upper]
    w = (force - a.force) / (b.force - a.force)
    first = levels[0]
    return ElasticityCurve(
        span=first.span,
        span_length=first.span_length,
        force=force,
        position=first.position,
        elasticity=(1.0 - w) * a.elasticity + w * b.elasticity,
    )


def check_method(method: str) -> str:
    """Return ``method`` if it is one of :data:`PRESAG_METHODS`, else raise ModelError."""
    if method not in PRESAG_METHODS:
        raise ModelError(f"method = {method!r} is not one of {', '.join(PRESAG_METHODS)}")
    return method


def elasticity_difference(curve: ElasticityCurve, method: str) -> float:
    """The elasticity difference the pre-sag compensates: e_mid − e_mast or Δe = e_max − e_min. [m/N]"""
    check_method(method)
    return curve.e_mid - curve.e_mast if method == "mid-mast" else curve.delta_e


def presag_quasi_static(curve: ElasticityCurve, mean_force: float, method: str = "delta-e") -> float:
    r"""Quasi-static pre-sag S = F_m (e_mid − e_mast) or S = F_m Δe.

    Parameters
    ----------
    curve : ElasticityCurve
        Elasticity of the span, normally at ``mean_force`` (see :func:`interpolate_elasticity`);
        the single-curve study passes a curve at another force on purpose.
    mean_force : float
        Mean contact force F_m. [N]
    method : {"delta-e", "mid-mast"}
        ``"delta-e"``: S = F_m (e_max − e_min) (eq. 5); ``"mid-mast"``: S = F_m (e_mid − e_mast)
        (eq. 2 with F_m and computed elasticities).

    Returns
    -------
    float
        Mid-span pre-sag S. [m]

    Notes
    -----
    The pre-sag compensates the difference of the span's elasticity e(x) at the mean contact force,
    so that the contact wire under the moving force F_m runs level (eq. 5, the Δe rule; eq. 2 with
    the mid-span and mast elasticities):

    .. math::

        S = F_m\,\Delta e = F_m \left(\max_x e(x) - \min_x e(x)\right), \qquad
        S_{rel} = S / l.

    Examples
    --------
    A 60 m span whose elasticity runs from 0.40 mm/N at the masts to 0.82 mm/N at mid-span, at
    F_m = 133 N:

    >>> import numpy as np
    >>> from presag_opt.design.quasi_static import presag_quasi_static
    >>> from presag_opt.elasticity.curves import ElasticityCurve
    >>> x = np.linspace(0.0, 60.0, 13)
    >>> curve = ElasticityCurve(span=0, span_length=60.0, force=133.0, position=x,
    ...                         elasticity=0.40e-3 + 0.42e-3 * np.sin(np.pi * x / 60.0))
    >>> print(f"S = {presag_quasi_static(curve, 133.0) * 1e3:.1f} mm")
    S = 55.9 mm

    References
    ----------
    Schick, Liu, Stichel (2025), doi:10.1108/RS-05-2025-0016, eq. (2), (5).
    """
    if not mean_force > 0.0:
        raise ModelError(f"mean force = {mean_force:g} N is outside the valid range (0, inf) N")
    return mean_force * elasticity_difference(curve, method)
