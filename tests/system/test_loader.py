"""Model files: built-in models load with units converted and provenance kept; malformed files fail
with a message that names the key, the value, the unit and the valid range."""

from __future__ import annotations

import textwrap
from pathlib import Path

import pytest

from presag_opt.errors import ModelError
from presag_opt.system.components import SpringSupport, SteadyArm
from presag_opt.system.loader import builtin_model_names, load_catenary, models_root
from presag_opt.system.quantity import SOURCES


def test_builtin_models_are_listed():
    assert set(builtin_model_names()) >= {
        "st_7.1_ideal", "st_9.8_ideal", "st_9.8_mixed", "st_7.1_mixed", "en50318_reference"
    }


def test_st98_values_in_si():
    cat = load_catenary("st_9.8_ideal")
    assert cat.contact_wire.tension == 9800.0
    assert cat.messenger_wire.tension == 9800.0
    assert cat.contact_wire.axial_stiffness == pytest.approx(14.4e6, rel=1e-12)
    assert cat.layout.span_lengths == (60.0,) * 10
    assert cat.presag_of_span(5) == pytest.approx(0.030, abs=1e-12)  # 0.5 ‰ of 60 m
    assert isinstance(cat.contact_wire_support, SteadyArm)
    assert cat.stagger == 0.30


def test_mixed_section_matches_the_papers_summary():
    # Paper, section 3: 31 spans, 1340.2 m in total, 24.7 to 58.4 m.
    layout = load_catenary("st_9.8_mixed").layout
    assert layout.n_spans == 31
    assert sum(layout.span_lengths) == pytest.approx(1340.2, abs=1e-9)
    assert min(layout.span_lengths) == 24.7
    assert max(layout.span_lengths) == 58.4
    assert "stand-in" in layout.label


def test_en50318_reference_uses_spring_supports():
    cat = load_catenary("en50318_reference")
    assert isinstance(cat.contact_wire_support, SpringSupport)
    assert cat.contact_wire_support.stiffness == 300.0
    assert isinstance(cat.messenger_wire_support, SpringSupport)
    assert cat.messenger_wire_support.stiffness == 50e3
    assert cat.droppers.stiffness == 100e3
    assert cat.damping.rayleigh_alpha == 0.0125


@pytest.mark.parametrize("name", ["st_7.1_ideal", "st_9.8_ideal", "st_9.8_mixed", "st_7.1_mixed", "en50318_reference"])
def test_every_number_has_a_provenance_tag(name):
    cat = load_catenary(name)
    assert cat.provenance, "no provenance recorded"
    assert {p.source for p in cat.provenance.values()} <= set(SOURCES)
    text = (Path(str(models_root())) / "catenaries" / f"{name}.toml").read_text()
    # every { value = ... } table in the file was recorded
    assert len(cat.provenance) == text.count("value =")


