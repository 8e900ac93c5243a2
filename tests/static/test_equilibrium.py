"""The equilibrium state: its memo computes each quantity once and holds only declared slots, a
re-solve under no extra load stays where it is, and a lone wire sags as a string."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from presag_opt.static.discretisation import StaticSettings
from presag_opt.static.equilibrium import StateMemo, lone_wire_state
from presag_opt.static.form_finding import form_find
from presag_opt.system.catenary import SpanLayout
from presag_opt.system.components import Wire
from presag_opt.system.loader import load_catenary

COARSE = StaticSettings(element_length=1.0)


@pytest.fixture(scope="module")
def state():
    catenary = load_catenary("st_9.8_ideal").with_layout(SpanLayout(span_lengths=(60.0, 60.0, 60.0)))
    return form_find(catenary, COARSE)


def test_the_memo_computes_once_and_holds_declared_slots_only(state):
    assert state.factorised_stiffness() is state.factorised_stiffness()
    assert state.memo.factor is state.factorised_stiffness()
    with pytest.raises(AttributeError):
        state.memo.anything_else = 1  # slots: a misspelt memo is an error, not a new dict key
    copy = dataclasses.replace(state, iterations=state.iterations + 1)
    assert isinstance(copy.memo, StateMemo) and copy.memo.factor is None  # a new state starts empty
    assert "memo" not in repr(state)  # not part of the state's value


def test_resolving_without_extra_load_stays_at_the_state(state):
    """The form-found state is balanced to the force tolerance (1e-4 N); the re-solve moves nodes by
    less than that over the smallest stiffness, far below 1 µm."""
    again = state.solve(np.zeros(state.discretisation.n_dofs))
    assert np.abs(again.positions - state.positions).max() <= 1e-6


def test_droppers_slack_under_a_large_uplift_are_counted(state):
    """Form-found, every dropper carries tension; 2 kN lifting the mid-span contact wire slackens the
    droppers around it (each carries well under 200 N)."""
    assert state.slack_dropper_count() == 0
    disc = state.discretisation
    lifted = state.solve(disc.cw_load_vector(90.0, 2000.0))
    assert lifted.slack_dropper_count() == int(np.sum(lifted.dropper_forces() <= 0.0)) > 0


def test_a_lone_wire_sags_as_a_string():
    """A 60 m wire of 1.08 kg/m at 10 kN, pinned at both ends: mid-span sag g·m·l²/(8T) = 0.0477 m.
    Its bending stiffness (bending length sqrt(EI/T) = 0.14 m against the 60 m span) and its stretch
    change that by well under the 0.5 % allowed; a missing weight term or a wrong tension misses by far more."""
    wire = Wire(tension=10_000.0, mass_per_length=1.08, axial_stiffness=1.2e7, bending_stiffness=195.0)
    state = lone_wire_state(wire, 60.0, StaticSettings(element_length=0.5))
    sag = -state.positions[:, 2].min()
    assert sag == pytest.approx(9.81 * 1.08 * 60.0**2 / (8 * 10_000.0), rel=5e-3)
