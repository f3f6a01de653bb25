"""The robot's stages: execute the composed OAC on ARMAR-III, verify the closed loop.

``execute_stage`` runs the composed OAC in MuJoCo (object poses read from the
simulation, the demonstration's binding as defaults) with :class:`VirtualMarkers`
observing, and renders the robot before the first step and after every step (small
frames, no shadows). ``verify_stage`` segments the virtual markers with the same AAS
(:func:`~oacdsl.pipeline.markers.robot_params`), matches the robot's sub-actions with
the same library, and compares the robot's world-state changes with the
demonstration's (:func:`oacdsl.verify.verify`).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from oacdsl.library import Library
from oacdsl.model import Oac, Scene
from oacdsl.pipeline.camera import StepCamera
from oacdsl.pipeline.markers import VirtualMarkers, robot_params
from oacdsl.runtime.overrides import SceneOverrides
from oacdsl.segmentation.params import AasParams
from oacdsl.segmentation.recording import Recording
from oacdsl.segmentation.result import Segmentation
from oacdsl.world import NOTHING

__all__ = ["ExecuteStage", "VerifyStage", "execute_stage", "verify_stage", "sim_contacts", "write_execution"]


@dataclass
class ExecuteStage:
    result: Any  # oacdsl.runtime.RunResult
    markers: VirtualMarkers
    doc: dict[str, Any]
    #: The simulation's own touching relations over the run (a ContactRecorder), or None.
    contacts: Any = None
    #: Why there are no pictures (no rendering backend), else None.
    render_note: str | None = None
    #: The rendered frames by name: robot_00 (before), robot_NN (after step NN), robot_NN_moment.
    frames: dict[str, Path] = field(default_factory=dict)


def execute_stage(
    library: Library,
    oac: Oac,
    scene: Scene,
    seed: int | None,
    frames_dir: Path | None,
    *,
    note: Callable[[str], None] | None = None,
    overrides: SceneOverrides | None = None,
    recording: Recording | None = None,
    warn: Callable[[str], None] | None = None,
) -> ExecuteStage:
    """Execute ``oac``; with ``frames_dir``, render the robot there (:class:`StepCamera`).
    The scene's initial state comes from the scene, under ``overrides``; with ``layout
    demonstrated`` the objects stand as at the first frame of ``recording``, and ``place`` sets
    them down where it does (:mod:`oacdsl.runtime.demo_places`).
    Raises RuntimeFailure for a call that cannot run (bad binding)."""
    from oacdsl.report import bound_conditions
    from oacdsl.runtime.demo_layout import first_frame_poses
    from oacdsl.runtime.demo_places import scene_hands, set_down_places
    from oacdsl.runtime.executor import prepare, run_prepared
    from oacdsl.runtime.layout import seed_note
    from oacdsl.segmentation.shapes import scene_shapes

    names = [i.name for i in scene.tracked()]
    shapes = scene_shapes(library, scene)
    demonstrated, headings = (first_frame_poses(recording, names, shapes) if recording is not None
                              else (None, None))
    hands = scene_hands(library, scene)
    set_downs = set_down_places(recording, names, hands) if recording is not None else None
    given = (overrides or SceneOverrides()).kwargs()
    run = prepare(
        library, oac, scene=scene, seed=seed, demonstrated=demonstrated, set_downs=set_downs,
        headings=headings, **given
    )
    if warn is not None and (moved := seed_note(run.world.layout)) is not None:
        warn(moved)
    from oacdsl.runtime.recorder import ContactRecorder

    markers = VirtualMarkers(run.world)
    contacts = ContactRecorder(markers.rate_hz, regrasps=run.controller.regrasps)
    run.controller.add_observer(markers)
    run.controller.add_observer(contacts)
    camera = StepCamera(run.world.model, run.steps, frames_dir) if frames_dir is not None else None
    total = len(run.steps)

    def announce(index: int) -> None:
        if note is not None and index < total:
            s = run.steps[index]
            note(f"step {index + 1}/{total}: {s.oac.name}({', '.join(s.args)})")

    def on_step(index: int, step: Any, world: Any) -> None:
        if camera is not None:
            camera.step_done(index, world)
        announce(index + 1)

    try:
        if camera is not None:
            camera.snapshot("robot_00", run.world)
            run.controller.add_observer(camera)
        announce(0)
        settings = overrides or SceneOverrides()
        if settings.strict or not run.oac.composed:
            result = run_prepared(run, on_step=on_step)
        else:  # adaptive (issue 22): the steps run are the ones the world asked for
            from oacdsl.runtime.adaptive import run_adaptive

            result = run_adaptive(run, on_step=on_step, max_repairs=settings.max_repairs)
    finally:
        if camera is not None:
            camera.close()
    doc = result.to_json()
    doc["initial"] = [list(r) for r in result.states[0].sorted_relations()] if result.states else []
    before = doc["initial"]
    executed = [(library.oacs[s.oac], s.binding) for s in result.steps]
    for step_doc, (step_oac, step_binding) in zip(doc["steps"], executed, strict=False):
        # ``observed`` is the set of touching relations (docs/report.md); the runtime adds
        # ``[x, "nothing"]`` for the step's instances that touch nothing, which that set implies
        step_doc["observed"] = [p for p in step_doc["observed"] if NOTHING not in p]
        ending = bound_conditions(step_oac, step_binding)["effect_not"]
        # an effect ``x <-> nothing`` predicts that every relation x had before the step ends
        cleared = {p[0] for p in step_doc["predicted"] if p[1] == NOTHING}
        ending += [p for p in before if (p[0] in cleared or p[1] in cleared) and p not in ending]
        step_doc["predicted_not"] = sorted(ending)
        before = step_doc["observed"]
    doc["binding"] = dict(run.binding)
    doc["grasp"] = "weld"
    layout = run.world.layout
    doc["layout"] = {
        "places": {
            p.name: {"x_m": round(p.x, 4), "y_m": round(p.y, 4), "yaw_deg": round(math.degrees(p.yaw), 1),
                     "from": layout.sources.get(p.name, "auto")}
            for p in layout.placements
        },
        "contents": {
            liquid: {"in": c, "balls": layout.ball_count(liquid)}
            for liquid, c in sorted(layout.liquids.items())
        },
    }
    if result.error:
        doc["error"] = result.error
    if camera is None:
        return ExecuteStage(result, markers, doc, contacts)
    return ExecuteStage(result, markers, doc, contacts, camera.unavailable, dict(camera.frames))


@dataclass
class VerifyStage:
    recording: Recording
    segmentation: Segmentation
    verification: Any  # oacdsl.verify.Verification (the relations check)
    doc: dict[str, Any]
    #: The robot's sub-actions as matched (transient keyframes dropped): change k ends sub-action k - 1.
    sub_actions: list[Any] = field(default_factory=list)
    #: The whole verdict (oacdsl.verify_execution.VerifyOutcome): verified, faithful, checks.
    outcome: Any = None
    #: The files written: the robot's virtual-marker recording and its contacts.
    files: list[Path] = field(default_factory=list)


#: The robot's recording in the run folder, and (beside it) the simulation's contacts.
EXECUTION_FILE = "execution.c3d"


def sim_contacts(recorder: Any, demo_params: AasParams, instances: list[str] | None = None) -> Any:
    """The contacts a ContactRecorder saw, as the verifier reads them (with the AAS parameters
    its virtual markers are segmented with)."""
    from oacdsl.verify_contacts import SimContacts, internal_windows
    from oacdsl.world import relation

    doc = recorder.to_json()
    changes = tuple((int(c["frame"]), frozenset(relation(a, b) for a, b in c["relations"]))
                    for c in doc["changes"])
    return SimContacts(float(doc["rate_hz"]), int(doc["frames"]), tuple(doc["instances"]), changes,
                       robot_params(demo_params).to_dict(), internal_windows(doc.get("internal", ())))


def write_execution(recording: Recording, contacts: Any, path: Path) -> list[Path]:
    """Write the robot's recording (C3D) to ``path`` and its contacts file beside it."""
    from oacdsl.segmentation.readers.c3d import write_c3d
    from oacdsl.verify_contacts import contacts_path, write_contacts

    written = [write_c3d(recording, path)]
    if contacts is not None:
        written.append(write_contacts(contacts, contacts_path(path)))
    return written


