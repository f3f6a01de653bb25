"""Draft a ``.oac`` scene for a recording: classes with estimated geometry, the scene, its sub-actions.

:func:`draft_scene` turns a grouped recording and its segmentation into the text of a
``.oac`` file that compiles (alone, or with the library it was drafted against) and that
the canonical printer leaves unchanged: every marker group becomes an instance — hands
(the segmentation's agents, ``*hand*``) of class ``Hand``, objects of a class of their own
with a box or cylinder from :mod:`oacdsl.draft.estimate` — next to ``table : Table
environment`` and ``layout demonstrated``; the sub-actions of the segmentation are listed
as comments. Every number says in a comment how it was found.
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass

import numpy as np

from oacdsl.draft.estimate import ShapeEstimate, estimate_shape, table_height
from oacdsl.draft.facing import MIN_TURN_DEG, demonstrator_forward, drafted_turn
from oacdsl.draft.hints import alike_notes, carried_notes, lying_notes, stacked_notes
from oacdsl.draft.names import camel_case, instance_name, library_class_for, unique
from oacdsl.draft.support import supports
from oacdsl.geometry import ROLE_SHAPES
from oacdsl.library import Library
from oacdsl.segmentation.poses import MIN_MARKERS
from oacdsl.segmentation.recording import Recording
from oacdsl.segmentation.result import Segmentation

__all__ = ["BASE_CLASSES", "DENSITY_KG_M3", "MIN_MASS_KG", "Draft", "draft_scene"]

#: Mass guess: the shape's volume times this density, kg/m³ (between a hollow container, ~100,
#: and solid wood, ~600).
DENSITY_KG_M3 = 300.0
#: The lightest mass drafted, kilograms (10 g).
MIN_MASS_KG = 0.010
#: The base classes a draft without a library carries (name → declaration).
BASE_CLASSES: dict[str, str] = {
    "Hand": "class Hand { shape hand }",
    "Graspable": "class Graspable",
    "Container": "class Container",
    "Liquid": "class Liquid { shape balls(radius 9mm, mass 3g) }",
    "Surface": "class Surface",
    "Tool": "class Tool : Graspable",
    "Table": "class Table : Surface { shape table }",
}
_NEEDED = ("Hand", "Graspable", "Surface", "Table")  # what a draft itself uses
_FACING = (", x the one nearer the demonstrator's forward: the robot stands an object with its x axis"
           " away from it, so it lies as the demonstrator had it.")
_PARENTS_NOTE = ("parents: Graspable (the robot may pick it up); also possible: Container (a liquid"
                 " or a tool can be in it: give it a 'shell' shape, a box holds nothing), Tool (a Graspable"
                 " used on another object), Surface (things stand on it)")


@dataclass(frozen=True)
class Draft:
    """A drafted scene: its text and what went into it.

    Attributes:
        text: the ``.oac`` file, canonical form.
        scene: the scene's name.
        instances: marker group → instance name.
        classes: instance name → its class.
        written: the classes the text declares (the others come from the library).
        estimates: instance name → its estimated shape (objects with ≥ 3 markers).
        table_z_m: the table top's estimated height, metres.
    """

    text: str
    scene: str
    instances: dict[str, str]
    classes: dict[str, str]
    written: tuple[str, ...]
    estimates: dict[str, ShapeEstimate]
    table_z_m: float


def _mm(x_m: float) -> str:
    v = int(round(x_m * 1000.0))
    return "0" if v == 0 else f"{v}mm"


def _mass(estimate: ShapeEstimate) -> tuple[str, float]:
    kg = max(estimate.volume_m3 * DENSITY_KG_M3, MIN_MASS_KG)
    return f"{int(round(kg * 1000))}g", kg


def _class_lines(cls: str, est: ShapeEstimate, table_z_m: float, n_markers: int, frames: int) -> list[str]:
    """The comments and the declaration of an object class with geometry."""
    top = table_z_m + est.height_m
    lines = [f"# {est.instance}: {n_markers} markers; constellation at frame {est.reference_frame}"
             f" (of {frames}: the first with the most markers seen)."]
    if est.shape == "cylinder":
        lines.append(f"# cylinder: {len(est.markers_m)} markers lie on a circle of radius"
                     f" {_mm(est.radius_m)} around a vertical axis (rms {est.round_rms_m * 1000:.1f} mm off"
                     " it): markers on a rim; on stalks off the surface (KIT's: 1-2.5 cm) the object's"
                     " radius is that much smaller.")
        size = f"shape cylinder(radius {_mm(est.radius_m)}, height {_mm(est.height_m)})"
    else:
        lines.append(f"# box: {est.length_m * 1000:.0f} x {est.width_m * 1000:.0f} mm = the markers'"
                     " extent along their principal horizontal axes (x, y)"
                     + (_FACING if est.facing else "."))
        size = f"shape box(length {_mm(est.length_m)}, width {_mm(est.width_m)}, height {_mm(est.height_m)})"
    lines.append(f"# height {est.height_m * 1000:.0f} mm = highest marker {top * 1000:.0f} mm - table top"
                 f" {table_z_m * 1000:.0f} mm; markers sit on the surface: the object may be larger.")
    if est.raised:
        lines.append(f"# {', '.join(est.raised)} raised to 1 cm: the markers lie in a line or a plane;"
                     " measure it.")
    mass, kg = _mass(est)
    lines.append(f"# mass {mass} = volume {est.volume_m3 * 1e6:.0f} cm3 x {DENSITY_KG_M3:g} kg/m3 (a guess"
                 f"{', raised to 10 g' if kg == MIN_MASS_KG else ''}); weigh the object.")
    lines.append("# markers: where they sat at that frame, in the object frame (origin at the base centre,"
                 f" x along {'that' if est.facing else 'the principal'} axis, z up)"
                 + (f"; {est.unseen} marker(s) unseen there are left out." if est.unseen else "."))
    lines.append(f"# {_PARENTS_NOTE}.")
    markers = ", ".join(f"({_mm(x)}, {_mm(y)}, {_mm(z)})" for x, y, z in est.markers_m)
    lines += [f"class {cls} : Graspable {{", f"    {size}", f"    mass {mass}", f"    markers {markers}", "}"]
    return lines


def _grasp_line(cls: str, est: ShapeEstimate) -> str:
    approach = "top" if est.height_m < 0.03 else "side"
    return (f"grasp {cls} {{ type power approach {approach} offset (0.0, 0.0,"
            f" {round(est.height_m / 2, 3)}) }}")


def _sub_actions(segmentation: Segmentation, rename: dict[str, str]) -> list[str]:
    """``# sub-action 2 (frames 21-27): + a <-> b`` per sub-action of the segmentation."""
    lines = []
    keyframes = segmentation.keyframes
    for i in range(1, len(keyframes)):
        before, after = keyframes[i - 1].state.relations, keyframes[i].state.relations

        def text(pairs: Iterable[tuple[str, str]], sign: str) -> list[str]:
            named = sorted(tuple(sorted((rename.get(a, a), rename.get(b, b)))) for a, b in pairs)
            return [f"{sign} {a} <-> {b}" for a, b in named]

        changes = text(after - before, "+") + text(before - after, "-")
        lines.append(f"# sub-action {i} (frames {keyframes[i - 1].frame}-{keyframes[i].frame}):"
                     f" {', '.join(changes) or 'no change'}")
    return lines or ["# (no sub-action found: nothing touches anything else in this recording)"]


