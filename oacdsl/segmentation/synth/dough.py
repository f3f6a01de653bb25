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

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from oacdsl.segmentation.synth.kinematics import min_jerk, rot_z
from oacdsl.segmentation.synth.scene import (
    BODIES,
    CUP_HANDLE_GRASP_M,
    LIQUID_IN_CUP_M,
    MIXER_HANDLE_GRASP_M,
    TABLE_Z_M,
)
from oacdsl.segmentation.synth.stage import (
    BOWL_AT_M,
    GRAVITY_M_S2,
    R_REST,
    REST_M,
    UP_M,
    Stage,
    Step,
)

__all__ = ["FLIGHT_S", "GRAVITY_M_S2", "Script", "Step", "dough_script", "paper_story"]

_RED_CUP_AT_M = np.array([-0.36, -0.02, TABLE_Z_M])
_GREEN_CUP_AT_M = np.array([0.36, -0.02, TABLE_Z_M])
_MIXER_AT_M = np.array([0.25, 0.42, TABLE_Z_M])
#: Hand frame in the cup frame when holding the handle (back of the hand away from the cup).
R_CUP_LEFT_HAND = np.array([[-1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, -1.0]])
R_CUP_RIGHT_HAND = np.array([[-1.0, 0.0, 0.0], [0.0, -1.0, 0.0], [0.0, 0.0, 1.0]])
#: Hand frame in the mixer frame: back of the hand to the right, fingers down round the handle.
_R_MIXER_HAND = np.array([[1.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, -1.0, 0.0]])
#: Release to landing of the liquid marker, seconds: a thrown-down parabola.
FLIGHT_S = 0.16
#: Control points (from the mixer's handle, m) of the reach to the mixer: low over the green cup
#: (the pass-by), then to the right of the handle, so that the hand arrives from the side.
_MIXER_VIA_M = np.array([[0.20, -0.40, 0.10], [0.30, 0.0, 0.05]])
_LOWER_S = 0.8  # lowering the beaters into the bowl, seconds
_INTO_BOWL_TAU = 0.75  # the beaters reach the bottom still moving briskly
_MIX_RADIUS_M = 0.010
_MIX_PERIOD_S = 5.0
YAW_PI = rot_z(np.pi)


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


def dough_stage(rng: np.random.Generator, rate_hz: float, flight_s: float) -> Stage:
    """The dough scene at its start: hands at rest, cups with their liquids, bowl and mixer."""

    def dur(seconds: float) -> float:
        return float(seconds * rng.uniform(0.9, 1.1))

    total_s = 40.0  # grid long enough for any timing; trimmed at the end
    times = np.arange(int(total_s * rate_hz) + 1) / rate_hz
    places: dict[str, tuple[np.ndarray, np.ndarray | None]] = {
        "left_hand": (REST_M["left_hand"], R_REST),
        "right_hand": (REST_M["right_hand"], R_REST),
        "red_cup": (_RED_CUP_AT_M, None),
        "green_cup": (_GREEN_CUP_AT_M, YAW_PI),
        "orange_bowl": (BOWL_AT_M, None),
        "mixer": (_MIXER_AT_M, None),
        "liquid_one": (_RED_CUP_AT_M + LIQUID_IN_CUP_M, None),
        "liquid_two": (_GREEN_CUP_AT_M + YAW_PI @ LIQUID_IN_CUP_M, None),
    }
    return Stage(times, places, {"red_cup": "liquid_one", "green_cup": "liquid_two"}, dur, flight_s)


def pour_with(
    stage: Stage, h: str, cup: str, side: float, r_cup_hand: np.ndarray, bounce: bool = False
) -> float:
    """grasp → pour → set back down where it stood, for one hand (side −1 left, +1 right)."""
    yaw = np.eye(3) if side < 0 else YAW_PI
    home, home_rot = stage[cup].last_pose
    t = stage.grasp(stage[h].now_s, h, cup, CUP_HANDLE_GRASP_M, r_cup_hand, side)
    t = stage.pour(t, h, cup, side, yaw)
    return stage.set_down(t, h, cup, home, home_rot, side, bounce=bounce)


