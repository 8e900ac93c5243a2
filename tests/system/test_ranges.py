"""Plausible ranges beside model-file values: loading, validation and the documented default."""

from __future__ import annotations

import textwrap

import pytest

from presag_opt.errors import ModelError
from presag_opt.system.loader import load_catenary, model_entries

MODEL = textwrap.dedent(
    """
    [system]
    name = "test"

    [layout]
    span_lengths = { value = [60.0], unit = "m", source = "assumed" }
    span_count = { value = 5, unit = "-", source = "assumed" }

    [geometry]
    contact_wire_height = { value = 5.5, unit = "m", source = "assumed" }
    system_height = { value = 1.2, unit = "m", source = "assumed", range = [1.0, 1.6], range_note = "why" }
    stagger = { value = 0.3, unit = "m", source = "assumed" }

    [contact_wire]
    tension = { value = 9.8, unit = "kN", source = "assumed" }
    mass_per_length = { value = 1070, unit = "g/m", source = "assumed", range = [1035, 1099], range_note = "EN 50149" }
    axial_stiffness = { value = 14.4, unit = "MN", source = "assumed" }
    bending_stiffness = { value = 150, unit = "N*m^2", source = "assumed" }

    [messenger_wire]
    tension = { value = 9.8, unit = "kN", source = "assumed" }
    mass_per_length = { value = 0.45, unit = "kg/m", source = "assumed" }
    axial_stiffness = { value = 5.0, unit = "MN", source = "assumed" }

    [droppers]
    end_distance = { value = 4.5, unit = "m", source = "assumed" }
    max_spacing = { value = 8.5, unit = "m", source = "assumed" }
    axial_stiffness = { value = 1.0, unit = "MN", source = "assumed" }

    [contact_wire_support]
    type = "steady_arm"
    length = { value = 1.0, unit = "m", source = "assumed" }
    mass = { value = 1.0, unit = "kg", source = "assumed" }

    [messenger_wire_support]
    type = "pin"
    """
)
SYSTEM_HEIGHT = 'system_height = { value = 1.2, unit = "m", source = "assumed", range = [1.0, 1.6], range_note = "why" }'


def load(tmp_path, text):
    path = tmp_path / "model.toml"
    path.write_text(text)
    return load_catenary(path)


def test_declared_ranges_are_read_in_si_with_their_reason(tmp_path):
    cat = load(tmp_path, MODEL)
    assert cat.provenance["geometry.system_height"].range == (1.0, 1.6)
    assert cat.provenance["geometry.system_height"].range_note == "why"
    # g/m -> kg/m: the range carries the value's unit (factors exact to rounding)
    assert cat.provenance["contact_wire.mass_per_length"].range == pytest.approx((1.035, 1.099), rel=1e-12)
    assert cat.provenance["messenger_wire.mass_per_length"].range is None


BAD = [
    ("range = [1.0, 1.6]", "range = [1.3, 1.6]", ["geometry.system_height", "does not contain the value 1.2 m"]),
    ("range = [1.0, 1.6]", "range = [1.6, 1.0]", ["geometry.system_height", "low < high"]),
    ("range = [1.0, 1.6]", "range = [1.0, 9.0]", ["geometry.system_height", "range end 9 m", "valid range"]),
    ("range = [1.0, 1.6]", "range = [1.0]", ["geometry.system_height", "two numbers", "in m"]),
    ("range = [1.0, 1.6]", 'range = ["low", 1.6]', ["geometry.system_height", "two numbers"]),
    (', range_note = "why"', "", ["geometry.system_height", "needs range_note"]),
    ("range = [1.0, 1.6], ", "", ["geometry.system_height", "range_note is given without a range"]),
]


@pytest.mark.parametrize("old,new,words", BAD, ids=[b[2][1] for b in BAD])
def test_bad_ranges_are_refused_in_one_line_naming_file_key_value_and_unit(tmp_path, old, new, words):
    text = MODEL.replace(SYSTEM_HEIGHT, SYSTEM_HEIGHT.replace(old, new, 1))
    assert text != MODEL, "test set-up: the replacement must change the file"
    with pytest.raises(ModelError) as info:
        load(tmp_path, text)
    message = str(info.value)
    assert message.startswith("model.toml: "), message
    assert "\n" not in message
    for word in words:
        assert word in message, f"{word!r} missing from: {message}"


def test_a_range_beside_a_list_is_refused(tmp_path):
    text = MODEL.replace('span_lengths = { value = [60.0], unit = "m", source = "assumed" }',
                         'span_lengths = { value = [60.0], unit = "m", source = "assumed", range = [50, 70], '
                         'range_note = "x" }')
    with pytest.raises(ModelError, match="layout.span_lengths: a range can only be declared beside a single value"):
        load(tmp_path, text)


def test_model_entries_report_the_range_as_written(tmp_path):
    path = tmp_path / "model.toml"
    path.write_text(MODEL)
    entries = {e.key: e for e in model_entries(path)}
    assert entries["contact_wire.mass_per_length"].range == (1035, 1099)
    assert entries["contact_wire.mass_per_length"].range_note == "EN 50149"




def test_every_shipped_range_holds_its_value():
    # loading validates it; the case study's files must load with their ranges
    from presag_opt.dynamics.case import load_case

    case = load_case("case_study_st98")
    ranges = [p.range for p in (*case.catenary.provenance.values(), *case.pantograph.provenance.values()) if p.range]
    assert len(ranges) >= 20
