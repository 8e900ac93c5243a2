"""The many-column banded Cholesky solve: its three back-ends, the choice among them, the fallback
without a compiler, and a C source edit that takes effect (no stale library).

Tolerances: the C sweep and its numba twin do the same operations in the same order, so they must
agree to the last bit (``np.array_equal``). LAPACK sums in another order; on the test matrix
(diagonally dominant, condition number below 10, 300 rows, bandwidth 7) each solution entry is a
sum of at most 2·300 rounded products, so the two may differ by a few hundred ulps of the largest
entry at most: 1e-12 relative to max|x| (about 4 500 ulps), while any real error (a wrong sign, a
missed band entry) moves entries by 1e-3 or more.
"""

from __future__ import annotations

import os
import subprocess
import sys

import numpy as np
import pytest
import scipy.linalg as sla

from presag_opt.errors import ModelError
from presag_opt.native import banded, compiler

ROWS, BANDWIDTH = 300, 7


def _band_matrix(seed: int = 0) -> np.ndarray:
    """A symmetric positive definite band matrix, diagonally dominant (condition number < 10), in
    LAPACK's lower band storage (``ab[i − j, j] = A[i, j]``)."""
    rng = np.random.default_rng(seed)
    ab = np.zeros((BANDWIDTH + 1, ROWS))
    ab[1:] = rng.uniform(-1.0, 1.0, (BANDWIDTH, ROWS))
    ab[0] = 4.0 * BANDWIDTH
    return ab


def _dense(ab: np.ndarray) -> np.ndarray:
    a = np.zeros((ROWS, ROWS))
    for k in range(BANDWIDTH + 1):
        idx = np.arange(ROWS - k)
        a[idx + k, idx] = ab[k, : ROWS - k]
        a[idx, idx + k] = ab[k, : ROWS - k]
    return a


@pytest.fixture(scope="module")
def problem():
    ab = _band_matrix()
    factor = sla.cholesky_banded(ab, lower=True)
    rhs = np.random.default_rng(1).normal(size=(ROWS, 40))
    return ab, factor, rhs


def test_compiled_equals_numba_to_the_last_bit(problem):
    _, factor, rhs = problem
    assert banded.compiled_available(), "banded.c was not built (no C compiler?): nothing is compared"
    compiled = banded.cholesky_solve(factor, rhs, "compiled")
    numba = banded.cholesky_solve(factor, rhs, "numba")
    assert np.array_equal(compiled, numba)
    one = banded.cholesky_solve(factor, rhs[:, :1], "compiled")
    assert np.array_equal(one, banded.cholesky_solve(factor, rhs[:, :1], "numba"))


@pytest.mark.parametrize("backend", ["compiled", "numba"])
def test_the_sweeps_match_lapack_and_solve_the_system(problem, backend):
    ab, factor, rhs = problem
    x = banded.cholesky_solve(factor, rhs, backend)
    reference = banded.cholesky_solve(factor, rhs, "lapack")
    assert np.abs(x - reference).max() <= 1e-12 * np.abs(reference).max()
    # and the LAPACK reference solves A x = b: residual at round-off of ‖A‖·‖x‖ (both about 30 and 1)
    assert np.abs(_dense(ab) @ reference - rhs).max() <= 1e-12 * 4.0 * BANDWIDTH * np.abs(reference).max() * ROWS


def test_a_vector_and_a_single_column_keep_their_shape(problem):
    _, factor, rhs = problem
    assert banded.cholesky_solve(factor, rhs[:, 0], "numba").shape == (ROWS,)
    assert np.array_equal(banded.cholesky_solve(factor, rhs[:, 0], "numba"),
                          banded.cholesky_solve(factor, rhs[:, :1], "numba")[:, 0])


def test_auto_decides_from_the_problem_and_the_runtime_only(test_runtime):
    assert banded.choose(10_000, banded.MANY_RIGHT_HAND_SIDES - 1) == "lapack"
    assert banded.choose(10_000, banded.MANY_RIGHT_HAND_SIDES) == "compiled"
    for _ in range(3):  # however many solves ran before: the same answer
        assert banded.choose(10, banded.MANY_RIGHT_HAND_SIDES) == "compiled"
    with test_runtime.replace(compile=False):
        assert banded.choose(10_000, 120) == "lapack"  # 1.2e6 < NUMBA_WORK
        assert banded.choose(20_000, 120) == "numba"  # 2.4e6 ≥ NUMBA_WORK
        assert banded.choose(20_000, 120, "lapack") == "lapack"
    assert banded.choose(10, banded.MANY_RIGHT_HAND_SIDES) == "compiled"  # the runtime's choice ends with it


