"""The kernel's numba cache key: every source file a compiled function depends on.

The end-to-end check (an edited law takes effect with a warm cache) is
``tests/dynamics/batch/test_kernel_cache.py``; here the key itself, on throwaway modules.
"""

from __future__ import annotations

import importlib.util
import json
import os
import subprocess
import sys

import numba
import numpy as np
import pytest
from numba.core import caching

from presag_opt.native import jit


def _load(path, name):
    spec = importlib.util.spec_from_file_location(name, path)
    module = importlib.util.module_from_spec(spec)
    sys.modules[name] = module
    spec.loader.exec_module(module)
    return module


def _helper_modules(tmp_path, **sources):
    """Write each source as ``<name>.py`` in ``tmp_path`` and import them in order (they may import the
    ones before); the modules, in order."""
    for name, source in sources.items():
        (tmp_path / f"{name}.py").write_text(source)
    sys.path.insert(0, str(tmp_path))
    try:
        return [_load(tmp_path / f"{name}.py", name) for name in sources]
    finally:
        sys.path.remove(str(tmp_path))


def _two_files(tmp_path, body="return 2.0 * x"):
    _, user = _helper_modules(
        tmp_path,
        jit_helper_law="from presag_opt.native.jit import kernel_part\n\n@kernel_part\ndef law(x):\n    " + body + "\n",
        jit_helper_user=("from presag_opt.native.jit import kernel_function\nfrom jit_helper_law import law\n\n"
                         "@kernel_function\ndef user(x):\n    return law(x) + 1.0\n"))
    return user


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
        "from presag_opt.native.jit import kernel_part\n\n@kernel_part\ndef law(x):\n    return 3.0 * x\n")
    assert jit.source_stamp(user.user.py_func) != before  # the user's own file did not change


def test_a_kernel_function_has_its_own_cache_and_numba_is_left_as_it_was(tmp_path):
    numba_locators = list(caching.CacheImpl._locator_classes)
    user = _two_files(tmp_path)
    assert caching.CacheImpl._locator_classes == numba_locators  # no global patch of numba
    assert jit.DependencyLocator not in numba_locators
    assert isinstance(user.user._cache, jit.KernelCache)
    locator = user.user._cache._impl.locator
    assert isinstance(locator, jit.DependencyLocator)
    assert locator.get_source_stamp() == jit.source_stamp(user.user.py_func)
    law = sys.modules["jit_helper_law"].law
    assert not isinstance(law._cache, jit.KernelCache)  # a kernel part has no cache of its own
    assert isinstance(law, jit.KernelPart) and law.targetoptions.get("no_cpython_wrapper")


def test_a_kernel_part_is_compiled_once_for_literal_and_variable_arguments_and_refuses_python_calls(tmp_path):
    """``law(2.0)`` and ``law(x)`` in a kernel function share one compilation of the part; called from
    Python (it has no Python entry point) it raises instead of crashing."""
    (module,) = _helper_modules(tmp_path, jit_helper_literal=(
        "from presag_opt.native.jit import kernel_function, kernel_part\n\n"
        "@kernel_part\ndef scale(x, k):\n    return k * x\n\n"
        "@kernel_function\ndef user(x):\n    return scale(x, 2) + scale(x, int(x))\n"))
    assert module.user(3.0) == 15.0
    assert len(module.scale.signatures) == 1
    with pytest.raises(TypeError, match="part of the compiled kernel"):
        module.scale(3.0, 2)


def test_a_kernel_part_leaves_no_machine_code_and_runs_inside_its_callers(tmp_path):
    """A part's LLVM code is linked into its callers (here also through another part) and never added to
    numba's JIT engine: its function has no address there, the caller's has, and the caller computes
    with it."""
    (module,) = _helper_modules(tmp_path, jit_helper_nested=(
        "from presag_opt.native.jit import kernel_function, kernel_part\n\n"
        "@kernel_part\ndef inner(x):\n    return 2.0 * x\n\n"
        "@kernel_part\ndef outer(x):\n    return inner(x) + 1.0\n\n"
        "@kernel_function\ndef user(x):\n    return 3.0 * outer(x)\n"))
    assert module.user(1.5) == 12.0
    engine = module.user.targetctx.codegen()._engine
    for part in (module.inner, module.outer):
        (compiled,) = part.overloads.values()
        assert isinstance(compiled.library, jit.PartLibrary)
        assert not engine.is_symbol_defined(compiled.fndesc.llvm_func_name)
    (compiled,) = module.user.overloads.values()
    assert engine.is_symbol_defined(compiled.fndesc.llvm_func_name)


