"""Synthetic demonstrations of the actions no KIT development clip has: Open, Close, Peel,
Transfer and RollOut, for the example scenes of ``library/examples`` (issue 19).

Each is a motion-capture recording as a person would make it, written with the rigid-body
tracks of :mod:`oacdsl.segmentation.synth.kinematics` (minimum-jerk moves; a held object follows
its hand): one marker group per tracked instance of the scene, four markers on each object
(where its class declares ``markers``, there; else on its outside), five on each hand (KIT's
``?HTS ?HPS ?IFD ?WTS ?WPS``, :func:`oacdsl.segmentation.synth.scene.hand_markers`), 100 Hz, no
noise. World frame as the synthetic dough scene's: x to the demonstrator's right, y away from
the demonstrator across the table, z up, metres; the table top at 0.75 m.

``write(task, folder)`` writes one as C3D; ``TASKS`` maps a task to (its writer, the example
scene, the OAC that runs it on the robot).

A :class:`Capture` makes a demonstration more like a real recording (every writer takes one;
:data:`KIT_LIKE`): Gaussian marker noise, an object's markers on stalks off its axis (where its
class declares no ``markers``), and one marker missing for a while.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from oacdsl.segmentation.points import recording_from_points
from oacdsl.segmentation.recording import Recording
from oacdsl.segmentation.synth.kinematics import Track, min_jerk, rot_y, rot_z
from oacdsl.segmentation.synth.scene import hand_markers
from oacdsl.segmentation.takes import resampled

__all__ = ["CLEAN", "KIT_10HZ", "KIT_LIKE", "LAYOUT", "TASKS", "TURN_DEG", "Capture", "turned", "write"]

RATE_HZ = 100.0
TABLE_Z_M = 0.75
_HAND_LABELS = ("HTS", "HPS", "IFD", "WTS", "WPS")
#: How far the synthetic Open and Close turn the lid unless told, degrees (KIT's Open clip, by
#: issue 19's account, turned it 535°: ``turn_deg`` of the writers).
TURN_DEG = 240.0
#: A hand taking something from above: the back of the hand (its x) up.
FROM_ABOVE = rot_y(-np.pi / 2)


def _cm(*points: tuple[float, float, float]) -> np.ndarray:
    return np.array(points, dtype=float) / 100.0


#: Body-frame markers (m) of each object: origin at the middle of its base, z up.
MARKERS: dict[str, np.ndarray] = {
    "bottle": _cm((4.5, 0, 13), (-4.5, 0, 9), (0, 4.5, 4), (0, -4.5, 11)),
    "lid": _cm((3.5, 0, 2.5), (-1.75, 3.0, 2.5), (-1.75, -3.0, 1.0), (0, 0, 3.2)),
    "cucumber": _cm((7, 0, 4.5), (-5, 0, 0), (-5, 0, 4.5), (3, 0, 1)),
    "cutting_board_small": _cm((12, 7, 1.5), (-12, -7, 1.5), (-4, -4, 0), (3, 4, 1.5)),
    "peeler": _cm((3, 0, 0.5), (-3, 0, 1.5), (0, 0, 14), (0, 0, 9)),
    "board": _cm((14, 7, 1.5), (-14, -7, 1.5), (5, -3, 0), (-6, 4, 1.5)),
    "knife_black": _cm((6, 0, 0), (-6, 0, 0), (0, 0, 16), (0, 0, 10)),
    "mixing_bowl_green": _cm((12.5, 0, 12), (-12.5, 0, 12), (0, 12.5, 12), (0, 0, 0)),
    "rolling_pin": _cm((0, 15.5, 14), (0, -15.5, 14), (3, 5, 6), (-3, -8, 6)),
    "block": _cm((3, 0, 5), (-3, 0, 2), (0, 3, 4), (0, -3, 1)),
    "crate": _cm((7, 0, 7), (-7, 0, 3), (0, 7, 6), (0, -7, 2)),
    "mug": _cm((4, 0, 9), (-4, 0, 3), (0, 4, 6), (0, -4, 8)),
    "pot": _cm((9, 0, 11), (-9, 0, 4), (0, 9, 8), (0, -9, 2)),
    "pot_lid": _cm((8, 0, 1), (-8, 0, 1), (0, 8, 1), (0, 0, 4)),
}


#: Objects whose class in ``library/examples`` declares its markers (``markers (...)``, the
#: positions above): a capture keeps them there, as the person who measured them wrote them.
DECLARED = frozenset({"block", "crate", "mug", "pot", "pot_lid"})


@dataclass(frozen=True)
class Capture:
    """How a recording differs from the ideal tracks (all drawn from ``seed``).

    ``noise_m``: standard deviation of independent Gaussian noise on every coordinate of every
    frame (the KIT development clips' markers: a median 0.12–0.33 mm from second differences,
    docs/kit.md). ``stalk_m``: each marker of an object whose class declares no markers is moved
    out from the object's vertical axis by a length drawn from this range (a marker on the axis,
    a knife's or a peeler's, in a drawn direction), as markers stand on stalks and bases.
    ``gap_s``: one marker, drawn from all, missing for this long from a drawn time (0: none).
    ``rate_hz``: the recording resampled to this rate (the KIT clips' MMM files: 10 Hz)."""

    noise_m: float = 0.0
    stalk_m: tuple[float, float] = (0.0, 0.0)
    gap_s: float = 0.0
    seed: int = 0
    rate_hz: float | None = None

    def stalks(self, name: str, local_m: np.ndarray) -> np.ndarray:
        """``local_m`` (k, 3) body-frame markers of object ``name`` on their stalks."""
        lo, hi = self.stalk_m
        if hi <= 0 or name in DECLARED:
            return local_m
        rng = np.random.default_rng([self.seed, *name.encode()])
        out = local_m.copy()
        for k, point in enumerate(local_m):
            radial = np.array([point[0], point[1], 0.0])
            if np.linalg.norm(radial) < 1e-3:
                angle = rng.uniform(0.0, 2 * np.pi)
                radial = np.array([np.cos(angle), np.sin(angle), 0.0])
            out[k] = point + rng.uniform(lo, hi) * radial / np.linalg.norm(radial)
        return out

    def recorded(self, groups: dict[str, np.ndarray]) -> dict[str, np.ndarray]:
        """(F, k, 3) world points of each group with the noise and the gap."""
        rng = np.random.default_rng(self.seed)
        out = {}
        for name, points in groups.items():
            noise = rng.normal(0.0, self.noise_m, points.shape) if self.noise_m > 0 else 0.0
            out[name] = points + noise
        if self.gap_s > 0:
            names = sorted(out)
            name = names[int(rng.integers(len(names)))]
            marker = int(rng.integers(out[name].shape[1]))
            n_frames, length = out[name].shape[0], int(round(self.gap_s * RATE_HZ))
            start = int(rng.integers(max(1, n_frames - length)))
            out[name][start:start + length, marker] = np.nan
        return out


#: The ideal tracks: no noise, markers where :data:`MARKERS` puts them, no gap.
CLEAN = Capture()
#: Like a KIT capture: 0.3 mm noise, objects' markers on 1–2.5 cm stalks, a 0.3 s gap.
KIT_LIKE = Capture(noise_m=0.0003, stalk_m=(0.01, 0.025), gap_s=0.3, seed=0)
#: :data:`KIT_LIKE` at the 10 Hz of the KIT clips' MMM files.
KIT_10HZ = Capture(noise_m=0.0003, stalk_m=(0.01, 0.025), gap_s=0.3, seed=0, rate_hz=10.0)


class Story:
    """The tracks of one demonstration on a shared time grid."""

    def __init__(self, duration_s: float) -> None:
        self.times_s = np.arange(int(round(duration_s * RATE_HZ)) + 1) / RATE_HZ
        self.tracks: dict[str, Track] = {}

    def body(self, name: str, position_m: tuple[float, float, float], yaw_rad: float = 0.0) -> Track:
        track = Track(name, self.times_s, np.asarray(position_m, dtype=float), rot_z(yaw_rad))
        self.tracks[name] = track
        return track

    def hand(self, side: str) -> Track:
        x = 0.25 if side == "right" else -0.25
        return self.body(f"{side}_hand", (x, 0.0, TABLE_Z_M + 0.1))

    def recording(self, source: str, capture: Capture = CLEAN) -> Recording:
        groups, labels = {}, {}
        for name, track in self.tracks.items():
            track.finish()
            if name.endswith("_hand"):
                side = name.split("_")[0]
                local = hand_markers(side)
                labels[name] = [side[0].upper() + s for s in _HAND_LABELS]
            else:
                local = capture.stalks(name, MARKERS[name])
                labels[name] = [f"{name[:2].upper()}{k + 1}" for k in range(len(local))]
            groups[name] = track.world_points(local)
        rec = recording_from_points(capture.recorded(groups), RATE_HZ, source, labels)
        return rec if capture.rate_hz is None else resampled(rec, capture.rate_hz)


def spin(track: Track, t1_s: float, angle_rad: float, axis_xy_m: np.ndarray) -> Track:
    """Turn ``track`` by ``angle_rad`` about the vertical through ``axis_xy_m`` until ``t1_s``
    (minimum-jerk; any angle, not the shortest arc)."""
    start = track.cursor
    track.hold(t1_s)  # allocates the frames, then overwritten
    frames = np.arange(start, track.cursor)
    p0, r0 = track.position_m[start - 1].copy(), track.rotation[start - 1].copy()
    centre = np.array([axis_xy_m[0], axis_xy_m[1], 0.0])
    u = (track.times_s[frames] - track.times_s[start - 1]) / (t1_s - track.times_s[start - 1])
    for f, s in zip(frames, min_jerk(u), strict=True):
        r = rot_z(angle_rad * s)
        track.position_m[f] = centre + r @ (p0 - centre)
        track.rotation[f] = r @ r0
    return track


def strokes(track: Track, t1_s: float, direction: np.ndarray, amplitude_m: float, period_s: float) -> Track:
    """To and fro along ``direction`` from the last position: ``amplitude_m`` out and back
    once per ``period_s`` (a raised cosine: starts and ends at rest where it began)."""
    p0 = track.last_pose[0]
    t0 = track.now_s
    d = np.asarray(direction, dtype=float) / np.linalg.norm(direction)
    return track.path(t1_s, lambda t: p0 + (amplitude_m * 0.5 * (1 - np.cos(2 * np.pi * (t - t0) / period_s))
                                            )[:, None] * d)


def _spin_s(turn_deg: float) -> float:
    """How long the demonstrator turns a lid by ``turn_deg``, s: 4 s for 240° (60°/s), longer
    turns at the same pace (never under 1 s)."""
    return max(1.0, 4.0 * abs(turn_deg) / TURN_DEG)


def close_demo(capture: Capture = CLEAN, turn_deg: float = TURN_DEG) -> Recording:
    """Close: the right hand holds the bottle on the table, the left hand takes the lid, sets it
    on the bottle and screws it on (``turn_deg``, default 240°, clockwise seen from above, at
    60°/s); both hands keep holding."""
    extra = _spin_s(turn_deg) - 4.0
    end = 12.0 + extra
    s = Story(end)
    bottle_at, lid_at = np.array([0.12, 0.42, TABLE_Z_M]), np.array([-0.22, 0.40, TABLE_Z_M])
    bottle = s.body("bottle", tuple(bottle_at))
    lid = s.body("lid", tuple(lid_at))
    right, left = s.hand("right"), s.hand("left")
    right.hold(0.8).move(2.0, bottle_at + [0.055, 0.0, 0.08], end_tau=0.95)
    left.hold(2.6).move(3.6, lid_at + [0.0, 0.0, 0.045], FROM_ABOVE, end_tau=0.95).hold(4.0)
    on_top = bottle_at + [0.0, 0.0, 0.18 + 0.045]
    left.move(6.0, on_top, via_m=[lid_at + [0, 0, 0.15], on_top + [0, 0, 0.1]], end_tau=0.97).hold(6.5)
    spin(left, 10.5 + extra, np.radians(-abs(turn_deg)), bottle_at).hold(end)
    bottle.hold(end)
    lid.hold(3.6).follow(left, end)
    right.hold(end)
    return s.recording("synthetic Close", capture)


def _unscrewed(end_s: float, turn_deg: float = TURN_DEG) -> tuple[Story, Track, Track, Track, Track, float]:
    """The start of Open in a story of ``end_s`` seconds (plus the time a turn longer than 240°
    takes): the lid on the bottle; the right hand takes the bottle, the left the lid, unscrews it
    (``turn_deg`` counterclockwise, at 60°/s) and lifts it off (by 9.6 s, or that much later).
    (story, bottle, lid, right hand, left hand, how much later than for 240° everything after
    the turn is, s)."""
    extra = _spin_s(turn_deg) - 4.0
    s = Story(end_s + extra)
    bottle_at = np.array([0.12, 0.42, TABLE_Z_M])
    bottle = s.body("bottle", tuple(bottle_at))
    lid = s.body("lid", tuple(bottle_at + [0.0, 0.0, 0.181]))
    right, left = s.hand("right"), s.hand("left")
    right.hold(0.8).move(2.0, bottle_at + [0.055, 0.0, 0.08], end_tau=0.95)
    top = bottle_at + [0.0, 0.0, 0.181 + 0.045]
    left.hold(2.6).move(3.8, top, FROM_ABOVE, via_m=[top + [-0.05, 0, 0.15]], end_tau=0.95).hold(4.2)
    spin(left, 8.2 + extra, np.radians(abs(turn_deg)), bottle_at).hold(8.6 + extra)
    left.move(9.6 + extra, top + [0.0, 0.0, 0.08])
    return s, bottle, lid, right, left, extra


def open_demo(capture: Capture = CLEAN, turn_deg: float = TURN_DEG) -> Recording:
    """Open: the lid on the bottle; the right hand holds the bottle, the left hand takes the
    lid, unscrews it (``turn_deg``, default 240°, counterclockwise) and lifts it off; both hands
    keep holding."""
    s, bottle, lid, right, left, extra = _unscrewed(11.0, turn_deg)
    end = 11.0 + extra
    left.hold(end)
    bottle.hold(end)
    lid.hold(3.8).follow(left, end)
    right.hold(end)
    return s.recording("synthetic Open", capture)


def open_put_down_demo(capture: Capture = CLEAN, turn_deg: float = TURN_DEG) -> Recording:
    """Open as :func:`open_demo`, then the left hand sets the lid down on the table on its own
    side and withdraws (where the KIT Open clips' lid ends is not known here: the evaluation
    recordings are not opened); the right hand keeps holding the bottle."""
    s, bottle, lid, right, left, extra = _unscrewed(14.0, turn_deg)
    down_at = np.array([-0.30, 0.34, TABLE_Z_M])
    end = 14.0 + extra
    left.hold(9.8 + extra)
    grip = np.array([0.0, 0.0, 0.045])
    left.move(11.2 + extra, down_at + grip, via_m=[down_at + grip + [0, 0, 0.10]], end_tau=0.97)
    left.hold(11.8 + extra)
    left.move(13.0 + extra, down_at + [-0.15, -0.15, 0.20], start_tau=0.3).hold(end)
    bottle.hold(end)
    lid.hold(3.8).follow(left, 11.8 + extra).hold(end)
    right.hold(end)
    return s.recording("synthetic Open, the lid set down", capture)


def peel_demo(capture: Capture = CLEAN) -> Recording:
    """Peel: the left hand takes the cucumber and holds it up, the right hand takes the peeler
    and draws it along the cucumber, three strokes; both keep holding."""
    s = Story(13.0)
    cucumber_at, peeler_at = np.array([-0.15, 0.40, TABLE_Z_M]), np.array([0.25, 0.38, TABLE_Z_M])
    cucumber = s.body("cucumber", tuple(cucumber_at))
    s.body("cutting_board_small", (-0.30, 0.62, TABLE_Z_M))
    peeler = s.body("peeler", tuple(peeler_at))
    right, left = s.hand("right"), s.hand("left")
    left.hold(0.8).move(2.0, cucumber_at + [-0.10, -0.04, 0.05], end_tau=0.95).hold(2.3)
    left.move(3.5, cucumber_at + [-0.14, -0.14, 0.15])
    right.hold(2.4).move(3.4, peeler_at + [0.035, 0.0, 0.13], end_tau=0.95).hold(3.8)
    blade_on = left.position_m[left.frame(3.5)] + [0.10 + 0.01, 0.04, 0.045 - 0.05]  # peeler on the top
    right.move(5.6, blade_on + [0.035, 0.0, 0.13], via_m=[peeler_at + [0.035, 0, 0.3]], end_tau=0.97)
    right.hold(6.0)
    strokes(right, 12.0, np.array([1.0, 0.0, 0.0]), 0.05, 2.0).hold(13.0)
    left.hold(13.0)
    cucumber.hold(2.0).follow(left, 13.0)
    peeler.hold(3.4).follow(right, 13.0)
    return s.recording("synthetic Peel", capture)


def transfer_demo(capture: Capture = CLEAN) -> Recording:
    """Transfer: the left hand takes the bowl and holds it up beside the board, the right hand
    takes the knife and pushes it across the board towards the bowl, twice; both keep holding."""
    s = Story(12.0)
    bowl_at, board_at = np.array([-0.32, 0.42, TABLE_Z_M]), np.array([0.02, 0.45, TABLE_Z_M])
    knife_at = np.array([0.30, 0.36, TABLE_Z_M])
    bowl = s.body("mixing_bowl_green", tuple(bowl_at))
    s.body("board", tuple(board_at), yaw_rad=np.pi / 2)  # long (30 cm) along x
    knife = s.body("knife_black", tuple(knife_at), yaw_rad=np.pi / 2)
    right, left = s.hand("right"), s.hand("left")
    left.hold(0.8).move(2.0, bowl_at + [-0.125, 0.0, 0.12], end_tau=0.95).hold(2.3)
    left.move(3.5, bowl_at + [-0.145, -0.02, 0.20])
    right.hold(2.4).move(3.4, knife_at + [0.035, 0.0, 0.10], end_tau=0.95).hold(3.8)
    on_board = board_at + [0.08, 0.0, 0.015]
    right.move(5.6, on_board + [0.035, 0.0, 0.10], via_m=[knife_at + [0.035, 0, 0.25]], end_tau=0.97)
    right.hold(6.0)
    strokes(right, 10.0, np.array([-1.0, 0.0, 0.0]), 0.06, 2.0).hold(12.0)
    left.hold(12.0)
    bowl.hold(2.0).follow(left, 12.0)
    knife.hold(3.4).follow(right, 12.0)
    return s.recording("synthetic Transfer", capture)


def rollout_demo(capture: Capture = CLEAN) -> Recording:
    """RollOut: both hands take the rolling pin by its handles at once, set it on the (untracked)
    dough, roll it to and fro three times, and let go of it together."""
    s = Story(12.0)
    pin_at = np.array([0.0, 0.36, TABLE_Z_M])
    pin = s.body("rolling_pin", tuple(pin_at), yaw_rad=np.pi / 2)  # its long axis along x
    right, left = s.hand("right"), s.hand("left")
    right.hold(0.8).move(2.0, pin_at + [0.155, 0.0, 0.08], end_tau=0.95).hold(2.4)
    left.hold(0.8).move(2.0, pin_at + [-0.155, 0.0, 0.08], end_tau=0.95).hold(2.4)
    lift = np.array([0.0, 0.10, 0.012])  # onto the dough, 1.2 cm thick
    for hand, side in ((right, 1.0), (left, -1.0)):
        grip = pin_at + [side * 0.155, 0.0, 0.08]
        hand.move(4.0, grip + lift, via_m=[grip + [0, 0.05, 0.06]]).hold(4.3)
        strokes(hand, 10.3, np.array([0.0, 1.0, 0.0]), 0.06, 2.0).hold(10.6)
    pin.hold(2.0).follow(right, 10.6).hold(12.0)
    right.move(11.1, right.last_pose[0] + [0.15, -0.15, 0.15], start_tau=0.3).hold(12.0)
    left.move(11.1, left.last_pose[0] + [-0.15, -0.15, 0.15], start_tau=0.3).hold(12.0)
    return s.recording("synthetic RollOut", capture)


def stack_demo(capture: Capture = CLEAN) -> Recording:
    """Stack: the right hand takes a small box (6 cm), sets it on a larger one (8 cm high) standing
    on the table, lets go and withdraws; the left hand stays still."""
    s = Story(9.0)
    block_at, crate_at = np.array([0.25, 0.38, TABLE_Z_M]), np.array([-0.05, 0.45, TABLE_Z_M])
    block = s.body("block", tuple(block_at))
    s.body("crate", tuple(crate_at))
    right, left = s.hand("right"), s.hand("left")
    grip = np.array([0.04, 0.0, 0.03])  # the hand beside the block, at half its height
    right.hold(0.8).move(2.0, block_at + grip, end_tau=0.95).hold(2.4)
    on_crate = crate_at + [0.0, 0.0, 0.08]
    right.move(4.6, on_crate + grip, via_m=[block_at + grip + [0, 0, 0.15], on_crate + grip + [0, 0, 0.08]],
               end_tau=0.97).hold(5.4)
    right.move(6.6, on_crate + [0.20, -0.15, 0.15], start_tau=0.3).hold(9.0)
    block.hold(2.0).follow(right, 5.4).hold(9.0)
    left.hold(9.0)
    return s.recording("synthetic Stack", capture)


def handover_demo(capture: Capture = CLEAN) -> Recording:
    """Hand over: the right hand takes a mug and holds it up in the middle, the left hand takes
    it from the other side, the right lets go and withdraws, the left sets it down on its side."""
    s = Story(12.0)
    mug_at, down_at = np.array([0.22, 0.38, TABLE_Z_M]), np.array([-0.24, 0.40, TABLE_Z_M])
    mug = s.body("mug", tuple(mug_at))
    right, left = s.hand("right"), s.hand("left")
    side = np.array([0.055, 0.0, 0.06])  # beside the mug, at 6 cm of its 10
    right.hold(0.8).move(2.0, mug_at + side, end_tau=0.95).hold(2.3)
    meet = np.array([0.0, 0.36, TABLE_Z_M + 0.20])
    right.move(4.0, meet + side).hold(5.6)
    left.hold(3.0).move(4.8, meet - side * [1, 1, -1], end_tau=0.95).hold(5.6)
    right.move(6.8, meet + [0.25, -0.15, 0.05], start_tau=0.3).hold(12.0)
    left.move(8.8, down_at - side * [1, 1, -1], via_m=[down_at - side * [1, 1, -1] + [0, 0, 0.1]],
              end_tau=0.97).hold(9.4)
    left.move(10.6, down_at + [-0.25, -0.15, 0.15], start_tau=0.3).hold(12.0)
    mug.hold(2.0).follow(right, 5.2).follow(left, 9.4).hold(12.0)
    return s.recording("synthetic HandOver", capture)


def cover_demo(capture: Capture = CLEAN) -> Recording:
    """Cover: the left hand takes a pot's lid by its knob from above, sets it on the pot standing
    on the table, lets go and withdraws; the right hand stays still."""
    s = Story(9.0)
    lid_at, pot_at = np.array([-0.32, 0.36, TABLE_Z_M]), np.array([0.02, 0.45, TABLE_Z_M])
    lid = s.body("pot_lid", tuple(lid_at))
    s.body("pot", tuple(pot_at))
    right, left = s.hand("right"), s.hand("left")
    knob = np.array([0.0, 0.0, 0.045])
    left.hold(0.8).move(2.0, lid_at + knob, FROM_ABOVE, end_tau=0.95).hold(2.4)
    on_pot = pot_at + [0.0, 0.0, 0.12]
    left.move(4.6, on_pot + knob, via_m=[lid_at + knob + [0, 0, 0.15], on_pot + knob + [0, 0, 0.08]],
              end_tau=0.97).hold(5.4)
    left.move(6.6, on_pot + [-0.20, -0.15, 0.20], start_tau=0.3).hold(9.0)
    lid.hold(2.0).follow(left, 5.4).hold(9.0)
    right.hold(9.0)
    return s.recording("synthetic Cover", capture)


#: Task → (its demonstration, the example scene, the example OAC the robot runs directly).
TASKS: dict[str, tuple[Callable[[Capture], Recording], str, str]] = {
    "Close": (close_demo, "bottle_lid", "close_and_open"),
    "Open": (open_demo, "bottle_lid", "open_bottle"),
    "OpenPutDown": (open_put_down_demo, "bottle_lid", "open_bottle"),
    "Peel": (peel_demo, "peeling", "peel_cucumber"),
    "Transfer": (transfer_demo, "transferring", "transfer_to_bowl"),
    "RollOut": (rollout_demo, "rolling", "roll_the_pin"),
    "Stack": (stack_demo, "stacking", "stack_block"),
    "HandOver": (handover_demo, "handing", "hand_over"),
    "Cover": (cover_demo, "covering", "cover_pot"),
}


#: Task → the layout the robot's run uses: the demonstration's first frame (the lid starts on
#: the bottle only so) or the example scene's places (the dough, untracked, has no first frame).
LAYOUT: dict[str, str | None] = {
    "Close": "demonstrated", "Open": "demonstrated", "OpenPutDown": "demonstrated", "Peel": None,
    "RollOut": None, "Transfer": "demonstrated", "Stack": None, "HandOver": None, "Cover": "demonstrated",
}


def write(task: str, folder: Path, capture: Capture = CLEAN) -> Path:
    """The synthetic demonstration of ``task`` written as ``folder/synthetic_TASK.c3d``."""
    from oacdsl.segmentation.readers import write_recording

    return Path(write_recording(TASKS[task][0](capture), folder / f"synthetic_{task}.c3d"))


def turned(task: str, turn_deg: float | None = None) -> Callable[[Capture], Recording]:
    """The writer of ``task``'s demonstration, its lid turned ``turn_deg`` (Close, Open,
    OpenPutDown; ``None``: as written). A one-line error for another task."""
    writer = TASKS[task][0]
    if turn_deg is None:
        return writer
    if task not in ("Close", "Open", "OpenPutDown"):
        raise ValueError(f"{task}: no turn to set (Close, Open and OpenPutDown turn a lid)")
    return lambda capture: writer(capture, turn_deg)  # type: ignore[call-arg]
