"""``presag_opt.system.quantity``: units converted to SI with their dimension checked, valid ranges with
open and closed ends, and every bad value refused in one line naming field, value, unit and range."""

from __future__ import annotations

import dataclasses

import pytest

from presag_opt.errors import ModelError
from presag_opt.system.quantity import (
    DEFAULT_RANGE_SHARE,
    SI_UNIT,
    UNITS,
    check_value,
    default_range,
    dimension_of,
    quantity,
    range_text,
    to_si,
    validate_fields,
)
from presag_opt.units import KMH

SPEC = {"dimension": "length", "display": "m", "factor": 1.0, "low": 0.0, "high": 1.0,
        "low_open": False, "high_open": False, "allow_none": False}


def test_default_range_is_plus_minus_twenty_percent_inside_the_valid_range():
    assert DEFAULT_RANGE_SHARE == 0.2
    assert default_range(0.5, SPEC) == pytest.approx((0.4, 0.6), rel=1e-15)
    # cut at the valid range's closed end
    assert default_range(0.9, SPEC) == pytest.approx((0.72, 1.0), rel=1e-15)
    # an open end is not reached: halfway between the value and the end
    assert default_range(0.9, {**SPEC, "high_open": True}) == pytest.approx((0.72, 0.95), rel=1e-15)
    # a value of zero has no relative range
    assert default_range(0.0, SPEC) is None



@pytest.mark.parametrize(("value", "unit", "dimension", "si"), [
    (30.0, "mm", "length", 0.030), (9.8, "kN", "force", 9800.0), (1.07, "kg/m", "mass_per_length", 1.07),
    (50.0, "kN/m", "stiffness", 50e3), (1.12, "‰", "ratio", 1.12e-3), (2.0, "ms", "time", 2e-3),
    (180.0, "km/h", "speed", 50.0), (0.00097, "N/(km/h)^2", "aero_coefficient", 0.00097 * 3.6**2),
])
def test_values_are_converted_to_si(value, unit, dimension, si):
    assert to_si(value, unit, dimension, key="k") == pytest.approx(si, rel=1e-12)


def test_every_dimension_has_exactly_one_si_unit_and_each_spelling_one_dimension():
    assert SI_UNIT["speed"] == "m/s" and SI_UNIT["force"] == "N" and SI_UNIT["ratio"] == "-"
    spellings = [u for table in UNITS.values() for u in table]
    assert {u for u in spellings if spellings.count(u) > 1} == {"-"}  # only "-" (ratio, count) is shared
    assert dimension_of("kN/m") == "stiffness" and dimension_of("furlong") is None
    assert UNITS["speed"]["km/h"] == KMH


def test_a_unit_of_another_dimension_is_refused_naming_the_valid_ones():
    with pytest.raises(ModelError) as caught:
        to_si(9.8, "kg", "force", key="contact_wire.tension")
    assert str(caught.value) == "contact_wire.tension: unit 'kg' is not a unit of force; use one of N, kN, MN"


@pytest.mark.parametrize(("spec", "text"), [({}, "[0, 1] m"), ({"low_open": True}, "(0, 1] m"),
                                            ({"high_open": True, "display": "kN", "high": 60}, "[0, 60) kN")])
def test_range_text_marks_open_ends_with_parentheses(spec, text):
    assert range_text({**SPEC, **spec}) == text


@pytest.mark.parametrize(("value", "spec", "message"), [
    (1.5, {}, "x = 1.5 m is outside the valid range [0, 1] m"),
    (0.0, {"low_open": True}, "x = 0 m is outside the valid range (0, 1] m"),
    (1.0, {"high_open": True}, "x = 1 m is outside the valid range [0, 1) m"),
    (float("nan"), {}, "x = nan m is not a finite number; valid range [0, 1] m"),
    (9.9e3 * 7, {"display": "kN", "factor": 1e3, "high": 60.0}, "x = 69.3 kN is outside the valid range [0, 60] kN"),
])
def test_check_value_names_the_value_in_its_display_unit_and_the_range(value, spec, message):
    with pytest.raises(ModelError) as caught:
        check_value("x", value, {**SPEC, **spec})
    assert str(caught.value) == message


def test_the_ends_of_a_closed_range_are_valid():
    check_value("x", 0.0, SPEC)
    check_value("x", 1.0, SPEC)


@dataclasses.dataclass(frozen=True, kw_only=True)
class _Example:
    tension: float = quantity("force", 0.5, 60.0, display="kN", default=9800.0)
    spacings: tuple[float, ...] | None = quantity("length", 1.0, 100.0, default=None, allow_none=True)
    needed: float | None = quantity("length", 0.0, 1.0, default=0.5)


@pytest.mark.parametrize(("changes", "message"), [
    ({"tension": 70e3}, "wire.tension = 70 kN is outside the valid range [0.5, 60] kN"),
    ({"tension": True}, "wire.tension = True is not a number"),
    ({"tension": "9.8"}, "wire.tension = '9.8' is not a number"),
    ({"spacings": ()}, "wire.spacings is an empty list; give at least one value in [1, 100] m"),
    ({"spacings": (10.0, 0.5)}, "wire.spacings[1] = 0.5 m is outside the valid range [1, 100] m"),
    ({"needed": None}, "wire.needed is required (length in [0, 1] m)"),
])
def test_validate_fields_checks_scalars_lists_and_required_values(changes, message):
    validate_fields(_Example(), prefix="wire.")
    with pytest.raises(ModelError) as caught:
        validate_fields(_Example(**changes), prefix="wire.")
    assert str(caught.value) == message
