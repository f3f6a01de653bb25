"""How each object of a layout is turned about the vertical: its yaw on the robot's table.

The yaw (rad) turns an object about the vertical through its origin, from the robot's x axis
(forward) towards its y axis (left). It comes, first match wins, from

1. the demonstration's first frame, for an object laid out as demonstrated (``layout
   demonstrated``) whose class declares ``markers`` that pose its shape there
   (:func:`oacdsl.runtime.demo_layout.first_frame_poses`: the rigid fit of the recorded markers
   to the declared ones gives the direction of the class's x axis), mapped onto the table as
   the positions are (:meth:`oacdsl.runtime.demo_layout.TableMap.yaw_rad`: the demonstrator's
   forward is the robot's x, the demonstrator's left its y); an object that is the same solid
   half turned (:func:`alike_half_turned`: a box, a cucumber, a rolling pin, a round cup) takes
   the one of the two yaws that stand it alike nearer 0 (:func:`nearer_half_turn`), so that what
   its class says in its own frame (its grasp point, written for the robot with x away from
   it) stays on the side its author meant (KIT Cut's cucumber, turned by 178° as its declared
   markers fit, was held at its far end and the knife, cutting the near one, met the hand);
2. the scene's ``OBJECT at (x, y) turned ANGLE``, whatever placed the object (an object laid
   out as demonstrated whose class declares no markers keeps the scene's word: its markers do
   not say which way its class's x axis lies);
3. none: 0, the object's x axis pointing away from the robot.

The footprints the layout keeps apart are circles about each object's origin (its
:attr:`~oacdsl.runtime.bodies.Body.radius`), the same whichever way it is turned; the skills
read every object's pose from the simulation.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence

import numpy as np

from oacdsl.model import Scene
from oacdsl.runtime.bodies import Body
from oacdsl.runtime.demo_layout import table_map

__all__ = ["alike_half_turned", "nearer_half_turn", "object_yaws"]


def object_yaws(
    scene: Scene,
    names: Sequence[str],
    sources: Mapping[str, str],
    mapped: Sequence[str],
    demonstrated: Mapping[str, np.ndarray] | None,
    headings: Mapping[str, np.ndarray] | None,
    hands: Mapping[str, str],
    bodies: Mapping[str, Body],
) -> dict[str, float]:
    """The yaw (rad) of each object of ``names`` (module docstring). ``sources``: where each
    object's place came from (``Layout.sources``); ``mapped``: the objects whose first-frame
    positions were mapped onto the table (laid out as demonstrated, not stacked); ``demonstrated``
    the first-frame positions (m, hands included); ``headings`` the first-frame directions of the
    posed objects' x axes; ``hands`` hand instance → ``"r"``/``"l"``."""
    out = {n: (p.yaw_rad if (p := scene.place(n)) is not None else 0.0) for n in names}
    turned = [n for n in names if sources.get(n) == "demonstrated" and n in (headings or {})]
    if not turned or not demonstrated or headings is None:
        return out
    shown = {n: demonstrated[n] for n in mapped if n in demonstrated}
    demo_hands = {side: demonstrated[h] for h, side in hands.items() if h in demonstrated}
    mapping = table_map(shown, demo_hands, {n: bodies[n].radius for n in shown})
    for name in turned:
        yaw = mapping.yaw_rad(np.asarray(headings[name], float))
        out[name] = nearer_half_turn(yaw) if alike_half_turned(bodies[name]) else yaw
    return out


def alike_half_turned(body: Body) -> bool:
    """Whether ``body`` is the same solid turned half a turn about its vertical axis: each of its
    solids (a box, a rack, a round shape: each alike half turned about its own axis) has one of
    the same kind, sizes and mass where it is turned to (a rolling pin's two handles). A mesh is
    not known to be."""
    solids = body.solids
    if not solids or any(s.kind == "mesh" for s in solids):
        return False
    key = [(s.kind, sorted(s.dims.items()), s.mass) for s in solids]
    for i, s in enumerate(solids):
        turned = (-s.at[0], -s.at[1], s.at[2])
        if not any(key[j] == key[i] and np.allclose(o.at, turned, atol=1e-6) for j, o in enumerate(solids)):
            return False
    return True


def nearer_half_turn(yaw_rad: float) -> float:
    """Of ``yaw_rad`` and that plus half a turn, the one nearer 0 (in (-90°, 90°]), rad."""
    yaw = math.remainder(yaw_rad, math.pi)  # in [-90°, 90°]
    return -yaw if math.isclose(yaw, -math.pi / 2) else yaw
