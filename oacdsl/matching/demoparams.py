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

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from oacdsl.library import Library
from oacdsl.matching.demomotions import DemonstratedMotions, demonstrated_motions, dwelling
from oacdsl.model import Quantity, Scene, SkillParam
from oacdsl.segmentation.motion import SubActionMotion
from oacdsl.skills import PATH, SIGNATURES, MotionSource, SkillParamSpec

__all__ = [
    "CLEARANCE_M",
    "StepParams",
    "DemonstratedMotions",
    "demonstrated_motions",
    "dwelling",
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


def follows(skill: str | None) -> bool:
    """Whether ``skill`` takes a demonstrated path."""
    sig = SIGNATURES.get(skill or "")
    return sig is not None and any(p.unit == PATH for p in sig.params)
