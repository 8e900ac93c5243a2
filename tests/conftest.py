"""Shared fixtures: form-found states are expensive (1–5 s), so each is built once per session."""

from __future__ import annotations

import pytest

from presag_opt.static.equilibrium import form_find
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
