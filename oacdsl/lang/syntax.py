"""Syntax errors in words: what was found, and what was expected.

Lark reports the terminals it would have accepted (``NAME``, ``RBRACE``,
``$END``); authors want "a class name", "'}'", "end of input". The parser
state of the error is matched against a table of small bad snippets
(:data:`EXAMPLES`, Lark's ``match_examples``) to say what belongs there; when
no snippet matches, the accepted terminals are spelled out one by one.
"""

from __future__ import annotations

import functools

from lark import Token, UnexpectedCharacters, UnexpectedInput, UnexpectedToken
from lark.lexer import PatternStr

from oacdsl.lang.diagnostics import Diagnostic
from oacdsl.lang.parser import lark_parser
from oacdsl.model import Span

__all__ = ["EXAMPLES", "expected_words", "syntax_diagnostic"]

_DECL = "a declaration ('class', 'scene', 'grasp' or 'oac')"

#: (what is expected, snippets that fail at the same parser state).
EXAMPLES: list[tuple[str, list[str]]] = [
    ("':' and the parent classes, or " + _DECL, ["class A", "class A B"]),
    ("',' and more parent classes, or " + _DECL, ["class A : B", "class A : B C", "class A : B, C"]),
    (
        _DECL,
        [
            "}",
            "Cup",
            "scene s { }",
            "scene s { a : B }",
            "grasp G { type a approach b }",
            "grasp G { type a approach b offset (1, 2, 3) }",
            "oac f() { execute s }",
            "oac f(h: H) { execute s }",
            "oac f() { steps { } }",
            "oac f(h: H) { steps { } }",
            "scene s { } }",
            "grasp G { type a approach b } }",
            "grasp G { type a approach b offset (1, 2, 3) } }",
            "oac f() { execute s } }",
            "oac f(h: H) { execute s } }",
            "oac f() { steps { } } }",
            "scene s { a : B } }",
        ],
    ),
    (
        "a class name",
        [
            "class",
            "class A :",
            "class A : B,",
            "class A : B, C,",
            "scene s { a :",
            "scene s { a : B,",
            "scene s { a : B, C,",
            "scene s { a, b :",
        ],
    ),
    ("a scene name", ["scene", "scene {"]),
    ("'{' after the scene name", ["scene s", "scene s s"]),
    ("an instance name or '}'", ["scene s {"]),
    ("an instance name", ["scene s { a,", "scene s { a, }", "scene s { a, b,"]),
    (
        "':' and the instance's classes",
        ["scene s { a", "scene s { a b", "scene s { a, b", "scene s { a, b, c"],
    ),
    (
        "',' and more classes, 'markers (…)', 'environment', the next instance or '}'",
        [
            "scene s { a : B",
            "scene s { a : B, C",
            "scene s { a, b : B",
            "scene s { a : B :",
        ],
    ),
    (
        "'environment', the next instance or '}'",
        [
            'scene s { a : B markers ("x")',
            'scene s { a : B markers ("x",)',
            "scene s { a : B markers ()",
        ],
    ),
    (
        "the next instance or '}'",
        [
            "scene s { a : B environment",
            'scene s { a : B markers ("x") environment',
            "scene s { a : B environment :",
        ],
    ),
    (
        "a quoted marker name such as \"m1\" or ')'",
        [
            "scene s { a : B markers (",
            'scene s { a : B markers ("x",',
            'scene s { a : B markers ("x", "y",',
        ],
    ),
    ("'(' and the marker names", ["scene s { a : B markers", "scene s { a : B markers }"]),
    (
        "',' or ')' in the marker list",
        [
            'scene s { a : B markers ("x"',
            'scene s { a : B markers ("x", "y"',
            'scene s { a : B markers ("x", "y", "z"',
        ],
    ),
    ("the class to grasp", ["grasp", "grasp {"]),
    ("'{' after the class to grasp", ["grasp G", "grasp G type"]),
    ("'type' and a grasp type (power, precision, rim, handle)", ["grasp G {", "grasp G { approach"]),
    ("a grasp type (power, precision, rim, handle)", ["grasp G { type", "grasp G { type }"]),
    ("'approach' and a direction (side, top, front)", ["grasp G { type a", "grasp G { type a }"]),
    (
        "an approach direction (side, top, front)",
        ["grasp G { type a approach", "grasp G { type a approach }"],
    ),
    ("'offset (x, y, z)' or '}'", ["grasp G { type a approach b", "grasp G { type a approach b c"]),
    (
        "'(' and three numbers in metres",
        ["grasp G { type a approach b offset", "grasp G { type a approach b offset 1"],
    ),
    (
        "a number (metres)",
        [
            "grasp G { type a approach b offset (",
            "grasp G { type a approach b offset (1,",
            "grasp G { type a approach b offset (1, 2,",
        ],
    ),
    (
        "',' between the three numbers",
        [
            "grasp G { type a approach b offset (1",
            "grasp G { type a approach b offset (1, 2",
        ],
    ),
    ("')' after the three numbers", ["grasp G { type a approach b offset (1, 2, 3"]),
    ("'}' to close the grasp", ["grasp G { type a approach b offset (1, 2, 3)"]),
    ("the OAC's name", ["oac", "oac ("]),
    ("'(' and the OAC's parameters", ["oac f", "oac f {"]),
    ("a parameter 'name: Class' or ')'", ["oac f(", "oac f(h: H,", "oac f(h: H, o: O,", "oac f(h: H = x,"]),
    ("':' and the parameter's class", ["oac f(h", "oac f(h)", "oac f(h: H, o", "oac f(h: H, o: O, p"]),
    ("the parameter's class", ["oac f(h:", "oac f(h: )", "oac f(h: H, o:"]),
    ("',', '= instance' or ')'", ["oac f(h: H", "oac f(h: H h", "oac f(h: H, o: O", "oac f(h: H, o: O o"]),
    ("',' or ')' after the parameter", ["oac f(h: H = x", "oac f(h: H = x y", "oac f(h: H, o: O = x"]),
    ("the default instance", ["oac f(h: H =", "oac f(h: H = )"]),
    (
        "'{' and the OAC's body",
        [
            "oac f()",
            "oac f() pre",
            "oac f(h: H)",
            "oac f(h: H, o: O)",
            "oac f(h: H,)",
            "oac f(h: H = x)",
        ],
    ),
    ("'pre', 'effect', 'execute SKILL' or 'steps { … }'", ["oac f() {", "oac f() { }", "oac f(h: H) {"]),
    (
        "a relation such as 'h <-> o', 'h <-> nothing' or 'not h <-> o'",
        [
            "oac f() { pre",
            "oac f() { effect",
            "oac f() { pre }",
            "oac f() { effect }",
        ],
    ),
    (
        "a relation, 'effect', 'execute SKILL' or 'steps { … }'",
        [
            "oac f() { pre a <-> b,",
            "oac f() { pre a <-> b, c <-> d,",
            "oac f() { pre a <-> nothing,",
            "oac f() { pre not a <-> b,",
        ],
    ),
    (
        "a relation, 'execute SKILL' or 'steps { … }'",
        [
            "oac f() { effect a <-> b,",
            "oac f() { effect a <-> b, c <-> d,",
            "oac f() { pre a <-> b effect c <-> d,",
        ],
    ),
    ("an object or 'nothing' after 'not'", ["oac f() { pre not", "oac f() { pre not }"]),
    (
        "'<->' between the two objects",
        [
            "oac f() { pre a",
            "oac f() { pre a b",
            "oac f() { pre not a",
            "oac f() { pre not a b",
            "oac f() { pre nothing",
            "oac f() { pre not nothing",
            "oac f() { pre a <-> b, c",
        ],
    ),
    (
        "an object or 'nothing' after '<->'",
        [
            "oac f() { pre a <->",
            "oac f() { pre a <-> }",
            "oac f() { pre not a <->",
            "oac f() { pre nothing <->",
            "oac f() { pre not nothing <->",
        ],
    ),
    (
        "',', 'effect', 'execute SKILL' or 'steps { … }'",
        [
            "oac f() { pre a <-> b",
            "oac f() { pre a <-> b }",
            "oac f() { pre a <-> nothing",
            "oac f() { pre not a <-> b",
            "oac f() { pre not a <-> nothing",
            "oac f() { pre a <-> b, c <-> d",
            "oac f() { pre nothing <-> a",
            "oac f() { pre not nothing <-> a",
        ],
    ),
    (
        "',', 'execute SKILL' or 'steps { … }'",
        [
            "oac f() { effect a <-> b",
            "oac f() { effect a <-> b }",
            "oac f() { effect a <-> nothing",
            "oac f() { effect not a <-> b",
            "oac f() { effect not a <-> nothing",
            "oac f() { effect a <-> b, c <-> d",
            "oac f() { effect nothing <-> a",
            "oac f() { effect not nothing <-> a",
        ],
    ),
    ("the name of a skill", ["oac f() { execute", "oac f() { execute }"]),
    (
        "'}' to close the OAC",
        [
            "oac f() { execute s",
            "oac f() { execute s pre",
            "oac f() { steps { }",
            "oac f() { steps { g() }",
        ],
    ),
    ("'{' and the steps", ["oac f() { steps", "oac f() { steps }"]),
    ("a step such as 'grasp(h, o)' or '}'", ["oac f() { steps {", "oac f() { steps { g() )"]),
    (
        "the next step such as 'place(h, o)' or '}'",
        [
            "oac f() { steps { g(a)",
            "oac f() { steps { g(a) h(b)",
            "oac f() { steps { g(a) )",
        ],
    ),
    (
        "'(' and the step's arguments",
        ["oac f() { steps { g", "oac f() { steps { g }", "oac f() { steps { g() h"],
    ),
    ("an argument or ')'", ["oac f() { steps { g(", "oac f() { steps { g( }"]),
    ("an argument", ["oac f() { steps { g(a,", "oac f() { steps { g(a, )", "oac f() { steps { g(a, b,"]),
    (
        "',' or ')' after the argument",
        [
            "oac f() { steps { g(a",
            "oac f() { steps { g(a b",
            "oac f() { steps { g(a, b",
            "oac f() { steps { g(a, b c",
        ],
    ),
]

