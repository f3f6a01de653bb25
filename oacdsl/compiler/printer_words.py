"""The canonical printer's words: names (checked), numbers, strings, quantities, points,
atoms, comment lines and trailing notes, with the layout's width and indentation (see
:mod:`oacdsl.compiler.printer`)."""

from __future__ import annotations

import math
from collections.abc import Iterable

from oacdsl.compiler.grammar import name_pattern
from oacdsl.errors import LanguageError
from oacdsl.model import Atom, Node, Point, Quantity, atom_text

__all__ = [
    "INDENT",
    "WIDTH",
    "comment_lines",
    "format_atom",
    "format_quantity",
    "name_word",
    "number_word",
    "point_word",
    "string_word",
    "with_note",
]

#: A header or section longer than this (columns) goes one parameter or atom per line.
WIDTH = 100
#: One level of indentation.
INDENT = "    "


def name_word(name: str) -> str:
    """A name as written (:class:`LanguageError` for one the grammar does not take)."""
    if not name_pattern().fullmatch(name):
        raise LanguageError(
            f"cannot print {name!r}: not a name (letters, digits, '_', not starting with a digit)"
        )
    return name


def number_word(x: float) -> str:
    """A finite number as written (an offset, metres)."""
    if not math.isfinite(x):
        raise LanguageError(f"cannot print the number {x!r}: offsets must be finite (metres)")
    return repr(float(x))


def string_word(s: str) -> str:
    """A string literal, quoted and escaped."""
    escaped = s.replace("\\", "\\\\").replace('"', '\\"').replace("\n", "\\n").replace("\r", "\\r")
    escaped = escaped.replace("\t", "\\t")
    return f'"{escaped}"'


def _one_line(text: str) -> str:
    return " ".join(text.split("\n")).rstrip()


def comment_lines(comments: Iterable[str], indent: str) -> list[str]:
    """Leading comments, one ``#`` line each, at ``indent``."""
    out = []
    for comment in comments:
        for line in comment.split("\n"):
            line = line.rstrip()
            out.append(f"{indent}# {line}" if line else f"{indent}#")
    return out


def with_note(text: str, node: Node) -> str:
    """``text`` with the node's note after it (``  # note``)."""
    if node.note is None:
        return text
    note = _one_line(node.note)
    return f"{text}  # {note}" if note else f"{text}  #"


def format_atom(atom: Atom) -> str:
    """``not a <-> b`` — one relation, without its note (:class:`LanguageError` for a name that is none)."""
    return atom_text(atom, (name_word(atom.left), name_word(atom.right)))


def format_quantity(q: Quantity) -> str:
    """A quantity as written: ``56cm``, ``110deg``, ``0.3``."""
    if not math.isfinite(q.value):
        raise LanguageError(f"cannot print the number {q.value!r}: sizes must be finite")
    number = str(int(q.value)) if q.value.is_integer() and abs(q.value) < 1e15 else repr(q.value)
    if not q.unit:
        return number
    if "/" in q.unit:  # a speed: 5cm/s
        num, _, den = q.unit.partition("/")
        return number + f"{name_word(num)}/{name_word(den)}"
    return number + name_word(q.unit)


def point_word(p: Point) -> str:
    """A point as written: ``(1cm, 2cm, 0)``."""
    return f"({format_quantity(p.x)}, {format_quantity(p.y)}, {format_quantity(p.z)})"
