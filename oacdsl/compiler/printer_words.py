"""The canonical printer's words: names (checked), numbers, strings, quantities, points,
atoms, comment lines and trailing notes, with the layout's width and indentation (see
:mod:`oacdsl.compiler.printer`)."""

from __future__ import annotations

import math
from collections.abc import Iterable

from oacdsl.compiler.grammar import name_pattern
from oacdsl.errors import LanguageError
from oacdsl.model import Atom, Node, Point, Quantity, atom_text

__all__ = ["format_atom", "format_quantity"]

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