def verify_stage(
    demonstration: Segmentation,
    demo_params: AasParams,
    markers: VirtualMarkers,
    library: Library,
    scene: Scene,
    *,
    demo_recording: Recording | None = None,
    contacts: Any = None,
    folder: Path | None = None,
    any_hands: bool = False,
) -> VerifyStage:
    """Judge the robot's execution against the demonstration (:func:`~oacdsl.verify_execution.
    verify_execution`: relations from the simulation's contacts, end state, motion), after
    segmenting and matching the robot's virtual markers with the same AAS and library (the
    report's robot sub-actions; where that AAS disagrees with the contacts is a finding). With
    ``folder``, the robot's recording and contacts are written there (``execution.c3d``).
    ``any_hands``: the robot's two hands may be exchanged consistently (the runtime exchanged
    them: a left-handed demonstration in a scene laid out for the right hand)."""
    from oacdsl.matching import Matcher
    from oacdsl.matching.demonstration import match_segmentation
    from oacdsl.matching.transient import agents_of, stable_segmentation
    from oacdsl.pipeline.analyse import match_doc
    from oacdsl.segmentation import segment
    from oacdsl.verify import verify

    instances = list(demonstration.instances)
    recording = markers.to_recording("robot (virtual markers)", instances=instances)
    sim = sim_contacts(contacts, demo_params) if contacts is not None else None
    with ThreadPoolExecutor(max_workers=1) as pool:
        # the files are written while the verdict is computed (numpy and the file write let go
        # of the interpreter lock; both only read the recording)
        writing = pool.submit(write_execution, recording, sim, folder / EXECUTION_FILE) \
            if folder is not None else None
        params = robot_params(demo_params)
        seg = segment(recording, params)
        matcher = Matcher.from_library(library, scene)
        agents = agents_of(matcher.instance_classes)
        outcome = None
        if demo_recording is not None:
            from oacdsl.verify_execution import verify_execution

            outcome = verify_execution(demo_recording, recording, scene=scene, library=library,
                                       params=demo_params, contacts=sim, demo_segmentation=demonstration,
                                       execution_aas=seg, any_hands=any_hands)
            v = outcome.relations
        else:  # a segmentation only: the relations as the AAS of the virtual markers sees them
            demo_kfs = stable_segmentation(demonstration, agents.__contains__)[0].keyframes
            robot_kfs = stable_segmentation(seg, agents.__contains__)[0].keyframes
            v = verify(
                [k.state for k in demo_kfs],
                [k.state for k in robot_kfs],
                demonstration_frames=[k.frame for k in demo_kfs],
                robot_frames=[k.frame for k in robot_kfs],
                demonstration_times_s=[k.time_s for k in demo_kfs],
                robot_times_s=[k.time_s for k in robot_kfs],
                instances=instances,
            )
        files = writing.result() if writing is not None else []
    if outcome is not None and outcome.relations_source != "aas" and outcome.execution_segmentation:
        # the robot's sub-actions as the simulation's contacts delimit them (the relations check's)
        robot_matches = match_segmentation(outcome.execution_segmentation, matcher)
    else:  # as the AAS of the virtual markers delimits them
        robot_matches = match_segmentation(seg, matcher)
    doc = v.to_json()
    by_index = {m.index + 1: m for m in robot_matches}
    for change in doc["robot"]:  # the robot's own sub-action leading to each change, as matched
        m = by_index.get(change["index"])
        chosen = m.result.chosen if m is not None else None
        change["oac"] = chosen.text() if chosen is not None else None
    doc["segment"] = seg.to_json()
    doc["markers"] = len(recording.marker_names)
    doc["robot_match"] = match_doc(robot_matches)
    if outcome is not None:
        judged = outcome.to_json()
        doc["relations_verified"] = doc["verified"]
        doc["verified"], doc["faithful"] = outcome.verified, outcome.faithful
        doc["verdict"] = f"{outcome.summary()} (relations: {v.verdict()})"
        for key in ("checks", "relations_source", "findings", "notes", "tolerances"):
            doc[key] = judged[key]
        if folder is not None:
            doc["recording"] = EXECUTION_FILE
    return VerifyStage(recording, seg, v, doc, [m.sub_action for m in robot_matches], outcome, files)