def draft_scene(recording: Recording, segmentation: Segmentation, name: str,
                library: Library | None = None, *, hands: Iterable[str] = (),
                compose_hint: str = "") -> Draft:
    """The draft of ``recording`` (grouped) as a scene ``name`` (module doc).

    ``hands``: the agents among the groups (class ``Hand``); the sub-actions are those of
    :func:`~oacdsl.matching.transient.stable_segmentation` (as ``oacc match`` numbers them: an
    object briefly in flight splits none); ``library``: classes defined
    there are used, not written again; ``compose_hint``: the command that drafts the OACs.
    """
    from oacdsl.compiler import parse_text, print_module
    from oacdsl.matching.transient import stable_segmentation

    known = set(library.classes) if library is not None else set()
    buildable = [c for c, d in (library.classes.items() if library is not None else ())
                 if d.geometry is not None and d.geometry.shapes
                 and not {sh.primitive for sh in d.geometry.shapes} & ROLE_SHAPES]
    agents = set(hands)
    segmentation, _ = stable_segmentation(segmentation, agents.__contains__)  # as oacc match counts them
    groups = list(recording.instances)
    objects = [g for g in groups if g not in agents]
    table_z, lowest = table_height(recording, objects)
    forward = demonstrator_forward(recording, agents)
    support = supports(recording, objects, table_z)
    instances: dict[str, str] = {}
    explicit: dict[str, tuple[str, ...]] = {}
    for g in groups:
        inst, renamed = instance_name(g, set(instances.values()) | {"table"})
        instances[g] = inst
        if renamed:
            explicit[inst] = tuple(recording.marker_names[i] for i in recording.groups[g])
    bases = set(BASE_CLASSES)
    from_library: dict[str, str] = {}
    tie_notes: list[str] = []
    classes: dict[str, str] = {}
    estimates: dict[str, ShapeEstimate] = {}
    decls: list[list[str]] = []
    grasps: list[str] = []
    written: list[str] = []
    for g in groups:
        inst = instances[g]
        if g in agents:
            classes[inst] = "Hand"
            continue
        cls = camel_case(inst)
        cls = unique(f"{cls}Object", written) if cls in bases else cls  # a group called 'tool', 'container' …
        cls = unique(cls, written)
        reused: str | None = None
        tied: list[str] = []
        if cls not in known:
            reused, tied = library_class_for(g, buildable)
            if reused is not None:
                cls, from_library[inst] = reused, "its name's words are in the group's name"
            elif tied:
                tie_notes.append(f"    # {inst}: the library's {', '.join(tied)} all fit its name: none is"
                                 " chosen; write the one you mean as its class")
        classes[inst] = cls
        n = len(recording.groups[g])
        if cls in known:
            continue  # the library's class of that name is this object
        written.append(cls)
        seen_at_once = int(np.isfinite(recording.group_positions(g)).all(axis=2).sum(axis=1).max())
        if seen_at_once < MIN_MARKERS:
            why = (f"{n} marker(s)" if n < MIN_MARKERS
                   else f"{n} markers, but never more than {seen_at_once} seen at once")
            decls.append([f"# {g}: {why}; a shape needs at least {MIN_MARKERS} (a rigid fit): give it a"
                          " geometry block ('{ shape box(length …, width …, height …) mass … }') if the robot"
                          " should build it, or mark the instance 'ignored'.",
                          f"# {_PARENTS_NOTE}.", f"class {cls} : Graspable"])
            continue
        stand = support[g]
        est = estimate_shape(recording, g, stand.base_z_m)  # x along its length: turned, not remodelled
        estimates[inst] = est
        decl = _class_lines(cls, est, stand.base_z_m, n, recording.n_frames)
        if stand.on is not None:
            under = instances[stand.on]
            decl.insert(1, f"# it stands on {under} at frame {stand.frame}: its base is {under}'s highest"
                           f" marker ({stand.base_z_m * 1000:.0f} mm), not the table top.")
            decl[2:2] = stacked_notes(recording, g, under, stand.frame, stand.base_z_m)
            decl = [x.replace("- table top", f"- {under}'s top") for x in decl]
        decl[1:1] = carried_notes(recording, g, support, instances, stand.base_z_m) + lying_notes(est)
        if reused is None and not tied:
            decl[1:1] = alike_notes(g, inst, buildable, cls)
        decls.append(decl)
        grasps.append(_grasp_line(cls, est))
    base_names = list(BASE_CLASSES) if library is None else [c for c in _NEEDED if c not in known]
    base = [BASE_CLASSES[c] for c in base_names]
    width = max(len(i) for i in instances.values())
    scene = [f"scene {name} {{"]
    for g in groups:
        inst = instances[g]
        markers = f" markers ({', '.join(_quoted(m) for m in explicit[inst])})" if inst in explicit else ""
        if inst in explicit:
            scene.append(f"    # marker group {g!r} is not a name of the language: its markers are listed")
        elif inst in from_library:
            scene.append(f"    # class {classes[inst]} comes from the library ({from_library[inst]})")
        elif classes[inst] in known and g not in agents:
            scene.append(f"    # class {classes[inst]} comes from the library (named like the group)")
        scene += [t for t in tie_notes if t.startswith(f"    # {inst}:")]
        scene.append(f"    {inst:<{width}} : {classes[inst]}{markers}")
    scene += _turn_notes(estimates, forward)
    scene += [f"    # the table top stands at {table_z * 1000:.0f} mm (z up): the lowest object marker at the"
              f" first frame ({lowest}); it may sit a marker's radius (5-10 mm) above the table",
              f"    {'table':<{width}} : Table environment", "    layout demonstrated", "}"]
    sub = _sub_actions(segmentation, {g: i for g, i in instances.items()})
    header = ["# A draft scene written by oacc draft for", f"#   {recording.source}",
              "# Every size, mass and marker below is a first guess from the markers (the comments say",
              "# how); edit them, then check the file with: oacc compile THIS_FILE [LIBRARY]",
              "", "# base classes" if base else ""]
    body = [*base, "", *[line for d in decls for line in (*d, "")], *grasps, ""]
    hint = [f"# The sub-actions of the demonstration ({len(segmentation.keyframes)} keyframes), numbered as"
            " oacc match and compose number them (an object briefly in flight splits none): each needs an"
            " OAC."]
    if compose_hint:
        hint += ["# To draft the OACs a library lacks for them:", f"#   {compose_hint}"]
    text = "\n".join(_wrapped([*header, *body, *hint, *sub, *scene])) + "\n"
    module = parse_text(text, f"<draft {name}>")
    return Draft(print_module(module), name, instances, classes, tuple(written), estimates, table_z)


