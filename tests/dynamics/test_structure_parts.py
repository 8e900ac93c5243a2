"""Parts of the linearised structure (presag_opt.dynamics.structure) and the integrator that the other
tests leave implicit: stiffness-proportional damping alone, the support DOFs, a singular system."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sp

from presag_opt.dynamics.integrator import IntegratorSettings, State, integrate
from presag_opt.dynamics.structure import structural_model
from presag_opt.errors import ConvergenceError, ModelError
from presag_opt.system.components import Damping


def test_stiffness_proportional_damping_alone_has_no_mass_term(st98):
    """Damping(rayleigh_beta) without alpha: C = β K exactly (alpha is zero, not a default of 1)."""
    model = structural_model(st98, damping=Damping(rayleigh_beta=1e-3))
    assert (model.rayleigh_alpha, model.rayleigh_beta) == (0.0, 1e-3)
    # Same sparse arithmetic on both sides: equal to round-off of one product, 1e-12 relative.
    difference = abs(model.damping - 1e-3 * model.stiffness).max()
    assert difference <= 1e-12 * abs(model.stiffness).max()


def test_support_dofs_are_the_contact_wire_at_the_masts(st98):
    """``support_z`` indexes the vertical DOF of the contact wire at every mast, in mast order."""
    model = structural_model(st98)
    disc = st98.discretisation
    at_masts = np.searchsorted(disc.cw_nodes, disc.mast_cw_node)
    np.testing.assert_array_equal(model.support_z, model.cw_z[at_masts])
    assert len(model.support_z) == st98.catenary.layout.n_spans + 1


def test_a_singular_system_is_named_by_both_solution_paths():
    """M = C = K = 0: the effective (Newton) matrix is singular; each path says so in words."""
    zero = sp.csr_matrix((2, 2))
    rest = State(displacement=np.zeros(2), velocity=np.zeros(2), acceleration=np.zeros(2))
    for method, error, words in (("reference", ConvergenceError, "singular Newton matrix"),
                                 ("fast", ModelError, "effective matrix .* is singular")):
        with pytest.raises(error, match=words):
            integrate(zero, zero, zero, duration=0.01, settings=IntegratorSettings(method=method),
                      initial_state=rest, external_force=lambda t: np.ones(2))
