"""The potential energy: its gradient and tangent stiffness are the derivatives of its energy
(central differences), and a slack dropper stores no energy."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from presag_opt.static.discretisation import StaticSettings
from presag_opt.static.form_finding import form_find
from presag_opt.system.catenary import SpanLayout
from presag_opt.system.loader import load_catenary


@pytest.fixture(scope="module")
def state():
    catenary = load_catenary("st_9.8_ideal").with_layout(SpanLayout(span_lengths=(60.0, 60.0, 60.0)))
    return form_find(catenary, StaticSettings(element_length=1.0))


def test_gradient_is_the_derivative_of_the_energy(state):
    """Central differences at h = 1e-4 m: truncation h²·|Π'''| (about 1e-6 N) and round-off ε|Π|/h
    (|Π| ≈ 1e6 J, so about 1e-6 N) against forces of order 100 N: 1e-4 N is far below any real
    error (a missing term moves components by newtons)."""
    functions, params = state.model.functions, state.params
    x = state.positions.ravel().copy()
    rng = np.random.default_rng(0)
    x += rng.normal(scale=1e-3, size=x.shape)  # off equilibrium: the gradient is not zero
    gradient = functions.gradient(x, params)
    h = 1e-4
    for dof in rng.choice(functions.free_dofs, 12, replace=False):
        e = np.zeros_like(x)
        e[dof] = h
        difference = (functions.energy(x + e, params) - functions.energy(x - e, params)) / (2 * h)
        assert abs(difference - gradient[dof]) <= 1e-4 * max(1.0, abs(gradient[dof])), dof


def test_tangent_stiffness_is_the_derivative_of_the_gradient(state):
    """Central differences of the gradient at h = 1e-6 m against the assembled Hessian column:
    1e-5 relative to the largest entry of the column (stiffnesses up to 1e8 N/m, round-off
    ε·|g|/h about 1e-8 relative)."""
    functions, params = state.model.functions, state.params
    x = state.positions.ravel().copy()
    matrix, _ = functions.hessian(x, params)
    free = functions.free_dofs
    h = 1e-6
    for column in (0, len(free) // 3, len(free) - 1):
        e = np.zeros_like(x)
        e[free[column]] = h
        difference = (functions.gradient(x + e, params) - functions.gradient(x - e, params))[free] / (2 * h)
        exact = matrix[:, column].toarray().ravel()
        assert np.abs(difference - exact).max() <= 1e-5 * np.abs(exact).max()


def test_a_slack_dropper_stores_no_energy(state):
    """Shortening a dropper's clamp distance below its unstretched length adds no energy when it may
    go slack, and k/2·s² when it may not (exact: the other terms do not change)."""
    functions, params = state.model.functions, state.params
    drop = state.discretisation.dropper_elements[0]
    assert params.slack_allowed[drop] == 1.0  # form-found droppers are tension-only
    unstretched = params.unstretched_length.copy()
    unstretched[drop] = state.element_lengths()[drop] + 0.01  # 10 mm too long: pushed by 10 mm
    loose = dataclasses.replace(params, unstretched_length=unstretched)
    stiff = dataclasses.replace(loose, slack_allowed=np.zeros_like(params.slack_allowed))
    x = state.positions.ravel()
    k = params.axial_stiffness[drop]
    others = functions.energy(x, dataclasses.replace(loose, axial_stiffness=_without(params.axial_stiffness, drop)))
    assert functions.energy(x, loose) == pytest.approx(others, rel=1e-12, abs=1e-6)
    assert functions.energy(x, stiff) - others == pytest.approx(0.5 * k * 0.01**2, rel=1e-6)


def _without(stiffness, element):
    out = stiffness.copy()
    out[element] = 0.0
    return out
