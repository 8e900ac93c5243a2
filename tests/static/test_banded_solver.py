"""The banded solver: the track-wise ordering narrows the band, the factorisation solves the system
(Cholesky, or SuperLU when not positive definite), and the solve back-ends agree.

Tolerances: the stiffness of a form-found section spans 1e2…1e8 N/m, so its condition number is
about 1e8 or more; solutions are compared by their residual relative to ‖K‖·‖u‖ (backward error),
which a stable solve keeps near machine precision whatever the conditioning: 1e-12 allows for n·ε
growth over a few thousand rows. The C and numba back-ends must agree to the last bit.
"""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sp

from presag_opt.static.banded_solver import BandedSolver
from presag_opt.static.discretisation import StaticSettings
from presag_opt.static.form_finding import form_find
from presag_opt.system.catenary import SpanLayout
from presag_opt.system.loader import load_catenary


@pytest.fixture(scope="module")
def state():
    catenary = load_catenary("st_9.8_ideal").with_layout(SpanLayout(span_lengths=(60.0, 60.0, 60.0)))
    return form_find(catenary, StaticSettings(element_length=1.0))


def _backward_error(matrix, u, rhs):
    return np.abs(matrix @ u - rhs).max() / (abs(matrix).sum(axis=1).max() * np.abs(u).max())


def test_the_ordering_gives_a_narrow_band(state):
    solver = state.model.functions.solver
    pattern = solver.pattern.tocoo()
    natural = int(np.abs(pattern.row - pattern.col).max())
    assert solver.bandwidth < 40 < natural  # a few dozen after reordering, hundreds before
    assert sorted(solver.permutation) == list(range(pattern.shape[0]))


@pytest.mark.parametrize("backend", ["auto", "lapack", "compiled", "numba"])
def test_every_backend_solves_the_stiffness(state, backend):
    matrix = state.tangent_stiffness()
    rhs = np.random.default_rng(0).normal(size=(matrix.shape[0], 20))
    factor = state.factorised_stiffness()
    assert factor.positive_definite
    u = factor.solve(rhs, backend)
    assert _backward_error(matrix, u, rhs) <= 1e-12


def test_compiled_and_numba_agree_to_the_last_bit(state):
    factor = state.factorised_stiffness()
    rhs = np.random.default_rng(1).normal(size=(state.tangent_stiffness().shape[0], 20))
    assert np.array_equal(factor.solve(rhs, "compiled"), factor.solve(rhs, "numba"))


def test_an_indefinite_matrix_goes_to_superlu(state):
    """A negative spring on one DOF makes K indefinite: Cholesky fails, SuperLU solves exactly."""
    solver = state.model.functions.solver
    values = state.model.functions.hessian_values(state.positions.ravel(), state.params)[0].copy()
    matrix = solver.matrix(values)
    diagonal = matrix.diagonal()
    shift = sp.diags(np.where(np.arange(len(diagonal)) == 5, -2 * diagonal.max(), 0.0)).tocsc()
    indefinite = (matrix + shift).tocsc()
    indefinite.sort_indices()
    factor = BandedSolver.for_pattern(indefinite).factorise(indefinite.data)
    assert not factor.positive_definite
    rhs = np.ones(matrix.shape[0])
    assert _backward_error(indefinite, factor.solve(rhs), rhs) <= 1e-12


@pytest.mark.parametrize("backend", ["lapack", "compiled", "numba"])
def test_an_inverse_block_equals_the_full_solves_rows(state, backend):
    """K⁻¹[rows, rows] from the trailing factor equals the rows of the full solve: the same
    substitutions, the skipped rows only ever contributing zeros (to the last bit on this machine;
    compared to 1e-14 of the block's largest entry so another BLAS cannot fail it)."""
    factor = state.factorised_stiffness()
    n = state.tangent_stiffness().shape[0]
    rows = np.random.default_rng(2).choice(np.arange(n // 3, n), size=25, replace=False)
    unit = np.zeros((n, len(rows)))
    unit[rows, np.arange(len(rows))] = 1.0
    full = factor.solve(unit, backend)[rows]
    block = factor.inverse_block(rows, backend)
    assert np.abs(block - full).max() <= 1e-14 * np.abs(full).max()
    assert np.allclose(block, block.T, rtol=1e-10, atol=0.0)  # K⁻¹ is symmetric
    skipped = int(factor.solver.position[rows].min())
    assert skipped > 0  # the rows drawn from the last two thirds leave leading rows unsolved


def test_an_inverse_block_of_an_indefinite_matrix_comes_from_superlu(state):
    solver = state.model.functions.solver
    values = state.model.functions.hessian_values(state.positions.ravel(), state.params)[0].copy()
    matrix = solver.matrix(values)
    shift = sp.diags(np.where(np.arange(matrix.shape[0]) == 5, -2 * matrix.diagonal().max(), 0.0)).tocsc()
    indefinite = (matrix + shift).tocsc()
    indefinite.sort_indices()
    factor = BandedSolver.for_pattern(indefinite).factorise(indefinite.data)
    rows = np.array([7, 3, 40])
    dense = np.linalg.inv(indefinite.toarray())[np.ix_(rows, rows)]
    assert np.allclose(factor.inverse_block(rows), dense, rtol=1e-9, atol=0.0)
