"""Per-mast geometry (presag_opt.system.masts): values kept as given, every length and range checked."""

from __future__ import annotations

import pytest

from presag_opt.errors import ModelError
from presag_opt.system.masts import MastGeometry


def geometry(**change):
    values = dict(stagger=(0.3, -0.3, 0.3), contact_wire_height=(5.5, 5.3, 5.5), system_height=(1.2, 0.9, 1.2),
                  push_off=(False, True, False))
    values.update(change)
    return MastGeometry(**values)


def test_values_are_kept_as_floats_and_bools_in_track_order():
    g = geometry(stagger=[0.3, -0.3, 0.3], push_off=[0, 1, 0])
    assert g.n_masts == 3
    assert g.stagger == (0.3, -0.3, 0.3) and g.push_off == (False, True, False)
    assert g.contact_wire_height == (5.5, 5.3, 5.5)


@pytest.mark.parametrize("field, values, message", [
    ("stagger", (0.3, 0.6, 0.3), r"masts.stagger\[1\] = 0.6 m is outside the valid range \[-0.5, 0.5\] m"),
    ("contact_wire_height", (5.5, 2.9, 5.5), r"masts.contact_wire_height\[1\] = 2.9 m is outside .*\[3, 8\] m"),
    ("system_height", (1.2, float("nan"), 1.2), r"masts.system_height\[1\] = nan m is outside .*\[0.2, 4\] m"),
    ("push_off", (False, True), r"masts.push_off has 2 values but masts.stagger has 3"),
])
def test_a_bad_value_is_named_with_its_mast_and_range(field, values, message):
    with pytest.raises(ModelError, match=message):
        geometry(**{field: values})
