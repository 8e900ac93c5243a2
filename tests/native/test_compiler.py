"""The C build tool: a library per source, flags and compiler (keyed by their hash), in the runtime's
library folder, nothing built when the runtime turns compiling off or the source does not compile, and
no half-written library left behind."""

from __future__ import annotations

import ctypes

import pytest

from presag_opt.native import compiler
from presag_opt.runtime import Runtime, default_cache_directory

SOURCE = "double presag_test_value(void) { return %s; }\n"


@pytest.fixture()
def library_folder(tmp_path, test_runtime):
    """A runtime that compiles into an empty folder of this test's."""
    folder = tmp_path / "presag_opt" / "compiled"
    with test_runtime.replace(compile=True, library_folder=folder):
        yield folder


def _value(library):
    function = ctypes.CDLL(str(library)).presag_test_value
    function.restype = ctypes.c_double
    return function()


def test_a_library_per_source_and_flags(library_folder):
    one = compiler.build("probe", SOURCE % "1.5", ["-O2"])
    assert one is not None and one.parent == library_folder and one.name.startswith("probe-")
    assert _value(one) == 1.5
    assert compiler.build("probe", SOURCE % "1.5", ["-O2"]) == one  # the same inputs: the same file
    two = compiler.build("probe", SOURCE % "2.5", ["-O2"])
    assert two != one and _value(two) == 2.5  # an edited source is a new library
    assert compiler.build("probe", SOURCE % "1.5", ["-O1"]) != one  # so are other flags
    assert sorted(p.suffix for p in library_folder.iterdir()) == [".so", ".so", ".so"]  # no temporary files left


def test_nothing_is_built_when_compiling_is_off_or_fails(library_folder, monkeypatch, test_runtime):
    assert compiler.build("broken", "this is not C", ["-O2"]) is None
    with test_runtime.replace(compile=False, library_folder=library_folder):
        assert compiler.compiling_disabled()
        assert compiler.build("probe", SOURCE % "3.5", ["-O2"]) is None
    assert not compiler.compiling_disabled()
    monkeypatch.setenv("CC", "/nonexistent/cc")
    assert compiler.build("probe", SOURCE % "4.5", ["-O2"]) is None
    assert not library_folder.exists() or not list(library_folder.glob("broken-*"))
    assert not library_folder.exists() or not list(library_folder.glob("probe-*"))


def test_the_runtime_follows_the_environment(tmp_path):
    environ = {"XDG_CACHE_HOME": str(tmp_path), "PRESAG_NO_COMPILE": "1", "PRESAG_NO_CACHE": "0"}
    assert default_cache_directory(environ) == tmp_path / "presag_opt"
    runtime = Runtime.from_environment(environ, state_cache=True)
    assert runtime == Runtime(state_cache=tmp_path / "presag_opt", compile=False,
                              library_folder=tmp_path / "presag_opt" / "compiled", debug=False)
    assert Runtime.from_environment({**environ, "PRESAG_NO_CACHE": "1"}, state_cache=True).state_cache is None
    assert Runtime.from_environment(environ).state_cache is None  # the library's default: no cache
    assert Runtime.from_environment({"PRESAG_NO_COMPILE": "0", "PRESAG_DEBUG": "1"}).compile
