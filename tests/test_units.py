import math

import pytest
from hypothesis import given
from hypothesis import strategies as st

from oacdsl.errors import UsageError
from oacdsl.units import format_quantity, parse_quantity


@pytest.mark.parametrize(
    ("text", "unit", "si"),
    [
        ("150mm", "m", 0.15),
        ("0.15m", "m", 0.15),
        ("15cm", "m", 0.15),
        ("15 cm", "m", 0.15),
        ("1e2mm", "m", 0.1),
        (".5m", "m", 0.5),
        ("50mm/s", "m/s", 0.05),
        ("0.05m/s", "m/s", 0.05),
        ("5cm/s", "m/s", 0.05),
        ("0.3s", "s", 0.3),
        ("300ms", "s", 0.3),
        ("0s", "s", 0.0),
        ("3", "frames", 3.0),
        ("3 frames", "frames", 3.0),
        ("1frame", "frames", 1.0),
    ],
)
def test_parse_quantity_converts_to_si(text, unit, si):
    assert math.isclose(parse_quantity(text, unit), si, rel_tol=1e-12)


@pytest.mark.parametrize(
    ("text", "unit", "needle"),
    [
        ("150", "m", "has no unit; write a length with one of m, cm, mm"),
        ("50", "m/s", "has no unit; write a speed with one of m/s, cm/s, mm/s"),
        ("0.3", "s", "has no unit; write a duration with one of s, ms"),
        ("150mm/s", "m", "unknown unit 'mm/s'"),
        ("150 furlongs", "m", "unknown unit 'furlongs'"),
        ("50mm", "m/s", "a speed takes one of m/s, cm/s, mm/s"),
        ("abc", "m", "cannot read 'abc' as a length"),
        ("", "s", "cannot read '' as a duration"),
        ("2.5", "frames", "not a whole number of frames"),
        ("3s", "frames", "not a frame count"),
        ("1e999m", "m", "not a finite number"),
    ],
)
def test_parse_quantity_rejects_with_expected_units(text, unit, needle):
    with pytest.raises(UsageError, match="^--x: ") as err:
        parse_quantity(text, unit, what="--x")
    assert needle in str(err.value)
    assert "\n" not in str(err.value)


def test_unknown_unit_kind_is_a_programming_error():
    with pytest.raises(ValueError):
        parse_quantity("1m", "kg")


@given(st.integers(min_value=0, max_value=10**6))
def test_format_then_parse_round_trips_millimetres(mm):
    for unit in ("m", "m/s"):
        assert math.isclose(parse_quantity(format_quantity(mm / 1000, unit), unit), mm / 1000,
                            rel_tol=1e-12, abs_tol=1e-15)
