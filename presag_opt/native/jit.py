"""numba compilation of the batch kernel, its on-disk cache keyed by every source file it depends on.

numba's ``cache=True`` keys a function's cached machine code by its own source file only: a compiled
function that calls a function of another file (linked into its code) keeps the old code when only that
other file changes (numba's documented limitation, numba/numba#1833). :func:`kernel_function`
compiles with the cache, but under :class:`DependencyLocator`, whose source stamp is a hash of the
contents of every file the function's compiled code comes from: its own, and, followed through the
module globals it reads, the file of every numba function it can call, recursively (the laws of
:mod:`presag_opt.dynamics.laws` included, which :mod:`presag_opt.dynamics.batch.forces` compiles
as kernel parts). An edit of any of them makes numba recompile the function on its next use and overwrite the
stale entry; the cache stays where numba keeps it (``__pycache__`` beside the source, or
``NUMBA_CACHE_DIR``).

Compiling the kernel takes about 13 s of one core (:func:`kernel_part` and
:func:`shared_kernel_function` say why not more). :func:`compile_once` compiles a kernel entry
point for the types of a call before the call, one process at a time: a process that finds another
compiling (the workers of a pool started together, two commands, the workers of a test run) waits
for it and then loads its cache instead of compiling the same code again on a core that has other
work. The lock is one per kernel function, so that two processes can compile two of them at once
(the kernel's first compilation on two cores, :mod:`presag_opt.dynamics.batch.compilation`).

A :func:`shared_kernel_function` is called at its own machine code by the kernel functions that
call it, not linked into theirs; their cached code names it. A cached caller whose named function
is not loaded in the process is a cache miss and is compiled again (loading it would end the
process with a fatal LLVM error, not an exception), so load the shared function first where the
caller is in the cache (as :func:`presag_opt.dynamics.batch.compilation.compile_kernel` does).

Only the functions compiled by :func:`kernel_function` use the locator: each gets a cache of its own
class (:class:`KernelCache`, numba's function cache with :class:`DependencyLocator` as its one locator)
when it is defined; numba's own list of locators and every other numba function are left as they are,
and importing this module changes nothing in numba.
"""

from __future__ import annotations

import contextlib
import functools
import hashlib
import os
import types
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import IO

import llvmlite.binding as llvm
from numba import njit
from numba.core import caching, compiler, config, sigutils
from numba.core import types as numba_types
from numba.core.codegen import JITCodeLibrary
from numba.core.compiler_lock import global_compiler_lock
from numba.core.dispatcher import Dispatcher
from numba.core.registry import CPUDispatcher

KERNEL_OPTIMISATION = 1
"""LLVM's optimisation level for the kernel functions and their parts (numba's default is 3). [-]

Measured on the batch kernel (``benchmarks/bench_kernel_compile.py``, ``benchmarks/bench_batch_rate.py``):
level 1 compiles the kernel in about 12 % less processor time than level 3, and its batches run as
fast within the machine's noise (the sweeps that dominate a step are C or simple loops; the inlining
the kernel parts rely on is done at level 1 too). The numbers are the same to the last bit: no level
reorders floating-point operations (numba compiles without fast-math, and LLVM keeps IEEE semantics).
Part of every kernel function's cache key, so a cache compiled at another level is compiled again."""


PART_OPTIONS = {"no_cpython_wrapper": True, "no_cfunc_wrapper": True, "_nrt": False}
"""numba's options for a :func:`kernel_part`: no Python entry point, no C wrapper, and no reference
counting (numba's runtime, NRT, off). Part of every kernel function's cache key.

Without the runtime a part takes its arrays as borrowed from the kernel function that calls it, which
holds them for the whole call: numba emits no reference count changes for them and no allocation.
With it, every call of a part counted a reference up and down for each array of each named tuple it
takes (``shared`` alone holds 25), whether the part reads it or not, with an atomic instruction each,
and the parts allocated their small arrays per run and step: about 10 % of a batch's time
(``perf`` on the case-study decision's 12-run batch), where the atomic operations stood as the two
hottest instructions outside the sweeps. A part that allocates an array (``np.empty``, ``np.eye``,
``.copy()``) or returns one it did not receive does not compile (numba's typing error: no
implementation of ``np.empty`` without its runtime); its arrays belong in
:class:`~presag_opt.dynamics.batch.kernel_data.Scratch`, allocated once per batch."""


