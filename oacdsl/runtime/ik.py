"""Whole-body inverse kinematics with placo: planar base, torso and both arms.

One :class:`WholeBodyIK` holds a placo robot (the generated URDF) and a kinematics
solver with: joint limits (the base restricted to a small area in front of the
table, see :data:`BASE_LIMITS`), velocity limits, a posture task that pulls towards
the home posture (weak; keeps the base still unless the arms need it), soft frame
tasks for the hands (a hand target out of reach is approached as closely as possible
instead of making the QP infeasible), and self-collision avoidance for the link pairs
of :data:`~oacdsl.runtime.urdf.SELF_COLLISION_PAIRS`. The head and the fingers are
masked: fingers are driven directly, the head keeps still.

A solve that fails (placo's ``QPError``) raises :class:`IKError` carrying the target,
frame and last residual; the skills turn it into a :class:`~oacdsl.errors.RuntimeFailure`.
"""

from __future__ import annotations

import itertools
from collections.abc import Iterator, Mapping, Sequence
from contextlib import contextmanager
from dataclasses import dataclass

import numpy as np
import placo

from oacdsl.errors import RuntimeFailure
from oacdsl.runtime.armar3 import ARM_JOINTS, BASE_JOINTS, HEAD_JOINTS, TORSO_JOINTS
from oacdsl.runtime.build import home_posture
from oacdsl.runtime.hands import finger_joint_names
from oacdsl.runtime.urdf import URDF_PATH

__all__ = [
    "WholeBodyIK", "IKError", "BASE_LIMITS", "POSTURE_WEIGHTS", "Residual", "rotation_angle",
    "ANGLE_M_PER_RAD",
]

#: Limits of the planar base in the IK (m, m, rad): the platform may shift a little
#: but never drive into the table whose front edge is 5 cm beyond the platform at x = 0.
BASE_LIMITS: dict[str, tuple[float, float]] = {
    "base_x": (-0.15, 0.03),
    "base_y": (-0.25, 0.25),
    "base_yaw": (-0.6, 0.6),
}


#: Joint speed limits in the IK (rad/s, m/s): slow enough that the arm never whips the
#: hand around (the wrist sensor would feel its own inertia), fast enough for the skills.
VELOCITY_LIMITS: tuple[tuple[tuple[str, ...], float], ...] = (
    (("base_x", "base_y"), 0.3),
    (("base_yaw",), 0.6),
    (TORSO_JOINTS, 0.8),
    ((*ARM_JOINTS["r"], *ARM_JOINTS["l"]), 1.5),
)

#: Weights of the posture tasks relative to a hand task (1.0 per metre of position error).
POSTURE_WEIGHTS: dict[str, float] = {"base": 3e-3, "torso": 3e-3, "arms": 3e-4}


class IKError(RuntimeFailure):
    """The IK problem could not be solved (infeasible QP or target out of reach)."""

    def __init__(
        self,
        message: str,
        *,
        frame: str = "",
        target: np.ndarray | None = None,
        residual_m: float = float("nan"),
    ) -> None:
        super().__init__(message)
        self.frame, self.target, self.residual_m = frame, target, residual_m


#: How much an angle counts in a reach's miss, m per rad.
ANGLE_M_PER_RAD = 0.1


@dataclass(frozen=True)
class Residual:
    """How far a hand frame is from its target: position (m) and angle (rad)."""

    position_m: float
    angle_rad: float

    @property
    def miss_m(self) -> float:
        """One figure of how far off: the position's miss, the angle's counted
        :data:`ANGLE_M_PER_RAD` m per rad."""
        return self.position_m + ANGLE_M_PER_RAD * self.angle_rad


def rotation_angle(r: np.ndarray) -> float:
    """Angle (rad) of a rotation matrix."""
    return float(np.arccos(np.clip((np.trace(r) - 1.0) / 2.0, -1.0, 1.0)))


