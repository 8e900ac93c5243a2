"""Sections (presag_opt.design.section): per-span pre-sag on a mixed section, default spans."""

from __future__ import annotations

import numpy as np
import pytest

from presag_opt.design import default_spans, section_elasticity
from presag_opt.system.loader import load_catenary


def test_mixed_section_presag_per_span(short_mixed):
    section = section_elasticity(short_mixed, force_levels=(100.0, 150.0), step=1.0)
    assert section.spans == (1, 2, 3)  # end spans excluded by default
    result = section.presag(120.0, "delta-e")
    lengths = np.array([58.4, 24.7, 40.7])
    np.testing.assert_array_equal(result.span_lengths, lengths)
    # Definitions, exact up to rounding: S_i = F_m Δe_i, S_rel,i = S_i/l_i, built S ∝ l.
    np.testing.assert_allclose(result.presag, 120.0 * result.elasticity_difference, rtol=1e-14)
    np.testing.assert_allclose(result.presag_rel, result.presag / lengths, rtol=1e-14)
    assert result.presag_rel_mean == pytest.approx(result.presag_rel.mean(), rel=1e-14)
    np.testing.assert_allclose(result.presag_proportional / lengths, result.presag_rel_mean, rtol=1e-14)
    # Spans of different length do need different relative pre-sag (the paper's Fig. 5a point).
    assert np.ptp(result.presag_rel) > 0.05 * result.presag_rel_mean


def test_default_spans():
    assert default_spans(load_catenary("st_9.8_ideal")) == (5,)
    assert default_spans(load_catenary("st_9.8_mixed")) == tuple(range(1, 30))
