"""Atoms typed on the command line (``--goal``, ``--state``): ``liquid_one <-> orange_bowl,
not mixer <-> nothing``, the language's atom syntax, each name the grammar's ``NAME``.

Parsed here token by token, not inside a wrapping OAC: a text that is more or less than
comma-separated atoms (``a <->``, ``a <-> b c``, ``a <-> b effect c <-> d``) is a one-line
:class:`~oacdsl.errors.UsageError` at its column, ``--goal:1:COL: …``, naming what was
expected, and never taken for another part of an OAC.
"""

from __future__ import annotations

import re

from oacdsl.errors import UsageError
from oacdsl.model import Atom, Span

__all__ = ["parse_atoms"]

_TOKENS = re.compile(r"<->|,|[^\s,<]+|<\S*")
_A_RELATION = "a relation such as 'h <-> o', 'h <-> nothing' or 'not h <-> o'"
#: What each state of the parser expects next.
_EXPECTED = {
    "start": _A_RELATION,
    "not": "an object after 'not'",
    "left": "'<->' between the two objects",
    "arrow": "an object or 'nothing' after '<->'",
    "right": "',' and another relation",
}


def parse_atoms(text: str, what: str = "--goal") -> tuple[Atom, ...]:
    """The comma-separated atoms of ``text``, sorted and without repeats as an OAC's conditions
    are (UsageError ``--goal:1:COL: …`` on a syntax error). Each atom's span is on line 1 of
    ``what`` at the column where it starts."""
    from oacdsl.compiler.grammar import name_pattern

    if not text.strip():
        raise UsageError(f"{what}: no atoms given (e.g. \"liquid_one <-> orange_bowl\")")
    if "\n" in text or "\r" in text:
        raise UsageError(f"{what}: atoms are written on one line, separated by commas")
    name = name_pattern()
    atoms: list[Atom] = []
    state, negated, left, start = "start", False, "", 0

    def fail(column: int, found: str) -> UsageError:
        return UsageError(f"{what}:1:{column}: {found}, expected {_EXPECTED[state]}")

    for match in _TOKENS.finditer(text):
        tok, col = match.group(), match.start() + 1
        is_name = bool(name.fullmatch(tok))
        if state == "start" and tok == "not":
            state, negated, start = "not", True, col
        elif state in ("start", "not") and is_name:
            start = col if state == "start" else start
            state, left = "left", tok
        elif state == "left" and tok == "<->":
            state = "arrow"
        elif state == "arrow" and is_name:
            span = Span(file=what, line=1, column=start, end_line=1, end_column=match.end() + 1)
            atoms.append(Atom(left=left, right=tok, negated=negated, span=span))
            state, negated = "right", False
        elif state in ("right", "start") and tok == ",":
            if state == "start":  # two commas, or a leading one
                raise fail(col, "unexpected ','")
            state = "start"
        else:
            raise fail(col, f"unexpected {tok!r}")
    if state not in ("start", "right"):
        raise fail(len(text) + 1, "the text ends")
    if not atoms:
        raise UsageError(f"{what}: no atoms given (e.g. \"liquid_one <-> orange_bowl\")")
    return tuple(sorted(dict.fromkeys(atoms), key=Atom.sort_key))
