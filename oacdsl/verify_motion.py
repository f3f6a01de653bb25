"""Motion per sub-action: is the execution's motion the demonstration's? (``faithful``)

Each demonstrated sub-action (keyframe → keyframe after transient states are dropped) is
paired with the execution's sub-action that the relations check aligned with it (a split:
the span of its robot changes together). Both paths are the moved object's pose in its
target's frame (:func:`~oacdsl.segmentation.motion.sub_action_motion`, the execution's
re-expressed with the demonstration's moved object and target) and their features
(:mod:`oacdsl.segmentation.motionfeatures`). Judged only where the demonstration's feature is
reliable — both rigid fits' median residual below ``reliable_residual_m`` — and present:

- **strokes / cycles**: the demonstration shows an oscillation (a period found) of at least
  ``min_cycles`` cycles: the execution must oscillate with at least ``cycles_share`` of
  them, its radius within ``amplitude_factor`` of the demonstration's. Where the execution's
  span read whole shows none, its oscillation is read on each run of stretches in which the
  object keeps moving relative to its target (:func:`oscillation`): a robot sets its tools
  down and rests before its hands let go, within the span, and that rest can be longer than
  its circles (its path's core, where it dwells, is then the rest);
- **turn** about the target's axis (a lid): the demonstration turns ``min_turn_rad`` or
  more: the execution turns at least ``turn_share`` of it, the same way round (either way
  when hands may be exchanged: a mirrored take turns the other way);
- **tilt** relative to the target (a pour): the tilt the object gains within the sub-action
  reaches ``min_tilt_rad`` in the demonstration: the execution's gain must come within
  ``tilt_reached_rad`` of it.

A sub-action that *makes* the moved object's relation with its target (brings it there) is
not judged: a transport carries the object however the executor holds it; the work on the
target happens while the relation holds and ends when it is broken (those are judged, and so
are paths in the world's frame). A hand's own motion (reaching for an object, leaving it) is
not judged: how a robot's hand approaches is its own business; nor is a liquid's (its balls
are no rigid body). Cycles, turns and tilts do not
depend on speed, frame rate or the room's frame.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, replace
from typing import Any

import numpy as np

from oacdsl.segmentation.motion import SubActionMotion, sub_action_motion
from oacdsl.segmentation.motionfeatures import MotionFeatures, core_entry, motion_features
from oacdsl.segmentation.poses import ObjectPoses, relative
from oacdsl.segmentation.recording import Recording
from oacdsl.segmentation.result import SubAction
from oacdsl.verify_spans import AlignedSpan, Unmerged, demonstration_frames, execution_frames
from oacdsl.verify_tolerances import VerifyTolerances

__all__ = ["MotionCheck", "motion_checks", "moving_stretches", "oscillation", "tilt_gain"]


@dataclass(frozen=True)
class MotionCheck:
    sub_action: int
    feature: str  # cycles, turn, tilt
    passed: bool
    demonstration: str
    execution: str
    tolerance: str
    detail: str
    label: str  # "moved → target"


def tilt_gain(T_target_object: np.ndarray, times_s: np.ndarray | None = None) -> float:
    """Largest tilt (rad) of the object relative to the target from where it reaches the target
    to the span's end, less its tilt there (module doc): from the moment the path enters its
    core (:func:`~oacdsl.segmentation.motionfeatures.core_entry`, between two frames; the span's
    first posed frame for a path without one; the path in time when ``times_s`` is given)."""
    T = np.asarray(T_target_object, dtype=np.float64)
    ok = np.isfinite(T[:, 0, 0])
    if ok.sum() < 2:
        return 0.0
    tilt = np.arccos(np.clip(T[:, 2, 2], -1.0, 1.0))
    a, w = core_entry(T[:, :3, 3], times_s)
    after = tilt[a:][ok[a:]]
    if after.size == 0:
        return 0.0
    start = float(tilt[a - 1] + w * (tilt[a] - tilt[a - 1])) if w < 1.0 else float(after[0])
    return max(float(after.max()), start) - start


def moving_stretches(times_s: np.ndarray, T_target_object: np.ndarray, still_speed_m_s: float,
                     still_pause_s: float) -> list[tuple[int, int]]:
    """``[a, b)`` frame ranges in which the object keeps moving relative to its target: split
    where it is slower than ``still_speed_m_s`` (m/s) for ``still_pause_s`` (s) or longer;
    frames without a pose do not split."""
    t = np.asarray(times_s, dtype=np.float64)
    p = np.asarray(T_target_object, dtype=np.float64)[:, :3, 3]
    ok = np.isfinite(p).all(axis=1)
    still = np.zeros(len(t), dtype=bool)
    if ok.sum() >= 2:
        speed = np.linalg.norm(np.gradient(p[ok], t[ok], axis=0), axis=1)
        still[ok] = speed < still_speed_m_s
    dt = float(np.median(np.diff(t))) if len(t) > 1 else 0.0
    edges = np.diff(np.r_[0, still.astype(np.int8), 0])
    pause = np.zeros(len(t), dtype=bool)
    for a, b in zip(np.flatnonzero(edges == 1), np.flatnonzero(edges == -1), strict=True):
        if (b - a) * dt >= still_pause_s:
            pause[a:b] = True
    edges = np.diff(np.r_[0, (~pause).astype(np.int8), 0])
    starts, stops = np.flatnonzero(edges == 1), np.flatnonzero(edges == -1)
    return [(int(a), int(b)) for a, b in zip(starts, stops, strict=True)]


def oscillation(times_s: np.ndarray, T_target_object: np.ndarray, tol: VerifyTolerances) -> MotionFeatures:
    """The features of an execution's path (``T_target_object``, metres, over ``times_s``)
    as the cycles check reads them: the whole path's, or, where that shows no oscillation, those
    of the run of consecutive moving stretches (:func:`moving_stretches`) with the most cycles
    (module doc): a single stretch holds circles the robot stopped after, before it sets the
    tool down; joined, stretches hold strokes with a stop at each end."""
    t = np.asarray(times_s, dtype=np.float64)
    whole = motion_features(t, T_target_object)
    if whole.cycles is not None:
        return whole
    best = whole
    stretches = moving_stretches(t, T_target_object, tol.still_speed_m_s, tol.still_pause_s)
    for i, (a, _) in enumerate(stretches):
        for _, b in stretches[i:]:
            if b - a < 2 or (a, b) == (0, len(t)):
                continue
            f = motion_features(t[a:b], T_target_object[a:b])
            if f.cycles is not None and (best.cycles is None or f.cycles > best.cycles):
                best = f
    return best


def _reexpressed(rec: Recording, a: int, b: int, moved: str, target: str | None,
                 posed: Mapping[str, ObjectPoses]) -> np.ndarray | None:
    if moved not in posed or (target is not None and target not in posed):
        return None
    T = posed[moved].T_world_object[a : b + 1]
    if target is not None:
        T = relative(posed[target].T_world_object[a : b + 1], T)
    return T


def motion_checks(
    demo_rec: Recording,
    demo_subs: Sequence[SubAction],
    demo_posed: Mapping[str, ObjectPoses],
    run_rec: Recording,
    run_spans: Mapping[int, AlignedSpan],
    run_posed: Mapping[str, ObjectPoses],
    name_map: Mapping[str, str],
    tolerances: VerifyTolerances,
    any_hands: bool,
    liquids: frozenset[str] = frozenset(),
    unmerged: tuple[Unmerged, Unmerged] | None = None,
    agents: frozenset[str] = frozenset(),
) -> tuple[list[MotionCheck], list[str]]:
    """The checks, and a note per demonstrated sub-action whose features are not judged.

    ``run_spans``: demonstration sub-action index → the execution's frames aligned with it
    (:func:`~oacdsl.verify_spans.aligned_spans`); a pair is read on the frames
    :mod:`oacdsl.verify_spans` gives, in both recordings, with ``unmerged`` (the
    demonstration's and the execution's keyframes without merging, ``(frame, relations)``,
    asked for only where a keyframe merges the pair's change with another; default: none
    found; ``agents``: the hands); ``name_map``: demonstration instance → the execution's."""
    checks: list[MotionCheck] = []
    notes: list[str] = []
    times = np.asarray(run_rec.times_s, dtype=np.float64)
    demo_unmerged, run_unmerged = unmerged or (list, list)
    for k, sub in enumerate(demo_subs):
        d: SubActionMotion = sub_action_motion(demo_rec, sub, demo_posed)
        if d.moved is not None and d.moved != d.hand and d.target is not None \
                and d.relation in ("kept", "broken"):
            previous = demo_subs[k - 1].start if k else None
            a, b = demonstration_frames(sub, previous, d.moved, d.target, d.relation, demo_unmerged, agents)
            if (a, b) != (sub.start.frame, sub.end.frame):
                part = SubAction(sub.index, replace(sub.start, frame=a), replace(sub.end, frame=b))
                d = sub_action_motion(demo_rec, part, demo_posed, pair=(d.moved, d.target))
        if d.moved is None or d.features is None:
            continue
        label = f"{d.moved} → {d.target or 'world'}"
        if d.moved == d.hand or d.moved in liquids:  # a hand reaching or leaving; a liquid's balls
            continue  # are no rigid body
        if d.relation == "made":
            notes.append(f"sub-action {k + 1} ({label}): not judged, it brings the object to its target")
            continue
        if not (d.residual_m < tolerances.reliable_residual_m):
            notes.append(f"sub-action {k + 1} ({label}): not judged, the rigid fit is loose"
                         f" ({d.residual_m * 1000:.0f} mm)")
            continue
        feats = d.features
        wanted = []
        if feats.cycles is not None and feats.cycles >= tolerances.min_cycles:
            wanted.append("cycles")
        if abs(feats.twist_rad) >= tolerances.min_turn_rad:
            wanted.append("turn")
        gain = tilt_gain(d.T_target_object, d.times_s)
        if gain >= tolerances.min_tilt_rad:
            wanted.append("tilt")
        if not wanted:
            continue
        aligned = run_spans.get(k)
        moved = name_map.get(d.moved, d.moved)
        target = None if d.target is None else name_map.get(d.target, d.target)
        span = None if aligned is None else (aligned.start, aligned.end) if target is None else \
            execution_frames(aligned, moved, target, d.relation, run_unmerged, agents)
        T = None if span is None else _reexpressed(run_rec, span[0], span[1], moved, target, run_posed)
        for feature in wanted:
            checks.append(_judge(k, feature, d, feats, gain, span, T, times, label, tolerances, any_hands))
    return checks, notes


