"""The one place of the version (presag_opt/version.py) and who reads it."""

from __future__ import annotations

import tomllib
from pathlib import Path

ROOT = Path(__file__).parents[1]
PROJECT = tomllib.loads((ROOT / "pyproject.toml").read_text())


def test_the_version_is_written_once_and_cited_and_logged():
    """``presag_opt.version`` is the one place: the metadata reads it, and the citation file and the
    changelog name it."""
    import presag_opt
    from presag_opt.cli import _version
    from presag_opt.version import VERSION

    assert presag_opt.__version__ == VERSION == _version()
    assert PROJECT["project"]["dynamic"] == ["version"] and "version" not in PROJECT["project"]
    assert PROJECT["tool"]["setuptools"]["dynamic"]["version"] == {"attr": "presag_opt.version.VERSION"}
    citation = (ROOT / "CITATION.cff").read_text()
    assert f"\nversion: {presag_opt.__version__}\n" in citation
    assert f"## {presag_opt.__version__} " in (ROOT / "docs" / "project" / "changelog.md").read_text()
