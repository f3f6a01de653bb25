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

from typing import Annotated, Any, Literal

from pydantic import BaseModel, ConfigDict, Field, ValidationError, model_validator

from oacdsl.errors import ResultError

__all__ = ["MAX_DEPTH", "SCHEMA_VERSION", "Result", "validate_result"]

#: The version of the result.json schema this code writes and reads.
SCHEMA_VERSION = 1
#: How deeply a result may nest (objects and arrays); the pipeline's go 8 deep.
MAX_DEPTH = 64

Pair = tuple[str, str]
Image = str | None
#: A count or an index: a whole number ≥ 0.
Count = Annotated[int, Field(ge=0)]
#: A share: a number in [0, 1].
Fraction = Annotated[float, Field(ge=0.0, le=1.0)]
#: A duration or a time stamp, seconds ≥ 0.
Seconds = Annotated[float, Field(ge=0.0)]


class _Doc(BaseModel):
    # numbers must be finite: JSON's NaN and Infinity (which Python reads) are refused
    model_config = ConfigDict(extra="allow", allow_inf_nan=False)


def _index_ok(index: int | None, size: int, what: str) -> None:
    if index is not None and not 0 <= index < size:
        raise ValueError(f"{what} {index} is out of range (there are {size})")


class Demonstration(_Doc):
    recording: str
    title: str | None = None
    scene: str | None = None
    library: list[str] = []
    seed: Count | None = None
    command: str | None = None


class Verdict(_Doc):
    success: bool
    summary: str
    failed_stage: str | None = None
    verified: bool | None = None  # oacc verify's verdict: relations and end state hold
    faithful: bool | None = None  # ... and the motion too
    failed_checks: list[str] = []  # the names of the checks that failed


class Stage(_Doc):
    name: str
    status: Literal["ok", "failed", "skipped"]
    duration_s: Seconds | None = None
    detail: str | None = None


class KeyframeDoc(_Doc):
    frame: Count
    time_s: float
    relations: list[Pair]
    image: Image = None  # the demonstration at this keyframe (e.g. a marker snapshot)
    graph: Image = None  # a world-state graph; drawn from the relations when absent


class SegmentDoc(_Doc):
    recording: str
    rate_hz: Annotated[float, Field(gt=0.0)]
    frames: Count
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
        _index_ok(self.chosen, len(self.matches), "chosen")
        return self


class MatchSection(_Doc):
    sub_actions: list[SubActionDoc]


class CallDoc(_Doc):
    oac: str
    binding: dict[str, str]


class ProvenanceDoc(_Doc):
    kind: Literal["pre", "effect", "ended"]
    relation: Pair
    step: Count | None = None  # index into compose.steps
    keyframe: Count | None = None  # index into segment.keyframes
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
    duration_s: Seconds | None = None
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
    index: Count
    frame: Count | None = None
    time_s: float | None = None
    added: list[Pair]
    removed: list[Pair]


class AlignDoc(_Doc):
    op: Literal["match", "split", "merge", "substitute", "missing", "extra"]
    demonstration: Count | None
    robot: Count | None
    robot_last: Count | None = None  # a split: the robot's changes robot … robot_last
    demonstration_last: Count | None = None  # a merge: demonstration … demonstration_last at once


class StatesDoc(_Doc):
    equal: bool
    demonstration: list[Pair]
    robot: list[Pair]


class VerificationDoc(_Doc):
    demonstration: list[ChangeDoc]
    robot: list[ChangeDoc]
    alignment: list[AlignDoc]
    distance: Count
    relation_distance: Count | None = None
    fidelity: Fraction
    initial: StatesDoc
    final: StatesDoc
    verified: bool
    verdict: str
    tolerance: Count = 0
    plot: Image = None  # e.g. the robot recording's distance plot

    @model_validator(mode="after")
    def _alignment_in_range(self) -> VerificationDoc:
        for i, a in enumerate(self.alignment):
            _index_ok(a.demonstration, len(self.demonstration), f"alignment.{i}.demonstration")
            _index_ok(a.robot, len(self.robot), f"alignment.{i}.robot")
        return self


