"""The moves the dough stories are written with: grasp a cup, pour from it, set it down, hand it over.

A :class:`Stage` holds one rigid-body :class:`~oacdsl.segmentation.synth.kinematics.Track`
per instance on a shared time grid, the hands' closure ramps, and the scripted sub-actions.
Each move writes the tracks it drives from their last filled frame on; what a story does
with the other tracks meanwhile (hold them, start the other hand early) is the story's.
Durations come from ``dur(seconds)``: the story's seeded variation (±10 %).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from oacdsl.segmentation.synth.kinematics import Track, min_jerk, rot_x, rot_y
from oacdsl.segmentation.synth.scene import BODIES, CUP_LIP_M, HAND_IFD_CLOSE_M, TABLE_Z_M

__all__ = [
    "BOWL_AT_M",
    "GRAVITY_M_S2",
    "R_REST",
    "REST_M",
    "UP_M",
    "Stage",
    "Step",
    "approach",
    "retreat",
]

#: Gravitational acceleration, m/s².
GRAVITY_M_S2 = 9.81

BOWL_AT_M = np.array([0.0, 0.06, TABLE_Z_M])
REST_M = {
    "left_hand": np.array([-0.45, -0.42, TABLE_Z_M + 0.03]),
    "right_hand": np.array([0.45, -0.42, TABLE_Z_M + 0.03]),
}
#: Palm down on the table: back of the hand up, fingers forward.
R_REST = np.array([[0.0, 0.0, -1.0], [0.0, 1.0, 0.0], [1.0, 0.0, 0.0]])
#: Where each liquid comes to rest in the bowl, bowl frame (radius 9 cm from the axis), metres.
_LANDING_M = {
    "liquid_one": np.array([-0.0846, 0.0308, 0.025]),
    "liquid_two": np.array([0.0846, -0.0308, 0.025]),
}
_POUR_TILT_RAD = np.deg2rad(110.0)
#: Flights longer than this are a slow stream (straight, steady speed), not a parabola, seconds.
_BALLISTIC_MAX_S = 0.3
_SETTLE_S = 0.015  # time constant of the short roll after landing, seconds
_SETTLE_ROLL_M = 0.005
#: Motions that end in a contact (or leave one) are cut minimum-jerk profiles: they stop
#: (start) at 80 % of the profile, still moving at about 40 % of the peak speed.
CONTACT_TAU = 0.8
#: Reaches finish turning the hand at this fraction of their duration and then only translate.
TURN = 0.7
_DROP_M = 0.005  # the red cup is let go this high above the table, metres
_RESTITUTION = 0.3
UP_M = np.array([0.0, 0.0, 0.12])  # carried objects arc this much above the straight line


@dataclass(frozen=True)
class Step:
    """One scripted sub-action: the OAC it demonstrates, its arguments, and when it happens (s)."""

    oac: str
    args: tuple[str, ...]
    time_s: float
    added: tuple[tuple[str, str], ...]
    removed: tuple[tuple[str, str], ...]


class Stage:
    """Tracks of every instance of the dough scene plus what the story scripted so far."""

    def __init__(
        self,
        times_s: np.ndarray,
        places_m: dict[str, tuple[np.ndarray, np.ndarray | None]],
        contents: dict[str, str],
        dur: Callable[[float], float],
        flight_s: float,
    ) -> None:
        self.times_s = times_s
        self.tracks = {name: Track(name, times_s, p, r) for name, (p, r) in places_m.items()}
        #: container → the liquid in it (a liquid follows its container while it is in it)
        self.contents = dict(contents)
        self.dur = dur
        self.flight_s = flight_s
        self.grips: dict[str, list[tuple[float, float, float]]] = {"left_hand": [], "right_hand": []}
        self.steps: list[Step] = []
        self.marks: dict[str, float] = {}

    def __getitem__(self, name: str) -> Track:
        return self.tracks[name]

    def sync(self, t_s: float) -> None:
        """Hold every track that ends before ``t_s`` (seconds) until then."""
        for tr in self.tracks.values():
            if tr.cursor - 1 < tr.frame(t_s):
                tr.hold(t_s)

    def latest_s(self) -> float:
        """The last filled time of any track, seconds."""
        return max(tr.now_s for tr in self.tracks.values())

    # -- hands and cups (each move starts at ``t_s`` and returns when it ends, seconds) -----
    def grasp(
        self,
        t_s: float,
        h: str,
        obj: str,
        grasp_m: np.ndarray,
        r_obj_hand: np.ndarray,
        side: float,
        via_m: np.ndarray | None = None,
        reach_s: float = 1.2,
    ) -> float:
        """Reach ``obj``'s point ``grasp_m`` (its frame, m) in about ``reach_s`` (s), arriving from
        ``side`` (or through the control points ``via_m``, m from the grasp point), and close the hand."""
        hd, ob = self.tracks[h], self.tracks[obj]
        if hd.cursor - 1 < hd.frame(t_s):  # the hand waits at rest until the reach starts
            hd.hold(t_s)
        t_reach = t_s + self.dur(reach_s)
        p, r = ob.last_pose
        target = (p + r @ grasp_m, r @ r_obj_hand)
        via = target[0] + (approach(side) if via_m is None else via_m)
        hd.move(t_reach, *target, via_m=via, end_tau=CONTACT_TAU, turn_until=TURN)
        self.steps.append(Step("grasp", (h, obj), t_reach, ((h, obj),), ()))
        self.marks.setdefault(f"grasp_{obj}", t_reach)
        t_closed = t_reach + self.dur(0.35)
        self.grips[h].append((t_reach, t_closed, 1.0))
        hd.hold(t_closed)
        ob.hold(t_closed)
        if obj in self.contents:
            self.tracks[self.contents[obj]].follow(ob, t_closed)
        return t_closed

    def carry(self, t_s: float, h: str, cup: str, to_m: np.ndarray, seconds: float) -> float:
        """Carry ``cup`` in an arc, upright, until its origin is at ``to_m`` (world, m)."""
        ob = self.tracks[cup]
        t1 = t_s + self.dur(seconds)
        p0, rot = ob.last_pose
        ob.move(t1, to_m, rot, via_m=0.5 * (p0 + to_m) + UP_M)
        self.tracks[h].follow(ob, t1)
        if cup in self.contents:
            self.tracks[self.contents[cup]].follow(ob, t1)
        return t1

    def pour(
        self, t_s: float, h: str, cup: str, side: float, yaw: np.ndarray, lip_m: np.ndarray = CUP_LIP_M
    ) -> float:
        """Carry ``cup`` beside the bowl (``side`` −1 left, +1 right), pour its liquid, tilt back.

        ``yaw``: the cup's heading while pouring; ``lip_m`` (cup frame, m): the lip it pours
        over, about which it turns towards the bowl.
        """
        ob = self.tracks[cup]
        liquid = self.contents.pop(cup)
        liq = self.tracks[liquid]
        # lift and carry in an arc to beside the bowl: upright, lip 27 cm above the table, 14 cm off the axis
        t_carry = t_s + self.dur(1.3)
        pre_lip = BOWL_AT_M + np.array([side * 0.14, -0.01, 0.27])
        home, home_rot = ob.last_pose
        lip0 = home + home_rot @ lip_m
        ob.move(t_carry, pre_lip, yaw, pivot_m=lip_m, via_m=0.5 * (lip0 + pre_lip) + UP_M)
        # tilt about the lip while moving it over the bowl; the liquid leaves at 80 % of the tilt
        t_tilt = t_carry + self.dur(1.2)
        pour_lip = BOWL_AT_M + np.array([side * 0.075, side * -0.02, 0.21])
        tilt = _tilt_towards(lip_m)
        ob.move(t_tilt, pour_lip, yaw @ tilt, pivot_m=lip_m)
        t_release = t_carry + 0.8 * (t_tilt - t_carry)
        t_hold = t_tilt + self.dur(0.6)
        ob.hold(t_hold)
        self.tracks[h].follow(ob, t_hold)
        liq.follow(ob, t_release)
        t_land = self._fly(liquid)
        self.steps.append(
            Step(
                "pour", (h, cup, liquid, "orange_bowl"), t_land, ((liquid, "orange_bowl"),), ((liquid, cup),)
            )
        )
        self.marks[f"pour_{liquid}"] = t_land
        # tilt back over the bowl
        t_back = t_hold + self.dur(1.0)
        ob.move(t_back, pre_lip, yaw, pivot_m=lip_m)
        return t_back

    def _fly(self, liquid: str) -> float:
        """The liquid's flight from where it left its cup into the bowl; returns the landing time."""
        liq, flight_s = self.tracks[liquid], self.flight_s
        p0 = liq.position_m[liq.cursor - 1].copy()
        landing = BOWL_AT_M + _LANDING_M[liquid]
        t_land = liq.now_s + flight_s
        t_rel0 = liq.now_s
        if flight_s <= _BALLISTIC_MAX_S:
            g = np.array([0.0, 0.0, -GRAVITY_M_S2])
            v0 = (landing - p0 - 0.5 * g * flight_s**2) / flight_s
            liq.path(
                t_land, lambda ts: p0 + np.outer(ts - t_rel0, v0) + 0.5 * np.outer((ts - t_rel0) ** 2, g)
            )
        else:
            liq.path(t_land, lambda ts: p0 + np.outer((ts - t_rel0) / flight_s, landing - p0))
        roll = np.array([_LANDING_M[liquid][0], _LANDING_M[liquid][1], 0.0])
        roll = _SETTLE_ROLL_M * roll / float(np.linalg.norm(roll))  # rolls a little towards the wall
        t_land0 = liq.now_s
        liq.path(t_land + 0.3, lambda ts: landing + np.outer(1.0 - np.exp(-(ts - t_land0) / _SETTLE_S), roll))
        return t_land

    def set_down(
        self,
        t_s: float,
        h: str,
        cup: str,
        at_m: np.ndarray,
        rot: np.ndarray,
        side: float,
        bounce: bool = False,
    ) -> float:
        """Carry ``cup`` to ``at_m`` (world, m; rotation ``rot``), let go and bring the hand home.

        ``bounce``: let go 5 mm up; the cup bounces and the hand flinches back (three raw
        changes within the merge window).
        """
        hd, ob = self.tracks[h], self.tracks[cup]
        t_home = t_s + self.dur(1.3)
        above = at_m + np.array([0.0, 0.0, _DROP_M if bounce else 0.0])
        ob.move(
            t_home,
            above,
            rot,
            via_m=0.5 * (ob.last_pose[0] + above) + UP_M,
            end_tau=1.0 if bounce else CONTACT_TAU,
        )
        hd.follow(ob, t_home)
        if bounce:
            # let go: the cup drops the last few mm and bounces; the hand flinches back 5 cm,
            # hovers (touching again by the rule) and then leaves: three changes, each within
            # 0.3 s of the next, each lasting longer than the rule's n frames (0.1 s)
            t_let = t_home + 0.03
            ob.hold(t_let)
            hd.hold(t_let)
            ob.path(t_let + 0.3, lambda ts: at_m + np.outer(_bounce_height(ts - t_let), [0.0, 0.0, 1.0]))
            self.grips[h].append((t_let - 0.02, t_let + 0.1, 0.0))
            hd.hold(t_let + 0.03)
            p_hand, r_hand = hd.last_pose
            hd.move(t_let + 0.15, p_hand + 0.05 * r_hand[:, 0], r_hand, start_tau=0.2, end_tau=0.8)
            t_leave = t_let + 0.38
            self.marks["bounce"] = t_let
        else:
            t_leave = t_home + self.dur(0.3)
            self.grips[h].append((t_home, t_leave, 0.0))
        return self._leave(t_leave, h, cup, side)

    def release(self, t_s: float, h: str, obj: str, side: float, holder: str) -> float:
        """Open ``h`` on ``obj``, which ``holder`` holds still meanwhile (the end of a hand-over),
        and bring ``h`` home; returns when ``h`` is open (the other hand may carry on)."""
        t_open = t_s + self.dur(0.3)
        self.tracks[h].hold(t_s)
        self.grips[h].append((t_s, t_open, 0.0))
        self.tracks[obj].hold(t_open)
        self.tracks[holder].hold(t_open)
        self._leave(t_open, h, obj, side)
        return t_open

    def _leave(self, t_leave_s: float, h: str, obj: str, side: float) -> float:
        hd = self.tracks[h]
        hd.hold(t_leave_s)
        t_away = t_leave_s + self.dur(1.0)
        out = hd.last_pose[0] + retreat(side)  # straight out along the handle, then home
        hd.move(
            t_away, REST_M[h], R_REST, via_m=np.array([out, REST_M[h] + UP_M]), start_tau=1.0 - CONTACT_TAU
        )
        self.steps.append(Step("place", (h, obj), t_leave_s, (), ((h, obj),)))
        self.marks.setdefault(f"place_{obj}", t_leave_s)
        return t_away

    def markers(self, n: int) -> dict[str, np.ndarray]:
        """(n, k, 3) world marker positions per instance, the hands' closure applied."""
        out: dict[str, np.ndarray] = {}
        for name, tr in self.tracks.items():
            tr.finish()
            pts = tr.world_points(BODIES[name].local_m)
            if name in self.grips:
                closure = _grip_ramp(self.times_s, self.grips[name])
                pts[:, 2] += closure[:, None] * np.einsum("fij,j->fi", tr.rotation, HAND_IFD_CLOSE_M)
            out[name] = pts[:n]
        return out


