"""The demonstrated motion of every sub-action: what moved, relative to what, and how.

For each sub-action (keyframe *i* → *i* + 1, frames inclusive) :func:`sub_action_motions`
names

- the **hand**: an agent (an instance named like ``*hand*``) holding something in
  the world state before the span;
- the **moved** object: what that hand holds, or the hand itself when it holds
  nothing and reaches for an object or leaves it (a hand relation made or broken);
- the **target**, what the moved object works on: the other side of the relation it
  *makes* (in the state after, not before), *breaks* (before, not after) or *keeps*
  (both) with an object that is not an agent; ``None`` when there is none (the
  trajectory is then in the world frame);

and the moved object's pose in the target's frame over the span,
``T_target_object`` (metres; times in seconds), with its :class:`MotionFeatures`.
When several candidates fit (both hands hold something, as in Stir: spoon in the
cup held by the other hand), the one whose moved object travels farthest in the
world during the span is chosen (a made or broken relation before a kept one only
between equally long paths); a held object with no such relation is taken (in the
world frame) only when no candidate has a target. Poses come from the rigid fit of
:mod:`oacdsl.segmentation.poses` (instances with ≥ 3 markers).
"""

from __future__ import annotations

import fnmatch
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np

from oacdsl.segmentation.motionfeatures import MotionFeatures, motion_features
from oacdsl.segmentation.poses import ObjectPoses, fit_poses, relative
from oacdsl.segmentation.recording import Recording
from oacdsl.segmentation.result import Segmentation, SubAction

__all__ = ["AGENT_PATTERN", "SubActionMotion", "sub_action_motion", "sub_action_motions"]

#: Glob (case-insensitive) naming the agents, as the adaptive detector names them.
AGENT_PATTERN = "*hand*"

_RELATION_RANK = {"made": 0, "broken": 0, "kept": 1, None: 2}


@dataclass(frozen=True)
class SubActionMotion:
    """The demonstrated motion of one sub-action (SI units).

    Attributes:
        index: the sub-action's number (keyframe ``index`` → ``index + 1``).
        start_frame, end_frame: its first and last frame (inclusive).
        hand: the agent that moves the object (``None``: no hand acts).
        moved: the moved object (a held object, or the hand itself).
        target: what it works on; ``None``: the trajectory is in the world frame.
        relation: ``"made"``, ``"broken"`` or ``"kept"`` (moved ↔ target), or ``None``.
        times_s: (n,) frame times, seconds.
        T_target_object: (n, 4, 4) the moved object's pose in the target's frame (or the
            world's), metres; NaN where either has no pose.
        features: summary of that path.
        residual_m: the larger median rigid-fit residual of the two, metres.
    """

    index: int
    start_frame: int
    end_frame: int
    hand: str | None
    moved: str | None
    target: str | None
    relation: str | None
    times_s: np.ndarray
    T_target_object: np.ndarray
    features: MotionFeatures | None
    residual_m: float

    @property
    def frame_name(self) -> str:
        """The name of the frame the trajectory is given in (``target`` or ``world``)."""
        return self.target or "world"

    def to_json(self, trajectory: bool = True) -> dict[str, Any]:
        """A JSON-ready dict; ``trajectory`` adds times and 4×4 matrices (null in gaps)."""
        doc: dict[str, Any] = {
            "index": self.index,
            "start_frame": self.start_frame,
            "end_frame": self.end_frame,
            "start_s": round(float(self.times_s[0]), 6) if len(self.times_s) else None,
            "end_s": round(float(self.times_s[-1]), 6) if len(self.times_s) else None,
            "hand": self.hand,
            "moved": self.moved,
            "target": self.target,
            "frame": self.frame_name,
            "relation": self.relation,
            "residual_m": None if not np.isfinite(self.residual_m) else round(self.residual_m, 6),
            "features": self.features.to_json() if self.features else None,
        }
        if trajectory:
            doc["times_s"] = [round(float(t), 6) for t in self.times_s]
            doc["T_target_object"] = [
                None if not np.isfinite(T[0, 0]) else np.round(T, 6).tolist() for T in self.T_target_object
            ]
        return doc