class ReliabilityRow(_Doc):
    oac: str
    runs: Count
    successes: Count
    rate: Fraction
    ci_low: Fraction
    ci_high: Fraction
    median_duration_s: Seconds | None = None
    last_failure: str | None = None
    last_failure_utc: str | None = None


class ReliabilityDoc(_Doc):
    db: str | None = None
    oacs: list[ReliabilityRow]


class MotionFeaturesDoc(_Doc):
    """A sub-action's motion features (``SubActionMotion.features``, SI units)."""

    duration_s: Seconds
    path_length_m: Annotated[float, Field(ge=0.0)]
    extent_m: list[float]
    period_s: Seconds | None = None
    cycles: Annotated[float, Field(ge=0.0)] | None = None
    radius_m: Annotated[float, Field(ge=0.0)]
    tilt_max_rad: Annotated[float, Field(ge=0.0)]
    tilt_time_s: Seconds
    tilt_rise_s: Seconds | None = None
    twist_rad: float = 0.0


class MotionRow(_Doc):
    index: Count  # the demonstration's sub-action (as matched)
    oac: str | None = None
    params: dict[str, float] | None = None  # the skill parameters its step was given (SI)
    moved: str | None = None
    target: str | None = None  # None: the world frame
    demonstrated: MotionFeaturesDoc | None = None
    robot_index: Count | None = None  # the robot's sub-action aligned with it
    robot_moved: str | None = None
    robot_target: str | None = None
    executed: MotionFeaturesDoc | None = None


class MotionSection(_Doc):
    sub_actions: list[MotionRow] = []
    plot: Image = None  # one row per sub-action: demonstration (left), robot (right)


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
    motion: MotionSection | None = None
    reliability: ReliabilityDoc | None = None

    @model_validator(mode="after")
    def _indices_in_range(self) -> Result:
        if self.match is not None and self.run is not None:
            for i, sub in enumerate(self.match.sub_actions):
                _index_ok(sub.step, len(self.run.steps), f"match.sub_actions.{i}.step")
        if self.compose is not None:
            keyframes = len(self.segment.keyframes) if self.segment is not None else None
            for i, p in enumerate(self.compose.provenance):
                _index_ok(p.step, len(self.compose.steps), f"compose.provenance.{i}.step")
                if keyframes is not None:
                    _index_ok(p.keyframe, keyframes, f"compose.provenance.{i}.keyframe")
        if self.reliability is not None:
            for row in self.reliability.oacs:
                if row.successes > row.runs:
                    why = f"{row.successes} successes in {row.runs} runs"
                    raise ValueError(f"reliability of {row.oac}: {why}")
        return self


def _depth(value: Any) -> int:
    """How deeply ``value`` nests lists and dicts (iteratively: no recursion limit to hit)."""
    deepest, todo = 0, [(value, 1)]
    while todo:
        item, depth = todo.pop()
        if isinstance(item, dict | list):
            deepest = max(deepest, depth)
            if depth > MAX_DEPTH:
                break
            todo.extend((v, depth + 1) for v in (item.values() if isinstance(item, dict) else item))
    return deepest


def validate_result(result: Any, *, source: str = "result") -> Result:
    """Check a result dict against the schema; the first problem as a one-line ResultError (exit 1).

    Beyond the types: numbers finite, counts and indices ≥ 0 and in range of what they point
    into, shares (fidelity, rates) in [0, 1], nesting at most :data:`MAX_DEPTH` deep.
    """
    if _depth(result) > MAX_DEPTH:
        raise ResultError(f"nested more than {MAX_DEPTH} levels deep; not a result document", location=source)
    if isinstance(result, dict) and result.get("schema_version", SCHEMA_VERSION) != SCHEMA_VERSION:
        raise ResultError(
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
        raise ResultError(f"{where}: {err['msg']}{more}", location=source) from None
