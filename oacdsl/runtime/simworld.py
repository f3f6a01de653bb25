"""The simulated world at run time: stepping, joint targets, and what the skills may ask —
object poses, touching relations from contacts, balls in containers, grasp welds,
wrist force/torque readings, marker points.

Touching relations (the runtime's world state) come from MuJoCo contacts between the
bodies of two different tracked instances: a hand is all of its hand's bodies (palm,
finger plate, thumb), a liquid touches what any of its balls touches, and the table
(environment) and the rest of the robot take no part. Two liquids whose balls meet (both
poured into one bowl) are mixed, not touching: that pair is never reported. Whether an
object rests on something (``supported``: another object or the table) is asked apart.
"""

from __future__ import annotations

from collections.abc import Mapping

import mujoco
import numpy as np

from oacdsl.runtime.build import BuiltModel, home_posture
from oacdsl.world import WorldState

__all__ = ["SimWorld", "pose_of"]

_SLEEP = int(mujoco.mjtEnableBit.mjENBL_SLEEP)
_HAND_MARKERS = ((0.0, 0.0, 0.05), (0.0, 0.04, 0.10), (-0.03, 0.0, 0.115))


def pose_of(data: mujoco.MjData, body_id: int) -> np.ndarray:
    """T_world_body (4×4) of a body."""
    t = np.eye(4)
    t[:3, :3] = data.xmat[body_id].reshape(3, 3)
    t[:3, 3] = data.xpos[body_id]
    return t


