"""Scoring tool–target contacts during a clip's main action, and cross-hand contacts (KIT bimanual data).

The KIT labels say when each hand performs the clip's main action (Stir, Cut, …) but
not what touches what, so the true tool–target pairs of each clip are written down
here (:data:`KIT_TOOL_TARGETS`), from the dataset's README (which hand holds which
object) and the action's meaning, for every clip before any was scored:

- the **tool** is the object the acting hand holds; the **target** the object it works
  on (the cup stirred in, the bowl mixed in or scooped from, the cup scooped or poured
  into, the plate wiped, the cucumber cut or peeled, the bottle a lid is screwed on);
- the **window** is the frames either hand is labelled with the main action, widened by
  ``tolerance`` frames on both sides (labels and contacts disagree by up to 3 frames);
- a relation is a **contact during the action** when it touches on at least
  ``min_s`` seconds in a row inside the window (a flicker of a frame is not);
- per clip: **predicted** = the contacts during the action between a tool and another
  object (not a hand), **labelled** = the clip's tool–target pairs, **matched** =
  both; precision, recall and F1 as for events, summed over clips for the total.
  Contacts between two objects that are not tools (a cucumber lying on its board) are
  listed, not scored. **Coverage**: the fraction of the (unwidened) main-action frames on
  which a labelled pair touches.

**Cross-hand frames**: frames where a hand touches the object the other hand holds
(the object nearest to each hand during its labelled contact, see
:func:`segeval.evaluate.nearest_object`), when that object is not also
its own.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field

import numpy as np

from oacdsl.segmentation.result import Segmentation
from segeval.evaluate import CONTACT_LABELS, Score, states_per_frame

__all__ = ["KIT_TOOL_TARGETS", "MAIN_ACTIONS", "ToolScore", "cross_hand_frames", "score_tools"]

#: The main actions of the KIT bimanual clips (labels that are neither fine actions nor no-contact).
MAIN_ACTIONS = frozenset(CONTACT_LABELS - {"Move", "Hold", "Place"})

#: Main action → its (tool, target) pairs. RollOut has none: its dough carries no markers.
KIT_TOOL_TARGETS: dict[str, tuple[tuple[str, str], ...]] = {
    "Pour": (("milk_small", "cup_small"),),
    "Stir": (("tablespoon", "cup_large"),),
    "Mix": (("salad_spoon", "mixing_bowl_green"), ("salad_fork", "mixing_bowl_green")),
    "Scoop": (("ladle", "mixing_bowl_green"), ("ladle", "cup_small")),
    "Wipe": (("sponge_small", "plate_dish"),),
    "Cut": (("knife_black", "cucumber_attachment"),),
    "Open": (("apple_juice_lid", "apple_juice"),),
    "Close": (("apple_juice_lid", "apple_juice"),),
    "Peel": (("peeler", "cucumber_attachment"),),
    "RollOut": (),
    "Transfer": (("knife_black", "cutting_board_small"), ("knife_black", "mixing_bowl_green")),
}


@dataclass
class ToolScore:
    """Tool–target contacts of one clip during its main action."""

    action: str
    score: Score
    window: tuple[int, int]  # frames [a, b), widened
    labelled: list[tuple[str, str]]
    predicted: list[tuple[str, str]]  # (tool, other) contacts during the action
    coverage: dict[tuple[str, str], float] = field(default_factory=dict)  # labelled pair → fraction
    other: list[tuple[str, str]] = field(default_factory=list)  # object–object contacts not scored


def _pair_frames(segmentation: Segmentation, a: str, b: str) -> np.ndarray:
    """(F,) bool: frames on which ``a`` and ``b`` touch in the world state in force."""
    per_keyframe = [b in kf.state.partners(a) for kf in segmentation.keyframes]
    return np.array([per_keyframe[k] for k in states_per_frame(segmentation)], dtype=bool)


def _longest_run(mask: np.ndarray) -> int:
    padded = np.concatenate([[False], mask, [False]])
    edges = np.flatnonzero(padded[1:] != padded[:-1])
    return int((edges[1::2] - edges[::2]).max()) if edges.size else 0


def score_tools(
    action: str,
    segmentation: Segmentation,
    labels: Mapping[str, Sequence[str]],
    pairs: Sequence[tuple[str, str]],
    tolerance: int = 3,
    min_s: float = 0.3,
) -> ToolScore:
    """Score the contacts of the tools of ``pairs`` during the frames labelled ``action``."""
    hands = set(labels)
    acting = np.zeros(segmentation.frames, dtype=bool)
    for hand_labels in labels.values():
        acting |= np.array([lab == action for lab in hand_labels], dtype=bool)
    if not acting.any():
        return ToolScore(action, Score(0, 0, len(pairs)), (0, 0), list(pairs), [])
    where = np.flatnonzero(acting)
    lo, hi = max(0, int(where[0]) - tolerance), min(segmentation.frames, int(where[-1]) + 1 + tolerance)
    min_frames = max(1, round(min_s * segmentation.rate_hz))
    tools = {t for t, _ in pairs}
    objects = [i for i in segmentation.instances if i not in hands]
    predicted: list[tuple[str, str]] = []
    other: list[tuple[str, str]] = []
    for i, a in enumerate(objects):
        for b in objects[i + 1 :]:
            if _longest_run(_pair_frames(segmentation, a, b)[lo:hi]) < min_frames:
                continue
            if a in tools or b in tools:
                predicted.append((a, b) if a in tools else (b, a))
            else:
                other.append((a, b))
    label_set = {frozenset(p) for p in pairs}
    matched = sum(1 for p in predicted if frozenset(p) in label_set)
    coverage = {
        (t, g): float(_pair_frames(segmentation, t, g)[acting].mean()) if {t, g} <= set(objects) else 0.0
        for t, g in pairs
    }
    return ToolScore(
        action, Score(matched, len(predicted), len(pairs)), (lo, hi), list(pairs), predicted, coverage, other
    )


def cross_hand_frames(segmentation: Segmentation, held: Mapping[str, str | None]) -> dict[str, int]:
    """Hand → frames it touches the object ``held`` by the other hand (not also its own)."""
    out: dict[str, int] = {}
    for hand, own in held.items():
        foreign = {obj for other, obj in held.items() if other != hand and obj is not None and obj != own}
        frames = np.zeros(segmentation.frames, dtype=bool)
        for obj in foreign:
            frames |= _pair_frames(segmentation, hand, obj)
        out[hand] = int(frames.sum())
    return out
