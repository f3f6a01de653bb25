"""How much room an arm posture leaves between the arm and the table or the objects.

The whole-body IK knows the robot's own links only (it avoids self-collisions), not the table
or the objects on it: a hand pose it reaches may lay the forearm across a bowl or the elbow on
the table. A skill choosing among several poses of the hand (the side a cup is poured from)
asks :func:`arm_room` for the IK's posture at each: the smallest distance (m) from the arm's
links (upper arm, elbow, forearm, wrist; not the hand, whose room the skill keeps itself) to
anything in the scene, measured in a scratch copy of the simulation with the robot's joints
set to that posture and everything else where it is now. With ``hand=True`` the hand's links
(palm, finger plate, thumb) are measured too, as a hand that has let go of what it set down
backs off past its neighbours.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping

import mujoco
import numpy as np

from oacdsl.runtime.build import ROBOT_GROUP
from oacdsl.runtime.simworld import SimWorld

__all__ = ["arm_room", "room_to_object", "ARM_LINKS", "HAND_LINKS"]

#: The links of an arm (name prefixes, followed by ``_r``/``_l``) whose room is measured.
ARM_LINKS = ("upperarm", "elbow", "underarm", "wrist_1", "wrist_2")
#: The hand's bodies (``hand_r`` and these links followed by ``_r_link``).
HAND_LINKS = ("fingers_{side}_j0", "fingers_{side}_j1", "thumb_{side}_j0", "thumb_{side}_j1")
#: Balls and robot geoms are not obstacles of the arm (group of the balls).
_BALL_GROUP = 1


def _arm_geoms(model: mujoco.MjModel, side: str, hand: bool = False) -> list[int]:
    bodies = {model.body(f"{link}_{side}_link").id for link in ARM_LINKS}
    if hand:
        bodies |= {model.body(f"hand_{side}").id} | {model.body(f"{link.format(side=side)}_link").id
                                                     for link in HAND_LINKS}
    return [g for g in range(model.ngeom) if int(model.geom_bodyid[g]) in bodies
            and (model.geom_contype[g] or model.geom_conaffinity[g])]


def _scene_geoms(world: SimWorld, ignore: Iterable[str]) -> list[int]:
    """Geoms of the table and the objects (not the robot, the balls, nor ``ignore``'s bodies)."""
    m = world.model
    skip = tuple(f"{name}/" for name in ignore) + tuple(ignore)
    out = []
    for g in range(m.ngeom):
        if m.geom_group[g] in (ROBOT_GROUP, _BALL_GROUP) or not (m.geom_contype[g] or m.geom_conaffinity[g]):
            continue
        body = m.body(int(m.geom_bodyid[g])).name
        if body.startswith(skip) or body in skip:
            continue
        out.append(g)
    return out


def arm_room(
    world: SimWorld,
    side: str,
    posture: Mapping[str, float],
    ignore: Iterable[str] = (),
    within_m: float = 0.1,
    *,
    hand: bool = False,
) -> float:
    """The smallest distance (m, at most ``within_m``; negative: overlapping) between the links
    of arm ``side`` (and its hand's, with ``hand``) in ``posture`` (joint → rad or m, the IK's)
    and the table or an object other than ``ignore`` (what the hand holds; the table's name leaves
    the table out), everything else as it is now."""
    m = world.model
    data = mujoco.MjData(m)
    data.qpos[:] = world.data.qpos
    for name, value in posture.items():
        data.qpos[int(m.jnt_qposadr[m.joint(name).id])] = value
    mujoco.mj_kinematics(m, data)
    arm, scene = _arm_geoms(m, side, hand), _scene_geoms(world, ignore)
    best = within_m
    fromto = np.zeros(6)
    pos, bound = data.geom_xpos, m.geom_rbound
    for a in arm:
        for b in scene:
            if bound[b] > 0 and np.linalg.norm(pos[a] - pos[b]) > bound[a] + bound[b] + best:
                continue  # their bounding spheres are farther apart than the best so far
            best = min(best, float(mujoco.mj_geomDistance(m, data, a, b, within_m, fromto)))
    return best


def room_to_object(
    world: SimWorld,
    side: str,
    posture: Mapping[str, float],
    obj: str,
    t_world_obj: np.ndarray,
    within_m: float = 0.1,
) -> float:
    """The smallest distance (m, at most ``within_m``; negative: overlapping) between arm
    ``side`` with its hand in ``posture`` and object ``obj`` if it stood at ``t_world_obj``
    (everything else as it is now): whether an object set down there would be in the way of
    a posture the arm is to take later."""
    m = world.model
    data = mujoco.MjData(m)
    data.qpos[:] = world.data.qpos
    for name, value in posture.items():
        data.qpos[int(m.jnt_qposadr[m.joint(name).id])] = value
    body = m.body(obj)
    adr = int(m.jnt_qposadr[int(m.body_jntadr[body.id])])
    data.qpos[adr : adr + 3] = t_world_obj[:3, 3]
    quat = np.zeros(4)
    mujoco.mju_mat2Quat(quat, np.ascontiguousarray(t_world_obj[:3, :3]).reshape(-1))
    data.qpos[adr + 3 : adr + 7] = quat
    mujoco.mj_kinematics(m, data)
    prefix = f"{obj}/"
    mine = [g for g in range(m.ngeom) if (m.body(int(m.geom_bodyid[g])).name in (obj,)
                                          or m.body(int(m.geom_bodyid[g])).name.startswith(prefix))
            and (m.geom_contype[g] or m.geom_conaffinity[g])]
    best = within_m
    fromto = np.zeros(6)
    for a in _arm_geoms(m, side, hand=True):
        for b in mine:
            best = min(best, float(mujoco.mj_geomDistance(m, data, a, b, within_m, fromto)))
    return best
