"""The kernel's numba cache key: every source file a compiled function depends on.

The end-to-end check (an edited law takes effect with a warm cache) is
``tests/dynamics/test_kernel_cache.py``; here the key itself, on throwaway modules.
"""

from __future__ import annotations

import importlib.util
import sys

from numba.core import caching

from presag_opt.native import jit


def _load(path, name):
    spec = importlib.util.spec_from_file_location(name, path)
    module = importlib.util.module_from_spec(spec)
    sys.modules[name] = module
    spec.loader.exec_module(module)
    return module


def _two_files(tmp_path, body="return 2.0 * x"):
    (tmp_path / "jit_helper_law.py").write_text(
        "from presag_opt.native.jit import inline\n\n@inline\ndef law(x):\n    " + body + "\n")
    (tmp_path / "jit_helper_user.py").write_text(
        "from presag_opt.native.jit import kernel_function\nfrom jit_helper_law import law\n\n"
        "@kernel_function\ndef user(x):\n    return law(x) + 1.0\n")
    sys.path.insert(0, str(tmp_path))
    try:
        _load(tmp_path / "jit_helper_law.py", "jit_helper_law")
        return _load(tmp_path / "jit_helper_user.py", "jit_helper_user")
    finally:
        sys.path.remove(str(tmp_path))


def test_the_dependencies_follow_the_called_numba_functions(tmp_path):
    user = _two_files(tmp_path)
    files = {p.rsplit("/", 1)[-1] for p in jit.dependency_files(user.user.py_func)}
    assert {"jit_helper_user.py", "jit_helper_law.py"} <= files
    assert user.user(3.0) == 7.0


def test_the_stamp_changes_with_the_called_file_only(tmp_path):
    user = _two_files(tmp_path)
    before = jit.source_stamp(user.user.py_func)
    assert before == jit.source_stamp(user.user.py_func) and len(before) == 64
    (tmp_path / "jit_helper_law.py").write_text(
        "from presag_opt.native.jit import inline\n\n@inline\ndef law(x):\n    return 3.0 * x\n")
    assert jit.source_stamp(user.user.py_func) != before  # the user's own file did not change


def test_the_locator_takes_kernel_functions_only(tmp_path):
    user = _two_files(tmp_path)
    assert jit.DependencyLocator in caching.CacheImpl._locator_classes
    locator = jit.DependencyLocator.from_function(user.user.py_func, user.__file__)
    assert locator is not None and locator.get_source_stamp() == jit.source_stamp(user.user.py_func)
    law = sys.modules["jit_helper_law"].law
    assert jit.DependencyLocator.from_function(law.py_func, law.py_func.__code__.co_filename) is None
    assert law.targetoptions.get("inline") == "always"
