"""Physical quantities written with units on the command line: ``150mm``, ``50mm/s``, ``0.3s``.

Inside the package every quantity is SI (metres, metres per second, seconds);
only the command line and the docs speak millimetres. A length, a speed or a
duration must carry its unit: a bare ``150`` is rejected because it is
ambiguous (millimetres? metres?) and a wrong guess silently ruins a
segmentation. A frame count is a bare integer (``3``), optionally followed by
``frames``.
"""

from __future__ import annotations

import math
import re

from oacdsl.errors import UsageError

__all__ = [
    "LANGUAGE_UNITS", "UNITS", "format_mm", "format_quantity", "language_si", "parse_quantity", "unit_kind",
]

#: For each SI unit the accepted spellings and their factor to SI.
UNITS: dict[str, dict[str, float]] = {
    "m": {"m": 1.0, "cm": 0.01, "mm": 0.001},
    "m/s": {"m/s": 1.0, "cm/s": 0.01, "mm/s": 0.001},
    "s": {"s": 1.0, "ms": 0.001},
    "frames": {"": 1.0, "frames": 1.0, "frame": 1.0},
    "rad": {"rad": 1.0, "deg": math.pi / 180.0},
    "Hz": {"Hz": 1.0, "hz": 1.0, "kHz": 1000.0},
}

_KIND = {"m": "a length", "m/s": "a speed", "s": "a duration", "frames": "a frame count", "rad": "an angle",
         "Hz": "a frequency"}
_EXAMPLE = {"m": "150mm", "m/s": "50mm/s", "s": "0.3s", "frames": "3", "rad": "90deg", "Hz": "100Hz"}
_NUMBER = re.compile(r"^\s*([+-]?(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?)\s*([a-zA-Z/]*)\s*$")


def parse_quantity(text: str, unit: str, *, what: str | None = None) -> float:
    """Parse ``text`` (e.g. ``"150mm"``) as a quantity of SI ``unit``; return its SI value.

    ``unit`` is one of ``"m"`` (lengths: m, cm, mm), ``"m/s"`` (speeds: m/s, cm/s, mm/s),
    ``"s"`` (durations: s, ms), ``"rad"`` (angles: rad, deg), ``"Hz"`` (frequencies: Hz,
    kHz) or ``"frames"`` (a non-negative integer, optionally followed by ``frames``).
    ``what`` names the value in messages (``--distance``).
    Raises :class:`~oacdsl.errors.UsageError` naming the expected units.
    """
    if unit not in UNITS:
        raise ValueError(f"unknown unit kind {unit!r}; expected one of {sorted(UNITS)}")
    label = f"{what}: " if what else ""
    spellings = UNITS[unit]
    expected = ", ".join(s for s in spellings if s) if unit != "frames" else "an integer such as 3"
    match = _NUMBER.match(text)
    if match is None:
        raise UsageError(
            f"{label}cannot read {text!r} as {_KIND[unit]}; expected a number with a unit"
            f" ({expected}), e.g. {_EXAMPLE[unit]}"
        )
    number, suffix = match.group(1), match.group(2)
    value = float(number)
    if not math.isfinite(value):
        raise UsageError(f"{label}{text!r} is not a finite number")
    if unit == "frames":
        if suffix.lower() not in spellings:
            raise UsageError(f"{label}{text!r} is not a frame count; expected an integer such as 3")
        if value != int(value):
            raise UsageError(f"{label}{text!r} is not a whole number of frames")
        return float(int(value))
    if not suffix:
        raise UsageError(
            f"{label}{text!r} has no unit; write {_KIND[unit]} with one of {expected}, e.g. {_EXAMPLE[unit]}"
        )
    factor = spellings.get(suffix) or spellings.get(suffix.lower())
    if factor is None:
        raise UsageError(f"{label}unknown unit {suffix!r} in {text!r}; {_KIND[unit]} takes one of {expected}")
    return value * factor


def format_quantity(value: float, unit: str) -> str:
    """The inverse for messages and tables: 0.15 m → ``150mm``, 0.05 m/s → ``50mm/s``."""
    if unit == "m":
        return f"{value * 1000:g}mm"
    if unit == "m/s":
        return f"{value * 1000:g}mm/s"
    if unit == "s":
        return f"{value:g}s"
    if unit == "frames":
        return f"{int(value)}"
    if unit == "rad":
        return f"{math.degrees(value):g}deg"
    if unit == "Hz":
        return f"{value:g}Hz"
    raise ValueError(f"unknown unit kind {unit!r}")


def format_mm(length_m: float) -> str:
    """A length for a message, to the whole millimetre: 0.0013 m → ``1 mm``."""
    return f"{length_m * 1000:.0f} mm"


#: Units a ``.oac`` file may write after a number (``56cm``, ``110deg``): spelling → (SI unit, factor).
LANGUAGE_UNITS: dict[str, tuple[str, float]] = {
    "m": ("m", 1.0),
    "cm": ("m", 0.01),
    "mm": ("m", 0.001),
    "rad": ("rad", 1.0),
    "deg": ("rad", math.pi / 180.0),
    "s": ("s", 1.0),
    "ms": ("s", 0.001),
    "N": ("N", 1.0),
    "m/s": ("m/s", 1.0),
    "cm/s": ("m/s", 0.01),
    "mm/s": ("m/s", 0.001),
}

_KIND_WORDS = {
    "m": "a length (m, cm, mm)",
    "rad": "an angle (deg, rad)",
    "s": "a duration (s, ms)",
    "N": "a force (N)",
    "m/s": "a speed (m/s, cm/s, mm/s)",
    "": "a count (a whole number without unit)",
}


def language_si(number: float, unit: str) -> tuple[float, str]:
    """``(3.0, "cm")`` → ``(0.03, "m")``: the SI value and SI unit of a number written with
    ``unit`` in a ``.oac`` file, rounded to 12 significant digits so that ``56cm`` and
    ``0.56m`` are equal; a bare number stays as it is (unit ``""``); an unknown unit is
    returned unchanged for the checks to report."""
    if not unit:
        return float(number), ""
    known = LANGUAGE_UNITS.get(unit)
    if known is None:
        return float(number), unit
    si, factor = known
    if factor == 1.0:
        return float(number), si
    return float(f"{float(number) * factor:.12g}"), si  # 56cm == 0.56m exactly


def unit_kind(si_unit: str) -> str:
    """Words for an SI unit of the language: ``"rad"`` → ``"an angle (deg, rad)"``."""
    return _KIND_WORDS.get(si_unit, f"'{si_unit}'")
