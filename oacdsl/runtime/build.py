"""Assemble the MuJoCo model: the ARMAR-III URDF plus floor, table, objects, balls,
position actuators, wrist force/torque sensors and the (inactive) grasp welds.

The robot comes from the generated URDF (:mod:`oacdsl.runtime.urdf`), loaded with
``MjSpec.from_file``; everything else is added with ``MjSpec``. Robot bodies get
gravity compensation; robot geoms collide with objects and the table but not with
each other or the floor (placo keeps the robot free of self-collision).
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import mujoco
import numpy as np

from oacdsl.runtime.armar3 import BASE_JOINTS, HEAD_JOINTS, TORSO_JOINTS
from oacdsl.runtime.geoms import BALL_CONTYPE, OBJECT_CONAFFINITY, OBJECT_CONTYPE
from oacdsl.runtime.hands import OPEN, finger_joint_names
from oacdsl.runtime.layout import Layout
from oacdsl.runtime.objects import TABLE_TOP, add_balls, add_object, add_table
from oacdsl.runtime.transforms import quat_from_matrix
from oacdsl.runtime.urdf import URDF_PATH

__all__ = [
    "BuiltModel",
    "build_model",
    "TIMESTEP_S",
    "ROBOT_CONTYPE",
    "ROBOT_CONAFFINITY",
    "gains",
    "HOME",
    "home_posture",
    "ROBOT_GROUP",
]

#: Simulation time step, seconds.
TIMESTEP_S = 0.005
ROBOT_CONTYPE, ROBOT_CONAFFINITY = 2, 4
#: Geom groups: 0 = table and objects (what a downward ray may hit), 1 = balls, 2 = robot.
ROBOT_GROUP = 2
#: Robot links whose geoms collide with objects and the table (the arms from the upper arm on).
_TOUCHING_LINKS = ("hand_", "fingers_", "thumb_", "wrist_", "underarm_", "elbow_", "upperarm_")
#: Distance up to which a hand counts as touching an object, m.
TOUCH_MARGIN_M = 0.003

_LIQUID_RGBA = {0: (0.2, 0.4, 0.95, 1.0), 1: (0.95, 0.9, 0.2, 1.0), 2: (0.85, 0.3, 0.85, 1.0)}


@dataclass(frozen=True)
class BuiltModel:
    """The compiled model and the names the runtime needs to find things in it."""

    model: mujoco.MjModel
    layout: Layout
    robot_joints: tuple[str, ...]
    balls: dict[str, tuple[str, ...]]
    welds: dict[tuple[str, str], str]


def gains(joint: str) -> tuple[float, float]:
    """(kp, force limit) of the position actuator on ``joint`` (N/m or N·m/rad; N or N·m)."""
    if joint in BASE_JOINTS:
        return (4.0e4, 5.0e3) if joint != "base_yaw" else (2.0e4, 3.0e3)
    if joint in TORSO_JOINTS:
        return 8.0e3, 2.0e3
    if joint in HEAD_JOINTS:
        return 300.0, 100.0
    if "fingers" in joint or "thumb" in joint:
        return 4.0, 1.5
    return 1500.0, 400.0


def _robot_spec() -> mujoco.MjSpec:
    spec = mujoco.MjSpec.from_file(str(URDF_PATH))
    colours: dict[str, tuple[float, ...]] = {}
    visual = []
    for g in spec.geoms:
        if g.contype == 0 and g.conaffinity == 0:
            colours[g.name.replace("_v", "_c")] = tuple(g.rgba)
            visual.append(g)
    for g in visual:  # keep one geom per shape: the collision geom, coloured like the visual one
        spec.delete(g)
    for g in spec.geoms:
        g.contype, g.conaffinity, g.group = ROBOT_CONTYPE, ROBOT_CONAFFINITY, ROBOT_GROUP
        if not g.name.startswith(_TOUCHING_LINKS):
            # platform, torso, head and shoulders never reach the table top: no collisions
            g.contype = g.conaffinity = 0
        if g.name.startswith(("hand_", "fingers_", "thumb_")):
            # touching is reported up to 3 mm apart (contacts between margin - gap and margin
            # are detected but exert no force), so a hand resting on an object stays "touching"
            g.margin = g.gap = TOUCH_MARGIN_M
        g.friction = (1.5, 0.005, 0.0001)
        if g.name in colours:
            g.rgba = colours[g.name]
    for b in spec.bodies:
        if b.name != "world":
            b.gravcomp = 1.0
    return spec


def _add_actuators(spec: mujoco.MjSpec, joints: list[str]) -> None:
    for name in joints:
        j = spec.joint(name)
        j.armature = 0.002 if ("fingers" in name or "thumb" in name) else 0.1
        j.damping = (0.05 if ("fingers" in name or "thumb" in name) else 2.0, 0.0, 0.0)
        kp, limit = gains(name)
        act = spec.add_actuator()
        act.name, act.target, act.trntype = name, name, mujoco.mjtTrn.mjTRN_JOINT
        act.set_to_position(kp=kp, dampratio=1.0)
        act.forcelimited = mujoco.mjtLimited.mjLIMITED_TRUE
        act.forcerange = (-limit, limit)
        act.ctrllimited = mujoco.mjtLimited.mjLIMITED_TRUE
        act.ctrlrange = tuple(j.range) if j.type != mujoco.mjtJoint.mjJNT_FREE else (-1.0, 1.0)


def _add_sensors(spec: mujoco.MjSpec) -> None:
    for side in ("r", "l"):
        site = spec.body(f"hand_{side}").add_site()
        site.name, site.size = f"ft_{side}", (0.01, 0.0, 0.0)
        site.rgba = (0.9, 0.2, 0.2, 0.0)
        for kind, stype in (
            ("force", mujoco.mjtSensor.mjSENS_FORCE),
            ("torque", mujoco.mjtSensor.mjSENS_TORQUE),
        ):
            s = spec.add_sensor()
            s.name, s.type = f"ft_{side}_{kind}", stype
            s.objtype, s.objname = mujoco.mjtObj.mjOBJ_SITE, site.name


def _add_environment(spec: mujoco.MjSpec, table: str) -> None:
    floor = spec.worldbody.add_geom()
    floor.name, floor.type, floor.size = "floor", mujoco.mjtGeom.mjGEOM_PLANE, (3.0, 3.0, 0.05)
    floor.rgba, floor.contype, floor.conaffinity = (0.82, 0.82, 0.78, 1.0), 1, 1 | BALL_CONTYPE
    add_table(spec, table)
    for g in spec.body(table).geoms:
        g.contype, g.conaffinity = OBJECT_CONTYPE, OBJECT_CONAFFINITY
    light = spec.worldbody.add_light()
    light.pos, light.dir, light.castshadow = (0.5, -0.5, 3.0), (0.0, 0.2, -1.0), False
    for name, pos, target in CAMERAS:
        cam = spec.worldbody.add_camera()
        cam.name, cam.pos, cam.quat = name, pos, _look_at(np.array(pos), np.array(target))
    spec.visual.global_.offwidth, spec.visual.global_.offheight = 1280, 960
    spec.visual.quality.offsamples = 0  # no multisampling: software GL renders twice as fast


#: Fixed cameras: name, position and the point they look at (m).
CAMERAS = (
    ("overview", (1.6, 1.05, 1.75), (0.42, -0.05, 1.08)),
    ("front", (1.9, 0.0, 1.45), (0.45, 0.0, 0.95)),
)


def _look_at(pos: np.ndarray, target: np.ndarray) -> tuple[float, float, float, float]:
    """Camera quaternion (w, x, y, z) looking from ``pos`` at ``target`` with z up."""
    f = (target - pos) / np.linalg.norm(target - pos)
    x = np.cross(f, (0.0, 0.0, 1.0))
    x /= np.linalg.norm(x)
    y = np.cross(x, f)
    q = quat_from_matrix(np.column_stack([x, y, -f]))
    return (float(q[0]), float(q[1]), float(q[2]), float(q[3]))


def build_model(layout: Layout, seed: int | None = None) -> BuiltModel:
    """Compile the model of ``layout`` (``seed`` jitters the balls' starting slots)."""
    spec = _robot_spec()
    spec.option.timestep = TIMESTEP_S
    spec.option.integrator = mujoco.mjtIntegrator.mjINT_IMPLICITFAST
    spec.option.cone = mujoco.mjtCone.mjCONE_PYRAMIDAL
    # island sleeping: objects and balls at rest cost nothing until something touches them
    spec.option.enableflags |= int(mujoco.mjtEnableBit.mjENBL_SLEEP)
    _add_environment(spec, layout.table)
    joints = [j.name for j in spec.joints if j.type != mujoco.mjtJoint.mjJNT_FREE]
    _add_actuators(spec, joints)
    _add_sensors(spec)
    rng = np.random.default_rng(seed if seed is not None else 0)
    for p in layout.placements:
        base = TABLE_TOP + (layout.placement(p.on).body.height if p.on else 0.0)  # on top of another
        add_object(spec, p.name, p.body, (p.x, p.y, base), p.yaw)
    balls: dict[str, tuple[str, ...]] = {}
    for i, (liquid, container) in enumerate(sorted(layout.liquids.items())):
        p = layout.placement(container)
        body = layout.bodies[liquid]
        body = replace(body, rgba=_LIQUID_RGBA.get(i, body.rgba))
        balls[liquid] = tuple(
            add_balls(
                spec, liquid, layout.ball_count(liquid), np.array([p.x, p.y, TABLE_TOP]), p.body, body, rng
            )
        )
    welds: dict[tuple[str, str], str] = {}
    for side in ("r", "l"):
        for p in layout.placements:
            eq = spec.add_equality()
            eq.name = f"grasp_{side}/{p.name}"
            eq.type, eq.objtype = mujoco.mjtEq.mjEQ_WELD, mujoco.mjtObj.mjOBJ_BODY
            eq.name1, eq.name2, eq.active = f"hand_{side}", p.name, False
            eq.solref = (0.01, 1.0)
            welds[(side, p.name)] = eq.name
    model = spec.compile()
    return BuiltModel(model, layout, tuple(joints), balls, welds)


#: The robot's starting posture (rad): upper arms a little forward and out, hands open.
HOME: dict[str, float] = {
    "shoulder_1_r": -0.2,
    "shoulder_2_r": 0.15,
    "elbow_r": -0.2,
    "shoulder_1_l": -0.2,
    "shoulder_2_l": -0.15,
    "elbow_l": -0.2,
}


def home_posture() -> dict[str, float]:
    """Joint targets of the starting posture, hands open."""
    q = dict(HOME)
    for side in ("r", "l"):
        for suffix, joint in finger_joint_names(side).items():
            q[joint] = OPEN[suffix]
    return q