@contextlib.contextmanager
def kernel_optimisation() -> Iterator[None]:
    """numba's optimisation level set to :data:`KERNEL_OPTIMISATION` while the block compiles (numba
    reads it from its configuration for each compilation); restored after."""
    saved = config.OPT
    config.OPT = config._OptLevel(KERNEL_OPTIMISATION)
    try:
        yield
    finally:
        config.OPT = saved


def dependency_files(function: Callable) -> tuple[str, ...]:
    """The source files a compiled function's code comes from: its own and, through its module
    globals, those of every numba function it can call, recursively (sorted paths)."""
    files: set[str] = set()
    seen: set[int] = set()
    pending = [function]
    while pending:
        current = pending.pop()
        if id(current) in seen:
            continue
        seen.add(id(current))
        code = getattr(current, "__code__", None)
        if code is not None and os.path.exists(code.co_filename):
            files.add(os.path.abspath(code.co_filename))
        for value in list(getattr(current, "__globals__", {}).values()):
            if isinstance(value, Dispatcher):
                pending.append(value.py_func)
            elif isinstance(value, types.ModuleType) and value.__name__.startswith("presag_opt."):
                # a module the function reads attributes of: every numba function in it counts
                pending += [item.py_func for item in vars(value).values() if isinstance(item, Dispatcher)]
    return tuple(sorted(files))


@functools.cache
def _file_digest(path: str, mtime: float, size: int) -> bytes:
    with open(path, "rb") as handle:
        return hashlib.sha256(handle.read()).digest()


def source_stamp(function: Callable) -> str:
    """Hash of the contents of :func:`dependency_files`, of :data:`KERNEL_OPTIMISATION` and of
    :data:`PART_OPTIONS` (the key a cached compilation is valid for)."""
    digest = hashlib.sha256(f"LLVM optimisation {KERNEL_OPTIMISATION}; parts {sorted(PART_OPTIONS.items())}".encode())
    for path in dependency_files(function):
        status = os.stat(path)
        digest.update(os.path.basename(path).encode() + b"\0" + _file_digest(path, status.st_mtime, status.st_size))
    return digest.hexdigest()


class DependencyLocator(caching._CacheLocator):
    """numba cache locator of a kernel function: numba's own location, :func:`source_stamp` as the
    freshness stamp."""

    def __init__(self, inner: caching._CacheLocator, py_func: Callable):
        self._inner = inner
        self._py_func = py_func

    def ensure_cache_path(self) -> None:
        """Make sure numba's own cache directory exists and is writable (the inner locator's check)."""
        self._inner.ensure_cache_path()

    def get_cache_path(self) -> str:
        return self._inner.get_cache_path()

    def get_source_stamp(self) -> str:
        return source_stamp(self._py_func)

    def get_disambiguator(self) -> str:
        return self._inner.get_disambiguator()

    @classmethod
    def from_function(cls, py_func: Callable, py_file: str) -> DependencyLocator | None:
        """A locator for ``py_func`` (defined in ``py_file``), wrapping the first of numba's own
        locators that takes it; None if none does."""
        for locator in caching.CacheImpl._locator_classes:
            inner = locator.from_function(py_func, py_file)
            if inner is not None:
                return cls(inner, py_func)
        return None


