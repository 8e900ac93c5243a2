"""The C build tool: a library per source, flags and compiler (keyed by their hash), nothing built
when compiling is off or the source does not compile, and no half-written library left behind."""

from __future__ import annotations

import ctypes

import pytest

from presag_opt.native import compiler

SOURCE = "double presag_test_value(void) { return %s; }\n"


@pytest.fixture()
def cache_home(tmp_path, monkeypatch):
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path))
    monkeypatch.delenv(compiler.COMPILE_ENV_OFF, raising=False)
    compiler._build.cache_clear()
    yield tmp_path / "presag_opt" / "compiled"
    compiler._build.cache_clear()


def _value(library):
    function = ctypes.CDLL(str(library)).presag_test_value
    function.restype = ctypes.c_double
    return function()


def test_a_library_per_source_and_flags(cache_home):
    one = compiler.build("probe", SOURCE % "1.5", ["-O2"])
    assert one is not None and one.parent == cache_home and one.name.startswith("probe-")
    assert _value(one) == 1.5
    assert compiler.build("probe", SOURCE % "1.5", ["-O2"]) == one  # the same inputs: the same file
    two = compiler.build("probe", SOURCE % "2.5", ["-O2"])
    assert two != one and _value(two) == 2.5  # an edited source is a new library
    assert compiler.build("probe", SOURCE % "1.5", ["-O1"]) != one  # so are other flags
    assert sorted(p.suffix for p in cache_home.iterdir()) == [".so", ".so", ".so"]  # no temporary files left


def test_nothing_is_built_when_compiling_is_off_or_fails(cache_home, monkeypatch):
    assert compiler.build("broken", "this is not C", ["-O2"]) is None
    monkeypatch.setenv(compiler.COMPILE_ENV_OFF, "1")
    assert compiler.compiling_disabled()
    assert compiler.build("probe", SOURCE % "3.5", ["-O2"]) is None
    monkeypatch.setenv(compiler.COMPILE_ENV_OFF, "0")
    assert not compiler.compiling_disabled()
    monkeypatch.setenv("CC", "/nonexistent/cc")
    assert compiler.build("probe", SOURCE % "4.5", ["-O2"]) is None
    assert not cache_home.exists() or not list(cache_home.glob("broken-*"))


def test_the_cache_folder_follows_xdg(monkeypatch, tmp_path):
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path))
    assert compiler.default_cache_directory() == tmp_path / "presag_opt"
