"""The control loop: placo IK at 100 Hz feeding MuJoCo position actuators.

Each control tick solves the whole-body IK once towards the current hand targets,
sends the joint positions to the actuators, advances the simulation by one tick,
checks the wrist force/torque sensors against the safety limit, and calls the
observers (marker recorder, video) that are due. Motions are min-jerk
interpolations of a hand pose; a *guard* can end a motion early (contact felt).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from typing import Protocol

import numpy as np

from oacdsl.errors import RuntimeFailure
from oacdsl.runtime.hands import CLOSED, OPEN, finger_joint_names
from oacdsl.runtime.ik import WholeBodyIK
from oacdsl.runtime.simworld import SimWorld
from oacdsl.runtime.transforms import interpolate, min_jerk

__all__ = [
    "Controller",
    "Observer",
    "CONTROL_DT_S",
    "FORCE_LIMIT_N",
    "ORIENTATION_WEIGHT",
    "SIDE_NAME",
    "IDLE_HOLD_WEIGHT",
]

#: Control period (s): one IK solve per tick (50 Hz); observers still run at their own rate.
CONTROL_DT_S = 0.02
#: Safety limit on the change of a wrist force since the motion started, N.
FORCE_LIMIT_N = 60.0
#: Weight of the task that keeps the other hand where it is while one hand moves alone.
IDLE_HOLD_WEIGHT = 0.5
SIDE_NAME = {"r": "right", "l": "left"}
#: Weight of a moving hand's orientation task (its position's is 1).
ORIENTATION_WEIGHT = 0.3


class Observer(Protocol):
    """Called with the world every ``1 / rate_hz`` seconds of simulated time."""

    rate_hz: float

    def __call__(self, world: SimWorld) -> None: ...


class Controller:
    """Drives the simulated robot (see the module docstring)."""

    def __init__(
        self,
        world: SimWorld,
        ik: WholeBodyIK,
        observers: list[Observer] | None = None,
        force_limit_n: float = FORCE_LIMIT_N,
    ) -> None:
        self.world, self.ik = world, ik
        self.observers = list(observers or [])
        self._due = [0.0 for _ in self.observers]
        self.force_limit_n = force_limit_n
        self._ctrl = world.actuator_indices(ik.controlled)
        self.substeps = max(1, round(CONTROL_DT_S / world.model.opt.timestep))
        self.ik.solver.dt = self.substeps * world.model.opt.timestep
        self.ik.set_state(world.joint_positions())
        for side in ("r", "l"):
            self.ik.hold_hand(side)
        self._tare = {s: world.wrist_force(s) for s in ("r", "l")}
        #: each wrist's force with its hand empty and still (at the start): its own weight
        self._free = dict(self._tare)
        self.fingers: dict[str, dict[str, float]] = {s: dict(OPEN) for s in ("r", "l")}
        self.activity = "idle"
        #: (let go s, taken again s, hand side, object), simulated time, of every regrasp internal
        #: to a step (a hand that lets go and takes the object again to turn it further): not a
        #: change of the task (the contacts recorder keeps the hand on the object through it)
        self.regrasps: list[tuple[float, float, str, str]] = []
        #: (s, hand side, object), simulated time, of every time a turned object that had left
        #: its seat on the target was set back on (``motion.rotate.reseat``)
        self.reseats: list[tuple[float, str, str]] = []
        self._observe()

    def add_observer(self, observer: Observer) -> None:
        """Call ``observer`` from now on, at its rate."""
        self.observers.append(observer)
        self._due.append(self.world.time_s)
        observer(self.world)
        self._due[-1] += 1.0 / observer.rate_hz

    # --- one tick -------------------------------------------------------------------------------
    def tick(self) -> None:
        self.world.set_ctrl(self._ctrl, self.ik.step())
        if self.observers:  # step to each observer's due time within the tick
            for _ in range(self.substeps):
                self.world.step(1)
                self._observe()
        else:
            self.world.step(self.substeps)
        self._check_force()

    def _observe(self) -> None:
        t = self.world.time_s
        for i, obs in enumerate(self.observers):
            if t + 1e-9 >= self._due[i]:
                obs(self.world)
                self._due[i] = max(self._due[i] + 1.0 / obs.rate_hz, t)

    def tare(self, side: str) -> None:
        """Take the current wrist force of ``side`` as its zero (like a real F/T sensor)."""
        self._tare[side] = self.world.wrist_force(side)

    def force_change(self, side: str) -> np.ndarray:
        """Wrist force of ``side`` minus its tare, world axes, N."""
        return self.world.wrist_force(side) - self._tare[side]

    def _check_force(self) -> None:
        for side in ("r", "l"):
            d = self.force_change(side)
            f = math.sqrt(float(d @ d))
            if f > self.force_limit_n:
                raise RuntimeFailure(
                    f"safety stop while {self.activity}: the {SIDE_NAME[side]} wrist felt {f:.0f} N"
                    f" (limit {self.force_limit_n:.0f} N)"
                )

    def pushed_up_n(self, side: str) -> float:
        """How hard hand ``side`` is pushed up, N, beyond its own weight (its wrist force now
        against the empty, still hand's): what it presses down on pushing back; a held
        object hanging from it counts its weight negative. Meaningful while the arm is still."""
        return -float(self.world.wrist_force(side)[2] - self._free[side][2])

    # --- motions: the one control loop ---------------------------------------------------------
    def drive(
        self,
        paths: Mapping[str, Callable[[float], np.ndarray]],
        duration_s: float,
        guards: Mapping[str, Callable[[], bool]] | None = None,
        *,
        weights: Mapping[str, float] | None = None,
        stop_at_model: bool = False,
    ) -> dict[str, bool]:
        """The control loop every motion runs through: each hand of ``paths`` (side → a
        T_world_grasp for the phase ``s`` in [0, 1], min-jerk timed over ``duration_s``) is
        driven along its path, together, one IK solve per tick. A hand whose guard becomes true
        stops where it is (the simulation's frame; the IK model's with ``stop_at_model``: the
        arm lags its command, a hand waiting for the other would keep pressing); the loop ends
        when the time is over or every guarded hand stopped. ``weights``: a hand's orientation
        weight (0.3 otherwise). A hand not in ``paths`` keeps the controller's idle hold.
        Returns, per side, whether its guard stopped it."""
        guards = dict(guards or {})
        weights = dict(weights or {})
        for s in paths:
            self.tare(s)
        stopped = dict.fromkeys(paths, False)

        def aim(s: str, pose: np.ndarray) -> None:
            if s in weights:
                self.ik.set_hand_target(s, pose, orientation_weight=weights[s])
            else:
                self.ik.set_hand_target(s, pose)

        n = max(1, round(duration_s / CONTROL_DT_S))
        for k in range(1, n + 1):
            for s, path in paths.items():
                if not stopped[s]:
                    aim(s, path(min_jerk(k / n)))
            self.tick()
            for s, guard in guards.items():
                if not stopped[s] and guard():
                    stopped[s] = True
                    aim(
                        s,
                        self.ik.frame(f"grasp_{s}") if stop_at_model else self.world.frame_pose(f"grasp_{s}"),
                    )
            if guards and all(stopped[s] for s in guards):
                break
        return stopped

    def move(
        self,
        side: str,
        goal: np.ndarray,
        duration_s: float,
        guard: Callable[[], bool] | None = None,
        orientation_weight: float | None = None,
    ) -> bool:
        """Move hand ``side``'s grasp frame to ``goal`` in ``duration_s`` (min-jerk); the other
        hand holds still. Returns True when ``guard`` ended the motion early.
        ``orientation_weight``: of the hand's orientation task (None: the IK's default)."""
        start = self.ik.goal(side)
        other = "l" if side == "r" else "r"
        if self.ik.active[other]:
            self.ik.hold_hand(other, weight=IDLE_HOLD_WEIGHT)
        stopped = self.drive(
            {side: lambda s: interpolate(start, goal, s)},
            duration_s,
            {side: guard} if guard is not None else None,
            weights={side: orientation_weight} if orientation_weight is not None else None,
            stop_at_model=True,
        )
        return stopped[side]

    def wait(self, duration_s: float, until: Callable[[], bool] | None = None) -> bool:
        """Keep the targets for ``duration_s``; True when ``until`` became true first."""
        for _ in range(max(1, round(duration_s / CONTROL_DT_S))):
            self.tick()
            if until is not None and until():
                return True
        return False

    def set_fingers(self, side: str, targets: dict[str, float]) -> None:
        self.fingers[side] = dict(targets)
        names = finger_joint_names(side)
        self.world.set_targets({names[k]: v for k, v in targets.items()})
        self.ik.set_state({names[k]: v for k, v in targets.items()})

    def close_hand(
        self,
        side: str,
        duration_s: float = 0.6,
        until: Callable[[], bool] | None = None,
        targets: dict[str, float] | None = None,
    ) -> bool:
        """Close the fingers towards ``targets`` (default: all closed; force-limited actuators
        stop them on the object); True when ``until`` became true before ``duration_s`` was over."""
        self.set_fingers(side, CLOSED if targets is None else targets)
        return self.wait(duration_s, until=until)

    def open_hand(self, side: str, duration_s: float = 0.4) -> None:
        self.set_fingers(side, OPEN)
        self.wait(duration_s)
