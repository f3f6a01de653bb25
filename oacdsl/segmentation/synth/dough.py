"""The paper's dough demonstration as a script of rigid-body motions (noise-free).

Story (Wächter et al. 2013, section IV-B): the left hand grasps the red cup, pours
liquid one into the orange bowl and puts the cup back (it bounces once on the
table); the right hand does the same with the green cup and liquid two; then the
right hand — passing quickly over the green cup on its way — grasps the mixer,
puts it into the bowl and mixes until the recording ends.

:func:`dough_script` returns the noise-free marker trajectories and the scripted
steps. Timing varies a little with the seed (each pause and motion ±10 %), the
geometry not at all: the scene is laid out so that the paper's touching rule
(d = 150 mm) sees exactly the intended relations (see docs/demonstration.md).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from oacdsl.segmentation.synth.kinematics import Track, min_jerk, rot_y, rot_z
from oacdsl.segmentation.synth.scene import (
    BODIES,
    CUP_HANDLE_GRASP_M,
    CUP_LIP_M,
    HAND_IFD_CLOSE_M,
    LIQUID_IN_CUP_M,
    MIXER_HANDLE_GRASP_M,
    TABLE_Z_M,
)

__all__ = ["FLIGHT_S", "GRAVITY_M_S2", "Script", "Step", "dough_script"]

#: Gravitational acceleration, m/s².
GRAVITY_M_S2 = 9.81

_BOWL_AT_M = np.array([0.0, 0.06, TABLE_Z_M])
_RED_CUP_AT_M = np.array([-0.36, -0.02, TABLE_Z_M])
_GREEN_CUP_AT_M = np.array([0.36, -0.02, TABLE_Z_M])
_MIXER_AT_M = np.array([0.25, 0.42, TABLE_Z_M])
_REST_M = {
    "left_hand": np.array([-0.45, -0.42, TABLE_Z_M + 0.03]),
    "right_hand": np.array([0.45, -0.42, TABLE_Z_M + 0.03]),
}
#: Palm down on the table: back of the hand up, fingers forward.
_R_REST = np.array([[0.0, 0.0, -1.0], [0.0, 1.0, 0.0], [1.0, 0.0, 0.0]])
#: Hand frame in the cup frame when holding the handle (back of the hand away from the cup).
_R_CUP_LEFT_HAND = np.array([[-1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, -1.0]])
_R_CUP_RIGHT_HAND = np.array([[-1.0, 0.0, 0.0], [0.0, -1.0, 0.0], [0.0, 0.0, 1.0]])
#: Hand frame in the mixer frame: back of the hand to the right, fingers down round the handle.
_R_MIXER_HAND = np.array([[1.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, -1.0, 0.0]])

#: Where each liquid comes to rest in the bowl, bowl frame (radius 9 cm from the axis), metres.
_LANDING_M = {
    "liquid_one": np.array([-0.0846, 0.0308, 0.025]),
    "liquid_two": np.array([0.0846, -0.0308, 0.025]),
}
_POUR_TILT_RAD = np.deg2rad(110.0)
#: Release to landing of the liquid marker, seconds: a thrown-down parabola.
FLIGHT_S = 0.16
#: Flights longer than this are a slow stream (straight, steady speed), not a parabola, seconds.
_BALLISTIC_MAX_S = 0.3
_SETTLE_S = 0.015  # time constant of the short roll after landing, seconds
_SETTLE_ROLL_M = 0.005
#: Motions that end in a contact (or leave one) are cut minimum-jerk profiles: they stop
#: (start) at 80 % of the profile, still moving at about 40 % of the peak speed.
_CONTACT_TAU = 0.8
#: Reaches finish turning the hand at this fraction of their duration and then only translate.
_TURN = 0.7
_DROP_M = 0.005  # the red cup is let go this high above the table, metres
_RESTITUTION = 0.3
_UP_M = np.array([0.0, 0.0, 0.12])  # carried objects arc this much above the straight line
#: Control points (from the mixer's handle, m) of the reach to the mixer: low over the green cup
#: (the pass-by), then to the right of the handle, so that the hand arrives from the side.
_MIXER_VIA_M = np.array([[0.20, -0.40, 0.10], [0.30, 0.0, 0.05]])
_LOWER_S = 0.8  # lowering the beaters into the bowl, seconds
_INTO_BOWL_TAU = 0.75  # the beaters reach the bottom still moving briskly
_MIX_RADIUS_M = 0.010
_MIX_PERIOD_S = 5.0


@dataclass(frozen=True)
class Step:
    """One scripted sub-action: the OAC it demonstrates, its arguments, and when it happens (s)."""

    oac: str
    args: tuple[str, ...]
    time_s: float
    added: tuple[tuple[str, str], ...]
    removed: tuple[tuple[str, str], ...]


@dataclass(frozen=True)
class Script:
    """Noise-free trajectories of the dough demonstration.

    ``markers_m``: instance → (F, k, 3) marker positions, metres; ``labels``:
    instance → marker labels; ``steps``: the scripted sub-actions in order;
    ``marks``: named moments (seconds) used to place realism features.
    """

    rate_hz: float
    times_s: np.ndarray
    markers_m: dict[str, np.ndarray]
    labels: dict[str, tuple[str, ...]]
    initial: tuple[tuple[str, str], ...]
    steps: tuple[Step, ...]
    marks: dict[str, float]


def _grasp_target(obj: Track, grasp_m: np.ndarray, r_obj_hand: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    p, r = obj.last_pose
    return p + r @ grasp_m, r @ r_obj_hand


def _grip_ramp(times_s: np.ndarray, events: list[tuple[float, float, float]]) -> np.ndarray:
    """Hand closure 0 (open) … 1 (closed) over time from (start s, end s, target) ramps."""
    out = np.zeros_like(times_s)
    level = 0.0
    for t0, t1, target in events:
        s = min_jerk((times_s - t0) / (t1 - t0))
        out = np.where(times_s >= t0, level + s * (target - level), out)
        level = target
    return out


def dough_script(rng: np.random.Generator, rate_hz: float = 100.0, flight_s: float = FLIGHT_S) -> Script:
    """Script the dough demonstration; ``rng`` varies durations by ±10 %.

    ``flight_s``: seconds from the liquid leaving its cup to reaching the bowl. Up to
    0.3 s the liquid marker follows a parabola under gravity (the default 0.16 s: thrown
    slightly downwards); longer, it moves from the lip to the bowl on a straight line at a
    steady speed (about 0.2 m / ``flight_s``: a slow stream that lands later).
    """

    def dur(seconds: float) -> float:
        return float(seconds * rng.uniform(0.9, 1.1))

    total_s = 40.0  # grid long enough for any timing; trimmed below
    times = np.arange(int(total_s * rate_hz) + 1) / rate_hz
    yaw_pi = rot_z(np.pi)
    hand = {h: Track(h, times, _REST_M[h], _R_REST) for h in ("left_hand", "right_hand")}
    cups = {
        "red_cup": Track("red_cup", times, _RED_CUP_AT_M),
        "green_cup": Track("green_cup", times, _GREEN_CUP_AT_M, yaw_pi),
    }
    bowl = Track("orange_bowl", times, _BOWL_AT_M)
    mixer = Track("mixer", times, _MIXER_AT_M)
    liquids = {
        "liquid_one": Track("liquid_one", times, _RED_CUP_AT_M + LIQUID_IN_CUP_M),
        "liquid_two": Track("liquid_two", times, _GREEN_CUP_AT_M + yaw_pi @ LIQUID_IN_CUP_M),
    }
    grips: dict[str, list[tuple[float, float, float]]] = {"left_hand": [], "right_hand": []}
    steps: list[Step] = []
    marks: dict[str, float] = {}

    def pour_with(h: str, cup_name: str, liquid: str, side: float, r_cup_hand: np.ndarray) -> None:
        """grasp → pour → place for one hand (side −1 left, +1 right)."""
        hd, cup, liq = hand[h], cups[cup_name], liquids[liquid]
        yaw = np.eye(3) if side < 0 else yaw_pi
        home, home_rot = cup.last_pose
        t = hd.now_s
        # reach the handle, arriving along the handle's axis, and close the hand
        t_reach = t + dur(1.2)
        target = _grasp_target(cup, CUP_HANDLE_GRASP_M, r_cup_hand)
        hd.move(t_reach, *target, via_m=target[0] + _approach(side), end_tau=_CONTACT_TAU, turn_until=_TURN)
        steps.append(Step("grasp", (h, cup_name), t_reach, ((h, cup_name),), ()))
        marks[f"grasp_{cup_name}"] = t_reach
        t_closed = t_reach + dur(0.35)
        grips[h].append((t_reach, t_closed, 1.0))
        hd.hold(t_closed)
        cup.hold(t_closed)
        liq.follow(cup, t_closed)
        # lift and carry in an arc to beside the bowl: upright, lip 27 cm above the table, 14 cm off the axis
        t_carry = t_closed + dur(1.3)
        pre_lip = _BOWL_AT_M + np.array([side * 0.14, -0.01, 0.27])
        lip0 = home + home_rot @ CUP_LIP_M
        cup.move(t_carry, pre_lip, yaw, pivot_m=CUP_LIP_M, via_m=0.5 * (lip0 + pre_lip) + _UP_M)
        # tilt about the lip while moving it over the bowl; the liquid leaves at 80 % of the tilt
        t_tilt = t_carry + dur(1.2)
        pour_lip = _BOWL_AT_M + np.array([side * 0.075, side * -0.02, 0.21])
        cup.move(t_tilt, pour_lip, yaw @ rot_y(_POUR_TILT_RAD), pivot_m=CUP_LIP_M)
        t_release = t_carry + 0.8 * (t_tilt - t_carry)
        t_hold = t_tilt + dur(0.6)
        cup.hold(t_hold)
        hd.follow(cup, t_hold)
        liq.follow(cup, t_release)
        p0 = liq.position_m[liq.cursor - 1].copy()
        landing = _BOWL_AT_M + _LANDING_M[liquid]
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
        steps.append(
            Step(
                "pour",
                (h, cup_name, liquid, "orange_bowl"),
                t_land,
                ((liquid, "orange_bowl"),),
                ((liquid, cup_name),),
            )
        )
        marks[f"pour_{liquid}"] = t_land
        # tilt back, carry home, set down
        t_back = t_hold + dur(1.0)
        cup.move(t_back, pre_lip, yaw, pivot_m=CUP_LIP_M)
        bounce = cup_name == "red_cup"
        t_home = t_back + dur(1.3)
        above = home + np.array([0.0, 0.0, _DROP_M if bounce else 0.0])
        cup.move(
            t_home,
            above,
            home_rot,
            via_m=0.5 * (cup.last_pose[0] + above) + _UP_M,
            end_tau=1.0 if bounce else _CONTACT_TAU,
        )
        hd.follow(cup, t_home)
        if bounce:
            # let go: the cup drops the last few mm and bounces; the hand flinches back 5 cm,
            # hovers (touching again by the rule) and then leaves: three changes, each within
            # 0.3 s of the next, each lasting longer than the rule's n frames (0.1 s)
            t_let = t_home + 0.03
            cup.hold(t_let)
            hd.hold(t_let)
            cup.path(t_let + 0.3, lambda ts: home + np.outer(_bounce_height(ts - t_let), [0.0, 0.0, 1.0]))
            grips[h].append((t_let - 0.02, t_let + 0.1, 0.0))
            hd.hold(t_let + 0.03)
            p_hand, r_hand = hd.last_pose
            hd.move(t_let + 0.15, p_hand + 0.05 * r_hand[:, 0], r_hand, start_tau=0.2, end_tau=0.8)
            t_leave = t_let + 0.38
            marks["bounce"] = t_let
        else:
            t_leave = t_home + dur(0.3)
            grips[h].append((t_home, t_leave, 0.0))
        hd.hold(t_leave)
        t_away = t_leave + dur(1.0)
        out = hd.last_pose[0] + _retreat(side)  # straight out along the handle, then home
        hd.move(
            t_away,
            _REST_M[h],
            _R_REST,
            via_m=np.array([out, _REST_M[h] + _UP_M]),
            start_tau=1.0 - _CONTACT_TAU,
        )
        steps.append(Step("place", (h, cup_name), t_leave, (), ((h, cup_name),)))
        marks[f"place_{cup_name}"] = t_leave

    def sync(t_s: float) -> None:
        for tr in (*hand.values(), *cups.values(), mixer, *liquids.values()):
            if tr.cursor - 1 < tr.frame(t_s):
                tr.hold(t_s)

    sync(dur(1.0))
    pour_with("left_hand", "red_cup", "liquid_one", -1.0, _R_CUP_LEFT_HAND)
    sync(hand["left_hand"].now_s + dur(0.6))
    pour_with("right_hand", "green_cup", "liquid_two", +1.0, _R_CUP_RIGHT_HAND)
    rh = hand["right_hand"]
    sync(max(tr.now_s for tr in (*hand.values(), *cups.values(), *liquids.values())) + dur(0.8))
    # reach the mixer in one quick move that passes low over the green cup (a pass-by)
    t0 = rh.now_s
    t_reach = t0 + dur(1.5)
    target = _grasp_target(mixer, MIXER_HANDLE_GRASP_M, _R_MIXER_HAND)
    # first control point: low over the green cup; second: above the mixer, so the hand comes down onto it
    via = target[0] + _MIXER_VIA_M
    rh.move(t_reach, *target, via_m=via, end_tau=_CONTACT_TAU, turn_until=_TURN)
    marks["pass_by"] = t0 + 0.5 * (t_reach - t0)
    steps.append(Step("grasp", ("right_hand", "mixer"), t_reach, (("right_hand", "mixer"),), ()))
    marks["grasp_mixer"] = t_reach
    t_closed = t_reach + dur(0.35)
    grips["right_hand"].append((t_reach, t_closed, 1.0))
    rh.hold(t_closed)
    mixer.hold(t_closed)
    # lift over the bowl, lower the beaters in, mix in slow circles until the end
    t_over = t_closed + dur(1.3)
    over = _BOWL_AT_M + np.array([0.0, 0.0, 0.20])
    mixer.move(t_over, over, via_m=0.5 * (mixer.last_pose[0] + over) + 2.0 * _UP_M)
    t_in = t_over + dur(_LOWER_S)
    bottom = _BOWL_AT_M + np.array([0.0, 0.0, 0.02])
    mixer.move(t_in, bottom, end_tau=_INTO_BOWL_TAU)
    steps.append(Step("mix", ("right_hand", "mixer", "orange_bowl"), t_in, (("mixer", "orange_bowl"),), ()))
    marks["mix"] = t_in
    t_end = t_in + dur(4.0)

    t_stir = t_in + 0.5  # the beaters settle, then the hand starts moving them round

    def circles(ts: np.ndarray) -> np.ndarray:
        phase = 2.0 * np.pi * (ts - t_stir) / _MIX_PERIOD_S
        radius = _MIX_RADIUS_M * min_jerk((ts - t_stir) / 0.8)
        return bottom + radius[:, None] * np.stack([np.sin(phase), 1.0 - np.cos(phase), 0 * phase], -1)

    mixer.path(t_end, circles)
    rh.follow(mixer, t_end)
    n = mixer.frame(t_end) + 1
    for tr in (*hand.values(), *cups.values(), bowl, *liquids.values()):
        tr.finish()
    markers: dict[str, np.ndarray] = {}
    tracks = {**hand, **cups, "orange_bowl": bowl, "mixer": mixer, **liquids}
    for name, tr in tracks.items():
        pts = tr.world_points(BODIES[name].local_m)
        if name in grips:
            closure = _grip_ramp(times, grips[name])
            pts[:, 2] += closure[:, None] * np.einsum("fij,j->fi", tr.rotation, HAND_IFD_CLOSE_M)
        markers[name] = pts[:n]
    return Script(
        rate_hz,
        times[:n],
        markers,
        {k: b.labels for k, b in BODIES.items()},
        (("liquid_one", "red_cup"), ("liquid_two", "green_cup")),
        tuple(steps),
        marks,
    )


def _approach(side: float) -> np.ndarray:
    """Offset (m) from a cup's handle to the control point of a reach: far out along the handle axis.

    The hand then arrives almost straight along the handle, so every hand–cup marker pair
    closes in fast until the hand stops at the handle (no pair slides past sideways).
    """
    return np.array([side * 0.35, -0.10, -0.02])


def _retreat(side: float) -> np.ndarray:
    """Offset (m) from the handle to where a hand letting go heads first: straight out and up."""
    return np.array([side * 0.30, -0.07, 0.06])


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
