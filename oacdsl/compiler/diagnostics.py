"""Diagnostics: what ``oacc compile`` reports, with a stable code each.

A :class:`Diagnostic` names a code (``E…`` errors, ``W…`` warnings), a message,
the span it is about and optional notes ("defined here", hints). Rendering
follows the compiler convention::

    library/kitchen.oac:12:15: error[E003]: unknown class 'Cpu' (did you mean 'Cup'?)
       12 |     red_cup : Cpu
          |               ^^^
      library/classes.oac:7:7: note: class 'Cup' is defined here

:data:`CODES` lists every code with a one-line title; docs/language.md shows an
example message for each and a test checks the two agree.
"""

from __future__ import annotations

import functools
from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field
from typing import Any

from oacdsl.errors import LanguageError
from oacdsl.model import Span

__all__ = [
    "CODES",
    "EXCERPT_WIDTH",
    "MAX_RENDERED",
    "Diagnostic",
    "Note",
    "diagnostics_json",
    "language_error",
    "render",
    "render_one",
    "sort_diagnostics",
    "summary",
]

#: Every diagnostic code with its title. Errors start with E, warnings with W.
CODES: dict[str, str] = {
    "E001": "syntax error: unexpected token or end of input",
    "E002": "syntax error: a character that cannot start any token",
    "E003": "unknown class",
    "E004": "unknown instance",
    "E005": "unbound variable: neither a parameter nor a scene instance",
    "E006": "duplicate definition",
    "E007": "cycle in the class hierarchy",
    "E008": "relation of an object with itself",
    "E009": "precondition contradicts itself",
    "E010": "effect contradicts itself",
    "E011": "OAC states no effect",
    "E012": "effect changes nothing: every effect already holds before",
    "E013": "step calls an unknown OAC",
    "E014": "step passes the wrong number of arguments",
    "E015": "step passes an argument of the wrong class",
    "E016": "unknown skill: the runtime does not provide it",
    "E017": "default binding of the wrong class",
    "E018": "reserved word used as a name",
    "E019": "composed OAC calls itself (directly or through other OACs)",
    "E020": "unknown grasp type or approach direction",
    "E021": "environment or ignored instance in a relation",
    "E022": "marker assigned to two instances",
    "E023": "composed OAC without steps",
    "E024": "file is not UTF-8 text",
    "E025": "number too large to be a finite value",
    "E030": "unknown shape",
    "E031": "unknown, repeated or missing parameter of a shape",
    "E032": "unknown unit, or a unit of the wrong kind",
    "E033": "size, mass or friction not positive and finite, or sizes that do not fit together",
    "E034": "mesh file not found",
    "E035": "geometry property given twice",
    "E036": "hand, table or balls combined with other shapes",
    "E037": "unknown colour",
    "E040": "skill called with the wrong number of arguments",
    "E041": "skill argument of the wrong class",
    "E042": "unknown skill parameter",
    "E043": "quantity with the wrong or an unknown unit",
    "E044": "value out of range or not a whole number (skill parameter, ball count)",
    "E045": "unknown layout or scene statement",
    "E046": "scene state that does not fit the instance (a place for a hand, contents of a non-container, …)",
    "E047": "skill parameters on a step that calls a composed OAC",
    "E048": "untracked instance that the recording must track (a hand) or that names markers",
    "E049": "pinch grasp whose offset lies on the object's axis (a pinch takes an edge)",
    "E051": "steps of a together block that depend on each other",
    "W001": "unused variable",
    "W002": "name or relation listed twice",
    "W003": "effect already holds before (it is also a precondition)",
    "W004": "graspable instance whose classes have no grasp",
    "W005": "grasp offset longer than 0.5 m (offsets are metres)",
    "W006": "size over 5 m written without a unit (sizes without a unit are metres)",
    "W007": "instance without a shape (the robot's simulation cannot build it)",
    "W008": "together block of fewer than two steps",
    "W040": "number without unit that is implausible in SI units (radians, metres)",
}


@dataclass(frozen=True)
class Note:
    """A secondary message, optionally with its own location ("defined here")."""

    message: str
    span: Span | None = None

    def to_json(self) -> dict[str, Any]:
        out: dict[str, Any] = {"message": self.message}
        if self.span is not None:
            out.update(_span_json(self.span))
        return out


@dataclass(frozen=True)
class Diagnostic:
    """One error or warning about a span of a ``.oac`` file."""

    code: str
    message: str
    span: Span | None = None
    notes: tuple[Note, ...] = field(default=())

    @property
    def severity(self) -> str:
        """``"error"`` or ``"warning"`` (from the code's first letter)."""
        return "error" if self.code.startswith("E") else "warning"

    @property
    def is_error(self) -> bool:
        return self.code.startswith("E")

    def header(self) -> str:
        """``file:line:col: error[CODE]: message`` — the first line of the rendering."""
        where = f"{self.span}: " if self.span is not None else ""
        return f"{where}{self.severity}[{self.code}]: {self.message}"

    def sort_key(self) -> tuple[str, int, int, str, str]:
        s = self.span
        if s is None:
            return ("", 0, 0, self.code, self.message)
        return (s.file, s.line, s.column, self.code, self.message)

    def to_json(self) -> dict[str, Any]:
        out: dict[str, Any] = {"severity": self.severity, "code": self.code, "message": self.message}
        if self.span is not None:
            out.update(_span_json(self.span))
        out["notes"] = [n.to_json() for n in self.notes]
        return out