class SimWorld:
    """A MuJoCo model and its data, with the runtime's vocabulary on top."""

    def __init__(self, built: BuiltModel) -> None:
        self.built = built
        self.model = built.model
        self.data = mujoco.MjData(self.model)
        self.layout = built.layout
        m = self.model
        self.instances: tuple[str, ...] = tuple(
            sorted([*self.layout.hands, *(p.name for p in self.layout.placements), *built.balls])
        )
        index = {name: i for i, name in enumerate(self.instances)}
        self._body_instance = np.full(m.nbody, -1, dtype=int)
        self.hand_bodies: dict[str, list[int]] = {"r": [], "l": []}
        for b in range(m.nbody):
            name = m.body(b).name
            root = name.split("/")[0]
            if root in index:
                self._body_instance[b] = index[root]
        for inst, side in self.layout.hands.items():
            for b in range(m.nbody):
                name = m.body(b).name
                if name == f"hand_{side}" or name.startswith((f"fingers_{side}_", f"thumb_{side}_")):
                    self._body_instance[b] = index[inst]
                    self.hand_bodies[side].append(b)
        self._geom_instance = self._body_instance[m.geom_bodyid]
        # what can bear an object set down: another object or the environment (the table),
        # neither the robot nor a liquid's balls
        robot_root = m.body_rootid[m.body("base_link").id]
        liquid_bodies = np.isin(self._body_instance, [index[liq] for liq in built.balls])
        robot_bodies = m.body_rootid == robot_root
        self._bears = ~(robot_bodies | liquid_bodies)[m.geom_bodyid]
        # two liquids in one container are mixed, not "touching": their pairs are ignored
        liquid_index = [index[liq] for liq in built.balls]
        self._ignored = {(min(a, b), max(a, b)) for a in liquid_index for b in liquid_index if a != b}
        self._actuator = {m.actuator(i).name: i for i in range(m.nu)}
        self._qadr = {n: int(m.jnt_qposadr[m.joint(n).id]) for n in built.robot_joints}
        self._ball_ids = {liq: np.array([m.body(b).id for b in names]) for liq, names in built.balls.items()}
        self._weld_ids = {key: m.equality(name).id for key, name in built.welds.items()}
        self.held: dict[str, str | None] = {"r": None, "l": None}
        self._ft = {
            s: (
                m.site(f"ft_{s}").id,
                int(m.sensor(f"ft_{s}_force").adr[0]),
                int(m.sensor(f"ft_{s}_torque").adr[0]),
            )
            for s in ("r", "l")
        }
        self.reset()

    # --- time and control -------------------------------------------------------------------
    @property
    def time_s(self) -> float:
        return float(self.data.time)

    def reset(self, settle_s: float = 0.3) -> None:
        """Home posture, hands open, objects at their places; let things settle."""
        mujoco.mj_resetData(self.model, self.data)
        self.data.eq_active[:] = 0
        q = home_posture()
        for name, value in q.items():
            self.data.qpos[self._qadr[name]] = value
        self.set_targets(q)
        mujoco.mj_forward(self.model, self.data)
        self.step(int(settle_s / self.model.opt.timestep))
        self.data.time = 0.0

    def step(self, n: int = 1) -> None:
        mujoco.mj_step(self.model, self.data, nstep=max(n, 1))

    def set_targets(self, q: Mapping[str, float]) -> None:
        """Position-actuator targets for the named joints (rad or m)."""
        for name, value in q.items():
            self.data.ctrl[self._actuator[name]] = value

    def actuator_indices(self, joints: tuple[str, ...]) -> np.ndarray:
        """Indices into ``data.ctrl`` of the actuators of ``joints`` (for :meth:`set_ctrl`)."""
        return np.array([self._actuator[n] for n in joints])

    def set_ctrl(self, indices: np.ndarray, values: np.ndarray) -> None:
        """Position-actuator targets by index (the fast path of the control loop)."""
        self.data.ctrl[indices] = values

    def joint_positions(self) -> dict[str, float]:
        """Every robot joint's position now (rad, m), fingers included."""
        return {n: float(self.data.qpos[a]) for n, a in self._qadr.items()}

    def joint_velocity(self, name: str) -> float:
        return float(self.data.qvel[self.model.jnt_dofadr[self.model.joint(name).id]])

    # --- poses -------------------------------------------------------------------------------
    def body_pose(self, name: str) -> np.ndarray:
        return pose_of(self.data, self.model.body(name).id)

    def frame_pose(self, name: str) -> np.ndarray:
        """Pose of a robot frame (a body of the URDF such as ``grasp_r``)."""
        return self.body_pose(name)

    # --- relations ---------------------------------------------------------------------------
    def contact_geoms(self) -> np.ndarray:
        """(n, 2) geom ids of every contact now, sleeping bodies included.

        With island sleeping on, MuJoCo skips collisions between resting bodies; the
        contacts are then recomputed once with sleeping off (positions are unchanged)."""
        m, d = self.model, self.data
        if m.opt.enableflags & _SLEEP:
            m.opt.enableflags &= ~_SLEEP
            try:
                mujoco.mj_collision(m, d)
            finally:
                m.opt.enableflags |= _SLEEP
        return np.array(d.contact.geom[: d.ncon]).reshape(-1, 2)

    def contact_pairs(self) -> set[tuple[int, int]]:
        """Pairs of instance indices in contact now (index into :attr:`instances`), and each
        hand with what its grasp holds: the grasp is a weld, which holds the object also
        where the fingers lose their contact with it for a while (a tool leaned over in the
        hand), and an object the weld holds has not been let go of."""
        g = self.contact_geoms()
        pairs: set[tuple[int, int]] = set()
        if len(g):
            a, b = self._geom_instance[g[:, 0]], self._geom_instance[g[:, 1]]
            keep = (a >= 0) & (b >= 0) & (a != b)
            pairs = {(int(min(x, y)), int(max(x, y))) for x, y in zip(a[keep], b[keep], strict=True)}
        for side, obj in self.held.items():
            if obj is not None and self.hand_bodies[side] and obj in self.instances:
                h, o = int(self._body_instance[self.hand_bodies[side][0]]), self.instances.index(obj)
                pairs.add((min(h, o), max(h, o)))
        return pairs - self._ignored

    def relations(self) -> WorldState:
        """The touching relations among the tracked instances, now."""
        names = self.instances
        return WorldState.of(names, [(names[i], names[j]) for i, j in self.contact_pairs()])

    def touching(self, a: str, b: str) -> bool:
        return self.relations().touches(a, b)

    def gap_m(self, a: str, b: str, most_m: float = 0.05) -> float:
        """The simulation's distance between instances ``a`` and ``b``: the least over their
        colliding shapes (negative: pressed into each other), ``most_m`` when farther. Exact
        where a bounding box is not: a lid held 6° tilted has its box's corner 2 mm below its
        rim, and a lid judged pressed on a bottle by its box hung 0.2 mm above it."""
        m, d, ft = self.model, self.data, np.zeros(6)
        mine = [self._collides(self.instances.index(n)) for n in (a, b)]
        return min((mujoco.mj_geomDistance(m, d, g, h, most_m, ft) for g in mine[0] for h in mine[1]),
                   default=most_m)

    def _collides(self, instance: int) -> list[int]:
        m = self.model
        return [int(g) for g in np.flatnonzero(self._geom_instance == instance)
                if m.geom_contype[g] or m.geom_conaffinity[g]]

    def supported(self, obj: str) -> bool:
        """True when ``obj`` touches something that can bear it: another object or the
        environment (the table), not the robot (a hand holding it) nor a liquid's balls."""
        g = self.contact_geoms()
        if len(g) == 0:
            return False
        own = self.instances.index(obj)
        inst = self._geom_instance[g]
        for mine, other in ((0, 1), (1, 0)):
            if np.any((inst[:, mine] == own) & (inst[:, other] != own) & self._bears[g[:, other]]):
                return True
        return False

    def fingers_touch(self, side: str, obj: str) -> bool:
        """True when the finger plate or the thumb (not just the palm) touches ``obj``."""
        return bool(self.hand_parts_touching(side, obj) - {"palm"})

    def hand_parts_touching(self, side: str, obj: str) -> set[str]:
        """Which parts of hand ``side`` touch ``obj`` now: ``palm``, ``fingers`` (the finger
        plate), ``thumb``."""
        target = self.instances.index(obj)
        parts: set[str] = set()
        for g1, g2 in self.contact_geoms():
            b1, b2 = int(self.model.geom_bodyid[g1]), int(self.model.geom_bodyid[g2])
            for mine, other in ((b1, b2), (b2, b1)):
                if mine in self.hand_bodies[side] and self._body_instance[other] == target:
                    name = self.model.body(mine).name
                    parts.add(
                        "thumb"
                        if name.startswith("thumb_")
                        else "fingers"
                        if name.startswith("fingers_")
                        else "palm"
                    )
        return parts

    # --- liquids -----------------------------------------------------------------------------
    def ball_positions(self, liquid: str) -> np.ndarray:
        """(k, 3) world positions of the balls of ``liquid``."""
        return np.array(self.data.xpos[self._ball_ids[liquid]])

    def balls_inside(self, container: str, liquid: str | None = None) -> int:
        """Balls (of ``liquid``, or of every liquid) inside ``container``'s shell now."""
        shape = self.layout.bodies[container]
        t = self.body_pose(container)
        liquids = [liquid] if liquid is not None else sorted(self._ball_ids)
        count = 0
        for liq in liquids:
            local = (self.ball_positions(liq) - t[:3, 3]) @ t[:3, :3]
            radial = np.hypot(local[:, 0], local[:, 1])
            inside = (
                (radial < shape.inner_radius + 0.002)
                & (local[:, 2] > -0.005)
                & (local[:, 2] < shape.height + 0.03)
            )
            count += int(inside.sum())
        return count

    @property
    def balls_total(self) -> int:
        return int(sum(len(v) for v in self._ball_ids.values()))

    # --- grasping ----------------------------------------------------------------------------
    def weld(self, side: str, obj: str) -> None:
        """Hold ``obj`` rigidly in hand ``side`` at their current relative pose."""
        eq = self._weld_ids[(side, obj)]
        h, o = self.model.body(f"hand_{side}").id, self.model.body(obj).id
        t_ho = np.linalg.inv(pose_of(self.data, h)) @ pose_of(self.data, o)
        quat = np.zeros(4)
        mujoco.mju_mat2Quat(quat, t_ho[:3, :3].flatten())
        # weld data: anchor (3), relative pose of body2 (object) in body1 (hand): pos 3, quat 4; torquescale
        self.model.eq_data[eq, 0:3] = 0.0
        self.model.eq_data[eq, 3:6] = t_ho[:3, 3]
        self.model.eq_data[eq, 6:10] = quat
        self.model.eq_data[eq, 10] = 1.0
        self.data.eq_active[eq] = 1
        self.held[side] = obj

    def release(self, side: str) -> None:
        obj = self.held[side]
        if obj is not None:
            self.data.eq_active[self._weld_ids[(side, obj)]] = 0
        self.held[side] = None

    def wrist_force(self, side: str) -> np.ndarray:
        """Force (N) of the wrist F/T sensor ``side``, in world axes."""
        site, force, _ = self._ft[side]
        return self.data.site_xmat[site].reshape(3, 3) @ self.data.sensordata[force : force + 3]

    def wrist_wrench(self, side: str) -> tuple[np.ndarray, np.ndarray]:
        """Force (N) and torque (N·m) of the wrist F/T sensor ``side``, in world axes."""
        site, force, torque = self._ft[side]
        r = self.data.site_xmat[site].reshape(3, 3)
        return r @ self.data.sensordata[force : force + 3], r @ self.data.sensordata[torque : torque + 3]

    # --- markers and diagnostics -------------------------------------------------------------
    def marker_points(self) -> dict[str, np.ndarray]:
        """Instance → (k, 3) world points of its virtual markers (hands, objects, balls)."""
        out: dict[str, np.ndarray] = {}
        for inst, side in self.layout.hands.items():
            t = self.body_pose(f"hand_{side}")
            out[inst] = (t[:3, :3] @ np.array(_HAND_MARKERS).T).T + t[:3, 3]
        for p in self.layout.placements:
            t = self.body_pose(p.name)
            out[p.name] = (t[:3, :3] @ np.array(p.body.markers).T).T + t[:3, 3]
        for liq in self._ball_ids:
            out[liq] = self.ball_positions(liq)
        return out

    def warnings(self) -> dict[str, int]:
        """MuJoCo warnings raised so far (name → count), only those that occurred."""
        out = {}
        for i in range(len(self.data.warning)):
            if self.data.warning[i].number:
                out[mujoco.mjtWarning(i).name] = int(self.data.warning[i].number)
        return out
