"""Pantograph models: built-in files, malformed files, matrices, friction, contact and time step."""

from __future__ import annotations

import numpy as np
import pytest

from presag_opt.dynamics.pantograph import (
    FrictionRegularisation,
    Pantograph,
    PantographStage,
    load_pantograph,
)
from presag_opt.errors import ModelError
from presag_opt.system.loader import builtin_model_names

EN50318_FILE = """
[pantograph]
name = "test"

[[stages]]
name = "head"
mass = { value = 7.2, unit = "kg", source = "secondary-source" }
stiffness = { value = 4200, unit = "N/m", source = "secondary-source" }
damping = { value = 10, unit = "N*s/m", source = "secondary-source" }

[[stages]]
name = "frame"
mass = { value = 15.0, unit = "kg", source = "secondary-source" }
stiffness = { value = 50, unit = "N/m", source = "secondary-source" }
damping = { value = 90, unit = "N*s/m", source = "secondary-source" }
"""


def test_builtin_pantographs_are_listed():
    assert {"case_study_2mass_friction", "en50318_2mass", "generic_3mass"} <= set(builtin_model_names("pantographs"))


def test_en50318_pantograph_matrices():
    """docs/assumptions.md §4.3: head 7.2 kg on 4200 N/m and 10 N·s/m over frame 15 kg on 50 N/m and 90 N·s/m.
    Exact: the matrices are sums of the file's numbers."""
    pantograph = load_pantograph("en50318_2mass")
    np.testing.assert_array_equal(pantograph.mass_matrix(), np.diag([7.2, 15.0]))
    np.testing.assert_array_equal(pantograph.stiffness_matrix(), [[4200.0, -4200.0], [-4200.0, 4250.0]])
    np.testing.assert_array_equal(pantograph.damping_matrix(), [[10.0, -10.0], [-10.0, 100.0]])
    assert (pantograph.head_dof, pantograph.uplift_dof) == (0, 1)
    assert pantograph.contact.stiffness == 50e3
    assert not pantograph.has_friction
    assert pantograph.provenance["stages[1].stiffness"].source == "secondary-source"


def test_case_study_pantograph_has_frame_friction_and_no_frame_spring():
    """docs/assumptions.md §4.2: all values assumed except the paper's 50 kN/m contact stiffness."""
    pantograph = load_pantograph("case_study_2mass_friction")
    head, frame = pantograph.stages
    assert (head.mass, head.stiffness, head.damping) == (7.2, 4200.0, 10.0)
    assert (frame.mass, frame.stiffness, frame.damping, frame.friction) == (15.0, 0.0, 90.0, 5.0)
    assert pantograph.provenance["stages[0].mass"].source == "assumed"
    assert pantograph.provenance["contact.stiffness"].source == "paper"
    assert pantograph.contact.stiffness == pytest.approx(50e3, rel=1e-15)


def test_three_mass_pantograph_chain():
    """Each spring joins a stage to the one below: the 3x3 stiffness matrix is tridiagonal with the
    published s1 = 9430, s2 = 14100, s3 = 0.1 N/m (exact sums)."""
    pantograph = load_pantograph("generic_3mass")
    assert pantograph.n_dofs == 3 and pantograph.uplift_dof == 2
    np.testing.assert_array_equal(
        pantograph.stiffness_matrix(),
        [[9430.0, -9430.0, 0.0], [-9430.0, 23530.0, -14100.0], [0.0, -14100.0, 14100.1]],
    )
    assert {p.source for p in pantograph.provenance.values()} == {"secondary-source", "assumed"}


