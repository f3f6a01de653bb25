"""Skill parameters from the demonstration on each step of a composition
(:func:`with_demo_params`), also on a step that calls a **composed** OAC.

The runtime hands a parameter written on such a step down to the one step inside whose skill
takes it (:mod:`oacdsl.passdown`); :func:`composed_params` chooses which step inside did the
demonstrated motion and what of it to write (docs/language.md, "Skill parameters of a step").
What each skill parameter takes from a motion: :mod:`oacdsl.matching.demoparams`.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping
from typing import Any

from oacdsl.library import Library
from oacdsl.matching.composer import Composition
from oacdsl.matching.demoparams import DemonstratedMotions, StepParams, follows, step_params
from oacdsl.model import Call, Oac, Scene, sorted_skill_params
from oacdsl.segmentation.motion import SubActionMotion
from oacdsl.skills import SIGNATURES

__all__ = ["composed_params", "with_demo_params"]


def _against_written(found: StepParams, oac: Oac) -> StepParams:
    """``found`` with its comment saying where a demonstrated value has the opposite sign of
    what ``oac`` writes on its skill (a mirrored take's unscrewing turns clockwise: ``angle
    -240deg`` on ``screw_off``'s written ``240deg``): the step then does the opposite of what
    the OAC's name says, and the author should know."""
    from oacdsl.model import Quantity
    from oacdsl.units import language_si

    written = {q.name: q.value for q in oac.skill_params if isinstance(q.value, Quantity)}
    notes = []
    for p in found.params:
        w = written.get(p.name)
        if w is None or not isinstance(p.value, Quantity):
            continue
        got, was = language_si(p.value.value, p.value.unit)[0], language_si(w.value, w.unit)[0]
        if got * was < 0:
            notes.append(f"{p.name} the other way from {oac.name}'s written {w.value:g}{w.unit}")
    if not notes or found.comment is None:
        return found
    return dataclasses.replace(found, comment=f"{found.comment}; {'; '.join(notes)}")


def composed_params(oac: Oac, mapping: Mapping[str, str], motion: SubActionMotion | None,
                    library: Library, scene: Scene) -> StepParams:
    """What the demonstration sets on a step calling the composed ``oac`` (its parameters bound
    by ``mapping``): the parameters of the one step inside it that does the demonstrated motion
    (:mod:`oacdsl.passdown`: the runtime hands them down to it). That step is the one whose
    skill has parameters from the demonstration and moves the motion's object (the skill's
    second argument) relative to the motion's target (its last; the world when that one is
    untracked: no frame to measure in); none or several: nothing is written. A motion that
    keeps or ends a relation is left out: :func:`dwelling` already counts it in the motion of
    the step that made the relation (KIT Pour: the pour, inside the step that puts the carton
    down, is in the motion of the step that brought it onto the cup). A parameter
    written on the step inside (the author fixed it) or taken by another step inside too is
    not written."""
    from oacdsl.passdown import inner_steps
    from oacdsl.runtime.binding import expand

    if motion is None or motion.moved is None or motion.relation in ("kept", "broken"):
        return StepParams((), None, ())
    try:
        steps = expand(library, oac, mapping)[0]
    except Exception:  # noqa: BLE001 - a broken OAC is the compiler's to report
        return StepParams((), None, ())
    inner = inner_steps(library.oacs, oac)
    untracked = {i.name for i in scene.untracked()}

    def does_it(s: Any) -> bool:  # moves the motion's object relative to the motion's frame
        sig = SIGNATURES.get(str(s.oac.skill))
        pair = sig.measured_pair(s.args) if sig is not None else None
        if sig is None or not any(p.source is not None for p in sig.params) or pair is None:
            return False
        target = pair[1] if pair[1] not in untracked else None
        return bool(pair[0] == motion.moved and target == motion.target)

    chosen = [k for k, s in enumerate(steps) if does_it(s)]
    if len(chosen) != 1 or len(inner) != len(steps):
        return StepParams((), None, ())
    k = chosen[0]
    step = steps[k]
    found = step_params(step.oac.skill, motion, step.args, library, scene)
    params, rows = [], []
    for row in found.rows:
        others = [s for j, s in enumerate(inner) if j != k and s.takes(row["name"])]
        why = ("written on the step inside" if row["name"] in inner[k].written
               else f"'{others[0].oac.name}' inside takes it too" if others else None)
        rows.append({**row, "how": why, "value": None} if why is not None else row)
    for p in found.params:
        shared = any(j != k and s.takes(p.name) for j, s in enumerate(inner))
        if p.name not in inner[k].written and not shared:
            params.append(p)
    kept = {p.name for p in params}
    texts = [t for t in (found.comment or "").split(": ", 1)[-1].split("; ")
             if t.split(" ", 1)[0] in kept] if params else []
    if not params:
        return StepParams((), None, ())
    head = (found.comment or "").split(": ", 1)[0]
    comment = f"{head}, for {step.oac.skill} in {step.oac.name}: " + "; ".join(texts)
    return StepParams(tuple(params), comment, tuple(rows))


def with_demo_params(comp: Composition, motions: Mapping[int, SubActionMotion],
                     library: Library, scene: Scene) -> Composition:
    """``comp`` with each step's parameters from the motion of its sub-action (``motions``: by
    the sub-action's first frame), a comment per step, and ``demo_params`` (module doc)."""
    calls: list[Call] = []
    doc: list[dict[str, Any]] = []
    for k, (call, step) in enumerate(zip(comp.oac.steps or (), comp.steps, strict=True)):
        motion = motions.get(step.start_frame) if step.start_frame is not None else None
        if step.oac.composed:
            found = composed_params(step.oac, step.mapping, motion, library, scene)
        else:
            args = tuple(step.mapping.get(a, a) for a in step.oac.skill_arguments())
            pair = _measured_pair(step.oac.skill, args)
            if (motion is not None and pair is not None and isinstance(motions, DemonstratedMotions)
                    and step.start_frame is not None and _another_pair(step.oac.skill, motion, pair)):
                # a parameter is measured on the step's own objects, by the skill's roles (the
                # held object, second, relative to its target, the last argument unless the skill
                # names another: SkillSignature.measured_in): the sub-action's motion of
                # that pair when the demonstration moved it (a ladle leaving the cup for the bowl:
                # to the bowl; KIT Wipe at twice the speed, where the sponge leaves the plate and
                # the plate reaches the rack in one keyframe: the plate's tilt in the rack, not
                # the sponge's against the plate). A path is also the pair's seen from the other.
                motion = motions.of_pair(step.start_frame, *pair) or motion
            found = step_params(step.oac.skill, motion, args, library, scene)
            found = _against_written(found, step.oac)
        if found.comment is None:
            calls.append(call)
            continue
        calls.append(
            call.model_copy(
                update={
                    "skill_params": sorted_skill_params(found.params),
                    "comments": (*call.comments, found.comment),
                }
            )
        )
        doc.append(
            {
                "step": k,
                "oac": step.oac.name,
                "skill": step.oac.skill,
                "sub_action": step.start_keyframe,
                "moved": motion.moved if motion is not None else None,
                "frame": motion.frame_name if motion is not None else None,
                "comment": found.comment,
                "params": [_json_row(r) for r in found.rows],
            }
        )
    oac = comp.oac.model_copy(update={"steps": tuple(calls)})
    return dataclasses.replace(comp, oac=oac, demo_params=tuple(doc))


def _measured_pair(skill: str | None, args: tuple[str, ...]) -> tuple[str, str] | None:
    """(moved, frame) the skill's demonstrated parameters are measured on, by its roles
    (:attr:`~oacdsl.skills.SkillSignature.measured_in`); None for a skill that takes nothing
    from the demonstrated motion."""
    sig = SIGNATURES.get(skill or "")
    if sig is None or not (follows(skill) or any(p.source is not None for p in sig.params)):
        return None
    return sig.measured_pair(args)


def _another_pair(skill: str | None, motion: SubActionMotion, pair: tuple[str, str]) -> bool:
    """Whether ``motion`` is of another pair than ``pair`` (a path may be the pair seen from
    either side)."""
    if follows(skill):
        return {motion.moved, motion.target} != set(pair)
    return (motion.moved, motion.target) != pair


def _json_row(row: Mapping[str, Any]) -> dict[str, Any]:
    return {k: (round(v, 6) if isinstance(v, float) else v) for k, v in row.items()}
