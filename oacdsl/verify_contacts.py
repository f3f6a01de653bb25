"""A simulated run's own contacts: the file beside its recording, and the keyframes they make.

``oacc run``/``oacc reproduce`` record, beside the robot's virtual markers, the touching
relations MuJoCo reports between the tracked instances (:class:`~oacdsl.runtime.recorder.
ContactRecorder`). They are written next to the recording as ``NAME.contacts.json``
(``execution.c3d`` → ``execution.contacts.json``); ``oacc verify`` reads that file when
it is there, and the relations check then compares the demonstration with what the
simulation says touched, not with what an AAS sees in the virtual markers (the AAS's view
is reported beside it, as a segmentation finding).

The keyframes: per relation, a change counts once the new value has held
:attr:`~oacdsl.verify_tolerances.VerifyTolerances.contact_hold_s` (a contact flickering
for a step or two is no change); a contact that lifts off for less than ``contact_gap_s``
and comes back is held on (a stirring tool that rises off the bowl's floor between two
touches); changes closer than ``contact_merge_s`` are one keyframe, at the last of them
(as the AAS merges). A hand that let go of an object only to take it again within one step
(a turn continued in strokes, :mod:`oacdsl.runtime.motion.rotate`) is no change of the task:
the runtime records each such regrasp, the file lists it under ``internal`` (the relation and
its frames), and the relation holds through it.
"""

from __future__ import annotations

import json
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from oacdsl.errors import InputError
from oacdsl.segmentation.result import Keyframe, Segmentation
from oacdsl.verify_tolerances import DEFAULT_TOLERANCES, VerifyTolerances
from oacdsl.world import Relation, WorldState, relation

__all__ = ["FORMAT", "SimContacts", "contacts_path", "read_contacts", "write_contacts", "internal_windows"]

#: The ``format`` field of a contacts file.
FORMAT = "oacdsl-sim-contacts"


@dataclass(frozen=True)
class SimContacts:
    """Touching relations of a simulated run: the set after each change (frame 0 included)."""

    rate_hz: float
    frames: int
    instances: tuple[str, ...]
    changes: tuple[tuple[int, frozenset[Relation]], ...]
    #: The AAS parameters the run's virtual markers are segmented with (``AasParams`` fields).
    aas: Mapping[str, Any]
    #: (relation, from frame, to frame): a hand let go of an object and took it again within a
    #: step (a regrasp); the relation holds through these frames.
    internal: tuple[tuple[Relation, int, int], ...] = ()

    @classmethod
    def from_json(cls, doc: Mapping[str, Any], where: str = "contacts") -> SimContacts:
        try:
            if doc.get("format") != FORMAT:
                raise ValueError(f"format is {doc.get('format')!r}, expected {FORMAT!r}")
            changes = tuple(
                (int(c["frame"]), frozenset(relation(str(a), str(b)) for a, b in c["relations"]))
                for c in doc["changes"]
            )
            rate = float(doc["rate_hz"])
            if not rate > 0 or any(b[0] < a[0] for a, b in zip(changes, changes[1:], strict=False)):
                raise ValueError("a positive rate and frames in order are needed")
            return cls(rate, int(doc["frames"]), tuple(str(i) for i in doc["instances"]), changes,
                       dict(doc.get("aas", {})), internal_windows(doc.get("internal", ())))
        except (KeyError, TypeError, ValueError) as error:
            what = f"missing key {error}" if isinstance(error, KeyError) else str(error)
            raise InputError(f"not a contacts file: {what}", location=where) from None

    def to_json(self) -> dict[str, Any]:
        return {
            "format": FORMAT,
            "version": 1,
            "rate_hz": self.rate_hz,
            "frames": self.frames,
            "instances": list(self.instances),
            "aas": dict(self.aas),
            "changes": [{"frame": f, "relations": [list(r) for r in sorted(rels)]}
                        for f, rels in self.changes],
            "internal": [{"relation": list(r), "from_frame": a, "to_frame": b} for r, a, b in self.internal],
        }

    def segmentation(
        self, instances: tuple[str, ...], tolerances: VerifyTolerances = DEFAULT_TOLERANCES,
        source: str = "simulation contacts",
    ) -> Segmentation:
        """Keyframes of the relations among ``instances`` (module docstring)."""
        names = tuple(sorted(instances))
        keep = set(names)
        pairs = sorted({r for _, rels in self.changes for r in rels if r[0] in keep and r[1] in keep})
        n = max(self.frames, (self.changes[-1][0] + 1) if self.changes else 1)
        on = np.zeros((n, len(pairs)), dtype=bool)
        bounds = [f for f, _ in self.changes] + [n]
        for (start, rels), stop in zip(self.changes, bounds[1:], strict=True):
            for j, p in enumerate(pairs):
                if p in rels:
                    on[start:stop, j] = True
        for r, a, b in self.internal:  # a regrasp within a step: the hand holds on through it
            if r in pairs:
                on[max(a, 0):min(b, n), pairs.index(r)] = True
        hold = max(1, int(round(tolerances.contact_hold_s * self.rate_hz)))
        gap = int(round(tolerances.contact_gap_s * self.rate_hz))
        on = np.stack([_bridged(_debounced(on[:, j], hold), gap) for j in range(len(pairs))], axis=1) \
            if pairs else on
        change_frames = [0] + [int(i) + 1 for i in np.flatnonzero((on[1:] != on[:-1]).any(axis=1))]
        merge = tolerances.contact_merge_s * self.rate_hz
        kept: list[int] = [0]
        for f in change_frames[1:]:
            if len(kept) > 1 and f - kept[-1] < merge:
                kept[-1] = f  # merged into the last of them
            else:
                kept.append(f)

        def state(f: int) -> WorldState:
            return WorldState.of(names, [p for j, p in enumerate(pairs) if on[f, j]])

        keyframes = tuple(Keyframe(f, f / self.rate_hz, state(f)) for f in kept)
        params = {"source": "simulation contacts", "hold_s": tolerances.contact_hold_s,
                  "merge_s": tolerances.contact_merge_s}
        return Segmentation(source, self.rate_hz, n, names, keyframes, params)