def test_a_kernel_part_that_reads_numba_s_environment_is_refused_when_compiled(tmp_path):
    """``print`` needs numba's environment at run time, which a part inlined into its callers does not
    have: the compilation says so instead of the call failing later with numba's "missing Environment"."""
    (module,) = _helper_modules(tmp_path, jit_helper_noisy=(
        "from presag_opt.native.jit import kernel_function, kernel_part\n\n"
        "@kernel_part\ndef noisy(x):\n    print(x)\n    return x\n\n"
        "@kernel_function\ndef user(x):\n    return noisy(x) + 1.0\n"))
    with pytest.raises(Exception, match="reads numba's environment"):
        module.user(2.0)


_COUNTING = ("from numba import njit\nfrom presag_opt.native import jit\n\n"
             "@jit.kernel_part\ndef product(x, y):\n    return x * y\n\n"
             "def total(arrays, n):\n    a, b, c = arrays\n    acc = 0.0\n    for i in range(n):\n"
             "        if a[i] < 0.0:\n            return -1.0\n        acc += a[i] + product(b[i], c[i])\n    return acc\n\n"
             "part = jit.kernel_part(total)\n"
             "counting = njit(**{**jit.PART_OPTIONS, '_nrt': True}, pipeline_class=jit.PartCompiler)(total)\n\n"
             "@jit.kernel_function\ndef user(arrays, n):\n    return part(arrays, n) + 1.0\n\n"
             "@jit.kernel_function\ndef counting_user(arrays, n):\n    return counting(arrays, n) + 1.0\n")


def test_a_kernel_part_counts_no_references_to_the_arrays_it_takes(tmp_path):
    """The same function compiled as a part and as a part with numba's runtime on (as parts were
    compiled before), each called from a kernel function with a tuple of arrays: with the runtime
    its code counts references to the tuple's arrays up and down around a call of another part (which
    numba's pruning of reference counts cannot see through); the part has no reference count
    operation, and computes the same."""
    (module,) = _helper_modules(tmp_path, jit_helper_counting=_COUNTING)
    arrays = tuple(np.arange(5.0) + k for k in range(3))
    assert module.user(arrays, 5) == module.counting_user(arrays, 5) == sum(a + b * c for a, b, c in zip(*arrays)) + 1.0
    (part,) = module.part.overloads.values()
    (counting,) = module.counting.overloads.values()
    assert "NRT_incref" not in str(part.library._final_module)
    assert "call void @NRT_incref" in str(counting.library._final_module)


def test_a_kernel_part_that_allocates_an_array_does_not_compile(tmp_path):
    """A part has no runtime to allocate with: its arrays come from the kernel's scratch arrays."""
    (module,) = _helper_modules(tmp_path, jit_helper_allocating=(
        "import numpy as np\nfrom presag_opt.native.jit import kernel_function, kernel_part\n\n"
        "@kernel_part\ndef allocating(x):\n    a = np.empty(3)\n    a[:] = x\n    return a.sum()\n\n"
        "@kernel_function\ndef user(x):\n    return allocating(x) + 1.0\n"))
    with pytest.raises(numba.core.errors.TypingError, match="empty"):
        module.user(2.0)


_SHARED = "from presag_opt.native.jit import shared_kernel_function\n\n@shared_kernel_function\ndef heavy(x):\n    return 2.0 * x\n"
_CALLER = ("from presag_opt.native.jit import kernel_function\nfrom jit_helper_heavy import heavy\n\n"
           "@kernel_function\ndef caller(x):\n    return heavy(x) + 1.0\n")


