"""The options that override a scene's initial state, alike in ``oacc run`` and ``oacc reproduce``.

``--place OBJECT=X,Y`` (lengths with units; a bare number is metres), ``--fill
LIQUID=CONTAINER[:BALLS]`` and ``--layout auto|demonstrated``; they override the
scene's ``at``, ``in`` and ``layout`` statements (docs/language.md).
"""

from __future__ import annotations

import argparse

from oacdsl.errors import UsageError
from oacdsl.model import LAYOUTS, MAX_BALLS
from oacdsl.runtime.overrides import SceneOverrides
from oacdsl.units import parse_quantity

__all__ = ["add_scene_options", "pairs", "scene_overrides"]


def add_scene_options(p: argparse.ArgumentParser) -> None:
    """Add ``--place``, ``--fill`` and ``--layout`` (in a group of their own)."""
    g = p.add_argument_group(
        "the robot's initial scene (over the scene's 'at', 'in' and 'layout' statements)"
    )
    g.add_argument(
        "--place",
        action="append",
        default=[],
        metavar="OBJECT=X,Y",
        help="put an object at (X, Y) on the robot's table, x forward, y left; lengths such as"
        " 60cm,-20cm (bare numbers are metres; repeatable)",
    )
    g.add_argument(
        "--fill",
        action="append",
        default=[],
        metavar="LIQUID=CONTAINER[:BALLS]",
        help="start a liquid in a container, optionally with a number of balls (repeatable)",
    )
    g.add_argument(
        "--layout",
        choices=LAYOUTS,
        help="where objects without a place start: auto (free slots) or demonstrated (the"
        " recording's first frame mapped into reach); default: the scene's layout",
    )


def pairs(items: list[str], flag: str, shape: str) -> dict[str, str]:
    """``KEY=VALUE`` items of a repeatable option; a key given twice with different values is a
    usage error (not last-wins), the same value twice is once."""
    out: dict[str, str] = {}
    for item in items:
        key, sep, value = item.partition("=")
        key, value = key.strip(), value.strip()
        if not sep or not key or not value:
            raise UsageError(f"{flag} {item!r}: expected {shape}")
        if key in out and out[key] != value:
            raise UsageError(f"{flag} {key}: given twice ({key}={out[key]}, {key}={value}); give it once")
        out[key] = value
    return out


def _length(text: str, flag: str) -> float:
    text = text.strip()
    try:
        return float(text)  # a bare number is metres, as in the language
    except ValueError:
        return parse_quantity(text, "m", what=flag)


def scene_overrides(args: argparse.Namespace) -> SceneOverrides:
    """The overrides given on the command line (UsageError for a malformed one)."""
    places: dict[str, tuple[float, float]] = {}
    for name, value in pairs(args.place, "--place", "OBJECT=X,Y").items():
        parts = value.split(",")
        if len(parts) != 2:
            raise UsageError(f"--place {name}={value}: expected OBJECT=X,Y (lengths, e.g. 60cm,-20cm)")
        places[name] = (_length(parts[0], f"--place {name}"), _length(parts[1], f"--place {name}"))
    fill: dict[str, str] = {}
    balls: dict[str, int] = {}
    for liquid, value in pairs(args.fill, "--fill", "LIQUID=CONTAINER[:BALLS]").items():
        container, sep, count = value.partition(":")
        fill[liquid] = container.strip()
        if sep:
            count = count.strip()
            if not (count.isascii() and count.isdigit()) or not 1 <= int(count) <= MAX_BALLS:
                raise UsageError(
                    f"--fill {liquid}={value}: the number of balls is a whole number from 1 to {MAX_BALLS}"
                )
            balls[liquid] = int(count)
    return SceneOverrides(places, fill, balls, args.layout)
