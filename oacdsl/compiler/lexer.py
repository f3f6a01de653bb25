"""A fast lexer for the OAC grammar that keeps Lark's contextual keywords.

Lark's contextual lexer tries one regular expression per acceptable terminal
for every token. This lexer matches one master expression and decides between
a keyword and ``NAME`` from the parser's state, as the contextual lexer does:
a word is a keyword where the parser accepts that keyword (or accepts no
name), else a name, so an OAC may still be called ``grasp``. It produces the
same tokens and the same kinds of errors (``UnexpectedCharacters`` with the
parser state, for :mod:`oacdsl.compiler.syntax`), about twice as fast; a test
compares it with Lark's contextual lexer on the library and on random edits
of it. One difference, on purpose: where no name is acceptable, Lark's lexer
reads ``classh`` as the keyword ``class`` followed by ``h``; this one reads
the word ``classh`` and reports it.

The terminals come from the grammar: keywords and punctuation by their text;
``NAME``, ``NUMBER``, ``QUANTITY`` (a number with its unit, ``56cm``), ``STRING``,
``COMMENT`` and ``WS`` must keep the
patterns written below (a test checks they agree with ``grammar/oac.lark``).

Lines end at LF (CR LF and CR are turned into LF before lexing). The other characters
some tools take for a line end — VT, FF, NEL (U+0085), U+2028 and U+2029 — are no
whitespace and end a comment, so each is an error at its own position (E002,
:data:`NOT_LINE_ENDS`) instead of hiding what follows in a comment.
"""

from __future__ import annotations

import re
from collections.abc import Callable, Iterator
from typing import Any

from lark import Token, UnexpectedCharacters
from lark.common import LexerConf
from lark.lexer import Lexer, LexerState, PatternStr

__all__ = ["NOT_LINE_ENDS", "PATTERNS", "OacLexer"]

#: Characters that end a line for some tools but not in a ``.oac`` file: an error (E002).
NOT_LINE_ENDS = {
    "\x0b": "VT (vertical tab)",
    "\x0c": "FF (form feed)",
    "\x85": "NEL (U+0085 NEXT LINE)",
    "\u2028": "U+2028 LINE SEPARATOR",
    "\u2029": "U+2029 PARAGRAPH SEPARATOR",
}

#: The regular terminals of the grammar, as written in grammar/oac.lark.
PATTERNS = {
    "NAME": r"[A-Za-z_][A-Za-z0-9_]*",
    "STRING": r'"(\\.|[^"\\\n])*"',
    "NUMBER": r"[+-]?(\d+(\.\d*)?|\.\d+)([eE][+-]?\d+)?",
    "QUANTITY": (
        r"[+-]?(\d+(\.\d*)?|\.\d+)([eE][+-]?\d+)?(?![eE][+-]?\d)[A-Za-z]+(\/[A-Za-z]+)?(?![A-Za-z0-9_])"
    ),
    "COMMENT": r"#[^\n\x0b\x0c\x85\u2028\u2029]*",
    "WS": r"[ \t\r\n]+",
}

_MASTER = re.compile(
    "|".join(
        [
            f"(?P<WS>{PATTERNS['WS']})",
            f"(?P<COMMENT>{PATTERNS['COMMENT']})",
            f"(?P<NAME>{PATTERNS['NAME']})",
            f"(?P<QUANTITY>{PATTERNS['QUANTITY']})",
            f"(?P<NUMBER>{PATTERNS['NUMBER']})",
            f"(?P<STRING>{PATTERNS['STRING']})",
            r"(?P<PUNCT><->|[{}(),:=\[\]])",
        ]
    )
)


class OacLexer(Lexer):
    """Lark lexer (``Lark(lexer=OacLexer)``) for grammar/oac.lark."""

    __future_interface__ = True

    def __init__(self, conf: LexerConf) -> None:
        literals = {t.pattern.value: t.name for t in conf.terminals if isinstance(t.pattern, PatternStr)}
        self.keywords = {text: name for text, name in literals.items() if text.isidentifier()}
        self.punctuation = {text: name for text, name in literals.items() if not text.isidentifier()}
        self.on_comment: Callable[[Token], Any] | None = conf.callbacks.get("COMMENT")

    def lex(self, lexer_state: LexerState, parser_state: Any) -> Iterator[Token]:
        text = lexer_state.text
        if not isinstance(text, str):  # lark >= 1.3 hands the lexer a TextSlice, a view of the input
            text = text.text[text.start : text.end]
        states = parser_state.parse_conf.states
        keywords, punctuation, on_comment = self.keywords, self.punctuation, self.on_comment
        match = _MASTER.match
        pos, line, line_start, size = 0, 1, 0, len(text)
        while pos < size:
            m = match(text, pos)
            if m is None:
                accepted = set(states[parser_state.position]) - {"$END"}
                raise UnexpectedCharacters(
                    text, pos, line, pos - line_start + 1, allowed=accepted, state=parser_state
                )
            kind: str = m.lastgroup or ""
            value = m.group()
            end = m.end()
            if kind == "WS":
                newlines = value.count("\n")
                if newlines:
                    line += newlines
                    line_start = pos + value.rindex("\n") + 1
                pos = end
                continue
            column = pos - line_start + 1
            if kind == "NAME":
                keyword = keywords.get(value)
                if keyword is not None:
                    accepted_here = states[parser_state.position]
                    if keyword in accepted_here or "NAME" not in accepted_here:
                        kind = keyword
            elif kind == "PUNCT":
                kind = punctuation[value]
            token = Token(kind, value, pos, line, column, line, column + len(value), end)
            pos = end
            if kind == "COMMENT":
                if on_comment is not None:
                    on_comment(token)
                continue
            yield token
