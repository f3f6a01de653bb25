"""The result of ``reproduce`` while its stages build it: a typed record, each part checked as it is set.

Every stage adds its part of ``result.json`` (:mod:`oacdsl.report.schema`):
``segment``, ``match``, ``compose``, ``run``, ``verification``, ``reliability``.
:meth:`ResultRecord.put` validates the part against the schema there and then
(so a wrong document fails in the stage that made it, not when the report is
written) and keeps both the document, as it will be written, and its typed
view, which later stages and the verdict read. :meth:`ResultRecord.to_json`
assembles ``result.json`` with the verdict and the stages' timings.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Literal, TypeVar, cast

from pydantic import BaseModel, ValidationError

from oacdsl.errors import OacError
from oacdsl.report.schema import (
    SCHEMA_VERSION,
    ComposeDoc,
    Demonstration,
    MatchSection,
    MotionSection,
    ReliabilityDoc,
    RunDoc,
    SegmentDoc,
    Verdict,
    VerificationDoc,
)

__all__ = ["PARTS", "Part", "ResultRecord"]

Part = Literal["segment", "match", "compose", "run", "verification", "motion", "reliability"]

#: The parts of result.json the stages add, in the order they are written, with their schema.
PARTS: dict[str, type[BaseModel]] = {
    "segment": SegmentDoc,
    "match": MatchSection,
    "compose": ComposeDoc,
    "run": RunDoc,
    "verification": VerificationDoc,
    "motion": MotionSection,
    "reliability": ReliabilityDoc,
}

M = TypeVar("M", bound=BaseModel)


def _checked(model: type[M], doc: dict[str, Any], where: str) -> M:
    try:
        return model.model_validate(doc)
    except ValidationError as error:
        first = error.errors()[0]
        path = ".".join([where, *(str(p) for p in first["loc"])])
        raise OacError(f"result.json would not match its schema: {path}: {first['msg']}") from None


@dataclass
class ResultRecord:
    """``result.json`` in the making: provenance first, then one part per stage."""

    created_utc: str
    oacdsl_version: str
    demonstration: dict[str, Any]
    docs: dict[str, dict[str, Any] | None] = field(default_factory=dict)
    typed: dict[str, BaseModel] = field(default_factory=dict, repr=False)

    def __post_init__(self) -> None:
        _checked(Demonstration, self.demonstration, "demonstration")

    def put(self, part: Part, doc: dict[str, Any] | None) -> None:
        """Set ``part`` to ``doc`` after checking it against its schema (:data:`PARTS`; None: null)."""
        if doc is None:
            self.typed.pop(part, None)
        else:
            self.typed[part] = _checked(PARTS[part], doc, part)
        self.docs[part] = doc

    def __contains__(self, part: str) -> bool:
        return part in self.docs

    @property
    def run(self) -> RunDoc | None:
        return cast(RunDoc | None, self.typed.get("run"))

    @property
    def verification(self) -> VerificationDoc | None:
        return cast(VerificationDoc | None, self.typed.get("verification"))

    def to_json(
        self, verdict: dict[str, Any], stages: list[dict[str, Any]], warnings: list[str]
    ) -> dict[str, Any]:
        """The whole ``result.json`` document (the verdict checked like the parts)."""
        _checked(Verdict, verdict, "verdict")
        out: dict[str, Any] = {
            "schema_version": SCHEMA_VERSION,
            "created_utc": self.created_utc,
            "oacdsl_version": self.oacdsl_version,
            "demonstration": self.demonstration,
        }
        out.update((part, self.docs[part]) for part in PARTS if part in self.docs)
        out["verdict"] = verdict
        out["stages"] = stages
        if warnings:
            out["warnings"] = warnings
        return out
