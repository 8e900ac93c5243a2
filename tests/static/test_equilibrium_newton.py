"""Newton's method on the potential: it meets the force tolerance, the tolerance has its round-off
floor, a factorisation kept from a previous solve gives the same equilibrium, and a solve that cannot
converge raises."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from presag_opt.errors import ConvergenceError
from presag_opt.static.discretisation import StaticSettings
from presag_opt.static.equilibrium_newton import ROUND_OFF_FACTOR, force_tolerance, newton_equilibrium, newton_solve
from presag_opt.static.form_finding import form_find
from presag_opt.system.catenary import SpanLayout
from presag_opt.system.loader import load_catenary

COARSE = StaticSettings(element_length=1.0)


@pytest.fixture(scope="module")
def state():
    catenary = load_catenary("st_9.8_ideal").with_layout(SpanLayout(span_lengths=(60.0, 60.0, 60.0)))
    return form_find(catenary, COARSE)


def _loaded(state, force=-500.0):
    """The state's parameters with a downward point force on the middle contact-wire node. [N]"""
    disc = state.discretisation
    node = disc.cw_nodes[len(disc.cw_nodes) // 2]
    nodal = state.params.nodal_force.copy()
    nodal[3 * node + 2] += force
    return dataclasses.replace(state.params, nodal_force=nodal), 3 * node + 2


def test_a_loaded_equilibrium_meets_the_force_tolerance(state):
    params, dof = _loaded(state)
    x0 = state.positions.ravel()
    x, iterations = newton_equilibrium(state.model, params, x0, COARSE)
    residual = np.abs(state.model.functions.gradient(x, params)[state.model.functions.free_dofs]).max()
    assert residual <= force_tolerance(params, x, COARSE)
    assert 1 <= iterations < COARSE.max_newton_iterations
    assert x[dof] < x0[dof] - 1e-3  # 500 N down moves the contact wire down by millimetres


def test_the_tolerance_never_falls_below_round_off(state):
    x = state.positions.ravel()
    floor = ROUND_OFF_FACTOR * np.finfo(float).eps * state.params.axial_stiffness.max() * np.abs(x).max()
    tight = dataclasses.replace(COARSE, force_tolerance=1e-8)
    assert force_tolerance(state.params, x, tight) == max(1e-8, floor)
    assert force_tolerance(state.params, x, COARSE) == max(COARSE.force_tolerance, floor)


def test_terms_of_a_previous_solve_give_the_same_equilibrium(state):
    """Started from the terms of the unloaded solve (its gradient and factorisation), the loaded
    solve meets the same tolerance and lands within it of the fresh solve: |Δx| below the
    tolerance over the smallest stiffness of the section's free DOFs is far below 1 µm."""
    params, _ = _loaded(state)
    x0 = state.positions.ravel()
    _, _, terms = newton_solve(state.model, state.params, x0, COARSE)
    free = state.model.functions.free_dofs
    moved = (state.params.nodal_force - params.nodal_force)[free]  # the gradient moves with the load
    shifted = dataclasses.replace(terms, gradient=terms.gradient + moved)
    x_reused, _, _ = newton_solve(state.model, params, x0, COARSE, shifted)
    x_fresh, _ = newton_equilibrium(state.model, params, x0, COARSE)
    assert np.abs(x_reused - x_fresh).max() <= 1e-6


def test_a_solve_that_cannot_converge_raises(state):
    params, _ = _loaded(state, force=-5000.0)
    one_step = dataclasses.replace(COARSE, max_newton_iterations=1)
    with pytest.raises(ConvergenceError, match="equilibrium did not converge: largest out-of-balance force"):
        newton_equilibrium(state.model, params, state.positions.ravel(), one_step)
