"""A take's segmentation scored against the original's labels (issue 20: hand-contact F1 on
takes, the stand-in for clips and variations the project has not seen).

A take (:mod:`oacdsl.segmentation.takes`) changes the recording's positions (rotated, moved,
scaled, mirrored, a marker gap), its pace (``stretched``: the same motion in ``factor`` times the
time) or its frame rate (``resampled``), never what happens when. So the take's moment ``u``
shows the original's moment ``t0 + (u - u0) / factor``, where ``factor`` is the take's duration
over the original's (1 for every take but a stretched one).

The take's segmentation is put on the original's frames (:func:`on_original_grid`): the state at
an original frame is the take's state at the moment that frame shows, as if the take had been
recorded at the original's rate and pace. Its events are then scored against the original's own
labels with the original's tolerance in frames, the hands renamed for a mirrored take
(:func:`labels_for_take`). Scoring on the take's own frames instead (the labels mapped onto them,
the tolerance in the same seconds) moves events the original finds exactly at the tolerance from
their label (KIT Cut's right-hand grasp, Mix's right-hand let-go: 0.3 s, 3 frames) just outside it
whenever the take's frames fall elsewhere, though the segmentation found the same moment.
"""

from __future__ import annotations

import dataclasses
import math
import re
from collections.abc import Mapping, Sequence

from oacdsl.segmentation.result import Segmentation

__all__ = ["labels_for_take", "on_original_grid", "stated_factor", "take_factor"]

_STRETCH = re.compile(r"\(time x([0-9.eE+-]+)\)")


def take_factor(original_times_s: Sequence[float], take_times_s: Sequence[float]) -> float:
    """The take's duration over the original's (2: twice as slow); 1 for a single frame."""
    before = float(original_times_s[-1]) - float(original_times_s[0])
    after = float(take_times_s[-1]) - float(take_times_s[0])
    return after / before if before > 0 and after > 0 else 1.0


def stated_factor(source: str) -> float | None:
    """The time factor a take's ``source`` says it was made with (``stretched`` appends ``(time
    x0.8)``; several multiply), or ``None`` when it names none. Exact, where the durations are not:
    a stretched take ends on its last whole frame, up to a frame short (KIT Mix ×0.8: 0.792 by the
    durations, which put its right hand's let-go, 5.78 s, a frame late)."""
    found = [float(k) for k in _STRETCH.findall(source)]
    return math.prod(found) if found else None


def on_original_grid(take: Segmentation, original_times_s: Sequence[float],
                     take_times_s: Sequence[float], factor: float | None = None) -> Segmentation:
    """``take`` (a segmentation of a take) on the original's frames. A keyframe at take frame
    ``k`` says the change happened after frame ``k - 1``'s moment and by frame ``k``'s: at its
    ``change_s`` where the segmentation tells (a contact's distance crossing its threshold,
    :mod:`oacdsl.segmentation.subframe`), else in the middle of the two. It goes to the first
    original frame at or after that moment, as the original's rate would have seen it (KIT Mix's
    right hand leaves the spoon at 5.78 s, seen at 5.8 s by the original and at 5.875 s by a take
    ×0.8, whose middle of the two frames, 5.81 s, put it a frame later). Keyframes that fall on
    one frame leave the last one's state. ``factor``: the take's time factor, when known
    (:func:`stated_factor`); else from the durations (:func:`take_factor`)."""
    t0, u0 = float(original_times_s[0]), float(take_times_s[0])
    n = len(original_times_s)
    rate = (n - 1) / (float(original_times_s[-1]) - t0) if n > 1 else 1.0
    factor = take_factor(original_times_s, take_times_s) if factor is None else factor
    moved = []
    for kf in take.keyframes:
        seen = float(take_times_s[kf.frame]) - u0
        before = float(take_times_s[kf.frame - 1]) - u0 if kf.frame > 0 else seen
        moment = (before + seen) / 2 if kf.change_s is None else kf.change_s - u0
        frame = min(n - 1, max(0, math.ceil(moment / factor * rate - 1e-6)))
        if moved and moved[-1].frame == frame:
            moved.pop()
        moved.append(dataclasses.replace(kf, frame=frame, time_s=float(original_times_s[frame])))
    return dataclasses.replace(take, frames=n, rate_hz=rate, keyframes=tuple(moved))


def labels_for_take(labels: Mapping[str, Sequence[str]], hand_map: Mapping[str, str] | None = None
                    ) -> dict[str, list[str]]:
    """The original's labels under the take's hand names (``hand_map``: original → take's)."""
    hands = dict(hand_map or {})
    return {hands.get(hand, hand): list(per_frame) for hand, per_frame in labels.items()}
