"""The ``result.json`` schema (version 1): everything the report page shows, as data.

The pipeline (``oacc reproduce``) builds one dict of this shape; the page is rendered from
it alone. The parts are the documents the stages already print (``oacc segment --json``,
``oacc match --json``, ``oacc compose --json``, ``oacc run --json``, the verification's
``to_json()``, ``oacc stats --json``), plus optional fields for pictures and provenance.
Unknown extra keys are kept (the schema is open), but the fields listed here are checked.

A *relation* is a pair ``[a, b]`` of instance names sorted alphabetically; a statement about
one instance is ``[x, "nothing"]``. An *image* is a path to a PNG or JPEG (relative to the
report's folder, or absolute) or a ``data:image/...`` URI; the page embeds it.
See docs/report.md for the field-by-field reference.
"""

from __future__ import annotations

from typing import Any, Literal

from pydantic import BaseModel, ConfigDict, ValidationError

from oacdsl.errors import InputError

__all__ = ["SCHEMA_VERSION", "Result", "validate_result"]

#: The version of the result.json schema this code writes and reads.
SCHEMA_VERSION = 1

Pair = tuple[str, str]
Image = str | None


class _Doc(BaseModel):
    model_config = ConfigDict(extra="allow")


class Demonstration(_Doc):
    recording: str
    title: str | None = None
    scene: str | None = None
    library: list[str] = []
    seed: int | None = None
    command: str | None = None


class Verdict(_Doc):
    success: bool
    summary: str
    failed_stage: str | None = None


class Stage(_Doc):
    name: str
    status: Literal["ok", "failed", "skipped"]
    duration_s: float | None = None
    detail: str | None = None


class KeyframeDoc(_Doc):
    frame: int
    time_s: float
    relations: list[Pair]
    image: Image = None  # the demonstration at this keyframe (e.g. a marker snapshot)
    graph: Image = None  # a world-state graph; drawn from the relations when absent


class SegmentDoc(_Doc):
    recording: str
    rate_hz: float
    frames: int
    parameters: dict[str, Any] = {}
    instances: list[str]
    keyframes: list[KeyframeDoc]
    plot: Image = None  # the Fig. 3-like distance plot


class MatchDoc(_Doc):
    oac: str
    binding: dict[str, str]
    pre: list[Pair] | None = None  # bound preconditions (the OAC's constraints)
    pre_not: list[Pair] = []
    effect: list[Pair] | None = None  # bound effects
    effect_not: list[Pair] = []
    note: str | None = None  # why it ranks where it does


class SubActionDoc(_Doc):
    from_frame: int
    to_frame: int
    before: list[Pair]
    after: list[Pair]
    matches: list[MatchDoc]
    chosen: int | None
    explanation: str | None = None
    step: int | None = None  # index into run.steps of its execution (default: in order)


class MatchSection(_Doc):
    sub_actions: list[SubActionDoc]


class CallDoc(_Doc):
    oac: str
    binding: dict[str, str]


class ProvenanceDoc(_Doc):
    kind: Literal["pre", "effect", "ended"]
    relation: Pair
    step: int | None = None  # index into compose.steps
    keyframe: int | None = None  # index into segment.keyframes
    note: str | None = None


class ComposeDoc(_Doc):
    name: str
    pre: list[Pair]
    effect: list[Pair]
    ended: list[Pair] = []
    steps: list[CallDoc]
    file: str | None = None
    text: str | None = None  # the emitted .oac declaration
    provenance: list[ProvenanceDoc] = []


class RunStepDoc(_Doc):
    oac: str
    binding: dict[str, str]
    success: bool
    duration_s: float | None = None
    predicted: list[Pair] = []
    predicted_not: list[Pair] = []
    observed: list[Pair] = []
    error: str | None = None
    frame: Image = None  # the robot after this step
    moment: Image = None  # the robot when the step's predicted effects first held


class RunDoc(_Doc):
    oac: str
    success: bool
    steps: list[RunStepDoc]
    metrics: dict[str, Any] = {}
    initial: list[Pair] | None = None  # observed relations before the first step
    frame: Image = None  # the robot before the first step
    video: str | None = None  # linked, not embedded
    grasp: str | None = None  # how grasps hold: "friction" or "weld"
    error: str | None = None  # why the run failed


class ChangeDoc(_Doc):
    index: int
    frame: int | None = None
    time_s: float | None = None
    added: list[Pair]
    removed: list[Pair]


class AlignDoc(_Doc):
    op: Literal["match", "substitute", "missing", "extra"]
    demonstration: int | None
    robot: int | None


class StatesDoc(_Doc):
    equal: bool
    demonstration: list[Pair]
    robot: list[Pair]


class VerificationDoc(_Doc):
    demonstration: list[ChangeDoc]
    robot: list[ChangeDoc]
    alignment: list[AlignDoc]
    distance: int
    relation_distance: int | None = None
    fidelity: float
    initial: StatesDoc
    final: StatesDoc
    verified: bool
    verdict: str
    tolerance: int = 0
    plot: Image = None  # e.g. the robot recording's distance plot


class ReliabilityRow(_Doc):
    oac: str
    runs: int
    successes: int
    rate: float
    ci_low: float
    ci_high: float
    median_duration_s: float | None = None
    last_failure: str | None = None
    last_failure_utc: str | None = None


class ReliabilityDoc(_Doc):
    db: str | None = None
    oacs: list[ReliabilityRow]


class Result(_Doc):
    schema_version: Literal[1] = 1
    created_utc: str | None = None
    oacdsl_version: str | None = None
    demonstration: Demonstration
    verdict: Verdict
    stages: list[Stage] = []
    segment: SegmentDoc | None = None
    match: MatchSection | None = None
    compose: ComposeDoc | None = None
    run: RunDoc | None = None
    verification: VerificationDoc | None = None
    reliability: ReliabilityDoc | None = None


def validate_result(result: Any, *, source: str = "result") -> Result:
    """Check a result dict against the schema; the first problem as a one-line InputError."""
    if isinstance(result, dict) and result.get("schema_version", SCHEMA_VERSION) != SCHEMA_VERSION:
        raise InputError(
            f"schema_version {result.get('schema_version')!r} is not supported (this oacdsl reads"
            f" {SCHEMA_VERSION})",
            location=source,
        )
    try:
        return Result.model_validate(result)
    except ValidationError as e:
        err = e.errors()[0]
        where = ".".join(str(p) for p in err["loc"]) or "(top)"
        more = f" (and {e.error_count() - 1} more)" if e.error_count() > 1 else ""
        raise InputError(f"{where}: {err['msg']}{more}", location=source) from None
