"""The result of a segmentation: keyframes with their world states."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

from oacdsl.world import WorldState


@dataclass(frozen=True)
class Keyframe:
    """A frame where the world state changed (frame 0: the initial state).

    ``frame`` counts from 0 at the file's first frame; ``time_s`` is seconds. ``change_s``: when
    the change it stands for happened, seconds, between the frame before and this one, where the
    detector can tell (a contact's distance crossing its threshold,
    :mod:`oacdsl.segmentation.subframe`); ``None``: at ``time_s``. Not part of the keyframe's
    identity (equality): the keyframe is the frame's world state.
    """

    frame: int
    time_s: float
    state: WorldState
    change_s: float | None = field(default=None, compare=False)

    @property
    def event_s(self) -> float:
        """When the change happened, seconds: ``change_s``, else the frame's time."""
        return self.time_s if self.change_s is None else self.change_s


@dataclass(frozen=True)
class SubAction:
    """The span between two consecutive keyframes."""

    index: int
    start: Keyframe
    end: Keyframe

    @property
    def before(self) -> WorldState:
        return self.start.state

    @property
    def after(self) -> WorldState:
        return self.end.state


@dataclass(frozen=True)
class Segmentation:
    """Keyframes of one recording plus the parameters that produced them."""

    recording: str
    rate_hz: float
    frames: int
    instances: tuple[str, ...]
    keyframes: tuple[Keyframe, ...]
    parameters: dict[str, Any] = field(default_factory=dict)

    def sub_actions(self) -> list[SubAction]:
        """Consecutive keyframe pairs, in time order."""
        kfs = self.keyframes
        return [SubAction(i, kfs[i], kfs[i + 1]) for i in range(len(kfs) - 1)]

    def to_json(self) -> dict[str, Any]:
        """The ``oacc segment --json`` document (relations sorted, pairs sorted)."""
        return {
            "recording": self.recording,
            "rate_hz": float(self.rate_hz),
            "frames": int(self.frames),
            "parameters": dict(self.parameters),
            "instances": list(self.instances),
            "keyframes": [
                {
                    "frame": int(k.frame),
                    "time_s": float(k.time_s),
                    **({} if k.change_s is None else {"change_s": round(float(k.change_s), 6)}),
                    "relations": [list(r) for r in k.state.sorted_relations()],
                }
                for k in self.keyframes
            ],
        }
