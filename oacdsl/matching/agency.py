"""Which hand acted: a tie between matches that the world states cannot break, broken by motion.

The touching relation is symmetric, so a world state cannot say which of two hands moved.
When the left hand holds a cucumber and the right hand a peeler and the two come to touch,
``touch(h, o, t)`` (``pre h <-> o, not o <-> t``, ``effect o <-> t``) matches as
``touch(right_hand, peeler, cucumber)`` and as ``touch(left_hand, cucumber, peeler)``, and the
two tie on every criterion of the ranking (:meth:`oacdsl.matching.results.Match.rank_key`): the
binding order would choose the left hand, which the demonstration kept still.

With the demonstration's motion capture, the tied leaders are ordered by how far the hands
(instances of class ``Hand``) each binds moved during the sub-action (:func:`hand_travel`): the
hand that acted moved. Only a tie is reordered, and only by a strictly longer path; ranks
1-4 stay as they are.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable, Collection

import numpy as np

from oacdsl.matching.results import Match, MatchResult
from oacdsl.segmentation.recording import Recording

__all__ = ["Travel", "by_motion", "hand_travel"]

#: (instance, first frame, last frame) → how far it moved, metres.
Travel = Callable[[str, int, int], float]


def hand_travel(recording: Recording) -> Travel:
    """How far an instance's markers moved between two frames (inclusive), metres: per marker
    the summed steps between frames where it is seen, the median over its markers (a marker
    dropping out does not move the rest)."""

    def travel(name: str, start: int, end: int) -> float:
        if name not in recording.groups or end <= start:
            return 0.0
        p = recording.group_positions(name)[max(0, start): end + 1]
        steps = np.linalg.norm(np.diff(p, axis=0), axis=2)  # (frames - 1, markers); NaN where unseen
        seen = ~np.isnan(steps).all(axis=0)
        return float(np.median(np.nansum(steps[:, seen], axis=0))) if seen.any() else 0.0

    return travel


def _agents_text(match: Match, agents: Collection[str], moved: dict[str, float]) -> str:
    hands = [i for _, i in match.binding if i in agents]
    return ", ".join(f"{h} {moved[h]:.2f} m" for h in hands) or "no hand"


def by_motion(
    result: MatchResult, agents: Collection[str], travel: Travel, start: int, end: int
) -> MatchResult:
    """``result`` with its tied leaders ordered by how far their hands moved over the frames
    ``start``-``end`` (longest first), when that tells them apart; else ``result`` itself."""
    if not result.ambiguous:
        return result
    key = result.matches[0].rank_key()[:4]
    n = next((k for k, m in enumerate(result.matches) if m.rank_key()[:4] != key), len(result.matches))
    tied = result.matches[:n]
    moved = {i: travel(i, start, end) for m in tied for _, i in m.binding if i in agents}
    score = [sum(moved.get(i, 0.0) for _, i in m.binding) for m in tied]
    best = max(range(n), key=lambda k: (score[k], -k))
    if any(score[k] >= score[best] for k in range(n) if k != best and not tied[k].same_meaning(tied[best])):
        return result  # no hand moved farther than the others
    order = [best, *(k for k in range(n) if k != best)]
    matches = tuple(tied[k] for k in order) + result.matches[n:]
    a, b = matches[0], matches[1]
    reason = (
        f"{len(matches)} matches; chose {a.text()}: it ties with {b.text()} on explained change, class"
        f" specificity, idle effects and number of conditions; the demonstration's motion decides: its"
        f" hands moved farther during the sub-action ({_agents_text(a, agents, moved)}; {b.text()}:"
        f" {_agents_text(b, agents, moved)})"
    )
    return dataclasses.replace(result, matches=matches, reason=reason, by_motion=True)
