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

__all__ = ["add_scene_options", "scene_overrides"]


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


def _pairs(items: list[str], flag: str, shape: str) -> dict[str, str]:
    out: dict[str, str] = {}
    for item in items:
        key, sep, value = item.partition("=")
        if not sep or not key.strip() or not value.strip():
            raise UsageError(f"{flag} {item!r}: expected {shape}")
        out[key.strip()] = value.strip()
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
    for name, value in _pairs(args.place, "--place", "OBJECT=X,Y").items():
        parts = value.split(",")
        if len(parts) != 2:
            raise UsageError(f"--place {name}={value}: expected OBJECT=X,Y (lengths, e.g. 60cm,-20cm)")
        places[name] = (_length(parts[0], f"--place {name}"), _length(parts[1], f"--place {name}"))
    fill: dict[str, str] = {}
    balls: dict[str, int] = {}
    for liquid, value in _pairs(args.fill, "--fill", "LIQUID=CONTAINER[:BALLS]").items():
        container, sep, count = value.partition(":")
        fill[liquid] = container.strip()
        if sep:
            if not count.strip().isdigit() or not 1 <= int(count) <= MAX_BALLS:
                raise UsageError(
                    f"--fill {liquid}={value}: the number of balls is a whole number from 1 to {MAX_BALLS}"
                )
            balls[liquid] = int(count)
    return SceneOverrides(places, fill, balls, args.layout)
