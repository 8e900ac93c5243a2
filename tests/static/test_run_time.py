"""The form-finding time estimate: the node count of the discretisation, a time that grows with it
as the fitted law says, and zero when the state is cached."""

from __future__ import annotations

import pytest

from presag_opt.static.discretisation import StaticSettings, discretise
from presag_opt.static.form_finding import form_find
from presag_opt.static.run_time import FORM_FIND_SECONDS, form_find_estimate
from presag_opt.system.catenary import SpanLayout
from presag_opt.system.loader import load_catenary

COARSE = StaticSettings(element_length=1.0)


@pytest.fixture(scope="module")
def catenary():
    return load_catenary("st_9.8_ideal").with_layout(SpanLayout(span_lengths=(60.0, 60.0, 60.0)))


@pytest.fixture
def no_cache(test_runtime):
    """A runtime without the form-finding cache."""
    with test_runtime.replace(state_cache=None):
        yield


def test_the_estimate_follows_the_fitted_law(catenary, no_cache):
    nodes, seconds = form_find_estimate(catenary, COARSE)
    assert nodes == discretise(catenary, COARSE).n_nodes
    a, b, n_ref, power = FORM_FIND_SECONDS
    assert seconds == pytest.approx(a + b * (nodes / n_ref) ** power, rel=1e-15)
    finer, finer_seconds = form_find_estimate(catenary, StaticSettings(element_length=0.5))
    assert finer > 1.5 * nodes and finer_seconds > seconds  # half the element length: more nodes, more time


def test_a_cached_state_costs_nothing(catenary, tmp_path, test_runtime):
    with test_runtime.replace(state_cache=tmp_path):
        assert form_find_estimate(catenary, COARSE)[1] > 0.0
        form_find(catenary, COARSE)
        assert form_find_estimate(catenary, COARSE)[1] == 0.0
