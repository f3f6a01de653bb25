"""Checks of a scene's initial state: ``layout``, ``at`` placements and ``in`` contents.

* ``layout NAME`` names a known layout (E045), once per scene (E006);
* ``x at (X, Y)`` names an instance of the scene (E004) that stands on the table:
  not a hand, a liquid, environment or ignored (E046); X and Y are lengths (E043),
  each instance placed once (E006); ``turned A`` is an angle (E043) within ±360deg (E044);
* ``l in c [balls N]``: ``l`` a Liquid and ``c`` a Container of the scene (E004,
  E046), each liquid in one container (E006), 1 ≤ N ≤ :data:`~oacdsl.model.MAX_BALLS` (E044);
* an ``untracked`` instance names no markers and is not a hand (E048).
"""

from __future__ import annotations

import math

from oacdsl.compiler.check_skills import check_quantity_unit, written
from oacdsl.compiler.context import Context
from oacdsl.compiler.diagnostics import Note
from oacdsl.errors import did_you_mean
from oacdsl.model import LAYOUTS, MAX_BALLS, Instance, Node, Scene, ScenePlace

__all__ = ["check_scene_state"]

#: Classes whose instances do not stand on the table by themselves (the robot's hands,
#: liquids: they start inside a container).
NOT_PLACEABLE = ("Hand", "Liquid")
#: Largest yaw of ``turned`` either way, rad (a full turn).
MAX_YAW_RAD = 2 * math.pi


def _known(ctx: Context, scene: Scene, name: str, node: Node, key: str) -> Instance | None:
    inst = scene.instance(name)
    if inst is None:
        names = [i.name for i in scene.instances]
        ctx.add(
            "E004",
            f"unknown instance '{name}' in scene '{scene.name}'{did_you_mean(name, names)}",
            node.part(key),
        )
    return inst


def _classes(ctx: Context, inst: Instance) -> set[str] | None:
    """Every class of ``inst``, inherited included; None when one is unknown (E003 already)."""
    if any(c not in ctx.library.classes for c in inst.classes):
        return None
    return set().union(*(ctx.library.ancestors(c) for c in inst.classes))


def _check_layout(ctx: Context, scene: Scene) -> None:
    if scene.layout is not None and scene.layout not in LAYOUTS:
        ctx.add(
            "E045",
            f"unknown layout '{scene.layout}'{did_you_mean(scene.layout, LAYOUTS)}"
            f" (valid: {', '.join(LAYOUTS)})",
            scene.part("layout"),
        )
    for key, *_ in scene.parts:
        if key.startswith("layout."):
            span = scene.part(key)
            ctx.add(
                "E006",
                f"the layout of scene '{scene.name}' is given twice",
                span,
                Note("first given here", scene.part("layout")),
            )


def _check_places(ctx: Context, scene: Scene) -> None:
    seen: dict[str, Node] = {}
    for place in scene.places:
        inst = _known(ctx, scene, place.instance, place, "instance")
        if place.instance in seen:
            ctx.add(
                "E006",
                f"the place of '{place.instance}' is given twice",
                place.part("instance"),
                Note("first given here", seen[place.instance].part("instance")),
            )
        seen.setdefault(place.instance, place)
        for q in (place.x, place.y):
            check_quantity_unit(ctx, q, "m", f"the position of '{place.instance}'")
        _check_yaw(ctx, place)
        if inst is None:
            continue
        why = None
        if inst.environment or inst.ignored:
            why = "environment" if inst.environment else "ignored"
        else:
            kinds = (_classes(ctx, inst) or set()) & set(NOT_PLACEABLE)
            if kinds:
                why = f"a {min(kinds)}" + (
                    " (it starts inside a container: write 'in')" if "Liquid" in kinds else " of the robot"
                )
        if why is not None:
            ctx.add(
                "E046", f"'{place.instance}' is {why}: it has no place on the table", place.part("instance")
            )


def _check_yaw(ctx: Context, place: ScenePlace) -> None:
    """``turned ANGLE``: an angle (E043), finite and within a full turn either way (E044)."""
    yaw = place.yaw
    if yaw is None or not check_quantity_unit(ctx, yaw, "rad", f"the yaw of '{place.instance}'"):
        return
    if not (math.isfinite(place.yaw_rad) and abs(place.yaw_rad) <= MAX_YAW_RAD + 1e-12):
        ctx.add(
            "E044",
            f"the yaw of '{place.instance}' must lie between -360deg and 360deg, not {written(yaw)}",
            place.part("yaw"),
        )


def _check_fills(ctx: Context, scene: Scene) -> None:
    seen: dict[str, Node] = {}
    for fill in scene.fills:
        liquid = _known(ctx, scene, fill.liquid, fill, "liquid")
        container = _known(ctx, scene, fill.container, fill, "container")
        if fill.liquid in seen:
            ctx.add(
                "E006",
                f"the container of '{fill.liquid}' is given twice",
                fill.part("liquid"),
                Note("first given here", seen[fill.liquid].part("liquid")),
            )
        seen.setdefault(fill.liquid, fill)
        liquid_classes = _classes(ctx, liquid) if liquid is not None else None
        container_classes = _classes(ctx, container) if container is not None else None
        if liquid is not None and liquid_classes is not None and "Liquid" not in liquid_classes:
            ctx.add(
                "E046",
                f"'{fill.liquid}' is a {'/'.join(liquid.classes)}, not a Liquid: only a liquid"
                " starts inside a container",
                fill.part("liquid"),
            )
        if (
            container is not None
            and container_classes is not None
            and ("Container" not in container_classes or container.environment or container.ignored)
        ):
            ctx.add(
                "E046",
                f"'{fill.container}' is a {'/'.join(container.classes)}"
                f"{' (ignored)' if container.ignored else ''}, not a Container: nothing can start in it",
                fill.part("container"),
            )
        if fill.balls is not None and not 1 <= fill.balls <= MAX_BALLS:
            ctx.add(
                "E044",
                f"'{fill.liquid}' has {fill.balls} balls: the number of balls is a whole number"
                f" (1 to {MAX_BALLS})",
                fill.part("balls"),
            )


def _check_untracked(ctx: Context, scene: Scene) -> None:
    for inst in scene.untracked():
        if inst.markers:
            ctx.add(
                "E048",
                f"'{inst.name}' is untracked: it has no marker group in the recording, so it cannot"
                " name markers; remove 'markers (…)' or 'untracked'",
                inst.part("markers.0"),
            )
        elif "Hand" in (_classes(ctx, inst) or set()):
            ctx.add(
                "E048",
                f"'{inst.name}' is a Hand: the demonstrator's hands are always tracked; 'untracked' is"
                " for an object the recording does not see (a liquid)",
                inst.part("name"),
            )


def check_scene_state(ctx: Context, scene: Scene) -> None:
    """Every check of the module docstring on one scene."""
    _check_untracked(ctx, scene)
    _check_layout(ctx, scene)
    _check_places(ctx, scene)
    _check_fills(ctx, scene)
