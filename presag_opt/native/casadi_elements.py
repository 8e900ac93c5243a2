"""The axial element functions of the static model as compiled C, built once per machine.

The Newton loops of the elasticity and of the form-finding's relaxation evaluate the axial element
energy, gradient and Hessian for every element many times. CasADi evaluates a mapped SX function in
its virtual machine; the C code CasADi generates for the same mapped function runs about ten times
faster (1.6 ms against 0.15 ms for the 2 481 axial elements of the 10-span section, measured) and
gives the same numbers to the last bit: it is the same expression graph, operation for operation, and
it is compiled without fast-math.

The C code is generated for a fixed chunk of :data:`CHUNK` elements, so that one library serves
every discretisation: a section's elements are padded up to whole chunks (the padding's results are
discarded). The library is compiled by :func:`presag_opt.native.build` into the user's
cache folder, named by a hash of its source (which names the CasADi version), the flags and the
compiler, so a change of any of them builds a new one; building takes about a quarter of a second.
Without a working compiler, or with compiling turned off in the runtime
(:attr:`presag_opt.runtime.Runtime.compile`; ``PRESAG_NO_COMPILE=1`` for the command line), the
functions run in CasADi's virtual machine: same results, slower.
"""

from __future__ import annotations

import functools
import os
import tempfile
from pathlib import Path

import casadi as ca

from presag_opt import native

CHUNK = 256
"""Elements per call of the compiled code; a section is padded up to whole chunks. [-]"""

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
    if function.name() not in _FUNCTIONS or native.compiling_disabled():
        return None
    return native.build("elements", _source(tuple(sorted(_FUNCTIONS))), ["-O2"])


@functools.cache
def _source(names: tuple[str, ...]) -> str:
    """The C source of the registered functions' chunks (generated once per process: the functions do
    not change once registered)."""
    with tempfile.TemporaryDirectory() as scratch:
        generator = ca.CodeGenerator("presag_elements.c", {"with_header": False})
        for name in names:
            generator.add(_FUNCTIONS[name].map(_chunk_name(_FUNCTIONS[name]), "serial", CHUNK, [], []))
        generator.generate(scratch + os.sep)
        text = (Path(scratch) / "presag_elements.c").read_text()
    return f"/* CasADi {ca.__version__} */\n{text}"