class _KernelCacheImpl(caching.CompileResultCacheImpl):
    """numba's cache of compiled functions, found by :class:`DependencyLocator` alone; an entry whose
    machine code calls a function that is not loaded is a miss (see :meth:`rebuild`)."""

    _locator_classes = [DependencyLocator]

    def rebuild(self, target_context: object, payload: tuple) -> object:
        """The cached compilation, or None (a miss: numba compiles the function again) where its code
        calls a compiled function (a :func:`shared_kernel_function`) that this process has not loaded
        under the name the code calls. Loading it would be a fatal LLVM error ("could not be
        resolved"), not an exception."""
        name, kind, data = payload[0]
        if kind == "object":
            engine = target_context.codegen()._engine
            for function in llvm.parse_bitcode(data[1]).functions:
                if (function.is_declaration and function.name.startswith("_ZN")
                        and not engine.is_symbol_defined(function.name)):
                    return None
        return super().rebuild(target_context, payload)


class KernelCache(caching.FunctionCache):
    """The on-disk cache of one kernel function: numba's function cache, keyed by :func:`source_stamp`."""

    _impl_class = _KernelCacheImpl


def signature(dispatcher: Dispatcher, *args: object) -> tuple:
    """The numba types of ``args`` as ``dispatcher`` sees them: the key of its compilation for them."""
    return tuple(dispatcher.typeof_pyval(a) for a in args)


def _cache_index(dispatcher: Dispatcher) -> dict:
    """The entries of a kernel function's on-disk cache index for the current sources (empty where
    there is none or it cannot be read)."""
    try:
        return dispatcher._cache._cache_file._load_index()
    except (AttributeError, OSError):
        return {}


def is_cached(dispatcher: Dispatcher, *args: object) -> bool:
    """Whether a kernel function is compiled for the types of ``args`` in this process or in its
    on-disk cache (read from the cache's index, nothing loaded)."""
    types_ = signature(dispatcher, *args)
    if types_ in dispatcher.overloads:
        return True
    try:
        key = dispatcher._cache._index_key(types_, dispatcher.targetctx.codegen())
    except AttributeError:
        return False
    return key in _cache_index(dispatcher)


def has_cache_entries(dispatcher: Dispatcher) -> bool:
    """Whether a kernel function is compiled in this process or has any entry, for any types, in its
    on-disk cache for the current sources (read from the cache's index, nothing loaded)."""
    return bool(dispatcher.overloads) or bool(_cache_index(dispatcher))


def compile_once(dispatcher: Dispatcher, *args: object) -> None:
    """Compile (or load from the cache) a kernel function for the types of ``args`` before it is
    called with them, holding a lock beside its cache while doing so (see the module notes).

    Parameters
    ----------
    dispatcher : numba Dispatcher
        A function made by :func:`kernel_function`.
    *args
        The arguments it is about to be called with (only their numba types matter).
    """
    types_ = signature(dispatcher, *args)
    if types_ in dispatcher.overloads:
        return
    with _compile_lock(dispatcher):
        dispatcher.compile(types_)


def lock_file(dispatcher: Dispatcher) -> IO[str] | None:
    """The kernel function's lock file in its cache folder, open (one per function, so that two
    processes can compile two functions at once); None where file locks or the folder are not
    available: each process then compiles on its own, as numba alone would."""
    try:
        import fcntl  # noqa: F401 - only where it exists

        locator = dispatcher._cache._impl.locator
        locator.ensure_cache_path()
        name = f"presag-kernel-{dispatcher.py_func.__qualname__}.lock"
        return open(Path(locator.get_cache_path()) / name, "a")  # noqa: SIM115 - the caller closes it
    except (ImportError, AttributeError, OSError):
        return None


def try_lock(handle: IO[str]) -> bool:
    """Take an exclusive lock on an open lock file (:func:`lock_file`) without waiting: True if taken
    (held until the file is closed), False if another process holds it."""
    import fcntl

    try:
        fcntl.flock(handle, fcntl.LOCK_EX | fcntl.LOCK_NB)
    except OSError:
        return False
    return True


