"""The compiled axial element functions give CasADi's own results, to the last bit, and the static
model falls back to CasADi's virtual machine when no library can be built."""

from __future__ import annotations

import numpy as np
import pytest

from presag_opt.native import casadi_elements as compiled
from presag_opt.static.equilibrium import lone_wire_state
from presag_opt.static.potential import build_potential
from presag_opt.system.components import Wire


def _terms(state, runtime, compile_off: bool):
    with runtime.replace(compile=not compile_off):
        functions = build_potential(state.discretisation)
    # A displaced state, so that every element is stretched differently (and some droppers slack).
    rng = np.random.default_rng(1)
    x = state.positions.ravel() + 1e-3 * rng.standard_normal(state.positions.size)
    hess, grad = functions.hessian_values(x, state.params)
    return hess, grad, functions.energy(x, state.params)


@pytest.mark.parametrize("system", ["st98", "lone_wire"])
def test_compiled_elements_equal_the_virtual_machine(system, st98, test_runtime):
    """Same expression graph, same operations, no fast-math: equal, not just close. The lone wire has
    fewer elements than a chunk (padding); the section has 2 481, not a multiple of the chunk."""
    state = st98 if system == "st98" else lone_wire_state(Wire(tension=10e3, mass_per_length=1.0, axial_stiffness=1e7), 30.0)
    assert compiled._library_of(compiled._FUNCTIONS["axial_element"]) is not None, "no compiled library was built"
    fast = _terms(state, test_runtime, compile_off=False)
    plain = _terms(state, test_runtime, compile_off=True)
    for a, b in zip(fast, plain):
        assert np.array_equal(a, b)


def test_without_a_compiler_the_virtual_machine_is_used(st98, monkeypatch):
    """No compiler on the path: no library, and the model still evaluates (CasADi's virtual machine)."""
    monkeypatch.setenv("CC", "/nonexistent/cc")
    assert compiled._library_of(compiled._FUNCTIONS["axial_element"]) is None
    function, padded = compiled.element_map(compiled._FUNCTIONS["axial_element"], 10)
    assert padded == 10 and function.size2_in(0) == 10
    hess, grad = build_potential(st98.discretisation).hessian_values(st98.positions.ravel(), st98.params)
    assert np.all(np.isfinite(hess)) and np.abs(grad).max() < 1e-3