def mix_until_end(stage: Stage, start_s: float) -> int:
    """The right hand reaches the mixer (passing low over the green cup), lowers it into the
    bowl and mixes in slow circles; returns the number of frames of the recording."""
    rh, mixer = stage["right_hand"], stage["mixer"]
    dur = stage.dur
    stage.sync(start_s)
    # reach the mixer in one quick move that passes low over the green cup (a pass-by); the
    # control points: low over the green cup, then above the mixer, so the hand comes down onto it
    t0 = rh.now_s
    t_closed = stage.grasp(
        t0, "right_hand", "mixer", MIXER_HANDLE_GRASP_M, _R_MIXER_HAND, +1.0, via_m=_MIXER_VIA_M, reach_s=1.5
    )
    stage.marks["pass_by"] = t0 + 0.5 * (stage.marks["grasp_mixer"] - t0)
    # lift over the bowl, lower the beaters in, mix in slow circles until the end
    t_over = t_closed + dur(1.3)
    over = BOWL_AT_M + np.array([0.0, 0.0, 0.20])
    mixer.move(t_over, over, via_m=0.5 * (mixer.last_pose[0] + over) + 2.0 * UP_M)
    t_in = t_over + dur(_LOWER_S)
    bottom = BOWL_AT_M + np.array([0.0, 0.0, 0.02])
    mixer.move(t_in, bottom, end_tau=_INTO_BOWL_TAU)
    stage.steps.append(
        Step("mix", ("right_hand", "mixer", "orange_bowl"), t_in, (("mixer", "orange_bowl"),), ())
    )
    stage.marks["mix"] = t_in
    t_end = t_in + dur(4.0)

    t_stir = t_in + 0.5  # the beaters settle, then the hand starts moving them round

    def circles(ts: np.ndarray) -> np.ndarray:
        phase = 2.0 * np.pi * (ts - t_stir) / _MIX_PERIOD_S
        radius = _MIX_RADIUS_M * min_jerk((ts - t_stir) / 0.8)
        return bottom + radius[:, None] * np.stack([np.sin(phase), 1.0 - np.cos(phase), 0 * phase], -1)

    mixer.path(t_end, circles)
    rh.follow(mixer, t_end)
    return mixer.frame(t_end) + 1


def paper_story(stage: Stage) -> int:
    """The paper's order: the left hand pours, then the right hand, then the right hand mixes."""
    dur = stage.dur
    stage.sync(dur(1.0))
    pour_with(stage, "left_hand", "red_cup", -1.0, R_CUP_LEFT_HAND, bounce=True)
    stage.sync(stage["left_hand"].now_s + dur(0.6))
    pour_with(stage, "right_hand", "green_cup", +1.0, R_CUP_RIGHT_HAND)
    hands_cups = ("left_hand", "right_hand", "red_cup", "green_cup", "liquid_one", "liquid_two")
    return mix_until_end(stage, max(stage[k].now_s for k in hands_cups) + dur(0.8))


def dough_script(
    rng: np.random.Generator,
    rate_hz: float = 100.0,
    flight_s: float = FLIGHT_S,
    story: Callable[[Stage], int] = paper_story,
) -> Script:
    """Script the dough demonstration; ``rng`` varies durations by ±10 %.

    ``flight_s``: seconds from the liquid leaving its cup to reaching the bowl. Up to
    0.3 s the liquid marker follows a parabola under gravity (the default 0.16 s: thrown
    slightly downwards); longer, it moves from the lip to the bowl on a straight line at a
    steady speed (about 0.2 m / ``flight_s``: a slow stream that lands later).
    ``story`` writes the sub-actions onto the stage and returns the number of frames: the
    paper's order, or one of :data:`~oacdsl.segmentation.synth.stories.STORY_SCRIPTS`.
    """
    stage = dough_stage(rng, rate_hz, flight_s)
    n = story(stage)
    return Script(
        rate_hz,
        stage.times_s[:n],
        stage.markers(n),
        {k: b.labels for k, b in BODIES.items()},
        (("liquid_one", "red_cup"), ("liquid_two", "green_cup")),
        tuple(sorted(stage.steps, key=lambda st: st.time_s)),
        stage.marks,
    )

