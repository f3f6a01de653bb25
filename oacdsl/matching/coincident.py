"""Near-coincident changes of the two hands: one OAC for their union when the library has one.

The segmentation keeps independent changes apart (``merge="connected"``: the left hand's grasp
and the right hand's are two keyframes however close they fall), so whether two such changes
meet in one keyframe no longer depends on a take's frame rate, speed or a one-frame shift. But a
library may have an OAC for the two at once (``grasp_both``, ``place_both``): a person who
takes a cup and a spoon 0.2 s apart did one bimanual action, and the robot should run it as one.

**The rule.** Two consecutive sub-actions ``i`` (keyframe ``k`` → ``k + 1``) and ``i + 1``
(``k + 1`` → ``k + 2``) are *near-coincident* when

- their changes name no instance in common (independent: each hand with its own objects), and
- keyframe ``k + 2`` comes less than the window after keyframe ``k + 1`` (the window: the
  segmentation's merge window in the demonstration's own time, ``merge_s`` × the recording's
  time factor ``parameters.scale.time``, :mod:`oacdsl.segmentation.scales`).

Keyframe ``k + 1`` is then dropped, and the two sub-actions become one (ending at keyframe
``k + 2``, where both changes are done, as the paper's merging places a group), **when an OAC matches
their union as a whole** (from the state before ``i`` to the state after ``i + 1``); else both
stay, each with its own match. So the union OAC is chosen whether or not the segmentation merged
the two changes into one keyframe (the paper's merging does so for changes within the window),
and in whichever order they were seen: a take at twice the speed that puts both grasps in one
10 Hz frame, or a 100 Hz take in which the other hand's grasp is seen first, composes to the
same ``grasp_both``. A longer chain of such sub-actions is joined pair by pair, left to right.

The rule lives in matching (as the transient rule, :mod:`oacdsl.matching.transient`) because it
needs the library: the segmentation reports every change it sees.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, replace

from oacdsl.matching.results import MatchResult
from oacdsl.matching.untracked import Untracked
from oacdsl.segmentation.keyframes import TIME_EPS_S
from oacdsl.segmentation.result import Keyframe, Segmentation, SubAction
from oacdsl.world import WorldState

__all__ = ["REFERENCE_FRAME_S", "Joined", "coincidence_window_s", "join_coincident", "matches_whole"]

#: Seconds: one frame of the reference demonstrations (the KIT bimanual clips, 10 Hz), by which
#: two changes the reference recording shows just outside the merge window may truly lie within it.
REFERENCE_FRAME_S = 0.1


@dataclass(frozen=True)
class Joined:
    """A dropped keyframe: the sub-actions on both sides (``gap_s`` apart) matched one OAC."""

    keyframe: Keyframe
    gap_s: float

    def to_json(self) -> dict[str, object]:
        return {"frame": int(self.keyframe.frame), "time_s": float(self.keyframe.time_s),
                "gap_s": round(float(self.gap_s), 6)}


def coincidence_window_s(segmentation: Segmentation) -> float:
    """The coincidence window of ``segmentation``, seconds: its parameters' merge window plus
    :data:`REFERENCE_FRAME_S`, in the demonstration's own time (times ``scale.time``); 0 (off)
    when the segmentation merges nothing (``merge_s`` 0) or was not made in the demonstration's
    pace (no ``parameters.scale``: ``--mode paper``, the robot's own segmentation, the paper's
    merging with fixed constants), whose consecutive keyframes the merge window already parts."""
    params = segmentation.parameters
    scale = params.get("scale")
    if not isinstance(scale, dict):
        return 0.0
    try:
        merge = float(params.get("merge_s", 0.0))
        factor = float(scale.get("time", 1.0))
    except (TypeError, ValueError):
        return 0.0
    return (merge + REFERENCE_FRAME_S) * factor if merge > 0 and factor > 0 else 0.0


def _names(before: WorldState, after: WorldState) -> set[str]:
    return {n for rel in before.relations ^ after.relations for n in rel}


def join_coincident(
    segmentation: Segmentation,
    matches_whole: Callable[[Keyframe, Keyframe], bool],
    window_s: float,
) -> tuple[Segmentation, tuple[Joined, ...]]:
    """``segmentation`` without the keyframes between near-coincident independent changes whose
    union an OAC matches (module doc), and those keyframes. ``matches_whole(start, end)``: does an
    OAC match the change from keyframe ``start`` (one of ``segmentation``'s) to ``end``'s state as
    a whole (the caller carries what matching needs along, e.g. predicted untracked relations)?"""
    kfs = list(segmentation.keyframes)
    if window_s <= 0 or len(kfs) < 3:
        return segmentation, ()
    kept: list[Keyframe] = [kfs[0]]
    joined: list[Joined] = []
    k = 1
    while k < len(kfs):
        cur = kfs[k]
        if k + 1 < len(kfs):
            prev, nxt = kept[-1], kfs[k + 1]
            gap = nxt.event_s - cur.event_s  # when the changes happened, below the frame
            if (gap < window_s - TIME_EPS_S
                    and not _names(prev.state, cur.state) & _names(cur.state, nxt.state)
                    and matches_whole(prev, nxt)):
                joined.append(Joined(cur, gap))  # the joined sub-action ends where both are done
                k += 1
                continue
        kept.append(cur)
        k += 1
    if not joined:
        return segmentation, ()
    return replace(segmentation, keyframes=tuple(kept)), tuple(joined)


def matches_whole(
    subs: Sequence[SubAction], match: Callable[[WorldState, WorldState], MatchResult],
    untracked: Untracked | None,
) -> Callable[[Keyframe, Keyframe], bool]:
    """The ``matches_whole`` of :func:`join_coincident` for sub-actions ``subs`` as matched (their
    states carry the predicted untracked relations, which the union is matched with)."""
    seen = {sa.start.frame: sa.before for sa in subs}

    def whole(start: Keyframe, end: Keyframe) -> bool:
        if untracked is None:
            return match(start.state, end.state).chosen is not None
        known = seen.get(start.frame)
        predicted = known.relations - start.state.relations if known is not None else untracked.initial
        before = untracked.with_predicted(start.state, predicted)
        return match(before, untracked.with_predicted(end.state, predicted)).chosen is not None

    return whole
