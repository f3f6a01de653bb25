"""Scoring hand–object contact keyframes against per-frame hand labels (KIT bimanual data).

The KIT Bimanual Manipulation data labels every frame of each hand with one of
Idle, Approach, Move, Hold, Place, Retreat or the clip's main action (Pour, Cut, …).
A hand is **in contact** on frames labelled Move, Hold, Place or a main action.
A segmentation says a hand is in contact on a frame when, in the world state in
force at that frame, it touches any instance that is not a hand.

**Events** are the contact starts (first frame of a contact run) and ends (first
frame after it) per hand. A predicted event matches a labelled event of the same
hand and kind within ``tolerance`` frames, one to one (closest pairs first).
Precision = matched / predicted, recall = matched / labelled, F1 their harmonic
mean; per clip and overall (events summed over clips).
"""

from __future__ import annotations

import csv
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from oacdsl.errors import RecordingError, did_you_mean
from oacdsl.segmentation.result import Segmentation

__all__ = [
    "CONTACT_LABELS",
    "HAND_COLUMNS",
    "NO_CONTACT_LABELS",
    "ClipScore",
    "Event",
    "Score",
    "contact_from_labels",
    "contact_from_segmentation",
    "events",
    "match_events",
    "nearest_object",
    "read_labels",
    "score_clip",
    "states_per_frame",
    "touched_objects",
]

#: Labels of frames in which the hand touches an object (the main actions and the fine
#: actions Move, Hold, Place).
CONTACT_LABELS = frozenset(
    {
        "Open",
        "Close",
        "Cut",
        "Mix",
        "Peel",
        "Pour",
        "RollOut",
        "Scoop",
        "Stir",
        "Transfer",
        "Wipe",
        "Move",
        "Hold",
        "Place",
    }
)
#: Labels of frames without contact.
NO_CONTACT_LABELS = frozenset({"Idle", "Approach", "Retreat"})
#: Label-file column → instance name of the hand.
HAND_COLUMNS = {"lhand_action": "left_hand", "rhand_action": "right_hand"}


@dataclass(frozen=True, order=True)
class Event:
    """A contact start (``kind="start"``) or end (``"end"``) of one hand at a frame."""

    frame: int
    hand: str
    kind: str


@dataclass
class Score:
    """Event counts and the measures derived from them."""

    matched: int = 0
    predicted: int = 0
    labelled: int = 0

    @property
    def precision(self) -> float:
        return self.matched / self.predicted if self.predicted else (1.0 if not self.labelled else 0.0)

    @property
    def recall(self) -> float:
        return self.matched / self.labelled if self.labelled else 1.0

    @property
    def f1(self) -> float:
        p, r = self.precision, self.recall
        return 2 * p * r / (p + r) if p + r else 0.0

    def __iadd__(self, other: Score) -> Score:
        self.matched += other.matched
        self.predicted += other.predicted
        self.labelled += other.labelled
        return self


@dataclass
class ClipScore:
    """The score of one clip, its events, and what each hand was found touching."""

    clip: str
    score: Score
    predicted: list[Event]
    labelled: list[Event]
    matches: list[tuple[Event, Event]]
    touched: dict[str, dict[str, int]] = field(default_factory=dict)  # hand → object → frames
    frame_agreement: dict[str, float] = field(default_factory=dict)  # hand → fraction of frames


def read_labels(path: str | Path) -> dict[str, list[str]]:
    """Per-hand frame labels of a ``*.labels.csv`` (``frame,time_s,lhand_action,rhand_action``)."""
    path = Path(path)
    location = str(path)
    try:
        with path.open(newline="", encoding="utf-8") as fh:
            rows = list(csv.reader(fh))
    except OSError as err:
        raise RecordingError(f"cannot read: {err.strerror or err}", location=location) from None
    if not rows:
        raise RecordingError("empty label file", location=location)
    header = [h.strip() for h in rows[0]]
    missing = [c for c in ("frame", *HAND_COLUMNS) if c not in header]
    if missing:
        raise RecordingError(
            f"line 1: no column {missing[0]!r} (expected frame,time_s,lhand_action,rhand_action)",
            location=location,
        )
    out: dict[str, list[str]] = {hand: [] for hand in HAND_COLUMNS.values()}
    known = CONTACT_LABELS | NO_CONTACT_LABELS
    for line_no, row in enumerate(rows[1:], start=2):
        if not any(f.strip() for f in row):
            continue
        if len(row) != len(header):
            raise RecordingError(
                f"line {line_no}: {len(row)} fields, expected {len(header)}", location=location
            )
        if row[header.index("frame")].strip() != str(len(out["left_hand"])):
            raise RecordingError(
                f"line {line_no}: frame {row[header.index('frame')]!r} is out of order", location=location
            )
        for column, hand in HAND_COLUMNS.items():
            label = row[header.index(column)].strip()
            if label not in known:
                raise RecordingError(
                    f"line {line_no}: unknown label {label!r}{did_you_mean(label, known)}", location=location
                )
            out[hand].append(label)
    if not out["left_hand"]:
        raise RecordingError("the label file has no frames", location=location)
    return out


