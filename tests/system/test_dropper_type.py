"""The dropper type a crew cuts (presag_opt.system.dropper_type): the cut-length arithmetic, the rounding
to the crew's step, the built-in type's provenance and the refusals."""

from __future__ import annotations

import numpy as np
import pytest

from presag_opt.errors import ModelError
from presag_opt.system.dropper_type import DropperType, load_dropper_type, rounded


def test_the_cut_length_is_the_clamp_length_plus_both_ends_allowances():
    kind = DropperType(name="test", terminal_allowance=0.04, loop_allowance=0.06)
    assert kind.allowance == pytest.approx(0.2, abs=1e-15)
    assert kind.cut_length(0.5123) == pytest.approx(0.7123, abs=1e-12)
    assert kind.cut_length(0.5123, 0.005) == pytest.approx(0.710, abs=1e-12)
    assert kind.cut_length(0.5126, 0.005) == pytest.approx(0.715, abs=1e-12)
    assert kind.cut_length(0.5126, 0.010) == pytest.approx(0.710, abs=1e-12)
    lengths = np.array([0.5, 0.81234, 1.065])
    np.testing.assert_allclose(kind.cut_length(lengths, 0.01), [0.70, 1.01, 1.27], atol=1e-12)


def test_step_zero_keeps_every_length_to_the_last_digit():
    lengths = np.array([0.514321987, 1.065432101])
    assert rounded(lengths, 0.0) is lengths


def test_a_rounded_length_is_a_whole_number_of_steps_within_half_a_step():
    lengths = np.random.default_rng(1).uniform(0.4, 1.6, 500)
    for step in (0.005, 0.01, 0.025):
        out = rounded(lengths, step)
        np.testing.assert_allclose(out / step, np.round(out / step), atol=1e-9)
        assert np.abs(out - lengths).max() <= step / 2 + 1e-12


@pytest.mark.parametrize("step", [-0.001, 0.051, float("nan")])
def test_a_step_out_of_range_is_refused_with_its_option_and_range(step):
    with pytest.raises(ModelError, match=r"--round = .* mm is outside the valid range \[0, 50\] mm"):
        rounded(1.0, step)


def test_the_built_in_type_carries_its_provenance():
    kind = load_dropper_type()
    assert kind.allowance == pytest.approx(0.2, abs=1e-12)
    assert {k: p.source for k, p in kind.provenance.items()} == {
        "dropper_type.terminal_allowance": "assumed", "dropper_type.loop_allowance": "assumed"}
    assert "assumed" in kind.describe()


def test_a_bad_dropper_type_file_names_the_key(tmp_path):
    path = tmp_path / "bad.toml"
    path.write_text('[dropper_type]\nname = "x"\nterminal_allowance = { value = 900, unit = "mm", source = "assumed" }\n'
                    'loop_allowance = { value = 50, unit = "mm", source = "assumed" }\n')
    with pytest.raises(ModelError, match="bad.toml: dropper_type.terminal_allowance"):
        load_dropper_type(path)