def internal_windows(items: Any) -> tuple[tuple[Relation, int, int], ...]:
    """The ``internal`` list of a contacts document as (relation, from frame, to frame)."""
    out = []
    for item in items:
        a, b = item["relation"]
        start, stop = int(item["from_frame"]), int(item["to_frame"])
        if stop < start:
            raise ValueError(f"an internal window ends (frame {stop}) before it starts ({start})")
        out.append((relation(str(a), str(b)), start, stop))
    return tuple(out)


def _debounced(x: np.ndarray, hold: int) -> np.ndarray:
    """``x`` with every run shorter than ``hold`` frames that lies between two others flipped
    (the value before it continues); the shortest runs go first."""
    y = x.copy()
    while True:
        edges = np.flatnonzero(y[1:] != y[:-1]) + 1
        starts = np.r_[0, edges]
        stops = np.r_[edges, len(y)]
        inner = [(b - a, a, b) for a, b in zip(starts[1:-1], stops[1:-1], strict=True) if b - a < hold]
        if not inner:
            return y
        _, a, b = min(inner)
        y[a:b] = y[a - 1]


def _bridged(x: np.ndarray, gap: int) -> np.ndarray:
    """``x`` with every run of False shorter than ``gap`` frames between two True runs set True."""
    y = x.copy()
    edges = np.flatnonzero(y[1:] != y[:-1]) + 1
    starts, stops = np.r_[0, edges], np.r_[edges, len(y)]
    for a, b in zip(starts[1:-1], stops[1:-1], strict=True):
        if not y[a] and b - a < gap:
            y[a:b] = True
    return y


def contacts_path(recording: str | Path) -> Path:
    """``run/execution.c3d`` → ``run/execution.contacts.json``."""
    path = Path(recording)
    name = path.name
    for suffix in (".mmm.xml", ".c3d", ".xml", ".tsv", ".csv"):
        if name.lower().endswith(suffix):
            name = name[: -len(suffix)]
            break
    return path.with_name(f"{name}.contacts.json")


def read_contacts(path: str | Path) -> SimContacts:
    """The contacts file at ``path``; :class:`InputError` naming it when it cannot be read."""
    try:
        doc = json.loads(Path(path).read_text(encoding="utf-8"))
    except OSError as error:
        raise InputError(f"cannot read: {error.strerror or error}", location=str(path)) from None
    except (UnicodeDecodeError, json.JSONDecodeError) as error:
        raise InputError(f"not a JSON document: {error}", location=str(path)) from None
    except RecursionError:
        raise InputError("nested too deeply; not a contacts file", location=str(path)) from None
    if not isinstance(doc, dict):
        raise InputError("not a contacts file: expected a JSON object", location=str(path))
    return SimContacts.from_json(doc, str(path))


def write_contacts(contacts: SimContacts, path: str | Path) -> Path:
    """Write ``contacts`` atomically (temporary file, then rename)."""
    from oacdsl.atomic import write_atomic

    return write_atomic(path, json.dumps(contacts.to_json()))
