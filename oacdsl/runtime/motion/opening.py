"""How far a hand letting go of an object opens beside its neighbours.

A hand that opens wide to let go (:data:`~oacdsl.runtime.hands.OPEN`: the finger plate
straight out) sweeps its fingers some centimetres beyond where they held the object: a cup
set down 14 cm from a mixer had the opening finger plate sweep into the mixer (a touch of
0.5 s, a change of the world the task does not have). :func:`clear_opening` opens the
fingers only part of the way (or not at all) when opening fully would bring the hand nearer
than the tuning's ``arm_room_m`` to another object (the table aside: opening does not lower the
fingers, :meth:`~oacdsl.runtime.motion.hand.Motion.release` keeps the thumb of a hand that
would); the hand opens fully once it has withdrawn.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import TYPE_CHECKING

from oacdsl.runtime.armroom import arm_room
from oacdsl.runtime.hands import finger_joint_names
from oacdsl.runtime.motion.tuning import TUNING, Tuning

if TYPE_CHECKING:
    from oacdsl.runtime.simworld import SimWorld

__all__ = ["hand_room", "clear_opening"]


def hand_room(world: SimWorld, side: str, fingers: Mapping[str, float], ignore: set[str]) -> float:
    """The room (m) between hand ``side`` (and its arm, as it is now) with its fingers at
    ``fingers`` (joint suffix → rad, as :data:`~oacdsl.runtime.hands.OPEN`) and the objects
    other than ``ignore`` (:func:`~oacdsl.runtime.armroom.arm_room`)."""
    names = finger_joint_names(side)
    return arm_room(world, side, {names[j]: v for j, v in fingers.items() if j in names}, ignore, hand=True)


def clear_opening(
    world: SimWorld, side: str, obj: str, shape: Mapping[str, float], tuning: Tuning = TUNING,
    commanded: Mapping[str, float] | None = None,
) -> dict[str, float] | None:
    """The fingers of hand ``side`` letting go of ``obj``, opened towards ``shape`` only by the
    largest of the tuning's ``release_open_share`` that keeps ``arm_room_m`` from the objects other
    than ``obj`` and the table, or as much room as the hand has now if that is less (share 0:
    the fingers only stop squeezing; a side grasp of a cup, barely curled round it, withdraws
    off it as it is); None when opening fully keeps ``arm_room_m`` or no share keeps enough.
    What ``obj`` stands on is no neighbour (the hand set it down there). The shares are taken
    from the fingers' ``commanded`` targets where given (measured, a thumb pressed on the
    object may be past its limit, and the IK, given that, finds no solution), else from
    where they are."""
    ignore = {obj, world.layout.table} | set(world.relations().partners(obj))
    if hand_room(world, side, shape, ignore) >= tuning.arm_room_m:
        return None
    q = world.joint_positions()
    now = {j: float(q[name]) for j, name in finger_joint_names(side).items()}
    now.update(commanded or {})
    keep = min(tuning.arm_room_m, hand_room(world, side, now, ignore))
    for share in tuning.release_open_share:
        part = {j: now.get(j, v) + share * (v - now.get(j, v)) for j, v in shape.items()}
        if hand_room(world, side, part, ignore) >= keep:
            return part
    return None
