"""The canonical printer: one layout for every model, comments kept.

Deterministic: the model already keeps parents, instance classes, instances
and atoms sorted; the printer keeps declarations, parameters, markers and
steps in their order (a ``together { … }`` block's too: the runtime runs them as written). Layout rules:

* four spaces of indentation, one blank line between declarations except
  between consecutive one-line ``class`` or ``grasp`` declarations;
* instances one per line with their colons aligned;
* ``pre``/``effect``/``execute`` aligned on one column; a section goes one
  atom per line when an atom carries a comment or the line passes 100 columns;
  parameters likewise go one per line when one carries a comment;
* leading comments on their own lines above the node, notes after it.

``parse_text(print_module(m)) == m`` and printing is idempotent (tests check both).
"""

from __future__ import annotations

import math
from collections.abc import Iterable

from oacdsl.compiler.grammar import name_pattern
from oacdsl.errors import LanguageError
from oacdsl.model import (
    Atom,
    Call,
    Decl,
    Geometry,
    Grasp,
    Instance,
    KeyPose,
    Module,
    Node,
    Oac,
    ObjectClass,
    Param,
    PathValue,
    Point,
    Quantity,
    Scene,
    Shape,
    SkillParam,
    atom_text,
    canonical_steps,
    step_groups,
)
from oacdsl.world import NOTHING

__all__ = ["format_atom", "format_decl", "format_oac", "format_quantity", "print_module"]

_WIDTH = 100
_IND = "    "


def _name(name: str) -> str:
    if not name_pattern().fullmatch(name):
        raise LanguageError(
            f"cannot print {name!r}: not a name (letters, digits, '_', not starting with a digit)"
        )
    return name


def _number(x: float) -> str:
    if not math.isfinite(x):
        raise LanguageError(f"cannot print the number {x!r}: offsets must be finite (metres)")
    return repr(float(x))


def _string(s: str) -> str:
    escaped = s.replace("\\", "\\\\").replace('"', '\\"').replace("\n", "\\n").replace("\r", "\\r")
    escaped = escaped.replace("\t", "\\t")
    return f'"{escaped}"'


def _one_line(text: str) -> str:
    return " ".join(text.split("\n")).rstrip()


def _comment_lines(comments: Iterable[str], indent: str) -> list[str]:
    out = []
    for comment in comments:
        for line in comment.split("\n"):
            line = line.rstrip()
            out.append(f"{indent}# {line}" if line else f"{indent}#")
    return out


def _with_note(text: str, node: Node) -> str:
    if node.note is None:
        return text
    note = _one_line(node.note)
    return f"{text}  # {note}" if note else f"{text}  #"


def format_atom(atom: Atom) -> str:
    """``not a <-> b`` — one relation, without its note (:class:`LanguageError` for a name that is none)."""
    return atom_text(atom, (_name(atom.left), _name(atom.right)))


def _quantity(q: Quantity) -> str:
    if not math.isfinite(q.value):
        raise LanguageError(f"cannot print the number {q.value!r}: sizes must be finite")
    number = str(int(q.value)) if q.value.is_integer() and abs(q.value) < 1e15 else repr(q.value)
    if not q.unit:
        return number
    if "/" in q.unit:  # a speed: 5cm/s
        num, _, den = q.unit.partition("/")
        return number + f"{_name(num)}/{_name(den)}"
    return number + _name(q.unit)


def format_quantity(q: Quantity) -> str:
    """A quantity as written: ``56cm``, ``110deg``, ``0.3``."""
    return _quantity(q)


def _point(p: Point) -> str:
    return f"({_quantity(p.x)}, {_quantity(p.y)}, {_quantity(p.z)})"


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


def _param(param: Param) -> str:
    text = f"{_name(param.name)}: {_name(param.cls)}"
    if param.default is not None:
        text += f" = {_name(param.default)}"
    return text


def _header(decl: Oac) -> list[str]:
    head = f"oac {_name(decl.name)}("
    params = [_param(p) for p in decl.params]
    one = f"{head}{', '.join(params)}) {{"
    if len(one) <= _WIDTH and not any(p.comments or p.note is not None for p in decl.params):
        return [one]
    lines = [head]
    for param, text in zip(decl.params, params, strict=True):
        lines += _comment_lines(param.comments, _IND)
        lines.append(_IND + _with_note(text + ",", param))
    lines.append(") {")
    return lines


def _display(oac: Oac, atoms: tuple[Atom, ...]) -> list[tuple[Atom, str]]:
    """Atoms in display order, each with its text.

    Positive atoms come before negated ones, then by parameter position; a pair
    is written with the earlier parameter on the left (``h <-> c`` for
    ``pour(h: Hand, c: Container, …)``). Names that are not parameters come
    after the parameters in alphabetical order; ``nothing`` is always on the right.
    """
    rank = {p.name: i for i, p in enumerate(oac.params)}
    n = len(oac.params)

    def key(name: str) -> tuple[int, str]:
        if name == NOTHING:
            return (n + 1, "")
        return (rank[name], "") if name in rank else (n, name)

    rows = []
    for atom in atoms:
        a, b = atom.left, atom.right
        if b != NOTHING and key(b) < key(a):
            a, b = b, a
        rows.append(((atom.negated, key(a), key(b)), atom, atom_text(atom, (_name(a), _name(b)))))
    rows.sort(key=lambda r: r[0])
    return [(atom, text) for _, atom, text in rows]


