"""The canonical printer's layout of classes (with their geometry), scenes (instances
aligned, initial state) and grasps (see :mod:`oacdsl.compiler.printer`)."""

from __future__ import annotations

from oacdsl.compiler.printer_words import (
    _IND,
    _comment_lines,
    _name,
    _number,
    _point,
    _quantity,
    _string,
    _with_note,
    format_quantity,
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

__all__: list[str] = []


def _shape(shape: Shape) -> str:
    args = ([_string(shape.file)] if shape.file is not None else []) + [
        f"{_name(d.name)} {_quantity(d.value)}" for d in shape.dims
    ]
    text = f"shape {_name(shape.primitive)}"
    if args:
        text += "(" + ", ".join(args) + ")"
    if shape.at is not None:
        text += " at " + _point(shape.at)
    return text


def _geometry(geometry: Geometry, indent: str) -> list[str]:
    """The lines inside a geometry block, each indented by ``indent``."""
    lines = [_shape(s) for s in geometry.shapes]
    if geometry.mass is not None:
        lines.append(f"mass {_quantity(geometry.mass)}")
    if geometry.friction is not None:
        lines.append(f"friction {_number(geometry.friction)}")
    if geometry.colour is not None:
        lines.append(f"colour {_name(geometry.colour)}")
    if geometry.markers:
        lines.append("markers " + ", ".join(_point(p) for p in geometry.markers))
    return [indent + line for line in lines]


def _class(decl: ObjectClass) -> list[str]:
    text = f"class {_name(decl.name)}"
    if decl.parents:
        text += " : " + ", ".join(_name(p) for p in decl.parents)
    if decl.geometry is None:
        return [_with_note(text, decl)]
    inside = _geometry(decl.geometry, _IND)
    if not inside:
        return [_with_note(text + " { }", decl)]
    return [text + " {", *inside, _with_note("}", decl)]


def _instance_line(names: list[str], inst: Instance, width: int) -> str:
    text = f"{', '.join(_name(n) for n in names):<{width}} : " + ", ".join(_name(c) for c in inst.classes)
    if inst.markers:
        text += " markers (" + ", ".join(_string(m) for m in inst.markers) + ")"
    if inst.environment:
        text += " environment"
    if inst.ignored:
        text += " ignored"
    if inst.untracked:
        text += " untracked"
    if inst.geometry is not None:
        inside = _geometry(inst.geometry, _IND * 2)
        if not inside:
            return _with_note(text + " { }", inst)
        return "\n".join([text + " {", *inside, _with_note(_IND + "}", inst)])
    return _with_note(text, inst)


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


def _scene(decl: Scene) -> list[str]:
    lines = [f"scene {_name(decl.name)} {{"]
    groups = _groups(decl.instances)
    width = max((len(", ".join(i.name for i in g)) for g in groups), default=0)
    for group in groups:
        lines += _comment_lines(group[0].comments, _IND)
        lines.append(_IND + _instance_line([i.name for i in group], group[0], width))
    lines += _scene_state(decl)
    lines.append(_with_note("}", decl))
    return lines


def _scene_state(decl: Scene) -> list[str]:
    """``layout …``, then the ``at`` and ``in`` statements, names aligned, after the instances."""
    rows: list[tuple[Node, str, str]] = []
    for place in decl.places:
        rows.append((place, place.instance, f"at ({format_quantity(place.x)}, {format_quantity(place.y)})"))
    for fill in decl.fills:
        text = f"in {_name(fill.container)}" + (f" balls {fill.balls}" if fill.balls is not None else "")
        rows.append((fill, fill.liquid, text))
    lines = [f"{_IND}layout {_name(decl.layout)}"] if decl.layout is not None else []
    if not rows and not lines:
        return lines
    if decl.instances:
        lines.insert(0, "")
    width = max((len(name) for _, name, _ in rows), default=0)
    for node, name, text in rows:
        lines += _comment_lines(node.comments, _IND)
        lines.append(_IND + _with_note(f"{_name(name):<{width}} {text}", node))
    return lines


def _grasp(decl: Grasp) -> list[str]:
    offset = ", ".join(_number(x) for x in decl.offset)
    text = (
        f"grasp {_name(decl.cls)} {{ type {_name(decl.type)} approach {_name(decl.approach)} "
        f"offset ({offset}) }}"
    )
    return [_with_note(text, decl)]
