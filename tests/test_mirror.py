"""The tests mirror the package (issue 19, item 6): every module of ``presag_opt`` that holds logic has
a test module at the same path, ``presag_opt/a/b.py`` → ``tests/a/test_b.py`` and a top-level
``presag_opt/x.py`` → ``tests/test_x.py``. ``__init__.py`` and ``__main__.py`` are left out (they hold
re-exports, registrations and entry points); a module with no logic of its own is exempt only with a
reason, in :data:`EXEMPT`."""

from __future__ import annotations

from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
PACKAGE = ROOT / "presag_opt"
TESTS = ROOT / "tests"

EXEMPT: dict[str, str] = {}
"""Module (path below ``presag_opt/``) -> why it needs no test module of its own. Empty: every module
that is not an ``__init__.py`` or ``__main__.py`` holds logic (``validation/paper.py``, the published
numbers as data, is checked against the paper's own formulas in ``tests/validation/test_paper.py``)."""

PENDING_FROM_OTHER_BRANCHES: dict[str, str] = {}
"""Module -> the branch that brings its test module, for a module merged ahead of its tests; empty on
``main``. An entry whose test module exists already fails below, so it cannot linger."""


def mirror_of(module: Path) -> Path:
    """The test module of a package module: ``a/b.py`` → ``tests/a/test_b.py``."""
    relative = module.relative_to(PACKAGE)
    return TESTS / relative.parent / f"test_{relative.name}"


def _modules() -> list[str]:
    return sorted(str(p.relative_to(PACKAGE)) for p in PACKAGE.rglob("*.py")
                  if p.name not in ("__init__.py", "__main__.py") and "__pycache__" not in p.parts)


def test_every_module_with_logic_has_its_mirror_test_module():
    missing = [m for m in _modules() if m not in EXEMPT and m not in PENDING_FROM_OTHER_BRANCHES
               and not mirror_of(PACKAGE / m).is_file()]
    assert not missing, "modules without a mirror test module (presag_opt/a/b.py -> tests/a/test_b.py): " + ", ".join(
        f"presag_opt/{m} -> {mirror_of(PACKAGE / m).relative_to(ROOT)}" for m in missing)


def test_the_exemptions_and_pending_entries_name_modules_that_exist_and_lack_a_test_module():
    modules = set(_modules())
    stale = [m for m in [*EXEMPT, *PENDING_FROM_OTHER_BRANCHES] if m not in modules]
    assert not stale, f"entries for modules that do not exist (renamed or removed?): {', '.join(stale)}"
    done = [m for m in PENDING_FROM_OTHER_BRANCHES if mirror_of(PACKAGE / m).is_file()]
    assert not done, f"pending modules that have their test module now; remove them from the list: {', '.join(done)}"
    assert all(reason.strip() for reason in EXEMPT.values()), "every exemption needs its reason"


def test_the_mirror_rule_maps_paths_as_documented():
    assert mirror_of(PACKAGE / "speed.py") == TESTS / "test_speed.py"
    assert mirror_of(PACKAGE / "cli" / "common.py") == TESTS / "cli" / "test_common.py"