def _judge(k: int, feature: str, d: SubActionMotion, feats: Any, gain: float,
           span: tuple[int, int] | None, T: np.ndarray | None, times: np.ndarray, label: str,
           tol: VerifyTolerances, any_hands: bool) -> MotionCheck:
    def out(passed: bool, demo: str, run: str, tolerance: str, detail: str) -> MotionCheck:
        return MotionCheck(k + 1, feature, passed, demo, run, tolerance, detail, label)

    if feature == "cycles":
        demo = f"{feats.cycles:.1f} cycles, radius {feats.radius_m * 1000:.0f} mm"
        tolerance = f">= {tol.cycles_share:g} x the cycles, radius within x{tol.amplitude_factor:g}"
    elif feature == "turn":
        demo = f"{math.degrees(feats.twist_rad):+.0f}°"
        tolerance = f">= {tol.turn_share:g} x the turn" + (", either way" if any_hands else ", same way")
    else:
        demo = f"{math.degrees(gain):.0f}°"
        tolerance = f"within {math.degrees(tol.tilt_reached_rad):.0f}° of it"
    if span is None or T is None:
        why = "the execution has no sub-action aligned with it" if span is None else "no pose of the objects"
        return out(False, demo, "—", tolerance, f"sub-action {k + 1} ({label}): {why}")
    t = times[span[0] : span[1] + 1]
    f = oscillation(t, T, tol) if feature == "cycles" else motion_features(t, T)
    if feature == "cycles":
        low, high = feats.radius_m / tol.amplitude_factor, feats.radius_m * tol.amplitude_factor
        enough = f.cycles is not None and f.cycles >= tol.cycles_share * feats.cycles
        ok = enough and low <= f.radius_m <= high
        run = ("no oscillation" if f.cycles is None else f"{f.cycles:.1f} cycles") + \
            f", radius {f.radius_m * 1000:.0f} mm"
        what = "strokes/circles"
    elif feature == "turn":
        same_way = any_hands or f.twist_rad * feats.twist_rad > 0
        ok = same_way and abs(f.twist_rad) >= tol.turn_share * abs(feats.twist_rad)
        run = f"{math.degrees(f.twist_rad):+.0f}°"
        what = "turn about the target's axis"
    else:
        g = tilt_gain(T, t)
        ok = g >= gain - tol.tilt_reached_rad
        run = f"{math.degrees(g):.0f}°"
        what = "tilt"
    detail = "" if ok else f"sub-action {k + 1} ({label}): {what} {run}, demonstrated {demo}"
    return out(ok, demo, run, tolerance, detail)
