"""The stages of ``reproduce`` between the checked inputs and the report (:func:`run_stages`):
segment → match → compose → execute → verify → record, each filling its part of the result
record; the first stage that fails stops those that need it (see :mod:`oacdsl.pipeline.run`)."""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np

from oacdsl.errors import OacError
from oacdsl.pipeline.inputs import Inputs
from oacdsl.pipeline.result import ResultRecord
from oacdsl.pipeline.verdict import untracked_judged
from oacdsl.progress import Progress
from oacdsl.runtime.overrides import SceneOverrides

__all__ = ["run_stages"]


class _Failed(Exception):
    """A stage failed; the error is recorded, the rest of the stages that need it are skipped."""


def run_stages(
    inputs: Inputs,
    result: ResultRecord,
    progress: Progress,
    staging: Path,
    *,
    name: str,
    seed: int | None,
    render: bool,
    force: bool,
    db: Path | None,
    warn: Callable[[str], None],
    overrides: SceneOverrides | None = None,
    demo_params: bool = True,
    late: list[Callable[[], None]] | None = None,
) -> tuple[str, OacError] | None:
    """Fill ``result`` stage by stage, each part checked as it is set; the first failed stage and
    its error, or None. ``late`` collects what the report stage draws (the robot's AAS plot)."""
    from oacdsl.pipeline import analyse, figures, robot

    failed: list[tuple[str, OacError]] = []
    figs = staging / figures.FIGURES

    def attempt(stage_name: str, body: Callable[[], Any]) -> Any:
        try:
            with progress.stage(stage_name):
                return body()
        except OacError as error:
            failed.append((stage_name, error))
            raise _Failed from None

    def segment() -> Any:
        seg = analyse.segment_stage(inputs.motion_capture(), inputs.params, inputs.shapes())
        seg.doc["plot"] = figures.distance_plot(seg.recording, seg.segmentation, figs, "aas.png")
        snaps = figures.keyframe_snapshots(seg.recording, seg.segmentation, figs)
        for kf, image in zip(seg.doc["keyframes"], snaps, strict=True):
            kf["image"] = image
        return seg

    def compose() -> Any:
        from oacdsl.matching.emit import library_files

        if matched.unmatched:
            from oacdsl.errors import MatchingError

            m = matched.unmatched[0]
            raise MatchingError(
                f"sub-action {m.index + 1} (frames {m.sub_action.start.frame}–"
                f"{m.sub_action.end.frame}) matches no OAC: {m.result.explanation}"
            )
        done = analyse.compose_stage(
            name,
            matched.matches,
            inputs.library,
            inputs.library_path,
            inputs.scene,
            source=inputs.source,
            outside_scene=inputs.outside_scene,
            force=force,
            recording=seg.recording if demo_params else None,
            also=[f for p in inputs.library_paths if p != inputs.library_path for f in library_files(p)],
        )
        from oacdsl.atomic import write_atomic

        write_atomic(staging / f"{name}.oac", done.emitted.text)
        return done

    def execute() -> Any:
        done = robot.execute_stage(
            inputs.library,
            composed.oac,
            inputs.scene,
            seed,
            figs if render else None,
            note=progress.note,
            overrides=overrides,
            recording=inputs.recording,
            warn=warn,
        )
        figures.attach_frames(done.doc, done.frames, staging)
        return done

    def verify() -> Any:
        done = robot.verify_stage(
            seg.segmentation, inputs.params, executed.markers, inputs.library, inputs.scene,
            demo_recording=seg.recording, contacts=executed.contacts, folder=staging,
            any_hands=any(a.get("kind") == "exchanged" for a in getattr(executed.result, "adaptations", ())),
        )

        def plot() -> None:  # a picture for the report, drawn in its stage
            done.doc["plot"] = figures.distance_plot(
                figures.decimated(done.recording, max_markers=figures.PLOT_MARKERS), done.segmentation,
                figs, "robot_aas.png",
            )
            result.put("verification", done.doc)

        if late is not None:
            late.append(plot)
        else:
            plot()
        return done

    def motion() -> dict[str, Any] | None:
        """Demonstrated against executed motion per sub-action (never fails the run)."""
        from oacdsl.pipeline.motion_compare import motion_doc

        try:
            return motion_doc(seg.recording, [m.sub_action for m in matched.matches], checked.recording,
                              checked.sub_actions, checked.doc, analyse.steps_by_sub_action(composed),
                              figs / "motion.png")
        except (OacError, ValueError, FloatingPointError, np.linalg.LinAlgError) as error:
            warn(f"the demonstrated and executed motion could not be compared: {error}")
            return None

    try:
        seg = attempt("segment", segment)
        result.put("segment", analyse.segment_doc(seg, inputs.source))
        matched = attempt(
            "match", lambda: analyse.match_stage(seg.segmentation, inputs.library, inputs.scene, name,
                                                 inputs.unmerged(), inputs.travel())
        )
        result.put("match", matched.doc)
        composed = attempt("compose", compose)
        result.put("compose", composed.doc)
        for w in composed.warnings:
            warn(w)
        executed = attempt("execute", execute)
        ran = len(executed.doc["steps"])  # a failed run stops early: later sub-actions ran no step
        for sub in matched.doc["sub_actions"]:
            if sub.get("step") is not None and sub["step"] >= ran:
                sub["step"] = None
        result.put("match", matched.doc)
        result.put("run", executed.doc)
        _unexecuted_steps(result, len(executed.doc.get("steps", [])))
        if executed.render_note:
            warn(f"{executed.render_note}; the report has no pictures of the robot")
        # a robot that failed a step is still verified: the report shows how far it got
        checked = attempt("verify", verify)
        checked.doc["untracked"] = untracked_judged(inputs.scene, executed.doc)
        result.put("verification", checked.doc)
        compared = motion()
        if compared is not None:
            result.put("motion", compared)
    except _Failed:
        pass
    done = {r["name"] for r in progress.records()}
    for later in ("segment", "match", "compose", "execute", "verify"):
        if later not in done:
            progress.skip(later, f"the {failed[0][0]} stage failed")
    if db is None:
        progress.skip("record", "no run store")
    elif "run" in result:
        try:
            attempt("record", lambda: _record(db, executed.doc, result, inputs, seed))
        except _Failed:
            pass
    else:
        progress.skip("record", "nothing was executed")
    return failed[0] if failed else None


def _unexecuted_steps(result: ResultRecord, executed: int) -> None:
    """A run that stopped at a failed step executed only its first ``executed`` steps: the
    sub-actions of the steps after it point at no execution (``step`` left out)."""
    match = result.docs.get("match")
    if not match or not any((s.get("step") or 0) >= executed for s in match["sub_actions"]):
        return
    for sub in match["sub_actions"]:
        if sub.get("step") is not None and sub["step"] >= executed:
            del sub["step"]
    result.put("match", match)


def _record(
    db: Path, run_doc: dict[str, Any], result: ResultRecord, inputs: Inputs, seed: int | None
) -> None:
    """Store the run's outcome per OAC; put the measured reliability into ``result``."""
    from oacdsl.report import reliability_doc
    from oacdsl.stats import RunStore

    v = result.verification
    with RunStore(db) as store:
        store.record_run_json(
            run_doc,
            recording=inputs.source,
            seed=seed,
            fidelity=v.fidelity if v else None,
            edit_distance=v.distance if v else None,
            command="reproduce",
        )
    result.put("reliability", reliability_doc(db))