def _agents(instances: tuple[str, ...]) -> list[str]:
    return [n for n in instances if fnmatch.fnmatch(n.lower(), AGENT_PATTERN)]


def _median(values: np.ndarray) -> float:
    finite = values[np.isfinite(values)]
    return float(np.median(finite)) if finite.size else float("nan")


def _travel(poses: ObjectPoses, a: int, b: int) -> float:
    pos = poses.positions_m[a : b + 1]
    pos = pos[np.isfinite(pos[:, 0])]
    return float(np.linalg.norm(np.diff(pos, axis=0), axis=1).sum()) if len(pos) > 1 else 0.0


def _candidates(
    sub: SubAction, agents: list[str], posed: Mapping[str, ObjectPoses]
) -> list[tuple[str, str, str | None, str | None]]:
    """(hand, moved, target, relation) that fit the sub-action (module doc)."""
    before, after = sub.before, sub.after
    objects = [o for o in sorted(before.instances) if o not in agents]
    out: list[tuple[str, str, str | None, str | None]] = []
    held = [(h, o) for h in agents for o in objects if before.touches(h, o) and o in posed]
    for h, o in held:
        for x in objects:
            if x == o or x not in posed:
                continue
            b, a = before.touches(o, x), after.touches(o, x)
            if b or a:
                out.append((h, o, x, "kept" if a and b else "made" if a else "broken"))
    holding = {h for h, _ in held}
    for h in agents:  # a free hand reaching for an object, or leaving one it did not carry
        if h in holding:
            continue
        for x in objects:
            b, a = before.touches(h, x), after.touches(h, x)
            if h in posed and x in posed and a != b:
                out.append((h, h, x, "made" if a else "broken"))
    return out or [(h, o, None, None) for h, o in held]


def sub_action_motions(
    recording: Recording, segmentation: Segmentation, poses: Mapping[str, ObjectPoses] | None = None
) -> list[SubActionMotion]:
    """The demonstrated motion of every sub-action of ``segmentation`` (module doc).

    ``poses`` defaults to :func:`~oacdsl.segmentation.poses.fit_poses` of the recording.
    """
    posed = dict(poses) if poses is not None else fit_poses(recording)
    return [sub_action_motion(recording, sub, posed) for sub in segmentation.sub_actions()]


def sub_action_motion(
    recording: Recording, sub: SubAction, posed: Mapping[str, ObjectPoses],
    pair: tuple[str, str] | None = None,
) -> SubActionMotion:
    """The demonstrated motion of one sub-action (module doc); ``posed``: the recording's
    :func:`~oacdsl.segmentation.poses.fit_poses` (instances with ≥ 3 markers). ``pair``
    (moved, target): that candidate when it is one (a step that names its objects: a ladle
    leaving the cup for the bowl moves relative to the bowl it goes into)."""
    agents = _agents(recording.instances)
    times = np.asarray(recording.times_s, dtype=np.float64)
    a, b = sub.start.frame, sub.end.frame
    span_t = times[a : b + 1]
    found = _candidates(sub, agents, posed)
    if pair is not None:
        found = [c for c in found if (c[1], c[2]) == pair] or found
    if not found:
        return SubActionMotion(
            sub.index,
            a,
            b,
            None,
            None,
            None,
            None,
            span_t,
            np.full((len(span_t), 4, 4), np.nan),
            None,
            float("nan"),
        )
    hand, moved, target, rel = min(
        found, key=lambda c: (-round(_travel(posed[c[1]], a, b), 4), _RELATION_RANK[c[3]], c[:3])
    )
    T_world_moved = posed[moved].T_world_object[a : b + 1]
    if target is None:
        T, residual = T_world_moved, _median(posed[moved].residual_m[a : b + 1])
    else:
        T = relative(posed[target].T_world_object[a : b + 1], T_world_moved)
        residual = max(_median(posed[n].residual_m[a : b + 1]) for n in (moved, target))
    return SubActionMotion(
        sub.index, a, b, hand, moved, target, rel, span_t, T, motion_features(span_t, T), residual
    )
