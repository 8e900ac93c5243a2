"""The case-study report written once (quick numerics); the headless Chromium that opens it is the
shared ``chromium`` fixture of ``tests/conftest.py``."""

from __future__ import annotations

import json

import pytest


@pytest.fixture(scope="session")
def case_study_report(tmp_path_factory, presag):
    """``presag report --quick --json`` of the case study: (folder, summary printed)."""
    folder = tmp_path_factory.mktemp("report")
    result = presag("report", "--out", str(folder), "--quick", "--json")
    assert result.returncode == 0, result.stderr
    return folder, json.loads(result.stdout)
