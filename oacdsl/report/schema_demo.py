"""The demonstration's parts of ``result.json``: the recording and verdict, the stages,
the segmentation, the match and the composed OAC (see :mod:`oacdsl.report.schema`)."""

from __future__ import annotations

from typing import Annotated, Any, Literal

from pydantic import Field, model_validator

from oacdsl.report.schema_types import Count, Doc, Image, Pair, Seconds, index_ok

__all__ = [
    "CallDoc",
    "ComposeDoc",
    "Demonstration",
    "KeyframeDoc",
    "MatchDoc",
    "MatchSection",
    "ProvenanceDoc",
    "SegmentDoc",
    "Stage",
    "SubActionDoc",
    "Verdict",
]


class Demonstration(Doc):
    recording: str
    title: str | None = None
    scene: str | None = None
    library: list[str] = []
    seed: Count | None = None
    command: str | None = None


class Verdict(Doc):
    success: bool
    summary: str
    failed_stage: str | None = None
    verified: bool | None = None  # oacc verify's verdict: relations and end state hold
    faithful: bool | None = None  # ... and the motion too
    failed_checks: list[str] = []  # the names of the checks that failed


class Stage(Doc):
    name: str
    status: Literal["ok", "failed", "skipped"]
    duration_s: Seconds | None = None
    detail: str | None = None


class KeyframeDoc(Doc):
    frame: Count
    time_s: float
    relations: list[Pair]
    image: Image = None  # the demonstration at this keyframe (e.g. a marker snapshot)
    graph: Image = None  # a world-state graph; drawn from the relations when absent


class SegmentDoc(Doc):
    recording: str
    rate_hz: Annotated[float, Field(gt=0.0)]
    frames: Count
    parameters: dict[str, Any] = {}
    instances: list[str]
    keyframes: list[KeyframeDoc]
    plot: Image = None  # the Fig. 3-like distance plot


class MatchDoc(Doc):
    oac: str
    binding: dict[str, str]
    pre: list[Pair] | None = None  # bound preconditions (the OAC's constraints)
    pre_not: list[Pair] = []
    effect: list[Pair] | None = None  # bound effects
    effect_not: list[Pair] = []
    note: str | None = None  # why it ranks where it does


class SubActionDoc(Doc):
    from_frame: Count
    to_frame: Count
    before: list[Pair]
    after: list[Pair]
    matches: list[MatchDoc]
    chosen: Count | None
    explanation: str | None = None
    step: Count | None = None  # index into run.steps of its execution (default: in order)

    @model_validator(mode="after")
    def _chosen_in_range(self) -> SubActionDoc:
        index_ok(self.chosen, len(self.matches), "chosen")
        return self


class MatchSection(Doc):
    sub_actions: list[SubActionDoc]


class CallDoc(Doc):
    oac: str
    binding: dict[str, str]


class ProvenanceDoc(Doc):
    kind: Literal["pre", "effect", "ended"]
    relation: Pair
    step: Count | None = None  # index into compose.steps
    keyframe: Count | None = None  # index into segment.keyframes
    note: str | None = None


class ComposeDoc(Doc):
    name: str
    pre: list[Pair]
    effect: list[Pair]
    ended: list[Pair] = []
    steps: list[CallDoc]
    file: str | None = None
    text: str | None = None  # the emitted .oac declaration
    provenance: list[ProvenanceDoc] = []