def approach(side: float) -> np.ndarray:
    """Offset (m) from a cup's handle to the control point of a reach: far out along the handle axis.

    The hand then arrives almost straight along the handle, so every hand–cup marker pair
    closes in fast until the hand stops at the handle (no pair slides past sideways).
    """
    return np.array([side * 0.35, -0.10, -0.02])


def retreat(side: float) -> np.ndarray:
    """Offset (m) from the handle to where a hand letting go heads first: straight out and up."""
    return np.array([side * 0.30, -0.07, 0.06])


def _tilt_towards(lip_m: np.ndarray) -> np.ndarray:
    """The cup-frame rotation that turns the cup's top towards its lip ``lip_m`` (on its x or y axis)."""
    if lip_m[1] == 0.0:
        return rot_y(float(np.sign(lip_m[0])) * _POUR_TILT_RAD)
    return rot_x(-float(np.sign(lip_m[1])) * _POUR_TILT_RAD)


def _grip_ramp(times_s: np.ndarray, events: list[tuple[float, float, float]]) -> np.ndarray:
    """Hand closure 0 (open) … 1 (closed) over time from (start s, end s, target) ramps."""
    out = np.zeros_like(times_s)
    level = 0.0
    for t0, t1, target in events:
        s = min_jerk((times_s - t0) / (t1 - t0))
        out = np.where(times_s >= t0, level + s * (target - level), out)
        level = target
    return out


def _bounce_height(t_s: np.ndarray) -> np.ndarray:
    """Height (m) of a cup let go at t = 0 from :data:`_DROP_M`: fall, two bounces, rest."""
    t = np.asarray(t_s, dtype=float)
    out = np.zeros_like(t)
    v_impact = np.sqrt(2.0 * GRAVITY_M_S2 * _DROP_M)
    t_fall = v_impact / GRAVITY_M_S2
    falling = t < t_fall
    out[falling] = _DROP_M - 0.5 * GRAVITY_M_S2 * t[falling] ** 2
    start, v = t_fall, v_impact * _RESTITUTION
    for _ in range(2):
        hop = 2.0 * v / GRAVITY_M_S2
        inside = (t >= start) & (t < start + hop)
        dt = t[inside] - start
        out[inside] = v * dt - 0.5 * GRAVITY_M_S2 * dt**2
        start, v = start + hop, v * _RESTITUTION
    return out