def test_friction_opposes_motion_saturates_and_has_a_consistent_tangent():
    """Regularised Coulomb law F0·tanh(dv/v_reg) on the frame's velocity relative to the car body.

    At 0.1 m/s (100 v_reg) it is 5 N to 1e-12; the tangent matches central differences (step 1e-7
    m/s) to 1e-6 relative, the truncation error of the difference quotient.
    """
    pantograph = load_pantograph("case_study_2mass_friction")
    regularisation = FrictionRegularisation(velocity=1e-3)
    force, _ = pantograph.friction_force(np.array([0.3, 0.1]), regularisation)
    assert force == pytest.approx([0.0, 5.0], abs=1e-12)
    assert pantograph.friction_force(np.array([0.0, -0.1]), regularisation)[0][1] == pytest.approx(-5.0, abs=1e-12)
    velocity = np.array([0.0004, 0.0007])
    _, tangent = pantograph.friction_force(velocity, regularisation)
    step = 1e-7
    numeric = np.column_stack(
        [
            (
                pantograph.friction_force(velocity + step * e, regularisation)[0]
                - pantograph.friction_force(velocity - step * e, regularisation)[0]
            )
            / (2.0 * step)
            for e in np.eye(2)
        ]
    )
    np.testing.assert_allclose(tangent, numeric, rtol=1e-6, atol=1e-6 * np.max(np.abs(tangent)))


def test_time_step_too_large_for_the_contact_stiffness_is_a_model_error():
    """Limit: a tenth of 2π·sqrt(7.2 kg / 50 kN/m) = 75.4 ms, i.e. 7.54 ms; 2 ms (the paper's step)
    passes, 10 ms fails."""
    pantograph = load_pantograph("en50318_2mass")
    assert pantograph.max_time_step() == pytest.approx(7.54e-3, rel=1e-3)
    pantograph.check_time_step(2e-3)
    with pytest.raises(ModelError, match=r"time_step = 10 ms is too large .* use at most 7.54 ms"):
        pantograph.check_time_step(10e-3)


@pytest.mark.parametrize(
    ("old", "new", "message"),
    [
        (
            'mass = { value = 15.0, unit = "kg", source = "secondary-source" }\n',
            "",
            r"bad\.toml: \[stages\[1\]\]: missing required key\(s\) mass",
        ),
        (
            'name = "frame"\n',
            'name = "frame"\nspring = { value = 50, unit = "N/m", source = "assumed" }\n',
            r"\[stages\[1\]\]: unknown key 'spring'; valid keys: name, mass, stiffness, damping, friction",
        ),
        (
            'value = 4200, unit = "N/m"',
            'value = 4200, unit = "N"',
            r"stages\[0\]\.stiffness: unit 'N' is not a unit of stiffness; use one of N/m, kN/m",
        ),
        (
            'value = 15.0, unit = "kg"',
            'value = 500, unit = "kg"',
            r"stages\[1\]\.mass = 500 kg is outside the valid range \(0, 200\] kg",
        ),
        (
            'value = 90, unit = "N*s/m"',
            'value = -90, unit = "N*s/m"',
            r"stages\[1\]\.damping = -90 N\*s/m is outside the valid range \[0, 10000\] N\*s/m",
        ),
        (
            'source = "secondary-source" }\n\n[[stages]]',
            'source = "textbook" }\n\n[[stages]]',
            r"stages\[0\]\.damping: source 'textbook' is not one of paper, standard",
        ),
        ('[pantograph]\nname = "test"\n', "", r"missing section \[pantograph\]"),
        (
            "",
            '\n[contact]\nstiffness = { value = 0, unit = "kN/m", source = "assumed" }\n',
            r"contact\.stiffness = 0 kN/m is outside the valid range \[1, 10000\] kN/m",
        ),
    ],
)
def test_malformed_pantograph_files_are_model_errors(tmp_path, old, new, message):
    text = EN50318_FILE.replace(old, new, 1) if old else EN50318_FILE + new
    assert text != EN50318_FILE
    path = tmp_path / "bad.toml"
    path.write_text(text, encoding="utf-8")
    with pytest.raises(ModelError, match=message):
        load_pantograph(path)


def test_pantograph_needs_two_or_three_stages():
    stage = PantographStage(mass=5.0)
    with pytest.raises(ModelError, match="4 given; a pantograph model has 2 or 3 stages"):
        Pantograph(name="four", stages=(stage,) * 4)


def test_unknown_builtin_name_lists_the_available_models():
    with pytest.raises(ModelError, match="en50318_2mass"):
        load_pantograph("no_such_pantograph")