def test_bad_backends_are_refused_in_one_line(test_runtime):
    with pytest.raises(ModelError, match="backend = 'fast' is not one of auto, lapack, compiled, numba"):
        banded.choose(10, 20, "fast")
    with test_runtime.replace(compile=False), pytest.raises(ModelError, match="backend = 'compiled' needs the C library"):
        banded.choose(10, 20, "compiled")


_NO_COMPILER = """
import numpy as np, scipy.linalg as sla
from presag_opt.native import banded
ab = np.zeros((3, 50)); ab[0] = 5.0; ab[1] = 1.0; ab[2] = -0.5
factor = sla.cholesky_banded(ab, lower=True)
rhs = np.arange(50 * 20, dtype=float).reshape(50, 20)
x = banded.cholesky_solve(factor, rhs)
print(banded.compiled_available(), banded.choose(50, 20), banded.choose(200_000, 20),
      float(np.abs(x - sla.cho_solve_banded((factor, True), rhs)).max() / np.abs(x).max()))
"""


@pytest.mark.parametrize("environment", [{"PRESAG_NO_COMPILE": "1"}, {"CC": "/nonexistent/cc"}])
def test_without_a_compiler_the_fallbacks_run(environment, tmp_path):
    """In a fresh process (nothing built or loaded before): no library, and the same solution."""
    env = {**os.environ, "XDG_CACHE_HOME": str(tmp_path), **environment}
    out = subprocess.run([sys.executable, "-c", _NO_COMPILER], capture_output=True, text=True, env=env,
                         check=True, timeout=300).stdout.split()
    assert out[:3] == ["False", "lapack", "numba"]
    assert float(out[3]) <= 1e-13  # LAPACK itself (auto at 50 × 20 rows × columns), against LAPACK
    assert not (tmp_path / "presag_opt" / "compiled").exists()  # nothing was built


def test_an_edited_c_source_takes_effect(problem, tmp_path, test_runtime):
    """A copy of banded.c with one sign flipped (the forward sweep adds the band products instead of
    subtracting them) builds a new library through the build tool, and the solve follows the edit:
    it then solves M Lᵀ x = b with M = L with its off-diagonal entries negated."""
    _, factor, rhs = problem
    source = banded.SOURCE.read_text()
    edited_path = tmp_path / "banded.c"
    forward = "for (int64_t b = 0; b < columns; b++) acc[b] -= value * xk[b];"
    assert source.count(forward) == 2  # the forward sweep's, then the backward sweep's
    edited_path.write_text(source.replace(forward, forward.replace("-=", "+="), 1))
    edited = edited_path.read_text()
    with test_runtime.replace(library_folder=tmp_path / "compiled"):
        original_library = compiler.build("banded", source, banded.FLAGS)
        edited_library = compiler.build("banded", edited, banded.FLAGS)
    assert original_library is not None and edited_library is not None
    assert original_library != edited_library  # keyed by the source text: the edit is a new library

    def run(library):
        x = np.array(rhs, order="C")
        by_rows = np.ascontiguousarray(factor.T)
        banded.load_solve(library)(by_rows.ctypes.data, x.ctypes.data, np.empty(x.shape[1]).ctypes.data,
                                   ROWS, BANDWIDTH + 1, x.shape[1], x.shape[1])
        return x

    lower = np.zeros((ROWS, ROWS))
    for k in range(BANDWIDTH + 1):
        idx = np.arange(ROWS - k)
        lower[idx + k, idx] = factor[k, : ROWS - k]
    negated = 2 * np.diag(np.diag(lower)) - lower
    expected = sla.solve_triangular(lower.T, sla.solve_triangular(negated, rhs, lower=True), lower=False)
    x_edited = run(edited_library)
    assert np.abs(x_edited - expected).max() <= 1e-9 * np.abs(expected).max()
    assert np.array_equal(run(original_library), banded.cholesky_solve(factor, rhs, "numba"))
    assert np.abs(x_edited - run(original_library)).max() > 1e-3 * np.abs(expected).max()
