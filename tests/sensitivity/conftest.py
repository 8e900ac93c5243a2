"""The analyses here run without a cache folder: a long analysis keeps its evaluations in the cache folder
when one is set (the command line sets it), and a test that ran an analysis before would then read its
evaluations back instead of computing the comparison it makes."""

from __future__ import annotations

import pytest


@pytest.fixture(autouse=True)
def _no_cache_folder():
    from presag_opt import runtime

    with runtime.current().replace(state_cache=None):
        yield