def _span_json(span: Span) -> dict[str, Any]:
    return {
        "file": span.file,
        "line": span.line,
        "column": span.column,
        "end_line": span.end_line,
        "end_column": span.end_column,
    }


def sort_diagnostics(diagnostics: Iterable[Diagnostic]) -> list[Diagnostic]:
    """Sorted by file, line, column; duplicates removed."""
    unique = {(d.sort_key(), d.notes): d for d in diagnostics}
    return [unique[k] for k in sorted(unique, key=lambda k: k[0])]


@functools.lru_cache(maxsize=8)
def _lines(text: str) -> list[str]:
    """``text`` split into lines, once per text (a file with 100,000 errors is split once, not
    100,000 times; a str caches its hash, so the lookup is cheap)."""
    return text.split("\n")


#: Characters of a source line shown around a diagnostic's column (a longer line is clipped).
EXCERPT_WIDTH = 100
#: Diagnostics :func:`render` shows in full; the rest are counted in one line (JSON lists all).
MAX_RENDERED = 200
#: Characters of a diagnostic's message shown in the text rendering (names echoed from input).
MAX_MESSAGE = 400


def _excerpt(span: Span, sources: Mapping[str, str]) -> list[str]:
    """The span's source line and a caret line, clipped to :data:`EXCERPT_WIDTH` characters around
    the span (a 180 kB line with 20,000 diagnostics is not printed 20,000 times)."""
    text = sources.get(span.file)
    if text is None:
        return []
    lines = _lines(text)
    if not 1 <= span.line <= len(lines):
        return []
    line = lines[span.line - 1].rstrip("\r")
    start = max(span.column - 1, 0)
    end = span.end_column - 1 if span.end_line == span.line else len(line)
    end = max(min(end, len(line)), start + 1)
    lo = max(0, min(start - EXCERPT_WIDTH // 3, len(line) - EXCERPT_WIDTH))
    hi = min(len(line), lo + EXCERPT_WIDTH)
    shown = ("…" if lo else "") + line[lo:hi] + ("…" if hi < len(line) else "")
    # Keep tabs in the caret line so that the caret stands under the right character.
    pad = (" " if lo else "") + "".join("\t" if ch == "\t" else " " for ch in line[lo:start])
    carets = "^" * max(1, min(end, hi) - start)
    gutter = " " * len(str(span.line))
    return [f"  {span.line} | {shown}", f"  {gutter} | {pad}{carets}"]


def _message(text: str) -> str:
    if len(text) <= MAX_MESSAGE:
        return text
    keep = MAX_MESSAGE // 2
    return f"{text[:keep]}…[{len(text) - 2 * keep} characters]…{text[-keep:]}"


def render_one(diagnostic: Diagnostic, sources: Mapping[str, str]) -> str:
    """The header, the source line with a caret under the span, then the notes."""
    out = [_message(diagnostic.header())]
    if diagnostic.span is not None:
        out += _excerpt(diagnostic.span, sources)
    for note in diagnostic.notes:
        where = f"{note.span}: " if note.span is not None else ""
        out.append(_message(f"  {where}note: {note.message}"))
    return "\n".join(out)


def render(diagnostics: Iterable[Diagnostic], sources: Mapping[str, str]) -> str:
    """The diagnostics, sorted, then a summary line (``2 errors, 1 warning``).

    At most :data:`MAX_RENDERED` are shown, errors first; a line counts the others.
    """
    ds = sort_diagnostics(diagnostics)
    shown = ds
    if len(ds) > MAX_RENDERED:
        errors = [d for d in ds if d.is_error][:MAX_RENDERED]
        warnings = [d for d in ds if not d.is_error][: MAX_RENDERED - len(errors)]
        shown = sort_diagnostics(errors + warnings)
    parts = [render_one(d, sources) for d in shown]
    if len(shown) < len(ds):
        kept = {id(d) for d in shown}
        rest = [d for d in ds if id(d) not in kept]
        parts.append(f"… {len(rest)} more not shown ({summary(rest)}; --format json lists every one)")
    parts.append(summary(ds))
    return "\n".join(parts)


def summary(diagnostics: Iterable[Diagnostic]) -> str:
    ds = list(diagnostics)
    errors = sum(d.is_error for d in ds)
    warnings = len(ds) - errors
    return f"{_plural(errors, 'error')}, {_plural(warnings, 'warning')}"


def _plural(n: int, word: str) -> str:
    return f"{n} {word}" + ("" if n == 1 else "s")


def diagnostics_json(diagnostics: Iterable[Diagnostic]) -> list[dict[str, Any]]:
    """The diagnostics, sorted, as JSON-ready dicts."""
    return [d.to_json() for d in sort_diagnostics(diagnostics)]


def language_error(diagnostics: Iterable[Diagnostic], sources: Mapping[str, str]) -> LanguageError:
    """A :class:`LanguageError` whose str is the first error's header line.

    It carries ``.diagnostics`` (all of them, sorted) and ``.rendered`` (the full
    report with source lines and carets).
    """
    ds = sort_diagnostics(diagnostics)
    first = next((d for d in ds if d.is_error), ds[0] if ds else None)
    message = _message(first.header()) if first is not None else "invalid OAC text"
    return LanguageError(message, diagnostics=ds, rendered=render(ds, sources))