@contextlib.contextmanager
def _compile_lock(dispatcher: Dispatcher) -> Iterator[None]:
    """An exclusive lock on the kernel function's lock file (:func:`lock_file`; none without one)."""
    handle = lock_file(dispatcher)
    if handle is None:
        yield
        return
    import fcntl

    with handle:
        fcntl.flock(handle, fcntl.LOCK_EX)  # released when the file is closed
        yield


class KernelFunction(CPUDispatcher):
    """A numba function of the kernel: compiled at LLVM's :data:`KERNEL_OPTIMISATION` level."""

    def compile(self, sig: tuple) -> object:
        """numba's compilation for the signature ``sig``, under :func:`kernel_optimisation` and numba's
        compiler lock (no other thread compiles at the kernel's level meanwhile)."""
        with global_compiler_lock, kernel_optimisation():
            return super().compile(sig)


def kernel_function(function: Callable) -> Dispatcher:
    """``numba.njit(cache=True)`` with the cache keyed by every source file the function depends on
    (see the module notes), compiled at the kernel's optimisation level. Define the function after
    the imports of what it calls."""
    dispatcher = njit(function)
    if not isinstance(dispatcher, CPUDispatcher):  # NUMBA_DISABLE_JIT: the function as written
        return dispatcher
    dispatcher.__class__ = KernelFunction
    dispatcher._cache = KernelCache(function)  # what ``cache=True`` sets up, with this cache class
    return dispatcher


class SharedKernelFunction(KernelFunction):
    """A kernel function whose callers call its machine code instead of linking its code into theirs
    (see :func:`shared_kernel_function`)."""

    def compile(self, sig: tuple) -> object:
        """numba's compilation (or cache load) for ``sig``, then registered for callers without its
        code library: a caller declares the function and the JIT engine resolves it to this machine
        code."""
        with global_compiler_lock:
            entry = super().compile(sig)
            args, _ = sigutils.normalize_signature(sig)
            compiled = self.overloads[tuple(args)]
            context = self.targetctx
            context.remove_user_function(compiled.entry_point)
            context.insert_user_function(compiled.entry_point, compiled.fndesc, ())
            return entry


def shared_kernel_function(function: Callable) -> Dispatcher:
    """:func:`kernel_function` for a large function that other kernel functions call: they call its
    own machine code (in their process, loaded from its cache entry or compiled) instead of
    linking its LLVM code into theirs and optimising and compiling it again with them.

    For a function called once per time step of a batch, as
    :func:`~presag_opt.dynamics.batch.kernel.newton_steps` is by ``advance``, the call costs
    nothing measurable, and ``advance`` compiles in about 0.9 s instead of 1.9 s. The numbers are
    the same to the last bit: the code is the same, called instead of inlined (no fast-math, so no
    operation is reordered either way). See the module notes for the cache."""
    dispatcher = kernel_function(function)
    if isinstance(dispatcher, KernelFunction):
        dispatcher.__class__ = SharedKernelFunction
    return dispatcher


class KernelPart(KernelFunction):
    """A numba function that only kernel functions call (see :func:`kernel_part`)."""

    python_call: Callable | None = None
    """What a call from Python runs (None: the call raises TypeError)."""

    def __call__(self, *args: object, **kwargs: object) -> object:
        if self.python_call is not None:
            return self.python_call(*args, **kwargs)
        raise TypeError(f"{self.py_func.__qualname__} is a part of the compiled kernel and has no Python entry: "
                        "call it from a kernel function")

    def get_call_template(self, args: tuple, kws: dict) -> tuple:
        """numba's call template for the argument types without their literal values: one compilation
        for ``f(b, 0)`` and ``f(b, count)``."""
        return super().get_call_template(tuple(numba_types.unliteral(a) for a in args), kws)