BASE = textwrap.dedent(
    """
    [system]
    name = "test"

    [layout]
    span_lengths = { value = [60.0], unit = "m", source = "assumed" }
    span_count = { value = 5, unit = "-", source = "assumed" }

    [geometry]
    contact_wire_height = { value = 5.5, unit = "m", source = "assumed" }
    system_height = { value = 1.2, unit = "m", source = "assumed" }
    stagger = { value = 0.3, unit = "m", source = "assumed" }
    presag = { value = 30, unit = "mm", source = "assumed" }

    [contact_wire]
    tension = { value = 9.8, unit = "kN", source = "assumed" }
    mass_per_length = { value = 1.07, unit = "kg/m", source = "assumed" }
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


def write(tmp_path: Path, text: str) -> Path:
    path = tmp_path / "model.toml"
    path.write_text(text)
    return path


def test_the_base_file_is_valid(tmp_path):
    cat = load_catenary(write(tmp_path, BASE))
    assert cat.presag_rel == pytest.approx(0.0005, rel=1e-12)


# (replacement of one line of BASE, words the message must contain)
MALFORMED = [
    ('tension = { value = 9.8, unit = "kN", source = "assumed" }\nmass_per_length = { value = 1.07',
     'tension = { value = -9.8, unit = "kN", source = "assumed" }\nmass_per_length = { value = 1.07',
     ["contact_wire.tension", "-9.8", "kN", "[0.5, 60] kN"]),
    ('mass_per_length = { value = 0.45, unit = "kg/m"', 'mass_per_length = { value = 0.45, unit = "kg"',
     ["messenger_wire.mass_per_length", "'kg'", "kg/m"]),
    ('[droppers]\n', '[droppers]\nspacing = { value = 8.5, unit = "m", source = "assumed" }\n',
     ["[droppers]", "unknown key 'spacing'", "max_spacing"]),
    ('[messenger_wire_support]', '[messenger_wire_supports]', ["unknown section [messenger_wire_supports]"]),
    ('stagger = { value = 0.3, unit = "m", source = "assumed" }', 'stagger = { value = 0.3, unit = "m" }',
     ["geometry.stagger", "missing 'source'"]),
    ('stagger = { value = 0.3, unit = "m", source = "assumed" }', 'stagger = { value = 0.3, unit = "m", source = "guess" }',
     ["geometry.stagger", "'guess'", "assumed"]),
    ('stagger = { value = 0.3, unit = "m", source = "assumed" }', 'stagger = 0.3',
     ["geometry.stagger", "unit", "[0, 0.5] m"]),
    ('stagger = { value = 0.3, unit = "m", source = "assumed" }', 'stagger = { value = 0.0, unit = "m", source = "assumed" }',
     ["stagger = 0 m", "steady arm", "(0, 0.5] m"]),
    ('presag = { value = 30, unit = "mm", source = "assumed" }', 'presag = { value = 9, unit = "‰", source = "assumed" }',
     ["geometry.presag", "9 ‰", "[0, 5] ‰"]),
    ('span_count = { value = 5, unit = "-", source = "assumed" }', 'span_count = { value = 2.5, unit = "-", source = "assumed" }',
     ["layout.span_count", "2.5", "[3, 200]"]),
    ('end_distance = { value = 4.5, unit = "m", source = "assumed" }', 'end_distance = { value = 35, unit = "m", source = "assumed" }',
     ["droppers.end_distance", "35 m", "[0.5, 20] m"]),
    ('axial_stiffness = { value = 1.0, unit = "MN", source = "assumed" }\n\n[contact_wire_support]',
     'axial_stiffness = { value = 1.0, unit = "MN", source = "assumed" }\nstiffness = { value = 100, unit = "kN/m", source = "assumed" }\n\n[contact_wire_support]',
     ["droppers", "exactly one of axial_stiffness", "stiffness"]),
    ('type = "steady_arm"', 'type = "cantilever"', ["contact_wire_support", "'cantilever'", "'steady_arm'", "'spring'"]),
    ('length = { value = 1.0, unit = "m", source = "assumed" }', '', ["contact_wire_support", "missing", "length"]),
    ('name = "test"', 'name = "test', ["not valid TOML"]),
    ('span_lengths = { value = [60.0], unit = "m", source = "assumed" }',
     'span_lengths = { value = [60.0], unit = "m", source = "assumed" }\ncurve_radii = { value = [50.0], unit = "m", source = "assumed" }',
     ["layout.curve_radii[0]", "50 m", "100 m"]),
]


@pytest.mark.parametrize("old,new,words", MALFORMED, ids=[m[2][0] for m in MALFORMED])
def test_malformed_model_files_give_a_clear_error(tmp_path, old, new, words):
    assert old in BASE, "test set-up: the replaced text must exist"
    path = write(tmp_path, BASE.replace(old, new, 1))
    with pytest.raises(ModelError) as info:
        load_catenary(path)
    message = str(info.value)
    assert message.startswith("model.toml"), message
    assert "\n" not in message
    for word in words:
        assert word in message, f"{word!r} missing from: {message}"


def test_unknown_model_name_lists_the_builtin_ones():
    with pytest.raises(ModelError, match="st_9.8_ideal"):
        load_catenary("st_9.9_ideal")


def test_cli_reports_a_bad_model_in_one_line_without_traceback(presag, tmp_path):
    path = write(tmp_path, BASE.replace('value = 9.8, unit = "kN"', 'value = 0, unit = "kN"', 1))
    result = presag("form-find", str(path))
    assert result.returncode == 2
    assert "Traceback" not in result.stderr
    lines = result.stderr.strip().splitlines()
    assert len(lines) == 1 and "contact_wire.tension = 0 kN" in lines[0], result.stderr
