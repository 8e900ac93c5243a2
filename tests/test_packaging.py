"""What a wheel would hold, checked from the source tree (the built wheel itself: tests/wheel/)."""

from __future__ import annotations

import tomllib
from pathlib import Path

ROOT = Path(__file__).parents[1]
PROJECT = tomllib.loads((ROOT / "pyproject.toml").read_text())


def test_every_subpackage_and_data_folder_is_listed_for_the_wheel():
    """A sub-package missing from ``[tool.setuptools] packages`` works in an editable install and is
    absent from the wheel (``presag_opt.pipeline`` once was); a data folder (no ``__init__.py``) is
    listed too, or setuptools warns that it would be ignored."""
    listed = set(PROJECT["tool"]["setuptools"]["packages"])
    folders = [p for p in (ROOT / "presag_opt").rglob("*") if p.is_dir() and "__pycache__" not in p.parts]
    found = {"presag_opt", *(".".join(p.relative_to(ROOT).parts) for p in folders)}
    models = {"presag_opt.builtin_models", *(f"presag_opt.builtin_models.{d.name}" for d in (ROOT / "models").iterdir()
                                             if d.is_dir() and d.name != "__pycache__")}
    assert listed == found | models, (sorted(found | models - listed), sorted(listed - found - models))


def test_every_data_file_of_the_package_is_declared():
    """Each non-Python file inside ``presag_opt/`` matches a ``package-data`` pattern of its package."""
    data = PROJECT["tool"]["setuptools"]["package-data"]
    missing = []
    for path in (ROOT / "presag_opt").rglob("*"):
        if not path.is_file() or path.suffix in {".py", ".pyc", ".nbi", ".nbc", ".lock"} or "__pycache__" in path.parts:
            continue
        package = ".".join(path.parent.relative_to(ROOT).parts)
        while package not in data and "." in package:
            package = package.rsplit(".", 1)[0]
        relative = path.relative_to(ROOT / package.replace(".", "/"))
        if not any(relative.match(pattern) for pattern in data.get(package, ())):
            missing.append(str(path.relative_to(ROOT)))
    assert not missing, missing
