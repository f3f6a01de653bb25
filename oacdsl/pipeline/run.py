"""``reproduce``: from a demonstration to a verified robot execution and its report.

Stages, each timed by :class:`~oacdsl.progress.Progress`: segment → match → compose →
execute → verify → record → report. Inputs are checked first (:func:`load_inputs`),
before anything is written. The outputs are built in a hidden folder inside ``out``
and published in one step at the end (:mod:`oacdsl.pipeline.publish`: ``out/runs/<id>/``
and the link ``out/current``; ``report.html``, ``result.json``, ``NAME.oac``, ``figures``
link to it), so ``out`` never shows half a report or entries of two runs. A stage that fails (no OAC
matches a sub-action, the robot drops a cup) stops the stages that need it and the
report says so, with a red verdict; the run store records every execution.
"""

from __future__ import annotations

import shutil
from collections.abc import Callable
from dataclasses import dataclass, field
from datetime import datetime, timezone
from pathlib import Path
from typing import Any

import numpy as np

from oacdsl.errors import InputError, OacError
from oacdsl.pipeline.inputs import Inputs
from oacdsl.pipeline.result import ResultRecord
from oacdsl.progress import Progress
from oacdsl.runtime.overrides import SceneOverrides

__all__ = ["STAGES", "Outcome", "reproduce"]

STAGES = ("segment", "match", "compose", "execute", "verify", "record", "report")


@dataclass
class Outcome:
    """What :func:`reproduce` produced: the exit status, the result document, the files."""

    exit_code: int
    result: dict[str, Any]
    files: list[Path] = field(default_factory=list)
    warnings: list[str] = field(default_factory=list)


class _Failed(Exception):
    """A stage failed; the error is recorded, the rest of the stages that need it are skipped."""


def _verdict(result: ResultRecord, failure: tuple[str, OacError] | None, name: str) -> dict[str, Any]:
    if failure is not None:
        stage, error = failure
        return {"success": False, "summary": f"The {stage} stage failed: {error}", "failed_stage": stage}
    run, v = result.run, result.verification
    if run is not None and not run.success:
        return {
            "success": False,
            "failed_stage": "execute",
            "summary": f"The robot did not complete {name}: {run.error or 'a step failed'}.",
        }
    extra = (v.model_extra or {}) if v is not None else {}
    flags = {"verified": bool(v.verified), "faithful": bool(extra.get("faithful", v.verified))} \
        if v is not None else {}
    failed = [c for c in extra.get("checks", []) if not c["passed"]]
    if v is not None and not v.verified:
        named = "; ".join(f"{c['name']}: {c['detail']}" for c in failed if c["kind"] != "motion")
        return {
            "success": False,
            "failed_stage": "verify",
            **flags,
            "failed_checks": [c["name"] for c in failed],
            "summary": f"The robot executed {name}, but the outcome differs from the demonstration:"
            f" {v.verdict}." + (f" Failed: {named}." if named else ""),
        }
    m = run.metrics if run is not None else {}
    balls = f", {m['balls_in_bowl']} of {m['balls_total']} balls in the bowl" if m.get("balls_total") else ""
    liquid = ""
    for u in (v.model_extra or {}).get("untracked", []) if v is not None else []:
        judged = "; ".join(
            f"step {j['step']} {j['oac']} observed " + ", ".join(" <-> ".join(p) for p in j["relations"])
            for j in u["judged_by"]
        )
        liquid += (f" The untracked {u['instance']} is not in the recording, so not compared: the robot's"
                   f" step effects judged it ({judged or 'no step predicts it'}).")
    n = len(v.demonstration) if v is not None else 0
    source = "its simulated contacts" if extra.get("relations_source") == "simulation contacts" else \
        "its own recording, segmented by the same AAS,"
    unfaithful = ""
    if flags and not flags["faithful"]:
        unfaithful = " Not faithful: " + "; ".join(f"{c['name']}: {c['detail']}" for c in failed) + "."
    ends = " every tracked object ends as demonstrated;" if "checks" in extra else ""
    return {
        "success": True,
        **flags,
        "failed_checks": [c["name"] for c in failed],
        "summary": f"ARMAR-III executed {name} ({len(run.steps) if run else 0} steps{balls}), and"
        f" {source} shows the demonstration's {n} world-state changes in order (edit distance"
        f" {v.distance if v else '–'});{ends} {'faithful' if flags.get('faithful') else 'verified'}."
        f"{unfaithful}{liquid}",
    }


