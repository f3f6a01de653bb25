"""Skill parameters of each composed step from the demonstrated motion, retargeted to the robot.

For every step of a composition whose OAC executes a skill, each parameter of that skill
that names a :class:`~oacdsl.skills.MotionSource` is set from the sub-action's
:class:`~oacdsl.segmentation.motion.SubActionMotion` features (docs/motion.md):

1. **demonstrated**: the feature's value (SI); a parameter whose feature, or whose
   ``needs`` feature, the motion does not have (no oscillation, no tilt; a moved object
   with fewer than three markers has no motion at all) is not written: the skill's
   default (or the OAC's ``execute … { }`` value) applies;
2. **scaled**: × the source's ``scale`` (a pour's tilt rise → its duration × 1.25, a
   wipe's extent → its length to either side × 0.5), rounded for a count;
3. **retargeted**: raised to the least value the robot's skill is known to work with
   (``MotionSource.least``: a pour's tilt, 125°, from where the robot's balls leave its cup
   reliably), a length no larger than the *room* the robot has on the skill's target
   (the object bound to the skill's last argument): a container's inner radius (its
   shell's radius less its wall), a box's half width, less the held tool's own radius
   (the object bound to the skill's second argument; not a length along the tool,
   ``MotionSource.within_target``: a saw's strokes) — then into the parameter's range
   (the skill's limits on the robot: speeds, angles, counts);
4. **written** rounded as an author would (1°, 10 ms, 1 mm, whole counts), and the step
   gets a comment saying what the demonstration showed and what was scaled or clamped.

The result's ``rows`` (one per parameter considered) feed ``result.json``'s
``compose.demo_params`` and the report's table of demonstrated against executed features.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from oacdsl.library import Library
from oacdsl.model import Quantity, Scene, SkillParam
from oacdsl.segmentation.motion import SubActionMotion
from oacdsl.segmentation.poses import ObjectPoses
from oacdsl.segmentation.recording import Recording
from oacdsl.segmentation.result import SubAction
from oacdsl.skills import PATH, SIGNATURES, MotionSource, SkillParamSpec

__all__ = [
    "CLEARANCE_M",
    "StepParams",
    "DemonstratedMotions",
    "demonstrated_motions",
    "follows",
    "path_params",
    "room_m",
    "step_params",
]

#: Kept between the tool and the target's edge when a length is retargeted, metres.
CLEARANCE_M = 0.005


@dataclass(frozen=True)
class StepParams:
    """What the demonstration sets on one step: the parameters, the comment, the rows."""

    params: tuple[SkillParam, ...]
    comment: str | None
    #: One per parameter with a source: name, feature, demonstrated (SI or None), value
    #: written (SI or None), unit, how (``as demonstrated`` / ``scaled …`` / ``clamped …`` /
    #: why nothing was written).
    rows: tuple[dict[str, Any], ...]


def _feature(motion: SubActionMotion, source: MotionSource, name: str | None = None) -> float | None:
    f = motion.features
    if f is None:
        return None
    value = getattr(f, name or source.feature)
    if isinstance(value, tuple):
        value = value[source.axis]
    return None if value is None or not math.isfinite(value) else float(value)


def _show(value: float, unit: str) -> str:
    """A value for a comment, as precise as it is worth: 110deg, 0.65s, 16mm, 3.4."""
    if unit == "rad":
        return f"{math.degrees(value):.0f}deg"
    if unit == "s":
        return f"{value:.2f}s"
    if unit == "m":
        return f"{value * 1000:.0f}mm"
    return f"{value:.1f}" if unit == "" else f"{value:.3g}{unit}"


def _written(value: float, spec: SkillParamSpec) -> Quantity:
    """The value as an author writes it, rounded and kept inside the range."""
    if spec.whole:
        return Quantity(value=float(round(value)))
    unit, factor, digits = {"rad": ("deg", 180 / math.pi, 0), "s": ("s", 1.0, 2), "m": ("mm", 1000.0, 0)}.get(
        spec.unit, (spec.unit, 1.0, 3)
    )
    shown = round(value * factor, digits)
    low, high = spec.low * factor, spec.high * factor
    step = 10.0**-digits
    shown = round(min(max(shown, math.ceil(low / step) * step), math.floor(high / step) * step), digits)
    return Quantity(value=float(shown), unit=unit)


def _size(geometry: Any) -> tuple[float | None, float | None]:
    """(inner half-width of a target, radius of a tool's cross-section) of a resolved geometry,
    metres (its first shape: a container's shell, a tool's handle or head)."""
    from oacdsl.geometry import si

    if geometry is None or not geometry.shapes:
        return None, None
    shape = geometry.shapes[0]
    dim = {d.name: si(d.value, "length") for d in shape.dims if d.name != "mass"}
    if shape.primitive == "shell":
        return dim["radius"] - dim["wall"], dim["radius"]
    if shape.primitive in ("cylinder", "capsule", "sphere"):
        return dim["radius"], dim["radius"]
    if shape.primitive == "box":  # a tool's narrow side: a spoon or a knife stands on it
        return min(dim["length"], dim["width"]) / 2, min(dim["length"], dim["width"]) / 2
    return None, None


def room_m(library: Library, scene: Scene, target: str, tool: str | None) -> float | None:
    """How far a held ``tool`` may move from the middle of ``target`` (metres; None: unknown)."""
    from oacdsl.geometry import resolve

    def geometry(name: str) -> Any:
        inst = scene.instance(name)
        return resolve(library, inst) if inst is not None else None

    inner = _size(geometry(target))[0]
    if inner is None:
        return None
    tool_r = (_size(geometry(tool))[1] if tool is not None else None) or 0.0
    # a tool's "radius" on a surface is half its footprint; in a container its base's radius
    return max(inner - min(tool_r, inner / 2) - CLEARANCE_M, 0.0)


def _one(spec: SkillParamSpec, source: MotionSource, motion: SubActionMotion | None, room: float | None
         ) -> tuple[SkillParam | None, str | None, dict[str, Any]]:
    row: dict[str, Any] = {"name": spec.name, "feature": source.describe(spec.unit), "unit": spec.unit,
                           "demonstrated": None, "value": None}
    if motion is None or motion.features is None:
        row["how"] = "no demonstrated motion (the moved object has fewer than 3 markers)"
        return None, None, row
    if source.needs is not None and _feature(motion, source, source.needs) is None:
        row["how"] = f"the motion has no {source.needs}"
        return None, None, row
    demo = _feature(motion, source)
    row["demonstrated"] = demo
    if demo is None:
        row["how"] = f"the motion has no {source.feature}"
        return None, None, row
    value = source.scale * demo
    what: list[str] = []
    how = ["as demonstrated"]
    if source.scale != 1.0:
        what.append(f"x{source.scale:g}")
        how = [f"scaled x{source.scale:g}"]
    if spec.whole:
        value = float(round(value))
    if source.least is not None and value < source.least:
        value = source.least
        what.append(f"raised to the robot's least ({_show(value, spec.unit)})")
        how.append("raised to the robot's least")
    if spec.unit == "m" and source.within_target and room is not None and value > room:
        value = room
        what.append(f"clamped to the room on the target ({_show(room, 'm')})")
        how.append("clamped to the target's room")
    if not spec.low <= value <= spec.high:
        value = min(max(value, spec.low), spec.high)
        what.append("clamped to the skill's range")
        how.append("clamped to the skill's range")
    q = _written(value, spec)
    from oacdsl.units import language_si

    row["value"] = language_si(q.value, q.unit)[0]
    row["how"] = ", ".join(h for h in how if h != "as demonstrated" or len(how) == 1)
    label = (source.feature.removesuffix("_s").removesuffix("_m").removesuffix("_rad")
             .replace("_max", "").replace("_", " "))
    text = f"{spec.name} {q.value:g}{q.unit}" + (
        f" from {label} {_show(demo, spec.unit)}, " + ", ".join(what)
        if what
        else " as demonstrated"
        if label == spec.name
        else f" = {label} {_show(demo, spec.unit)}"
    )
    return SkillParam(name=spec.name, value=q), text, row


def step_params(
    skill: str | None, motion: SubActionMotion | None, args: Sequence[str], library: Library, scene: Scene
) -> StepParams:
    """The parameters the demonstration sets on a step executing ``skill`` on the instances
    ``args`` (its arguments in the signature's order), with its comment (module doc)."""
    sig = SIGNATURES.get(skill or "")
    if sig is not None and any(p.unit == PATH for p in sig.params):
        return path_params(motion, args)
    specs = [p for p in sig.params if p.source is not None] if sig is not None else []
    if not specs:
        return StepParams((), None, ())
    room = room_m(library, scene, args[-1], args[1] if len(args) > 2 else None) if args else None
    params: list[SkillParam] = []
    texts: list[str] = []
    rows: list[dict[str, Any]] = []
    for spec in specs:
        if spec.source is None:
            continue
        param, text, row = _one(spec, spec.source, motion, room)
        rows.append(row)
        if param is not None and text is not None:
            params.append(param)
            texts.append(text)
    where = ""
    if motion is not None and motion.moved is not None:
        where = (f" ({motion.moved} relative to {motion.frame_name},"
                 f" frames {motion.start_frame}-{motion.end_frame})")
    if texts:
        comment = f"demonstrated{where}: " + "; ".join(texts)
    else:
        reasons = sorted({r["how"] for r in rows})
        comment = f"skill defaults: {'; '.join(reasons)}"
    return StepParams(tuple(params), comment, tuple(rows))


def path_params(motion: SubActionMotion | None, args: Sequence[str]) -> StepParams:
    """A ``follow(h, o, t)`` step's ``path``: the demonstrated motion of ``o`` relative to ``t``
    (:func:`~oacdsl.segmentation.followpath.turned_path`), written in mm, degrees and 10 ms; the
    inverse relative motion when the demonstrator moved ``t`` towards ``o``; nothing when the
    sub-action moved something else or relative to something else."""
    from oacdsl.model import KeyPose, PathValue, Point
    from oacdsl.segmentation.followpath import turned_path
    from oacdsl.segmentation.poses import invert

    row: dict[str, Any] = {"name": PATH, "feature": "the moved object's path in its target's frame",
                           "unit": PATH, "demonstrated": None, "value": None}
    wanted = (args[1], args[-1]) if len(args) >= 3 else None
    found = None
    moved, frame = (motion.moved, motion.frame_name) if motion is not None else (None, None)
    if motion is None or motion.moved is None:
        row["how"] = "no demonstrated motion (the moved object has fewer than 3 markers)"
    elif (motion.moved, motion.target) == wanted:
        found = turned_path(motion.times_s, motion.T_target_object)
        row["how"] = "fewer than two posed frames"
    elif (motion.target, motion.moved) == wanted:
        # the demonstrator moved t towards o (a cup lifted to the carton): the path of o relative
        # to t is the same relative motion seen from t, whichever of the two hands moved
        found = turned_path(motion.times_s, invert(motion.T_target_object))
        row["how"] = "fewer than two posed frames"
        moved, frame = wanted
    else:
        row["how"] = f"the demonstration moved {motion.moved} relative to {motion.frame_name}"
    if found is None or motion is None:
        return StepParams((), f"no demonstrated path: {row['how']}", (row,))

    def q(value: float, unit: str) -> Quantity:
        return Quantity(value=float(value) + 0.0, unit=unit)

    def point(v: np.ndarray, factor: float, unit: str) -> Point:
        x, y, z = (q(round(float(c) * factor), unit) for c in v)
        return Point(x=x, y=y, z=z)

    t, pos, rot = found
    poses = tuple(
        KeyPose(time=q(round(float(tk), 2), "s"), position=point(p, 1000.0, "mm"),
                rotation=point(r, 180.0 / math.pi, "deg"))
        for tk, p, r in zip(t, pos, rot, strict=True)
    )
    length = float(np.linalg.norm(np.diff(pos, axis=0), axis=1).sum())
    row.update(how="as demonstrated", demonstrated=len(poses), value=len(poses))
    comment = (f"demonstrated ({moved} relative to {frame}, frames {motion.start_frame}"
               f"-{motion.end_frame}): path of {len(poses)} keyframes over {t[-1]:.2f}s,"
               f" {length * 1000:.0f}mm")
    return StepParams((SkillParam(name=PATH, value=PathValue(poses=poses)),), comment, (row,))


def demonstrated_motions(recording: Recording, subs: Sequence[SubAction]) -> dict[int, SubActionMotion]:
    """The motion of each sub-action in ``subs`` (the matcher's: transient keyframes dropped),
    keyed by the sub-action's first frame; each one that *makes* a relation extended over the
    span the relation then lasts (:func:`dwelling`)."""
    from oacdsl.segmentation.motion import sub_action_motion
    from oacdsl.segmentation.poses import fit_poses

    posed = fit_poses(recording)
    motions = [sub_action_motion(recording, sub, posed) for sub in subs]
    found = DemonstratedMotions(
        {sub.start.frame: dwelling(recording, motions, k, posed, _made_with(sub, motions[k].target))
         for k, sub in enumerate(subs)})
    found.recording, found.posed, found.subs, found.motions = recording, posed, list(subs), motions
    return found


class DemonstratedMotions(dict[int, SubActionMotion]):
    """:func:`demonstrated_motions`' answer, which can also give a sub-action's motion of a
    named pair of objects (:meth:`of_pair`)."""

    recording: Recording
    posed: Mapping[str, ObjectPoses]
    subs: list[SubAction]
    motions: list[SubActionMotion]

    def of_pair(self, frame: int, moved: str, target: str) -> SubActionMotion | None:
        """The motion of ``moved`` relative to ``target`` in the sub-action starting at ``frame``
        (extended as :func:`dwelling` does), None when the demonstration has no such candidate."""
        from oacdsl.segmentation.motion import sub_action_motion

        k = next((i for i, sub in enumerate(self.subs) if sub.start.frame == frame), None)
        if k is None:
            return None
        m = sub_action_motion(self.recording, self.subs[k], self.posed, (moved, target))
        if (m.moved, m.target) != (moved, target):
            return None
        motions = [*self.motions[:k], m, *self.motions[k + 1 :]]
        return dwelling(self.recording, motions, k, self.posed, _made_with(self.subs[k], m.target))


def _made_with(sub: SubAction, target: str | None) -> frozenset[str]:
    """The instances that start touching ``target`` in ``sub``."""
    if target is None:
        return frozenset()
    return sub.after.partners(target) - sub.before.partners(target)


def dwelling(recording: Recording, motions: Sequence[SubActionMotion], k: int,
             posed: Mapping[str, ObjectPoses], together: frozenset[str] = frozenset()) -> SubActionMotion:
    """Motion ``k`` over the whole time its object stays with its target.

    A skill that stirs, wipes or cuts runs in the step whose effect is the tool touching
    its target (the sub-action that *makes* the relation); the demonstrated circles or
    strokes come after, while the relation is *kept*, until the sub-action that *breaks*
    it (or the recording's end, when nothing breaks it: the dough's mixing follows the
    last keyframe). So the motion of a sub-action that makes a relation is extended over
    the following sub-actions of the same object and target that keep it, and the one
    that breaks it; its features are computed on that span (the core still leaves out
    the way in and out). ``together``: the objects that started touching the target in the
    same sub-action (KIT Mix: fork and spoon into the bowl at once, mixed by both hands);
    a following sub-action that moves any of them in the target counts as well.
    """
    m = motions[k]
    if m.relation != "made" or m.target is None or m.moved is None:
        return m
    end = m.end_frame
    followers: list[SubActionMotion] = []
    for n in motions[k + 1 :]:
        same = n.target == m.target and n.moved in together | {m.moved}
        if not same or n.relation not in ("kept", "broken"):
            break
        end = n.end_frame
        followers.append(n)
        if n.relation == "broken":
            break
    else:  # the relation still holds at the last keyframe: it lasts to the recording's end
        end = len(recording.times_s) - 1
    if end == m.end_frame:
        return m
    from oacdsl.segmentation.motionfeatures import motion_features
    from oacdsl.segmentation.poses import relative

    a = m.start_frame
    times = np.asarray(recording.times_s[a : end + 1], dtype=np.float64)
    T = relative(posed[m.target].T_world_object[a : end + 1], posed[m.moved].T_world_object[a : end + 1])
    merged = dataclasses.replace(m, end_frame=end, times_s=times, T_target_object=T,
                                 features=motion_features(times, T))
    # a period at 10 Hz hangs on a sample or two: when the whole span shows none but a
    # following sub-action does (KIT Stir: frames 21-48 none, 27-48 0.50 s), that one tells
    periodic = [n for n in followers if n.features is not None and n.features.period_s is not None]
    if merged.features is not None and merged.features.period_s is None and periodic:
        return max(periodic, key=lambda n: n.end_frame - n.start_frame)
    return merged


def follows(skill: str | None) -> bool:
    """Whether ``skill`` takes a demonstrated path."""
    sig = SIGNATURES.get(skill or "")
    return sig is not None and any(p.unit == PATH for p in sig.params)