class PartLibrary(JITCodeLibrary):
    """numba's code library of a kernel part: LLVM code to link into callers, no machine code.

    A part is only ever linked into its callers' modules (numba links a callee's LLVM module into each
    caller's, where LLVM optimises it with the caller and inlines the small ones), so its own optimised module and
    machine code were work for nothing: numba would optimise the part's module as a whole, add it to
    its JIT engine and emit its machine code, and look up the part's Python entry and environment
    there. This library keeps numba's per-function optimisation (which it runs as the part is lowered:
    it keeps what callers link small) and finishes the module linked and verified, but does not
    optimise it as a module and leaves it out of the engine: no machine code, no address. A caller
    optimises the part's code within its own module at the kernel's level, as before, only without a
    first module-level pass over the part alone; no pass reorders floating-point operations, and the
    batch's results are the same to the last bit. A part that reads numba's environment (Python objects
    at run time) is refused: it would have none inside its callers."""

    def _optimize_final_module(self) -> None:
        """Nothing: each caller optimises the part's code as part of its own module."""

    def _finalize_final_module(self) -> None:
        self._finalize_dynamic_globals()
        self._verify_declare_only_symbols()
        text = str(self._final_module)
        if any("@_ZN08NumbaEnv" in line for line in text.splitlines() if not line.startswith("@")):
            raise TypeError(f"the kernel part {self.name} reads numba's environment (Python objects at run time, "
                            "e.g. print): a part has none inside its callers; make it a kernel_function")
        self._finalized = True

    def get_pointer_to_function(self, name: str) -> int:
        """No address: the part has no machine code of its own (0, numba's "not defined")."""
        self._ensure_finalized()
        return 0

    @property
    def codegen(self) -> _PartCodegen:
        """numba's code generator, through a view that does not look up the part's environment."""
        return _PartCodegen(self._codegen)


class _PartCodegen:
    """numba's code generator for a :class:`PartLibrary`'s users: setting the part's environment
    (numba's per-function pointer to its Python globals, kept in machine code) does nothing, as there
    is no machine code; everything else is numba's."""

    def __init__(self, inner: object):
        self._inner = inner

    def set_env(self, env_name: str, env: object) -> None:
        """Nothing to set: a part does not read its environment (:class:`PartLibrary` refuses one that
        does)."""

    def __getattr__(self, name: str) -> object:
        return getattr(self._inner, name)


class PartCompiler(compiler.Compiler):
    """numba's compiler pipeline with the function's code kept in a :class:`PartLibrary`."""

    def compile_extra(self, func: Callable) -> object:
        """numba's compilation of the Python function ``func``, into a :class:`PartLibrary` unless the
        caller gave a library."""
        if self.state.library is None:
            self.state.library = PartLibrary(self.state.targetctx.codegen(), func.__qualname__)
        return super().compile_extra(func)


def kernel_part(function: Callable, python_call: Callable | None = None) -> Dispatcher:
    """A plain-Python function compiled as a part of the kernel functions that call it.

    Compiled once per argument types (literal constants counted as their type) and linked into its
    callers, where LLVM optimises it with them: no Python entry point and no C wrapper is built for it
    (those were a third of the kernel's compile time), and neither machine code nor a module-level
    optimisation of its own (:class:`PartLibrary`: the kernel's cold compile about 10 % shorter). A
    part counts no references and allocates nothing (:data:`PART_OPTIONS`: a batch about 15 % faster).
    Called from Python it runs ``python_call``, the same computation for Python (for a part that numba
    alone can run), or, without one, raises TypeError.
    Not cached on its own: its callers' caches cover its file. Under ``NUMBA_DISABLE_JIT`` it is
    ``python_call`` or the function as written."""
    dispatcher = njit(**PART_OPTIONS, pipeline_class=PartCompiler)(function)
    if not isinstance(dispatcher, CPUDispatcher):
        return python_call or dispatcher
    dispatcher.__class__ = KernelPart
    dispatcher.python_call = python_call
    return dispatcher