def untracked_judged(scene: Any, run_doc: dict[str, Any]) -> list[dict[str, Any]]:
    """How each untracked instance (a liquid the recording does not track) was judged: the
    executed steps whose predicted effects name it (their effect judge observed them in the
    simulation, else the run failed there). The closed loop leaves these instances out."""
    out = []
    for inst in scene.untracked():
        judged = [
            {"step": k, "oac": s["oac"], "relations": [p for p in s["predicted"] if inst.name in p],
             "success": s["success"]}
            for k, s in enumerate(run_doc.get("steps", []), 1)
            if any(inst.name in p for p in s["predicted"])
        ]
        out.append({"instance": inst.name, "judged_by": judged})
    return out


def reproduce(
    inputs: Inputs,
    *,
    name: str,
    out: Path,
    db: Path | None,
    seed: int | None = None,
    render: bool = True,
    force: bool = False,
    quiet: bool = False,
    command: str | None = None,
    warn: Callable[[str], None] | None = None,
    overrides: SceneOverrides | None = None,
    demo_params: bool = True,
) -> Outcome:
    """Run every stage on checked ``inputs`` and write the report into ``out`` (see the module
    docstring). ``db``: the run store (None: do not record); ``overrides``: the command line's
    --place/--fill/--layout over the scene's initial state; ``demo_params``: steps carry the skill
    parameters of the demonstrated motion (``--no-demo-params``: the paper's plain steps)."""
    from oacdsl import __version__

    progress = Progress(list(STAGES), quiet=quiet)
    warnings: list[str] = []

    def note_warning(text: str) -> None:
        warnings.append(text)
        if warn is not None:
            warn(text)

    for text in inputs.warnings:  # learned files left out of the library (they no longer compile)
        note_warning(text)
    from oacdsl.atomic import remove_stale_temporaries
    from oacdsl.matching.emit import LEARNED
    from oacdsl.pipeline.publish import clean_stale, make_staging, publish

    library_root = inputs.library_path if inputs.library_path.is_dir() else inputs.library_path.parent
    remove_stale_temporaries(library_root / LEARNED)  # what killed runs left behind
    clean_stale(out)
    try:
        staging = make_staging(out)
    except OSError as error:
        why = error.strerror or str(error)
        raise InputError(f"cannot write the report here: {why}", location=str(out)) from None
    try:
        figures = staging / "figures"
        figures.mkdir()
        record = ResultRecord(
            created_utc=datetime.now(timezone.utc).replace(microsecond=0).isoformat(),
            oacdsl_version=__version__,
            demonstration={
                "recording": inputs.source,
                "scene": inputs.scene.name,
                "library": [str(p) for p in inputs.library_paths or (inputs.library_path,)],
                "seed": seed,
                "command": command,
                **({"scene_overrides": overrides.to_json()} if overrides and overrides.to_json() else {}),
            },
        )
        late: list[Callable[[], None]] = []  # the report's pictures of earlier stages
        failure = _stages(
            inputs,
            record,
            progress,
            staging,
            name=name,
            seed=seed,
            render=render,
            force=force,
            db=db,
            warn=note_warning,
            overrides=overrides,
            demo_params=demo_params,
            late=late,
        )
        with progress.stage("report"):
            from oacdsl.report import write_report

            for draw in late:
                draw()
            verdict = _verdict(record, failure, name)
            result = record.to_json(verdict, progress.records(), warnings)

            report = write_report(result, staging, source="result")
            for w in report.warnings:
                note_warning(w)
            try:
                files = publish(staging, out)
            except OSError as error:
                raise InputError(
                    f"cannot move the report into place: {error.strerror or error}", location=str(out)
                ) from None
        code = 0 if result["verdict"]["success"] else max(failure[1].exit_code if failure else 1, 1)
        return Outcome(code, result, files, warnings)
    finally:
        shutil.rmtree(staging, ignore_errors=True)


def _stages(
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
        seg = analyse.segment_stage(inputs.motion_capture(), inputs.params)
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
