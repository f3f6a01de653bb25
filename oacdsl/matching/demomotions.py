"""The demonstrated motion of each sub-action, for the skill parameters of the composed steps
(:mod:`oacdsl.matching.demoparams`): a sub-action that *makes* a relation extended over the
span the relation then lasts (:func:`dwelling`), and the motion of a named pair of objects on
demand (:meth:`DemonstratedMotions.of_pair`)."""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping, Sequence

import numpy as np

from oacdsl.segmentation.motion import SubActionMotion
from oacdsl.segmentation.poses import ObjectPoses
from oacdsl.segmentation.recording import Recording
from oacdsl.segmentation.result import SubAction

__all__ = ["DemonstratedMotions", "demonstrated_motions", "dwelling"]


def demonstrated_motions(recording: Recording, subs: Sequence[SubAction]) -> dict[int, SubActionMotion]:
    """The motion of each sub-action in ``subs`` (the matcher's: transient keyframes dropped),
    keyed by the sub-action's first frame; each one that *makes* a relation extended over the
    span the relation then lasts (:func:`dwelling`)."""
    from oacdsl.segmentation.motion import sub_action_motion
    from oacdsl.segmentation.poses import fit_poses

    posed = fit_poses(recording)
    motions = [sub_action_motion(recording, sub, posed) for sub in subs]
    found = DemonstratedMotions(
        {sub.start.frame: dwelling(recording, motions, k, posed, _made_with(sub, motions[k].target))
         for k, sub in enumerate(subs)})
    found.recording, found.posed, found.subs, found.motions = recording, posed, list(subs), motions
    return found


class DemonstratedMotions(dict[int, SubActionMotion]):
    """:func:`demonstrated_motions`' answer, which can also give a sub-action's motion of a
    named pair of objects (:meth:`of_pair`)."""

    recording: Recording
    posed: Mapping[str, ObjectPoses]
    subs: list[SubAction]
    motions: list[SubActionMotion]

    def of_pair(self, frame: int, moved: str, target: str) -> SubActionMotion | None:
        """The motion of ``moved`` relative to ``target`` in the sub-action starting at ``frame``
        (extended as :func:`dwelling` does), None when the demonstration has no such candidate."""
        from oacdsl.segmentation.motion import sub_action_motion

        k = next((i for i, sub in enumerate(self.subs) if sub.start.frame == frame), None)
        if k is None:
            return None
        m = sub_action_motion(self.recording, self.subs[k], self.posed, (moved, target))
        if (m.moved, m.target) != (moved, target):
            return None
        motions = [*self.motions[:k], m, *self.motions[k + 1 :]]
        return dwelling(self.recording, motions, k, self.posed, _made_with(self.subs[k], m.target))


def _made_with(sub: SubAction, target: str | None) -> frozenset[str]:
    """The instances that start touching ``target`` in ``sub``."""
    if target is None:
        return frozenset()
    return sub.after.partners(target) - sub.before.partners(target)


def dwelling(recording: Recording, motions: Sequence[SubActionMotion], k: int,
             posed: Mapping[str, ObjectPoses], together: frozenset[str] = frozenset()) -> SubActionMotion:
    """Motion ``k`` over the whole time its object stays with its target.

    A skill that stirs, wipes or cuts runs in the step whose effect is the tool touching
    its target (the sub-action that *makes* the relation); the demonstrated circles or
    strokes come after, while the relation is *kept*, until the sub-action that *breaks*
    it (or the recording's end, when nothing breaks it: the dough's mixing follows the
    last keyframe). So the motion of a sub-action that makes a relation is extended over
    the following sub-actions of the same object and target that keep it, and the one
    that breaks it; its features are computed on that span (the core still leaves out
    the way in and out). ``together``: the objects that started touching the target in the
    same sub-action (KIT Mix: fork and spoon into the bowl at once, mixed by both hands);
    a following sub-action that moves any of them in the target counts as well.
    """
    m = motions[k]
    if m.relation != "made" or m.target is None or m.moved is None:
        return m
    end = m.end_frame
    followers: list[SubActionMotion] = []
    for n in motions[k + 1 :]:
        same = n.target == m.target and n.moved in together | {m.moved}
        if not same or n.relation not in ("kept", "broken"):
            break
        end = n.end_frame
        followers.append(n)
        if n.relation == "broken":
            break
    else:  # the relation still holds at the last keyframe: it lasts to the recording's end
        end = len(recording.times_s) - 1
    if end == m.end_frame:
        return m
    from oacdsl.segmentation.motionfeatures import motion_features
    from oacdsl.segmentation.poses import relative

    a = m.start_frame
    times = np.asarray(recording.times_s[a : end + 1], dtype=np.float64)
    T = relative(posed[m.target].T_world_object[a : end + 1], posed[m.moved].T_world_object[a : end + 1])
    merged = dataclasses.replace(m, end_frame=end, times_s=times, T_target_object=T,
                                 features=motion_features(times, T))
    # a period at 10 Hz hangs on a sample or two: when the whole span shows none but a
    # following sub-action does (KIT Stir: frames 21-48 none, 27-48 0.50 s), that one tells
    periodic = [n for n in followers if n.features is not None and n.features.period_s is not None]
    if merged.features is not None and merged.features.period_s is None and periodic:
        return max(periodic, key=lambda n: n.end_frame - n.start_frame)
    return merged
