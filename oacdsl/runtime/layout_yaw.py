"""How each object of a layout is turned about the vertical: its yaw on the robot's table.

The yaw (rad) turns an object about the vertical through its origin, from the robot's x axis
(forward) towards its y axis (left). It comes, first match wins, from

1. the demonstration's first frame, for an object laid out as demonstrated (``layout
   demonstrated``) whose class declares ``markers`` that pose its shape there
   (:func:`oacdsl.runtime.demo_layout.first_frame_poses`: the rigid fit of the recorded markers
   to the declared ones gives the direction of the class's x axis), mapped onto the table as
   the positions are (:meth:`oacdsl.runtime.demo_layout.TableMap.yaw_rad`: the demonstrator's
   forward is the robot's x, the demonstrator's left its y);
2. the scene's ``OBJECT at (x, y) turned ANGLE``, whatever placed the object (an object laid
   out as demonstrated whose class declares no markers keeps the scene's word: its markers do
   not say which way its class's x axis lies);
3. none: 0, the object's x axis pointing away from the robot.

The footprints the layout keeps apart are circles about each object's origin (its
:attr:`~oacdsl.runtime.bodies.Body.radius`), the same whichever way it is turned; the skills
read every object's pose from the simulation.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np

from oacdsl.model import Scene
from oacdsl.runtime.bodies import Body
from oacdsl.runtime.demo_layout import table_map

__all__ = ["object_yaws"]


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
        out[name] = mapping.yaw_rad(np.asarray(headings[name], float))
    return out
