"""The axial element functions of the static model as compiled C, built once per machine.

The Newton loops of the elasticity and of the form-finding's relaxation evaluate the axial element
energy, gradient and Hessian for every element many times. CasADi evaluates a mapped SX function in
its virtual machine; the C code CasADi generates for the same mapped function runs about ten times
faster (1.6 ms against 0.15 ms for the 2 481 axial elements of the 10-span section, measured) and
gives the same numbers to the last bit: it is the same expression graph, operation for operation, and
it is compiled without fast-math.

The C code is generated for a fixed chunk of :data:`CHUNK` elements, so that one library serves
every discretisation: a section's elements are padded up to whole chunks (the padding's results are
discarded). The library is compiled with the system's C compiler (``$CC``, default ``cc``) into the
user's cache folder (``$XDG_CACHE_HOME/presag_opt/compiled``), named by a hash of its source, the
CasADi version and the compiler, so a change of any of them builds a new one; building takes about a
quarter of a second. Without a working compiler, or with ``PRESAG_NO_COMPILE=1``, the functions run
in CasADi's virtual machine: same results, slower.
"""

from __future__ import annotations

import functools
import hashlib
import os
import shutil
import subprocess
import tempfile
from pathlib import Path

import casadi as ca

from presag_opt.static import cache

CHUNK = 256
"""Elements per call of the compiled code; a section is padded up to whole chunks. [-]"""

COMPILE_ENV_OFF = "PRESAG_NO_COMPILE"
"""Environment variable that, set to anything but "" or "0", keeps the element functions in
CasADi's virtual machine."""


def element_map(function: ca.Function, count: int) -> tuple[ca.Function, int]:
    """A function evaluating an element function over ``count`` elements, and the element count it
    takes (``count`` padded up to whole :data:`CHUNK` when compiled code is used).

    Parameters
    ----------
    function : casadi.Function
        An element function among those :func:`compile_elements` was given.
    count : int
        Number of elements. [-]
    """
    library = _library_of(function)
    if library is None:
        return function.map(count), count
    chunks = max(1, -(-count // CHUNK))
    chunk = ca.external(_chunk_name(function), str(library))
    return chunk.map(chunks), chunks * CHUNK


_FUNCTIONS: dict[str, ca.Function] = {}
"""Element functions to compile, by name (registered by :func:`compile_elements`)."""


def compile_elements(*functions: ca.Function) -> None:
    """Register element functions whose mapped chunks go into the compiled library.

    Parameters
    ----------
    *functions : casadi.Function
        Element functions (scalar element in, scalar element out).
    """
    for function in functions:
        _FUNCTIONS[function.name()] = function


def _chunk_name(function: ca.Function) -> str:
    return f"{function.name()}_chunk{CHUNK}"


def _library_of(function: ca.Function) -> Path | None:
    if function.name() not in _FUNCTIONS or os.environ.get(COMPILE_ENV_OFF, "") not in ("", "0"):
        return None
    return _library(tuple(sorted(_FUNCTIONS)))


@functools.cache
def _library(names: tuple[str, ...]) -> Path | None:
    """The compiled library of the registered functions (built if missing), or None if it cannot be built."""
    compiler = shutil.which(os.environ.get("CC", "cc"))
    if compiler is None:
        return None
    with tempfile.TemporaryDirectory() as scratch:
        source = Path(scratch) / "presag_elements.c"
        generator = ca.CodeGenerator(source.name, {"with_header": False})
        for name in names:
            generator.add(_FUNCTIONS[name].map(_chunk_name(_FUNCTIONS[name]), "serial", CHUNK, [], []))
        generator.generate(scratch + os.sep)
        text = source.read_text()
        key = hashlib.sha256(f"{text}\0{ca.__version__}\0{compiler}".encode()).hexdigest()[:20]
        folder = cache.default_cache_directory() / "compiled"
        target = folder / f"elements-{key}.so"
        if target.exists():
            return target
        built = Path(scratch) / "elements.so"
        temporary = None
        try:
            subprocess.run([compiler, "-O2", "-fPIC", "-shared", str(source), "-o", str(built)],
                           check=True, capture_output=True, timeout=120)
            folder.mkdir(parents=True, exist_ok=True)
            handle, temporary = tempfile.mkstemp(dir=folder, suffix=".so.tmp")
            os.close(handle)
            shutil.copyfile(built, temporary)
            os.replace(temporary, target)  # atomic: concurrent processes build the same file
        except (OSError, subprocess.SubprocessError):
            if temporary is not None and os.path.exists(temporary):
                os.unlink(temporary)
            return None
    return target
