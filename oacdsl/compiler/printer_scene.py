"""The canonical printer's layout of classes (with their geometry), scenes (instances
aligned, initial state) and grasps (see :mod:`oacdsl.compiler.printer`)."""

from __future__ import annotations

from oacdsl.compiler.printer_words import (
    INDENT,
    comment_lines,
    format_quantity,
    name_word,
    number_word,
    point_word,
    string_word,
    with_note,
)
from oacdsl.model import (
    Geometry,
    Grasp,
    Instance,
    Node,
    ObjectClass,
    Scene,
    Shape,
)

__all__ = ["class_lines", "grasp_lines", "scene_lines"]


def _shape(shape: Shape) -> str:
    args = ([string_word(shape.file)] if shape.file is not None else []) + [
        f"{name_word(d.name)} {format_quantity(d.value)}" for d in shape.dims
    ]
    text = f"shape {name_word(shape.primitive)}"
    if args:
        text += "(" + ", ".join(args) + ")"
    if shape.at is not None:
        text += " at " + point_word(shape.at)
    return text


def _geometry(geometry: Geometry, indent: str) -> list[str]:
    """The lines inside a geometry block, each indented by ``indent``."""
    lines = [_shape(s) for s in geometry.shapes]
    if geometry.mass is not None:
        lines.append(f"mass {format_quantity(geometry.mass)}")
    if geometry.friction is not None:
        lines.append(f"friction {number_word(geometry.friction)}")
    if geometry.colour is not None:
        lines.append(f"colour {name_word(geometry.colour)}")
    if geometry.markers:
        lines.append("markers " + ", ".join(point_word(p) for p in geometry.markers))
    return [indent + line for line in lines]


def class_lines(decl: ObjectClass) -> list[str]:
    """The lines of one class declaration (with its geometry), without its leading comments."""
    text = f"class {name_word(decl.name)}"
    if decl.parents:
        text += " : " + ", ".join(name_word(p) for p in decl.parents)
    if decl.geometry is None:
        return [with_note(text, decl)]
    inside = _geometry(decl.geometry, INDENT)
    if not inside:
        return [with_note(text + " { }", decl)]
    return [text + " {", *inside, with_note("}", decl)]


def _instance_line(names: list[str], inst: Instance, width: int) -> str:
    classes = ", ".join(name_word(c) for c in inst.classes)
    text = f"{', '.join(name_word(n) for n in names):<{width}} : " + classes
    if inst.markers:
        text += " markers (" + ", ".join(string_word(m) for m in inst.markers) + ")"
    if inst.environment:
        text += " environment"
    if inst.ignored:
        text += " ignored"
    if inst.untracked:
        text += " untracked"
    if inst.geometry is not None:
        inside = _geometry(inst.geometry, INDENT * 2)
        if not inside:
            return with_note(text + " { }", inst)
        return "\n".join([text + " {", *inside, with_note(INDENT + "}", inst)])
    return with_note(text, inst)


def _groups(instances: tuple[Instance, ...]) -> list[list[Instance]]:
    """Instances that differ only in name share a line (``a, b : Hand``), in name order.

    An instance with markers or comments gets a line of its own.
    """
    groups: list[list[Instance]] = []
    by_kind: dict[tuple[tuple[str, ...], bool, bool, bool], list[Instance]] = {}
    for inst in instances:
        if inst.markers or inst.geometry is not None or inst.comments or inst.note is not None:
            groups.append([inst])
            continue
        key = (inst.classes, inst.environment, inst.ignored, inst.untracked)
        if key in by_kind:
            by_kind[key].append(inst)
        else:
            by_kind[key] = [inst]
            groups.append(by_kind[key])
    return groups


def scene_lines(decl: Scene) -> list[str]:
    """The lines of one scene declaration (instances aligned, initial state), without its leading comments."""
    lines = [f"scene {name_word(decl.name)} {{"]
    groups = _groups(decl.instances)
    width = max((len(", ".join(i.name for i in g)) for g in groups), default=0)
    for group in groups:
        lines += comment_lines(group[0].comments, INDENT)
        lines.append(INDENT + _instance_line([i.name for i in group], group[0], width))
    lines += _scene_state(decl)
    lines.append(with_note("}", decl))
    return lines


def _scene_state(decl: Scene) -> list[str]:
    """``layout …``, then the ``at`` and ``in`` statements, names aligned, after the instances."""
    rows: list[tuple[Node, str, str]] = []
    for place in decl.places:
        turned = f" turned {format_quantity(place.yaw)}" if place.yaw is not None else ""
        rows.append(
            (place, place.instance, f"at ({format_quantity(place.x)}, {format_quantity(place.y)}){turned}")
        )
    for fill in decl.fills:
        text = f"in {name_word(fill.container)}" + (f" balls {fill.balls}" if fill.balls is not None else "")
        rows.append((fill, fill.liquid, text))
    lines = [f"{INDENT}layout {name_word(decl.layout)}"] if decl.layout is not None else []
    if not rows and not lines:
        return lines
    if decl.instances:
        lines.insert(0, "")
    width = max((len(name) for _, name, _ in rows), default=0)
    for node, name, text in rows:
        lines += comment_lines(node.comments, INDENT)
        lines.append(INDENT + with_note(f"{name_word(name):<{width}} {text}", node))
    return lines


def grasp_lines(decl: Grasp) -> list[str]:
    """The lines of one grasp declaration, without its leading comments."""
    offset = ", ".join(number_word(x) for x in decl.offset)
    text = (
        f"grasp {name_word(decl.cls)} {{ type {name_word(decl.type)} approach {name_word(decl.approach)} "
        f"offset ({offset}) }}"
    )
    return [with_note(text, decl)]
