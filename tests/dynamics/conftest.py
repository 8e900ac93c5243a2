"""Shared pieces of the batch-engine tests: the case study and its form-found 5-span section."""

from __future__ import annotations

import pytest

from presag_opt.dynamics.case import load_case
from presag_opt.static.form_finding import form_find
from presag_opt.system.catenary import SpanLayout


@pytest.fixture(scope="module")
def case():
    return load_case("case_study_st98")


@pytest.fixture(scope="module")
def short_state(case):
    """Form-found 5-span ST 9,8/9,8 section (one lead-in span each side of the analysed central span)."""
    catenary = case.catenary.with_layout(SpanLayout(span_lengths=(60.0,) * 5, label="5 ideal spans"))
    return form_find(catenary, case.settings.static)
