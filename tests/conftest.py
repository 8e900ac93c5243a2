"""Shared fixtures: form-found states and elasticity sections are expensive (1–5 s), so each is built
once per session."""

from __future__ import annotations

import warnings

import pytest

from presag_opt.design import recommend, section_elasticity
from presag_opt.static.form_finding import form_find
from presag_opt.system.catenary import SpanLayout
from presag_opt.system.loader import load_catenary


@pytest.fixture(scope="session")
def st98():
    """Form-found ST 9,8/9,8 ideal section (10 × 60 m)."""
    return form_find(load_catenary("st_9.8_ideal"))


@pytest.fixture(scope="session")
def st71():
    """Form-found ST 7,1/7,1 ideal section (10 × 60 m)."""
    return form_find(load_catenary("st_7.1_ideal"))


@pytest.fixture(scope="session")
def st98_mixed():
    """Form-found ST 9,8/9,8 31-span representative section."""
    return form_find(load_catenary("st_9.8_mixed"))


FIG5B_LEVELS = (50.0, 100.0, 150.0, 200.0)


@pytest.fixture(scope="session")
def ideal98(st98):
    """ST 9,8/9,8 central span at 50–200 N (nominal 30 mm geometry)."""
    return section_elasticity(st98, force_levels=FIG5B_LEVELS)


@pytest.fixture(scope="session")
def ideal71(st71):
    """ST 7,1/7,1 central span at 100 and 150 N (they bracket Table 2's 140 N)."""
    return section_elasticity(st71, force_levels=(100.0, 150.0))


@pytest.fixture(scope="session")
def ideal98_70mm():
    """ST 9,8/9,8 central span at 50–200 N on the 70 mm geometry (Fig. 5b)."""
    return section_elasticity(load_catenary("st_9.8_ideal").with_presag(0.070 / 60.0), force_levels=FIG5B_LEVELS)


@pytest.fixture(scope="session")
def short_mixed():
    """A five-span mixed section cut from the stand-in span list (cheap to form-find)."""
    catenary = load_catenary("st_9.8_mixed")
    return catenary.with_layout(SpanLayout(span_lengths=(45.0, 58.4, 24.7, 40.7, 52.0), label="test: five spans"))


@pytest.fixture(scope="session")
def short_recommendation(short_mixed):
    """The case-study band on ideal ST 9,8/9,8 spans and the five-span mixed section, recomputed once."""
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # the case-study band must not warn on these layouts
        return recommend(models=[load_catenary("st_9.8_ideal"), short_mixed], recompute_at_recommended=True)


@pytest.fixture(scope="session", autouse=True)
def _cache_in_a_session_folder(tmp_path_factory):
    """Commands run by the tests cache form-found states in a folder of this session (shared by the
    tests, so later commands start faster), never in the user's cache."""
    with pytest.MonkeyPatch.context() as patch:
        patch.setenv("XDG_CACHE_HOME", str(tmp_path_factory.mktemp("cache")))
        yield


@pytest.fixture(scope="session", autouse=True)
def _static_models_built_in_this_session():
    """Start the session with no static model kept in memory (``static_model``'s cache). A mutation
    tester that forks each mutant's session from a process that already ran the tests would otherwise
    reuse discretisations built by the unmutated code, and a mutant in them would seem to survive."""
    from presag_opt.static.equilibrium import _static_model

    _static_model.cache_clear()
    yield