def _section(keyword: str, oac: Oac, atoms: tuple[Atom, ...]) -> list[str]:
    lead = f"{_IND}{keyword:<8}"
    shown = _display(oac, atoms)
    one = lead + ", ".join(text for _, text in shown)
    if len(one) <= _WIDTH and not any(a.comments or a.note is not None for a in atoms):
        return [one]
    pad = " " * len(lead)
    lines: list[str] = []
    for i, (atom, text) in enumerate(shown):
        comments = _comment_lines(atom.comments, pad)
        if i == 0 and comments:
            lines.append(lead.rstrip())
        lines += comments
        first = lead if i == 0 and not comments else pad
        sep = "," if i < len(shown) - 1 else ""
        lines.append(first + _with_note(text + sep, atom))
    return lines


def _skill_params(params: tuple[SkillParam, ...], indent: str = _IND) -> str:
    """`` { tilt 110deg  duration 2s }`` ("" for none); a path last, one keyframe a line
    (``indent``: the line's own indentation)."""
    if not params:
        return ""
    words = [f"{_name(s.name)} {format_quantity(s.value)}" for s in params if isinstance(s.value, Quantity)]
    for s in params:
        if isinstance(s.value, PathValue):
            poses = [f"{indent}{_IND}{_keypose(k)}," for k in s.value.poses]
            words.append(f"{_name(s.name)} [\n" + "\n".join(poses) + f"\n{indent}]")
    return " { " + "  ".join(words) + " }"


def _keypose(k: KeyPose) -> str:
    return f"{_quantity(k.time)} {_point(k.position)} {_point(k.rotation)}"


def _call(call: Call) -> str:
    head = f"{_name(call.oac)}(" + ", ".join(_name(a) for a in call.args) + ")"
    return _with_note(head + _skill_params(call.skill_params, _IND * 2), call)


def _oac(decl: Oac) -> list[str]:
    lines = _header(decl)
    if decl.pre:
        lines += _section("pre", decl, decl.pre)
    if decl.effect:
        lines += _section("effect", decl, decl.effect)
    if decl.steps is not None and decl.skill is not None:
        raise LanguageError(f"cannot print OAC '{decl.name}': it has both a skill and steps")
    if decl.steps is not None:
        lines.append(f"{_IND}steps {{")
        for group in step_groups(canonical_steps(decl.steps)):
            indent = _IND * (2 if len(group) == 1 else 3)
            if len(group) > 1:
                lines.append(f"{_IND * 2}together {{")
            for call in group:
                lines += _comment_lines(call.comments, indent)
                lines.append(indent + _call(call))
            if len(group) > 1:
                lines.append(f"{_IND * 2}}}")
        lines.append(f"{_IND}}}")
    elif decl.skill is not None:
        text = f"{_IND}{'execute':<8}{_name(decl.skill)}"
        if decl.skill_args is not None:
            text += "(" + ", ".join(_name(a) for a in decl.skill_args) + ")"
        lines.append(text + _skill_params(decl.skill_params, _IND))
    else:
        raise LanguageError(f"cannot print OAC '{decl.name}': it has neither a skill nor steps")
    lines.append(_with_note("}", decl))
    return lines


def _decl_lines(decl: Decl) -> list[str]:
    if isinstance(decl, ObjectClass):
        body = _class(decl)
    elif isinstance(decl, Scene):
        body = _scene(decl)
    elif isinstance(decl, Grasp):
        body = _grasp(decl)
    elif isinstance(decl, Oac):
        body = _oac(decl)
    else:
        raise LanguageError(f"cannot print {type(decl).__name__}: not a declaration")
    return _comment_lines(decl.comments, "") + body


def format_decl(decl: Decl) -> str:
    """One declaration in canonical form (with its comments), ending in a newline."""
    return "\n".join(_decl_lines(decl)) + "\n"


def format_oac(oac: Oac) -> str:
    """One OAC in canonical form, ending in a newline (what the composer writes)."""
    return format_decl(oac)


def _tight(prev: Decl, decl: Decl) -> bool:
    if any(isinstance(d, ObjectClass) and d.geometry is not None for d in (prev, decl)):
        return False
    return isinstance(decl, ObjectClass | Grasp) and type(prev) is type(decl) and not decl.comments


def print_module(module: Module) -> str:
    """The whole file in canonical form ("" for a file with nothing in it)."""
    if not module.decls:
        only = _comment_lines((*module.comments, *module.trailing), "")
        return "\n".join(only) + "\n" if only else ""
    lines: list[str] = _comment_lines(module.comments, "")
    if lines:
        lines.append("")
    prev: Decl | None = None
    for decl in module.decls:
        if prev is not None and not _tight(prev, decl):
            lines.append("")
        lines += _decl_lines(decl)
        prev = decl
    if module.trailing:
        lines.append("")
        lines += _comment_lines(module.trailing, "")
    return "\n".join(lines) + "\n"
