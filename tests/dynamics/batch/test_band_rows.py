"""The bands' nonzero entries by rows (:mod:`presag_opt.dynamics.batch.band_rows`): every nonzero entry once,
no zero, in a full-band sweep's order; and the case study's bands, whose zeros the sweeps skip."""

from __future__ import annotations

import numpy as np

from presag_opt.dynamics.batch.band_rows import lower_rows, symmetric_rows, upper_rows


def _random_band(n=40, bw=5, fill=0.4, seed=3):
    rng = np.random.default_rng(seed)
    band = np.where(rng.random((n, bw + 1)) < fill, rng.normal(size=(n, bw + 1)), 0.0)
    band[:, 0] = 10.0 + rng.random(n)
    for k in range(1, bw + 1):
        band[n - k:, k] = 0.0  # outside the matrix
    return band


def _dense_lower(band):
    n = band.shape[0]
    a = np.zeros((n, n))
    for j in range(n):
        for k in range(band.shape[1]):
            if j + k < n:
                a[j + k, j] = band[j, k]
    return a


def _matrix(rows, n):
    a = np.zeros((n, n))
    for j in range(n):
        for e in range(rows.start[j], rows.start[j + 1]):
            assert a[j, rows.column[e]] == 0.0, "an entry listed twice"
            a[j, rows.column[e]] = rows.value[e]
    return a


def test_the_symmetric_rows_are_the_off_diagonal_nonzeros_right_then_left_of_the_diagonal():
    band = _random_band()
    n, lower = band.shape[0], _dense_lower(band)
    full = lower + np.tril(lower, -1).T
    rows = symmetric_rows(band)
    assert np.array_equal(_matrix(rows, n), full - np.diag(np.diag(full)))
    assert np.all(rows.value != 0.0) and rows.start[-1] == np.count_nonzero(full) - n
    for j in range(n):  # offsets +1 … +bw, then −1 … −bw: the order of a full-band sweep
        offsets = rows.column[rows.start[j]:rows.start[j + 1]] - j
        right, left = offsets[offsets > 0], offsets[offsets < 0]
        assert np.array_equal(offsets, np.concatenate([right, left]))
        assert np.all(np.diff(right) > 0) and np.all(np.diff(left) < 0)


def test_the_factor_rows_are_the_strict_triangles_in_the_substitutions_order():
    band = _random_band(seed=5)
    n, lower = band.shape[0], _dense_lower(band)
    below, above = lower_rows(band), upper_rows(band)
    assert np.array_equal(_matrix(below, n), np.tril(lower, -1))
    assert np.array_equal(_matrix(above, n), np.tril(lower, -1).T)
    for rows, sign in ((below, -1), (above, 1)):
        for j in range(n):
            offsets = sign * (rows.column[rows.start[j]:rows.start[j + 1]] - j)
            assert np.all(offsets > 0) and np.all(np.diff(offsets) > 0)  # k = 1, 2, … as the bands are read


def test_an_empty_band_has_no_entries():
    band = np.zeros((4, 3))
    band[:, 0] = 1.0
    for rows in (symmetric_rows(band), lower_rows(band), upper_rows(band)):
        assert rows.start.tolist() == [0] * 5 and rows.column.size == rows.value.size == 0