class WholeBodyIK:
    """placo whole-body IK for ARMAR-III (see the module docstring)."""

    def __init__(self, *, self_collision: bool = True, dt: float = 0.02) -> None:
        flags = 0 if self_collision else placo.Flags.ignore_collisions
        self.robot = placo.RobotWrapper(str(URDF_PATH), flags)
        #: The joints the IK drives, in the order of :meth:`step`'s result.
        self.controlled: tuple[str, ...] = (*BASE_JOINTS, *TORSO_JOINTS, *ARM_JOINTS["r"], *ARM_JOINTS["l"])
        self._offsets = np.array([self.robot.get_joint_offset(n) for n in self.controlled])
        for name, (lo, hi) in BASE_LIMITS.items():
            self.robot.set_joint_limits(name, lo, hi)
        for names, limit in VELOCITY_LIMITS:
            for name in names:
                self.robot.set_velocity_limit(name, limit)
        self.solver = placo.KinematicsSolver(self.robot)
        self.solver.mask_fbase(True)
        self.solver.enable_joint_limits(True)
        self.solver.enable_velocity_limits(True)
        self.solver.dt = dt
        for name in (*HEAD_JOINTS, *finger_joint_names("r").values(), *finger_joint_names("l").values()):
            self.solver.mask_dof(name)
        home = home_posture()
        # posture: the base and the torso are stiffer than the arms, so that the arms do the
        # reaching and the platform moves only when the arms alone cannot get there
        self.posture: list[placo.JointsTask] = []
        for label, names, weight in (
            ("base", BASE_JOINTS, POSTURE_WEIGHTS["base"]),
            ("torso", TORSO_JOINTS, POSTURE_WEIGHTS["torso"]),
            ("arms", (*ARM_JOINTS["r"], *ARM_JOINTS["l"]), POSTURE_WEIGHTS["arms"]),
        ):
            task = self.solver.add_joints_task()
            task.set_joints({n: home.get(n, 0.0) for n in names})
            task.configure(f"posture_{label}", "soft", weight)
            self.posture.append(task)
        self.solver.add_regularization_task(1e-3)
        if self_collision:
            c = self.solver.add_avoid_self_collisions_constraint()
            c.self_collisions_margin = 0.01  # m
            c.self_collisions_trigger = 0.04  # m
            c.configure("self_collisions", "hard", 1.0)
        self.hand_tasks: dict[str, placo.FrameTask] = {}
        for side in ("r", "l"):
            task = self.solver.add_frame_task(f"grasp_{side}", np.eye(4))
            task.configure(f"hand_{side}", "soft", 1.0, 0.3)
            self.hand_tasks[side] = task
        self.active: dict[str, bool] = {"r": False, "l": False}
        self.set_state(home)
        for side in ("r", "l"):
            self.hold_hand(side)

    # --- state ---------------------------------------------------------------------------------
    def set_state(self, q: Mapping[str, float]) -> None:
        for name, value in q.items():
            self.robot.set_joint(name, float(value))
        self.robot.update_kinematics()

    def joints(self, names: tuple[str, ...] | None = None) -> dict[str, float]:
        """Joint positions (rad, m) of ``names`` (default: :attr:`controlled`)."""
        if names is None:
            q = self.robot.state.q[self._offsets]
            return dict(zip(self.controlled, q.tolist(), strict=True))
        return {n: float(self.robot.get_joint(n)) for n in names}

    def controlled_positions(self) -> np.ndarray:
        """Positions of :attr:`controlled` joints, in that order (a copy)."""
        return np.array(self.robot.state.q[self._offsets])

    def frame(self, name: str) -> np.ndarray:
        """T_world_frame of a robot frame in the IK model."""
        return np.array(self.robot.get_T_world_frame(name))

    # --- targets -------------------------------------------------------------------------------
    def set_hand_target(
        self,
        side: str,
        t_world_target: np.ndarray,
        *,
        position_weight: float = 1.0,
        orientation_weight: float = 0.3,
    ) -> None:
        """Make hand ``side``'s grasp frame track ``t_world_target`` (soft task)."""
        task = self.hand_tasks[side]
        task.T_world_frame = t_world_target
        task.configure(f"hand_{side}", "soft", position_weight, orientation_weight)
        self.active[side] = True

    def hold_hand(self, side: str, weight: float = 0.2) -> None:
        """Keep hand ``side`` where it is now (a weaker task, for the idle hand)."""
        task = self.hand_tasks[side]
        task.T_world_frame = self.frame(f"grasp_{side}")
        task.configure(f"hand_{side}", "soft", weight, weight)
        self.active[side] = False

    def target(self, side: str) -> np.ndarray:
        return np.array(self.hand_tasks[side].T_world_frame)

    def goal(self, side: str) -> np.ndarray:
        """T_world_grasp hand ``side`` is commanded to: its target while a skill drives it
        (:meth:`set_hand_target`), else where the IK model has it now (an idle hand)."""
        return self.target(side) if self.active[side] else self.frame(f"grasp_{side}")

    def residual(self, side: str) -> Residual:
        t = self.frame(f"grasp_{side}")
        goal = self.target(side)
        return Residual(
            float(np.linalg.norm(goal[:3, 3] - t[:3, 3])), rotation_angle(goal[:3, :3].T @ t[:3, :3])
        )

    # --- solving -------------------------------------------------------------------------------
    def step(self) -> np.ndarray:
        """One QP solve and integration (one control tick); returns the targets of the
        :attr:`controlled` joints."""
        try:
            self.solver.solve(True)
        except RuntimeError as error:  # placo raises QPError, a RuntimeError subclass
            side = "r" if self.active["r"] else "l"
            res = self.residual(side)
            raise IKError(
                f"whole-body IK failed: {self._no_solution()} ({error})",
                frame=f"grasp_{side}",
                target=self.target(side),
                residual_m=res.position_m,
            ) from None
        self.robot.update_kinematics()
        return self.controlled_positions()

    def _no_solution(self) -> str:
        """What an infeasible solve means, in words: the hands driven, each one's distance from
        its target, and what a library author may change."""
        driven = [s for s in ("l", "r") if self.active[s]] or ["r"]
        hands = " and ".join(f"the {'left' if s == 'l' else 'right'} hand"
                             f" ({self.residual(s).position_m * 100:.1f} cm from its target)" for s in driven)
        return (f"no motion within the joint limits moves {hands} on: a target out of reach or a"
                " turn the wrist cannot make (another grasp offset or approach may help)")

    def converge(self, iterations: int = 200, tolerance_m: float = 1e-4) -> Residual:
        """Solve repeatedly towards the current targets (a static solve); the final residual
        of the active hand (or of the right hand when none is active)."""
        side = "l" if self.active["l"] and not self.active["r"] else "r"
        last = self.residual(side)
        for _ in range(iterations):
            self.step()
            res = self.residual(side)
            if res.position_m < tolerance_m or abs(last.position_m - res.position_m) < 1e-7:
                return res
            last = res
        return last

    def snapshot(self) -> np.ndarray:
        return np.array(self.robot.state.q, copy=True)

    def restore(self, q: np.ndarray) -> None:
        self.robot.state.q = q
        self.robot.update_kinematics()

    def try_reach(
        self, side: str, t_world_target: np.ndarray, iterations: int = 150, *, arm_only: bool = False
    ) -> Residual:
        """Static solve towards a target without moving the robot: the residual the hand
        would keep there (the IK state and targets are restored afterwards). ``arm_only``:
        with the platform and the torso held where they are (the arm's own workspace)."""
        still = (*BASE_JOINTS, *TORSO_JOINTS) if arm_only else ()
        with self.trial():
            for name in still:
                self.solver.mask_dof(name)
            try:
                other = "l" if side == "r" else "r"
                self.hold_hand(other, weight=0.05)
                self.set_hand_target(side, t_world_target)
                return self.converge(iterations, tolerance_m=5e-4)
            finally:
                for name in still:
                    self.solver.unmask_dof(name)

    def reach_postures(
        self, side: str, targets: Sequence[np.ndarray], iterations: int | Sequence[int] = 150
    ) -> list[tuple[Residual, dict[str, float]]]:
        """Solves towards each of ``targets`` (T_world_grasp) in turn, each from the last one's
        posture (a path through them), without moving the robot: the residual and the posture
        (:meth:`joints`) at each. ``iterations``: solver steps per target, or one count for
        each (a motion's control ticks per target: how far the IK keeps up with it at its pace)."""
        counts = [iterations] * len(targets) if isinstance(iterations, int) else list(iterations)
        out = []
        with self.trial():
            self.hold_hand("l" if side == "r" else "r", weight=0.05)
            for target, n in zip(targets, counts, strict=True):
                self.set_hand_target(side, target)
                out.append((self.converge(n, tolerance_m=5e-4), self.joints()))
        return out

    def try_reach_both(self, targets: Mapping[str, np.ndarray], iterations: int = 150) -> float:
        """Static solve with each hand of ``targets`` (side → T_world_grasp) at its target, without
        moving the robot: the larger residual (m, angle weighted 0.1 m/rad)."""
        with self.trial():
            for s, t in targets.items():
                self.set_hand_target(s, t)
            for _ in range(iterations):
                self.step()
            return max(self.residual(s).miss_m for s in targets)

    def travel_s(self, postures: Sequence[Mapping[str, float]]) -> float:
        """The least time (s) in which the joints go through ``postures`` (:meth:`joints`) one
        after the other at their speed limits (:data:`VELOCITY_LIMITS`), at constant speed."""
        limit = {n: v for names, v in VELOCITY_LIMITS for n in names}
        worst = 0.0
        for a, b in itertools.pairwise(postures):
            worst += max((abs(b[n] - a[n]) / limit[n] for n in a if n in limit and n in b), default=0.0)
        return worst

    @contextmanager
    def trial(self) -> Iterator[None]:
        """A block that may move the IK state and the hands' targets: both are restored
        afterwards (a static solve that does not move the robot)."""
        q = self.snapshot()
        saved = {s: (self.target(s), self.active[s]) for s in ("r", "l")}
        try:
            yield
        finally:
            self.restore(q)
            for s, (target, active) in saved.items():
                if active:
                    self.set_hand_target(s, target)
                else:
                    self.hand_tasks[s].T_world_frame = target
                    self.hand_tasks[s].configure(f"hand_{s}", "soft", 0.2, 0.2)
                    self.active[s] = False
