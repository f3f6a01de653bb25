"""The ``result.json`` schema (version 1): everything the report page shows, as data.

The pipeline (``oacc reproduce``) builds one dict of this shape; the page is rendered from
it alone. The parts are the documents the stages already print (``oacc segment --json``,
``oacc match --json``, ``oacc compose --json``, ``oacc run --json``, the verification's
``to_json()``, ``oacc stats --json``), plus optional fields for pictures and provenance.
Unknown extra keys are kept (the schema is open), but the fields listed here are checked.

A *relation* is a pair ``[a, b]`` of instance names sorted alphabetically; a statement about
one instance is ``[x, "nothing"]``. An *image* is a path to a PNG or JPEG (relative to the
report's folder, or absolute) or a ``data:image/...`` URI; the page embeds it.
The value types are in :mod:`~oacdsl.report.schema_types`, the demonstration's parts in
:mod:`~oacdsl.report.schema_demo`, the robot's in :mod:`~oacdsl.report.schema_robot`; every
part is importable from here.
See docs/report.md for the field-by-field reference.
"""

from __future__ import annotations

from typing import Any, Literal

from pydantic import ValidationError, model_validator

from oacdsl.errors import ResultError
from oacdsl.report.schema_demo import (
    CallDoc,
    ComposeDoc,
    Demonstration,
    KeyframeDoc,
    MatchDoc,
    MatchSection,
    ProvenanceDoc,
    SegmentDoc,
    Stage,
    SubActionDoc,
    Verdict,
)
from oacdsl.report.schema_robot import (
    AlignDoc,
    ChangeDoc,
    MotionFeaturesDoc,
    MotionRow,
    MotionSection,
    ReliabilityDoc,
    ReliabilityRow,
    RunDoc,
    RunStepDoc,
    StatesDoc,
    VerificationDoc,
)
from oacdsl.report.schema_types import Count, Doc, Fraction, Image, Pair, Seconds, index_ok

__all__ = [
    "MAX_DEPTH",
    "SCHEMA_VERSION",
    "Result",
    "validate_result",
    "AlignDoc",
    "CallDoc",
    "ChangeDoc",
    "ComposeDoc",
    "Count",
    "Demonstration",
    "Fraction",
    "Image",
    "KeyframeDoc",
    "MatchDoc",
    "MatchSection",
    "MotionFeaturesDoc",
    "MotionRow",
    "MotionSection",
    "Pair",
    "ProvenanceDoc",
    "ReliabilityDoc",
    "ReliabilityRow",
    "RunDoc",
    "RunStepDoc",
    "Seconds",
    "SegmentDoc",
    "Stage",
    "StatesDoc",
    "SubActionDoc",
    "Verdict",
    "VerificationDoc",
]

#: The version of the result.json schema this code writes and reads.
SCHEMA_VERSION = 1
#: How deeply a result may nest (objects and arrays); the pipeline's go 8 deep.
MAX_DEPTH = 64


class Result(Doc):
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
                index_ok(sub.step, len(self.run.steps), f"match.sub_actions.{i}.step")
        if self.compose is not None:
            keyframes = len(self.segment.keyframes) if self.segment is not None else None
            for i, p in enumerate(self.compose.provenance):
                index_ok(p.step, len(self.compose.steps), f"compose.provenance.{i}.step")
                if keyframes is not None:
                    index_ok(p.keyframe, keyframes, f"compose.provenance.{i}.keyframe")
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