def _turn_notes(estimates: dict[str, ShapeEstimate], forward: np.ndarray | None) -> list[str]:
    """A ``turned`` statement (commented) per drafted box that lies turned from the demonstrator's
    forward (:func:`~oacdsl.draft.facing.drafted_turn`): laid out as demonstrated it is turned so
    by its markers; placed by ``at`` it needs the statement."""
    if forward is None:
        return []
    out = []
    for inst, est in sorted(estimates.items()):
        deg = drafted_turn(est.x_axis_xy, forward)
        if est.shape == "box" and abs(deg) >= MIN_TURN_DEG:
            out += [f"    # {inst} lies turned {deg:g}deg (its x, its length, from the demonstrator's forward"
                    " towards the left): 'layout demonstrated' turns it so by its markers; placed by 'at',"
                    " it needs:", f"    #   {inst} at (x, y) turned {deg:g}deg"]
    return out


def _wrapped(lines: list[str], width: int = 100) -> list[str]:
    """Comment lines longer than ``width`` broken into several, continued with an indent (not
    ``#   …`` lines: a command or a path to copy)."""
    import textwrap

    out = []
    for line in lines:
        stripped = line.lstrip()
        if len(line) <= width or not stripped.startswith("# ") or stripped.startswith("#   "):
            out.append(line)
            continue
        indent = line[: len(line) - len(stripped)]
        out += textwrap.wrap(stripped[2:], width=width, initial_indent=f"{indent}# ", break_long_words=False,
                             subsequent_indent=f"{indent}#   ", break_on_hyphens=False)
    return out


def _quoted(marker: str) -> str:
    escaped = marker.replace("\\", "\\\\").replace('"', '\\"').replace("\n", "\\n").replace("\r", "\\r")
    return '"' + escaped.replace("\t", "\\t") + '"'