def test_a_shared_kernel_function_is_called_at_its_address_not_linked_into_its_caller(tmp_path):
    """The caller's code declares the shared function and calls it; its code is not in the caller's."""
    heavy, caller = _helper_modules(tmp_path, jit_helper_heavy=_SHARED, jit_helper_caller=_CALLER)
    assert caller.caller(1.5) == 4.0
    (shared,) = heavy.heavy.overloads.values()
    (compiled,) = caller.caller.overloads.values()
    functions = {f.name: f.is_declaration for f in compiled.library._final_module.functions}
    assert functions[shared.fndesc.llvm_func_name]  # declared, not defined


_PROCESS = """
import json, sys
sys.path.insert(0, sys.argv[1])
order = sys.argv[2].split(",")
import jit_helper_caller, jit_helper_heavy
values = {}
for name in order:
    if name == "heavy":
        values[name] = jit_helper_heavy.heavy(1.5)
    else:
        values[name] = jit_helper_caller.caller(1.5)
stats = jit_helper_caller.caller.stats
print(json.dumps({"values": values, "hits": sum(stats.cache_hits.values()), "misses": sum(stats.cache_misses.values())}))
"""


def test_a_cached_caller_is_compiled_again_when_the_shared_function_it_calls_is_not_loaded(tmp_path):
    """Each process: a fresh interpreter with the caches of the ones before. The caller's cached code
    calls the shared function by name; loaded before it, it is a cache hit; loaded alone it is a miss
    and compiled again (loading it would be a fatal LLVM error that ends the process)."""
    (tmp_path / "jit_helper_heavy.py").write_text(_SHARED)
    (tmp_path / "jit_helper_caller.py").write_text(_CALLER)
    env = {**os.environ, "NUMBA_CACHE_DIR": str(tmp_path / "cache")}

    def run(order):
        done = subprocess.run([sys.executable, "-c", _PROCESS, str(tmp_path), order], env=env, capture_output=True,
                              text=True, timeout=120)
        assert done.returncode == 0, done.stderr[-2000:]
        return json.loads(done.stdout.strip().splitlines()[-1])

    first = run("caller")
    assert first["values"] == {"caller": 4.0} and first["misses"] == 1
    assert run("heavy,caller") == {"values": {"heavy": 3.0, "caller": 4.0}, "hits": 1, "misses": 0}
    alone = run("caller")
    assert alone["values"] == {"caller": 4.0} and alone["misses"] == 1 and alone["hits"] == 0


def test_the_kernel_cache_is_written_and_read_back(tmp_path):
    """Compiled once, the function's machine code is in the cache; a fresh dispatcher of the same
    source loads it (a hit, no compilation), and its index is stamped with the dependencies' hash."""
    user = _two_files(tmp_path)
    assert user.user(1.0) == 3.0
    assert sum(user.user.stats.cache_misses.values()) == 1
    again = _two_files(tmp_path)  # the same files loaded again: a new dispatcher, the same cache
    assert again.user(2.0) == 5.0
    assert sum(again.user.stats.cache_hits.values()) == 1 and not sum(again.user.stats.cache_misses.values())



def test_kernel_functions_and_parts_compile_at_the_kernel_level_and_leave_numba_at_its_own(tmp_path, monkeypatch):
    """Every compilation of a kernel function and of its parts sees numba's optimisation level at
    KERNEL_OPTIMISATION (numba reads it per compilation), and numba's own level is back after; the
    level is part of the cache key, so a cache compiled at another level is not loaded."""
    from numba.core import config, event

    seen = []

    class Levels(event.Listener):
        def on_start(self, ev):
            seen.append((ev.data["dispatcher"].py_func.__name__, int(config.OPT)))

        def on_end(self, ev):
            pass

    levels = Levels()
    event.register("numba:compile", levels)
    own = int(config.OPT)
    try:
        user = _two_files(tmp_path)
        stamp = jit.source_stamp(user.user.py_func)
        assert user.user(3.0) == 7.0
    finally:
        event.unregister("numba:compile", levels)
    assert {name for name, _ in seen} == {"user", "law"}
    assert all(level == jit.KERNEL_OPTIMISATION for _, level in seen), seen
    assert int(config.OPT) == own
    monkeypatch.setattr(jit, "KERNEL_OPTIMISATION", jit.KERNEL_OPTIMISATION + 1)
    assert jit.source_stamp(user.user.py_func) != stamp
