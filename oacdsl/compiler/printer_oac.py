"""The canonical printer's layout of OACs: the header with its parameters, the aligned
``pre``/``effect``/``execute`` sections, skill parameters and paths, steps and ``together``
blocks (see :mod:`oacdsl.compiler.printer`)."""

from __future__ import annotations

from oacdsl.compiler.printer_words import (
    INDENT,
    WIDTH,
    comment_lines,
    format_quantity,
    name_word,
    point_word,
    with_note,
)
from oacdsl.errors import LanguageError
from oacdsl.model import (
    Atom,
    Call,
    KeyPose,
    Oac,
    Param,
    PathValue,
    Quantity,
    SkillParam,
    atom_text,
    canonical_steps,
    step_groups,
)
from oacdsl.world import NOTHING

__all__ = ["oac_lines"]


def _param(param: Param) -> str:
    text = f"{name_word(param.name)}: {name_word(param.cls)}"
    if param.default is not None:
        text += f" = {name_word(param.default)}"
    return text


def _header(decl: Oac) -> list[str]:
    head = f"oac {name_word(decl.name)}("
    params = [_param(p) for p in decl.params]
    one = f"{head}{', '.join(params)}) {{"
    if len(one) <= WIDTH and not any(p.comments or p.note is not None for p in decl.params):
        return [one]
    lines = [head]
    for param, text in zip(decl.params, params, strict=True):
        lines += comment_lines(param.comments, INDENT)
        lines.append(INDENT + with_note(text + ",", param))
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
        rows.append(((atom.negated, key(a), key(b)), atom, atom_text(atom, (name_word(a), name_word(b)))))
    rows.sort(key=lambda r: r[0])
    return [(atom, text) for _, atom, text in rows]


def _section(keyword: str, oac: Oac, atoms: tuple[Atom, ...]) -> list[str]:
    lead = f"{INDENT}{keyword:<8}"
    shown = _display(oac, atoms)
    one = lead + ", ".join(text for _, text in shown)
    if len(one) <= WIDTH and not any(a.comments or a.note is not None for a in atoms):
        return [one]
    pad = " " * len(lead)
    lines: list[str] = []
    for i, (atom, text) in enumerate(shown):
        comments = comment_lines(atom.comments, pad)
        if i == 0 and comments:
            lines.append(lead.rstrip())
        lines += comments
        first = lead if i == 0 and not comments else pad
        sep = "," if i < len(shown) - 1 else ""
        lines.append(first + with_note(text + sep, atom))
    return lines


def _skill_params(params: tuple[SkillParam, ...], indent: str = INDENT) -> str:
    """`` { tilt 110deg  duration 2s }`` ("" for none); a path last, one keyframe a line
    (``indent``: the line's own indentation)."""
    if not params:
        return ""
    words = [
        f"{name_word(s.name)} {format_quantity(s.value)}" for s in params if isinstance(s.value, Quantity)
    ]
    for s in params:
        if isinstance(s.value, PathValue):
            poses = [f"{indent}{INDENT}{_keypose(k)}," for k in s.value.poses]
            words.append(f"{name_word(s.name)} [\n" + "\n".join(poses) + f"\n{indent}]")
    return " { " + "  ".join(words) + " }"


def _keypose(k: KeyPose) -> str:
    return f"{format_quantity(k.time)} {point_word(k.position)} {point_word(k.rotation)}"


def _call(call: Call) -> str:
    head = f"{name_word(call.oac)}(" + ", ".join(name_word(a) for a in call.args) + ")"
    return with_note(head + _skill_params(call.skill_params, INDENT * 2), call)


def oac_lines(decl: Oac) -> list[str]:
    """The lines of one OAC declaration (without its leading comments)."""
    lines = _header(decl)
    if decl.pre:
        lines += _section("pre", decl, decl.pre)
    if decl.effect:
        lines += _section("effect", decl, decl.effect)
    if decl.steps is not None and decl.skill is not None:
        raise LanguageError(f"cannot print OAC '{decl.name}': it has both a skill and steps")
    if decl.steps is not None:
        lines.append(f"{INDENT}steps {{")
        for group in step_groups(canonical_steps(decl.steps)):
            indent = INDENT * (2 if len(group) == 1 else 3)
            if len(group) > 1:
                lines.append(f"{INDENT * 2}together {{")
            for call in group:
                lines += comment_lines(call.comments, indent)
                lines.append(indent + _call(call))
            if len(group) > 1:
                lines.append(f"{INDENT * 2}}}")
        lines.append(f"{INDENT}}}")
    elif decl.skill is not None:
        text = f"{INDENT}{'execute':<8}{name_word(decl.skill)}"
        if decl.skill_args is not None:
            text += "(" + ", ".join(name_word(a) for a in decl.skill_args) + ")"
        lines.append(text + _skill_params(decl.skill_params, INDENT))
    else:
        raise LanguageError(f"cannot print OAC '{decl.name}': it has neither a skill nor steps")
    lines.append(with_note("}", decl))
    return lines
