"""The form-finding equations' sensitivity to the target heights (implicit-function theorem) against
an independent second method: re-solving the equations with IPOPT with one target raised."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from presag_opt.static import form_finding
from presag_opt.static.discretisation import StaticSettings
from presag_opt.static.equilibrium import static_model
from presag_opt.static.form_finding_equations import target_height_sensitivity
from presag_opt.static.form_finding_solver import solve_form_finding
from presag_opt.static.potential import PhysicalParameters
from presag_opt.system.catenary import SpanLayout
from presag_opt.system.loader import load_catenary

RAISE = 1e-4
"""Raise of one target height for the finite difference. [m]"""


@pytest.fixture(scope="module")
def problem():
    catenary = load_catenary("st_9.8_ideal").with_layout(SpanLayout(span_lengths=(60.0, 60.0, 60.0)))
    disc = static_model(catenary, StaticSettings(element_length=1.0)).discretisation
    ax = disc.axial
    x_design = disc.design_positions.ravel()
    params = PhysicalParameters(
        axial_stiffness=ax.stiffness, unstretched_length=ax.design_length.copy(), slack_allowed=np.zeros(len(ax)),
        bending_stiffness=disc.bending.bending_stiffness, spring_stiffness=disc.spring_stiffness,
        spring_reference=x_design[disc.spring_dofs], nodal_force=disc.gravity_force() + disc.termination_force,
    )
    return disc, params, form_finding._horizontal_wire_tension(disc), form_finding._target_dofs(disc), x_design


def test_the_sensitivity_matches_a_raised_target(problem):
    """Column j (the middle dropper) against (z(p + δ e_j) − z(p))/δ with δ = 0.1 mm: the equations are
    smooth, so the difference is first-order exact up to δ·|∂²z/∂p²| (the string model is nearly
    linear in the heights) and IPOPT's tolerance (1e-8 scaled) over δ; 1e-3 of the column's largest
    entry (which is 1, the raised target) covers both (measured: 4e-5), while a sign or scaling error
    misses by O(1)."""
    disc, params, tension, targets, x_design = problem
    base = solve_form_finding(disc, params, tension, targets, x_design)
    drops = disc.dropper_elements
    unstretched = params.unstretched_length.copy()
    unstretched[drops] = base.dropper_unstretched_length
    solved = dataclasses.replace(params, unstretched_length=unstretched, spring_reference=base.spring_reference)
    sensitivity = target_height_sensitivity(disc, solved, tension, targets, base.positions)
    j = len(drops) // 2
    raised_design = x_design.copy()
    raised_design[targets[j]] += RAISE
    raised = solve_form_finding(disc, params, tension, targets, raised_design)
    difference = (raised.positions[:, 2] - base.positions[:, 2]) / RAISE
    assert sensitivity[targets[j] // 3, j] == 1.0
    assert np.abs(difference - sensitivity[:, j]).max() <= 1e-3
    assert np.abs(sensitivity[:, j]).max() > 0.5  # the column is not trivially small