_NAMED = {
    "$END": "end of input",
    "NAME": "a name",
    "STRING": 'a quoted name such as "m1"',
    "NUMBER": "a number",
    "ENVIRONMENT": "'environment'",
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


@functools.lru_cache(maxsize=1)
def _tables() -> tuple[dict[tuple[int, frozenset[str]], str], dict[frozenset[str], str]]:
    """What is expected, in words, by LALR state and by set of acceptable terminals.

    Built once from :data:`EXAMPLES`: each snippet is parsed as it is (the
    error comes at the end of input) and followed by ``@`` (a character no
    token starts with), which stops the parser at the same place before any
    reduction. Like Lark's ``match_examples`` but keyed on the state and the
    acceptable terminals only (Lark's also compares the depth of the parser
    stack, so an example would only match errors with as many parameters or
    atoms before them). The table by acceptable terminals alone is the
    fallback and keeps only unambiguous sets.
    """
    by_state: dict[tuple[int, frozenset[str]], str] = {}
    by_accepts: dict[frozenset[str], str | None] = {}
    parser = lark_parser()
    for label, snippets in EXAMPLES:
        for snippet in snippets:
            for text in (snippet, snippet + " @"):
                try:
                    parser.parse(text)
                except UnexpectedInput as error:
                    state = _state(error)
                    accepts = frozenset(_accepted(error))
                    if state is not None:
                        by_state.setdefault((state, accepts), label)
                    if by_accepts.get(accepts, label) != label:
                        by_accepts[accepts] = None
                    else:
                        by_accepts[accepts] = label
    return by_state, {k: v for k, v in by_accepts.items() if v is not None}


def _state(error: UnexpectedInput) -> int | None:
    state = getattr(error, "state", None)
    position = getattr(state, "position", None)
    return position if isinstance(position, int) else None


def _accepted(error: UnexpectedInput) -> set[str]:
    if isinstance(error, UnexpectedToken):
        return set(error.accepts or error.expected)
    if isinstance(error, UnexpectedCharacters):
        return set(error.allowed or ())
    return set()


def _expected(error: UnexpectedInput) -> str:
    by_state, by_accepts = _tables()
    accepted = _accepted(error)
    state = _state(error)
    label = by_state.get((state, frozenset(accepted))) if state is not None else None
    if label is None:
        label = by_accepts.get(frozenset(accepted))
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