def contact_from_labels(labels: Sequence[str]) -> np.ndarray:
    """(F,) bool: frames whose label is a contact label."""
    return np.array([label in CONTACT_LABELS for label in labels], dtype=bool)


def states_per_frame(segmentation: Segmentation) -> list[int]:
    """Index of the keyframe in force at each frame."""
    index = np.zeros(segmentation.frames, dtype=np.intp)
    for k, kf in enumerate(segmentation.keyframes):
        index[kf.frame :] = k
    return index.tolist()


def contact_from_segmentation(segmentation: Segmentation, hand: str, hands: Iterable[str]) -> np.ndarray:
    """(F,) bool: frames where ``hand`` touches an instance that is not in ``hands``."""
    others = set(hands)
    per_keyframe = [any(p not in others for p in kf.state.partners(hand)) for kf in segmentation.keyframes]
    return np.array([per_keyframe[k] for k in states_per_frame(segmentation)], dtype=bool)


def touched_objects(segmentation: Segmentation, hand: str, hands: Iterable[str]) -> dict[str, int]:
    """Object → number of frames ``hand`` was found touching it."""
    others = set(hands)
    counts: dict[str, int] = {}
    for k in states_per_frame(segmentation):
        for partner in segmentation.keyframes[k].state.partners(hand):
            if partner not in others:
                counts[partner] = counts.get(partner, 0) + 1
    return dict(sorted(counts.items(), key=lambda kv: (-kv[1], kv[0])))


def events(contact: np.ndarray, hand: str) -> list[Event]:
    """Contact starts (first frame of a run, frame 0 included) and ends (first frame after a run)."""
    padded = np.concatenate([[False], np.asarray(contact, dtype=bool)])
    change = np.flatnonzero(padded[1:] != padded[:-1])
    return [Event(int(f), hand, "start" if contact[f] else "end") for f in change]


def match_events(
    predicted: Sequence[Event], labelled: Sequence[Event], tolerance: int
) -> list[tuple[Event, Event]]:
    """One-to-one matches (predicted, labelled) of the same hand and kind within ``tolerance`` frames."""
    candidates = sorted(
        (abs(p.frame - t.frame), i, j)
        for i, p in enumerate(predicted)
        for j, t in enumerate(labelled)
        if p.hand == t.hand and p.kind == t.kind and abs(p.frame - t.frame) <= tolerance
    )
    used_p: set[int] = set()
    used_t: set[int] = set()
    out = []
    for _, i, j in candidates:
        if i not in used_p and j not in used_t:
            used_p.add(i)
            used_t.add(j)
            out.append((predicted[i], labelled[j]))
    return sorted(out)


def score_clip(
    clip: str, segmentation: Segmentation, labels: Mapping[str, Sequence[str]], tolerance: int = 3
) -> ClipScore:
    """Score one clip's segmentation against its per-hand labels."""
    hands = tuple(labels)
    predicted: list[Event] = []
    labelled: list[Event] = []
    touched: dict[str, dict[str, int]] = {}
    agreement: dict[str, float] = {}
    for hand, hand_labels in labels.items():
        if len(hand_labels) != segmentation.frames:
            raise RecordingError(
                f"{len(hand_labels)} labelled frames for a recording of {segmentation.frames} frames",
                location=clip,
            )
        if hand not in segmentation.instances:
            raise RecordingError(
                f"no instance {hand!r} in the segmentation{did_you_mean(hand, segmentation.instances)}",
                location=clip,
            )
        truth = contact_from_labels(hand_labels)
        found = contact_from_segmentation(segmentation, hand, hands)
        labelled += events(truth, hand)
        predicted += events(found, hand)
        touched[hand] = touched_objects(segmentation, hand, hands)
        agreement[hand] = float(np.mean(truth == found))
    matches = match_events(predicted, labelled, tolerance)
    score = Score(len(matches), len(predicted), len(labelled))
    return ClipScore(clip, score, sorted(predicted), sorted(labelled), matches, touched, agreement)


def nearest_object(
    positions_hand: np.ndarray, objects: Mapping[str, np.ndarray], frames: np.ndarray
) -> str | None:
    """The object whose markers come closest to the hand's markers (median over ``frames``).

    ``positions_hand`` (F, h, 3), ``objects`` name → (F, k, 3), metres; ``frames`` (F,) bool.
    A reference for "which object did the hand hold" that needs no segmentation.
    """
    if not frames.any() or not objects:
        return None
    hand = positions_hand[frames]
    best: tuple[float, str] | None = None
    for name, pos in objects.items():
        dist = np.linalg.norm(hand[:, :, None, :] - pos[frames][:, None, :, :], axis=-1)
        median = float(np.nanmedian(np.nanmin(dist.reshape(dist.shape[0], -1), axis=1)))
        if best is None or median < best[0]:
            best = (median, name)
    return best[1] if best else None
