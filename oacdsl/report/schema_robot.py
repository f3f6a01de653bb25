"""The robot's parts of ``result.json``: the run and its steps, the verification, the
measured reliability and the demonstrated against executed motion (see
:mod:`oacdsl.report.schema`)."""

from __future__ import annotations

from typing import Annotated, Any, Literal

from pydantic import Field, model_validator

from oacdsl.report.schema_types import Count, Doc, Fraction, Image, Pair, Seconds, index_ok

__all__ = [
    "AlignDoc",
    "ChangeDoc",
    "MotionFeaturesDoc",
    "MotionRow",
    "MotionSection",
    "ReliabilityDoc",
    "ReliabilityRow",
    "RunDoc",
    "RunStepDoc",
    "StatesDoc",
    "VerificationDoc",
]


class RunStepDoc(Doc):
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


class RunDoc(Doc):
    oac: str
    success: bool
    steps: list[RunStepDoc]
    metrics: dict[str, Any] = {}
    initial: list[Pair] | None = None  # observed relations before the first step
    frame: Image = None  # the robot before the first step
    video: str | None = None  # linked, not embedded
    grasp: str | None = None  # how grasps hold: "friction" or "weld"
    error: str | None = None  # why the run failed
    # an adaptive run of a composed OAC: its effects hold at the end (also when a step failed)
    effects_hold: bool | None = None


class ChangeDoc(Doc):
    index: Count
    frame: Count | None = None
    time_s: float | None = None
    added: list[Pair]
    removed: list[Pair]


class AlignDoc(Doc):
    op: Literal["match", "split", "merge", "substitute", "missing", "extra"]
    demonstration: Count | None
    robot: Count | None
    robot_last: Count | None = None  # a split: the robot's changes robot … robot_last
    demonstration_last: Count | None = None  # a merge: demonstration … demonstration_last at once


class StatesDoc(Doc):
    equal: bool
    demonstration: list[Pair]
    robot: list[Pair]


class VerificationDoc(Doc):
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
            index_ok(a.demonstration, len(self.demonstration), f"alignment.{i}.demonstration")
            index_ok(a.robot, len(self.robot), f"alignment.{i}.robot")
        return self


class ReliabilityRow(Doc):
    oac: str
    runs: Count
    successes: Count
    rate: Fraction
    ci_low: Fraction
    ci_high: Fraction
    median_duration_s: Seconds | None = None
    last_failure: str | None = None
    last_failure_utc: str | None = None


class ReliabilityDoc(Doc):
    db: str | None = None
    oacs: list[ReliabilityRow]


class MotionFeaturesDoc(Doc):
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


class MotionRow(Doc):
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


class MotionSection(Doc):
    sub_actions: list[MotionRow] = []
    plot: Image = None  # one row per sub-action: demonstration (left), robot (right)
