"""``--place`` and ``--fill`` checked against the scene before any work (``oacc run``, ``oacc reproduce``).

The runtime's layout would refuse an unknown object or liquid, a container that is
none, or a place off the table, but only when the robot's world is built: for
``oacc reproduce`` that is after the demonstration was segmented, matched and composed,
the learned OAC written and a FAILED report published. Here they are usage errors
(exit 2) at once, with one more check the layout lacks: two objects placed so that
their footprints overlap (two cups in one spot), given by ``--place`` or by the
scene's ``at`` for an object ``--place`` does not move.
"""

from __future__ import annotations

import math
from typing import Any

from oacdsl.errors import UsageError, did_you_mean
from oacdsl.runtime.overrides import SceneOverrides

__all__ = ["check_overrides"]

#: Half the table's width, m (a place farther left or right is off the table).
_HALF_WIDTH_M = 0.8


def _fmt(xy: tuple[float, float]) -> str:
    return f"({xy[0]:.2f}, {xy[1]:.2f}) m"


def check_overrides(library: Any, scene: Any, overrides: SceneOverrides) -> None:
    """Refuse (:class:`~oacdsl.errors.UsageError`) overrides that ``scene`` cannot take."""
    if not overrides.places and not overrides.fill:
        return
    from oacdsl.geometry import ROLE_LIQUID, ROLE_OBJECT
    from oacdsl.runtime.bodies import bodies_for_scene
    from oacdsl.runtime.objects import TABLE_DEPTH, TABLE_FRONT
    from oacdsl.units import language_si

    built = scene.model_copy(update={"instances": tuple(i for i in scene.instances if not i.ignored)})
    bodies = bodies_for_scene(library, built)
    objects = sorted(n for n, b in bodies.items() if b.role == ROLE_OBJECT)
    liquids = sorted(n for n, b in bodies.items() if b.role == ROLE_LIQUID)
    containers = sorted(n for n, b in bodies.items() if b.container)
    for name, (x, y) in overrides.places.items():
        if name not in objects:
            raise UsageError(f"--place {name}: not an object on the table of scene {scene.name}"
                             f"{did_you_mean(name, objects)}")
        r = bodies[name].radius
        if not (TABLE_FRONT <= x - r and x + r <= TABLE_FRONT + TABLE_DEPTH and abs(y) + r <= _HALF_WIDTH_M):
            raise UsageError(
                f"--place {name}: {_fmt((x, y))} is off the table (x from {TABLE_FRONT:g} to"
                f" {TABLE_FRONT + TABLE_DEPTH:g} m, y within ±{_HALF_WIDTH_M:g} m, less the object's"
                f" radius {r:.2f} m)"
            )
    for liquid, container in overrides.fill.items():
        if liquid not in liquids:
            hint = did_you_mean(liquid, liquids)
            raise UsageError(f"--fill {liquid}: not a liquid of scene {scene.name}{hint}")
        if container not in containers:
            raise UsageError(f"--fill {liquid}={container}: not a container of scene {scene.name}"
                             f"{did_you_mean(container, containers)}")
    where: dict[str, tuple[tuple[float, float], str]] = {
        n: (xy, "--place") for n, xy in overrides.places.items()
    }
    if overrides.layout is None:  # a layout given on the command line replaces the scene's 'at's
        for place in scene.places:
            if place.instance in objects and place.instance not in where:
                x, y = (language_si(v.value, v.unit)[0] for v in (place.x, place.y))
                where[place.instance] = ((x, y), "the scene's 'at'")
    for a in sorted(overrides.places):
        for b in sorted(where):
            if b == a or (b in overrides.places and b < a):  # each pair once
                continue
            (pa, _), (pb, source) = where[a], where[b]
            gap = math.dist(pa, pb) - bodies[a].radius - bodies[b].radius
            if gap < 0:
                raise UsageError(
                    f"--place {a}: at {_fmt(pa)} it overlaps {b} at {_fmt(pb)} ({source}) by"
                    f" {-gap * 100:.1f} cm; place them farther apart"
                )
