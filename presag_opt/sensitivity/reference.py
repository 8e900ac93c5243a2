"""Analytic reference functions for checking the sensitivity methods (row by row, picklable).

References
----------
Ishigami, Homma, "An importance quantification technique in uncertainty analysis for computer
models", Proc. ISUMA '90 (1990), doi:10.1109/ISUMA.1990.151285; the indices in closed form are given
e.g. by Sobol', Levitan, "On the use of variance reducing multipliers in Monte Carlo computations of a
global sensitivity index", Comput. Phys. Commun. 117 (1999), doi:10.1016/S0010-4655(98)00156-8.
"""

from __future__ import annotations

import math

import numpy as np

ISHIGAMI_A = 7.0
"""Coefficient a of the Ishigami function. [-]"""

ISHIGAMI_B = 0.1
"""Coefficient b of the Ishigami function. [-]"""


def ishigami(row: np.ndarray) -> np.ndarray:
    """f(x) = sin x1 + a sin² x2 + b x3⁴ sin x1 on x ∈ [−π, π]³; further entries of ``row`` are ignored.

    Parameters
    ----------
    row : ndarray
        x1, x2, x3 (and any inputs f does not depend on). [-]

    Returns
    -------
    ndarray, shape (1,)
        f. [-]
    """
    x1, x2, x3 = row[0], row[1], row[2]
    return np.array([math.sin(x1) + ISHIGAMI_A * math.sin(x2) ** 2 + ISHIGAMI_B * x3**4 * math.sin(x1)])


def ishigami_indices() -> tuple[tuple[float, float, float], tuple[float, float, float]]:
    """Exact first-order and total Sobol indices (S1, ST) of x1, x2, x3 of :func:`ishigami`. [-]"""
    a, b, pi = ISHIGAMI_A, ISHIGAMI_B, math.pi
    v1 = 0.5 * (1.0 + b * pi**4 / 5.0) ** 2
    v2 = a**2 / 8.0
    v13 = b**2 * pi**8 * (1.0 / 18.0 - 1.0 / 50.0)
    total = v1 + v2 + v13
    return (v1 / total, v2 / total, 0.0), ((v1 + v13) / total, v2 / total, v13 / total)
