"""The Ishigami reference: the function and its exact indices against an independent quadrature."""

from __future__ import annotations

import math

import numpy as np
import pytest

from presag_opt.sensitivity.reference import ISHIGAMI_A, ISHIGAMI_B, ishigami, ishigami_indices


def test_the_function_at_known_points_and_ignoring_extra_inputs():
    assert ishigami(np.array([0.0, 0.0, 0.0]))[0] == 0.0
    # x1 = π/2, x2 = π/2, x3 = π: 1 + a + b π⁴
    assert ishigami(np.array([math.pi / 2, math.pi / 2, math.pi, 123.0]))[0] == pytest.approx(
        1.0 + ISHIGAMI_A + ISHIGAMI_B * math.pi**4, rel=1e-14)


def test_exact_indices_match_a_gauss_legendre_quadrature():
    """Var(E[f|x_i]) and E[Var(f|x_~i)] by 48-point quadrature on each axis (f is a polynomial of degree
    4 in x3 and smooth in x1, x2: the quadrature is exact to far below the 1e-9 tolerance)."""
    nodes, weights = np.polynomial.legendre.leggauss(48)
    x = math.pi * nodes
    w = weights / 2.0  # the uniform density on [-π, π]
    x1, x2, x3 = np.meshgrid(x, x, x, indexing="ij")
    f = np.sin(x1) + ISHIGAMI_A * np.sin(x2) ** 2 + ISHIGAMI_B * x3**4 * np.sin(x1)
    W = w[:, None, None] * w[None, :, None] * w[None, None, :]
    mean = np.sum(W * f)
    variance = np.sum(W * (f - mean) ** 2)
    first, total = [], []
    for axis in range(3):
        others = tuple(a for a in range(3) if a != axis)
        w_others = np.sum(W, axis=axis, keepdims=True)
        conditional = np.sum(W * f, axis=others, keepdims=True) / np.sum(W, axis=others, keepdims=True)
        first.append(float(np.sum(W * (conditional - mean) ** 2) / variance))
        given_others = np.sum(W * f, axis=axis, keepdims=True) / w_others
        total.append(float(np.sum(W * (f - given_others) ** 2) / variance))
    s1, st = ishigami_indices()
    np.testing.assert_allclose(first, s1, atol=1e-9)
    np.testing.assert_allclose(total, st, atol=1e-9)
    assert st[0] > s1[0] and st[2] > 0.0 == s1[2]  # x1 and x3 interact, x3 has no first-order effect
