"""The C sweeps' interface: lane padding, and argument lists that match ``sweeps.c``.

That the C sweeps give the numba sweeps' numbers bit for bit is ``tests/dynamics/test_native_sweeps.py``
(it needs a form-found catenary); here the parts of :mod:`presag_opt.native.sweeps` of its own.
"""

from __future__ import annotations

import ctypes
import re

import pytest

from presag_opt.native import sweeps


@pytest.mark.parametrize(("runs", "lanes"), [(1, 8), (8, 8), (9, 16), (12, 16), (16, 16), (17, 24)])
def test_runs_are_padded_to_whole_blocks(runs, lanes):
    assert sweeps.lanes_for(runs) == lanes and sweeps.LANES == 8


def test_the_lanes_in_the_c_source_are_the_python_ones():
    assert re.search(r"#define\s+LANES\s+(\d+)", sweeps.SOURCE.read_text()).group(1) == str(sweeps.LANES)


@pytest.mark.parametrize("name", sorted(sweeps.SIGNATURES))
def test_each_signature_matches_its_c_prototype(name):
    """As many arguments, of the same kinds (pointer / int64 / double), as the C function takes."""
    source = sweeps.SOURCE.read_text()
    prototype = re.search(rf"void\s+{name}\s*\((.*?)\)\s*{{", source, re.S).group(1)
    kinds = []
    for parameter in prototype.split(","):
        if "*" in parameter:
            kinds.append(ctypes.c_size_t)
        elif "int64_t" in parameter:
            kinds.append(ctypes.c_int64)
        elif "double" in parameter:
            kinds.append(ctypes.c_double)
        else:  # pragma: no cover - a new type in the C source
            raise AssertionError(f"{name}: unknown parameter type in {parameter!r}")
    assert tuple(kinds) == sweeps.SIGNATURES[name]


def test_the_kernel_always_gets_three_functions_of_the_signatures():
    """With or without a built library (stand-ins otherwise), the kernel's arguments have one type."""
    c = sweeps.sweeps()
    assert isinstance(c, sweeps.CSweeps) and len(c) == 3
    for function, arguments in zip(c, sweeps.SIGNATURES.values()):
        assert tuple(function.argtypes) == arguments
