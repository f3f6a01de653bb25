"""Which liquid starts in which container, and how many balls each has (the liquids of a
:class:`~oacdsl.runtime.layout.Layout`): the caller's ``contents`` (``--fill``, or the OAC's own
preconditions) over the scene's ``LIQUID in CONTAINER``."""

from __future__ import annotations

from collections.abc import Mapping

from oacdsl.errors import RuntimeFailure, did_you_mean
from oacdsl.geometry import ROLE_LIQUID
from oacdsl.model import Scene
from oacdsl.runtime.bodies import Body

__all__ = ["starting_liquids"]


def starting_liquids(
    scene: Scene, bodies: Mapping[str, Body], given: dict[str, str], balls: dict[str, int]
) -> tuple[dict[str, str], dict[str, int]]:
    """Liquid → container (``given`` over the scene's ``in``) and the liquids' ball counts.

    When ``given`` moves a liquid into a container the scene fills with another liquid,
    that other liquid takes the moved one's place in the scene, if it is free (a swap).
    """
    liquid_names = sorted(n for n, b in bodies.items() if b.role == ROLE_LIQUID)
    containers = sorted(n for n, b in bodies.items() if b.container)
    for liquid, container in given.items():
        if liquid not in liquid_names:
            raise RuntimeFailure(
                f"cannot fill {liquid!r}: not a liquid of the scene{did_you_mean(liquid, liquid_names)}"
            )
        if container not in containers:
            raise RuntimeFailure(
                f"cannot put {liquid!r} into {container!r}: not a container of the scene"
                f"{did_you_mean(container, containers)}"
            )
    declared = {f.liquid: f.container for f in scene.fills if f.liquid in liquid_names}
    counts = {f.liquid: f.balls for f in scene.fills if f.balls is not None}
    counts.update(balls)
    contents = dict(given)
    for liquid, container in declared.items():
        if liquid in contents:
            continue
        movers = [lq for lq, c in given.items() if c == container and declared.get(lq) != container]
        mover = movers[0] if movers else None
        if mover is not None and mover in declared and declared[mover] not in contents.values():
            container = declared[mover]
        contents[liquid] = container
    for liquid in liquid_names:
        if liquid not in contents:
            raise RuntimeFailure(
                f"liquid {liquid!r} has no container to start in: say '{liquid} in CONTAINER' in scene"
                f" {scene.name!r} or give --fill {liquid}=CONTAINER"
                f" (containers: {', '.join(containers) or 'none'})"
            )
    unknown = sorted(set(counts) - set(liquid_names))
    if unknown:
        raise RuntimeFailure(
            f"cannot give balls to {unknown[0]!r}: not a liquid of the scene"
            f"{did_you_mean(unknown[0], liquid_names)}"
        )
    return contents, counts
