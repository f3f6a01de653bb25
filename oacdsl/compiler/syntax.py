"""Syntax errors in words: what was found, and what was expected.

Lark reports the terminals it would have accepted (``NAME``, ``RBRACE``,
``$END``); authors want "a class name", "'}'", "end of input". The parser
state of the error is matched against a table of small bad snippets
(:data:`EXAMPLES`, in the manner of Lark's ``match_examples``) to say what
belongs there; when no snippet matches, the accepted terminals are spelled
out one by one.
"""

from __future__ import annotations

import functools

from lark import Token, UnexpectedCharacters, UnexpectedInput, UnexpectedToken
from lark.lexer import PatternStr

from oacdsl.compiler.diagnostics import Diagnostic
from oacdsl.compiler.grammar import lark_parser
from oacdsl.compiler.lexer import NOT_LINE_ENDS
from oacdsl.compiler.syntax_examples import EXAMPLES
from oacdsl.model import Span

__all__ = ["EXAMPLES", "expected_words", "syntax_diagnostic"]

_NAMED = {
    "$END": "end of input",
    "NAME": "a name",
    "STRING": 'a quoted name such as "m1"',
    "NUMBER": "a number",
    "QUANTITY": "a number with a unit such as 56cm",
    "ENVIRONMENT": "'environment'",
    "UNTRACKED": "'untracked'",
    "NOT": "'not'",
    "NOTHING": "'nothing'",
}


@functools.lru_cache(maxsize=1)
def _terminal_words() -> dict[str, str]:
    words = dict(_NAMED)
    for term in lark_parser().terminals:
        if term.name not in words and isinstance(term.pattern, PatternStr):
            words[term.name] = f"'{term.pattern.value}'"
    return words


def expected_words(terminals: set[str] | frozenset[str]) -> str:
    """``{"RBRACE", "$END"}`` → ``"'}' or end of input"`` (sorted, end of input last)."""
    words = _terminal_words()
    shown = sorted({words.get(t, t.lower()) for t in terminals}, key=lambda w: (w == "end of input", w))
    if not shown:
        return "nothing more"
    if len(shown) == 1:
        return shown[0]
    return ", ".join(shown[:-1]) + " or " + shown[-1]


def _found(token: Token) -> str:
    if token.type == "$END":
        return "end of input"
    return f"'{token}'"


_Key = tuple[tuple[int, ...], frozenset[str]]


@functools.lru_cache(maxsize=1)
def _tables() -> tuple[dict[_Key, str], dict[frozenset[str], str]]:
    """What is expected, in words, by LALR states and by set of acceptable terminals.

    Built once from :data:`EXAMPLES`: each snippet is parsed as it is (the
    error comes at the end of input) and followed by ``@`` (a character no
    token starts with), which stops the parser at the same place before any
    reduction. Like Lark's ``match_examples`` but keyed on the acceptable
    terminals and the state of the error, and once more on that state with
    the one below it on the parser stack (Lark's compares the whole stack, so
    an example would only match errors with as many parameters or atoms
    before them). The state below tells apart places that share a state:
    after the ',' of a list of classes, of instance names and of step
    arguments, where one rule ``NAME ("," NAME)*`` reads all three. The table
    by acceptable terminals alone is the fallback and keeps only unambiguous sets.
    """
    by_state: dict[_Key, str] = {}
    by_accepts: dict[frozenset[str], str | None] = {}
    parser = lark_parser()
    for label, snippets in EXAMPLES:
        for snippet in snippets:
            for text in (snippet, snippet + " @"):
                try:
                    parser.parse(text)
                except UnexpectedInput as error:
                    accepts = frozenset(_accepted(error))
                    stack = _stack(error)
                    if stack:
                        by_state.setdefault((stack[-2:], accepts), label)
                        by_state.setdefault((stack[-1:], accepts), label)
                    if by_accepts.get(accepts, label) != label:
                        by_accepts[accepts] = None
                    else:
                        by_accepts[accepts] = label
    return by_state, {k: v for k, v in by_accepts.items() if v is not None}


def _stack(error: UnexpectedInput) -> tuple[int, ...]:
    """The LALR states on the parser's stack when it failed (top last; empty when unknown)."""
    stack = getattr(getattr(error, "state", None), "state_stack", None)
    return tuple(stack) if isinstance(stack, list) and all(isinstance(s, int) for s in stack) else ()


def _accepted(error: UnexpectedInput) -> set[str]:
    if isinstance(error, UnexpectedToken):
        return set(error.accepts or error.expected)
    if isinstance(error, UnexpectedCharacters):
        # the contextual lexer's allowed set is its parser state's keys: rules too (``_decl``,
        # ``__start_star_0`` in the first state); only terminals (upper case) are expected text
        return {name for name in error.allowed or () if name == name.upper()}
    return set()


def _expected(error: UnexpectedInput) -> str:
    by_state, by_accepts = _tables()
    accepted = frozenset(_accepted(error))
    stack = _stack(error)
    label = by_state.get((stack[-2:], accepted)) or by_state.get((stack[-1:], accepted))
    if label is None:
        label = by_accepts.get(accepted)
    return label if label is not None else expected_words(accepted)


def syntax_diagnostic(error: UnexpectedInput, text: str, path: str) -> Diagnostic:
    """One E001/E002 diagnostic for a Lark syntax error."""
    line, column = max(error.line, 1), max(error.column, 1)
    if isinstance(error, UnexpectedToken):
        token = error.token
        expected = _expected(error)
        if token.type == "$END":
            line, column = _end_position(text)
            span = Span(file=path, line=line, column=column, end_line=line, end_column=column + 1)
        else:
            span = Span(
                file=path,
                line=line,
                column=column,
                end_line=token.end_line or line,
                end_column=token.end_column or column + 1,
            )
        return Diagnostic("E001", f"unexpected {_found(token)}, expected {expected}", span)
    if isinstance(error, UnexpectedCharacters):
        char = error.char
        if char == '"':
            message = "unterminated string: a quoted name must end with '\"' on the same line"
        elif char in NOT_LINE_ENDS:
            message = (
                f"{NOT_LINE_ENDS[char]} is not a line end (nor space) in a .oac file:"
                " lines end with LF, CR LF or CR; replace it"
            )
        else:
            shown = repr(char) if not char.isprintable() or char in "'\\" else f"'{char}'"
            message = f"unexpected character {shown}, expected {_expected(error)}"
        span = Span(file=path, line=line, column=column, end_line=line, end_column=column + 1)
        return Diagnostic("E002", message, span)
    span = Span(file=path, line=line, column=column, end_line=line, end_column=column + 1)
    return Diagnostic("E001", "syntax error", span)


def _end_position(text: str) -> tuple[int, int]:
    """Line and column of the last non-blank character's successor (where input ended)."""
    stripped = text.rstrip()
    if not stripped:
        return 1, 1
    line = stripped.count("\n") + 1
    column = len(stripped) - (stripped.rfind("\n") + 1) + 1
    return line, column
