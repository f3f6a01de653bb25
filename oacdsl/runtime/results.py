"""The result records of a run: one per primitive step, one per composed step, the run.

``RunResult.to_json()`` is the ``oacc run --json`` document (docs/runtime.md).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

from oacdsl.world import WorldState

__all__ = ["StepResult", "CallResult", "RunResult"]


@dataclass
class StepResult:
    """One executed primitive step (one entry of the JSON ``steps`` list)."""

    oac: str
    binding: dict[str, str]
    success: bool
    duration_s: float
    predicted: list[list[str]]
    observed: list[list[str]]
    error: str | None = None
    #: The skill parameters the OAC or its calling step set (SI units; the rest are defaults).
    #: A path (``follow``) is its keyframes; the JSON gives their number (``path_keyframes``).
    params: dict[str, Any] | None = None

    def to_json(self) -> dict[str, Any]:
        doc: dict[str, Any] = {
            "oac": self.oac,
            "binding": dict(self.binding),
            "success": self.success,
            "duration_s": round(self.duration_s, 4),
            "predicted": self.predicted,
            "observed": self.observed,
            "error": self.error,
        }
        if self.params:
            doc["params"] = {
                k: round(v, 6) for k, v in sorted(self.params.items()) if isinstance(v, float)
            } | {f"{k}_keyframes": float(len(v)) for k, v in self.params.items() if not isinstance(v, float)}
        return doc


@dataclass
class CallResult:
    """A composed step judged after its last primitive step (one entry of the JSON
    ``composed`` list); ``first``/``last`` are 1-based numbers of its primitive steps."""

    oac: str
    binding: dict[str, str]
    first: int
    last: int
    success: bool
    predicted: list[list[str]]
    observed: list[list[str]]
    error: str | None = None

    def to_json(self) -> dict[str, Any]:
        return {
            "oac": self.oac,
            "binding": dict(self.binding),
            "steps": [self.first, self.last],
            "success": self.success,
            "predicted": self.predicted,
            "observed": self.observed,
            "error": self.error,
        }


@dataclass
class RunResult:
    """The outcome of :func:`execute`; ``to_json()`` is the ``oacc run --json`` document."""

    oac: str
    success: bool
    steps: list[StepResult]
    metrics: dict[str, float | int]
    seed: int | None = None
    states: list[WorldState] = field(default_factory=list)
    composed: list[CallResult] = field(default_factory=list)
    failed_step: str | None = None
    #: What the adaptive executor changed: ``{"kind": "skipped"|"replanned"|"followed"|"exchanged"
    #: |"failed", "step": N, "text": …, "plan": [...]}`` (empty for a strict run).
    adaptations: list[dict[str, Any]] = field(default_factory=list)
    #: An adaptive run of a composed OAC: whether its effects hold at the end (None otherwise).
    #: They may hold while the run failed: a step failed and nothing made it good (its effects
    #: were not needed for the composed OAC's).
    effects_hold: bool | None = None
    #: Why :attr:`failed_step` failed, when that is not the first step error (a step that failed
    #: earlier was made good by a repair).
    failure: str | None = None

    @property
    def error(self) -> str | None:
        """Why the run failed, naming the failed step (``step 3 place(right_hand, cup): …``)."""
        if self.failure is not None:
            return f"{self.failed_step}: {self.failure}" if self.failed_step else self.failure
        reasons = [s.error for s in self.steps] + [c.error for c in self.composed]
        reason = next((r for r in reasons if r), None)
        if reason is None:
            return None
        return f"{self.failed_step}: {reason}" if self.failed_step else reason

    @property
    def outcome(self) -> str:
        """The run's outcome in a few words: ``success``; ``effects hold, but step 3 screw_on(…)
        failed`` (a step failed and nothing made it good, yet the composed OAC's effects hold:
        a failed run all the same); else ``failed at …``."""
        if self.success:
            return "success"
        if self.effects_hold and self.failed_step:
            return f"effects hold, but {self.failed_step} failed"
        return f"failed at {self.failed_step or 'the start'}"

    def to_json(self) -> dict[str, Any]:
        return {
            "oac": self.oac,
            "success": self.success,
            "failed_step": self.failed_step,
            "steps": [s.to_json() for s in self.steps],
            "composed": [c.to_json() for c in self.composed],
            "metrics": dict(self.metrics),
            **({"adaptations": list(self.adaptations)} if self.adaptations else {}),
            **({"effects_hold": self.effects_hold} if self.effects_hold is not None else {}),
        }
