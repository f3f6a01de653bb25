"""The parser's fast paths agree with the slow, obvious ones."""

import re
from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from lark import Lark, Token, UnexpectedInput

from oacdsl.compiler.fastmodel import make
from oacdsl.compiler.grammar import grammar_text
from oacdsl.compiler.lexer import PATTERNS, OacLexer
from oacdsl.model import Atom, Instance, Oac, Param, Span

ROOT = Path(__file__).resolve().parents[1]
TEXTS = [p.read_text(encoding="utf-8") for p in sorted((ROOT / "library").glob("*.oac"))]
TEXTS += [
    p.read_text(encoding="utf-8") for p in sorted((ROOT / "tests" / "golden" / "printer").glob("*.oac"))
]


def _lark(lexer):
    return Lark(grammar_text(), parser="lalr", lexer=lexer, maybe_placeholders=True)


CONTEXTUAL = _lark("contextual")
FAST = _lark(OacLexer)


def _outcome(parser, text):
    try:
        tree = parser.parse(text)
    except UnexpectedInput as error:
        return (type(error).__name__, error.line, error.column)
    return [
        (t.type, str(t), t.line, t.column, t.end_line, t.end_column)
        for t in tree.scan_values(lambda v: isinstance(v, Token))
    ]


def test_lexer_patterns_are_the_grammars():
    grammar = grammar_text()
    for name, pattern in PATTERNS.items():
        assert f"{name}: /{pattern}/" in grammar


@pytest.mark.parametrize("index", range(len(TEXTS)))
def test_fast_lexer_gives_the_same_parse_as_larks_contextual_lexer(index):
    assert isinstance(_outcome(FAST, TEXTS[index]), list)
    assert _outcome(FAST, TEXTS[index]) == _outcome(CONTEXTUAL, TEXTS[index])


EDITS = [
    "{",
    "}",
    "(",
    ")",
    ",",
    ":",
    "<->",
    "not",
    "nothing",
    "class",
    "oac",
    "grasp",
    "pre",
    "effect",
    "steps",
    "execute",
    "markers",
    "environment",
    "type",
    "offset",
    "h",
    '"m"',
    "1.5",
    "-2",
    "@",
    "<",
    "#x\n",
    "\n",
]


@settings(max_examples=60, deadline=None)
@given(st.sampled_from(TEXTS), st.data())
def test_fast_lexer_agrees_on_edited_text(text, data):
    for _ in range(data.draw(st.integers(1, 3))):
        start = data.draw(st.integers(0, len(text)))
        end = data.draw(st.integers(start, min(len(text), start + 8)))
        text = text[:start] + data.draw(st.sampled_from(EDITS)) + text[end:]
    fast, contextual = _outcome(FAST, text), _outcome(CONTEXTUAL, text)
    if isinstance(fast, list):
        assert fast == contextual
    elif isinstance(contextual, list):
        # Lark's contextual lexer split a word into a keyword and a name ('approachnotside'
        # read as 'approach notside'); the fast lexer rejects the glued word.
        assert _glued(contextual, text)
    else:
        # both reject the text; Lark's lexer may split 'classh' into 'class' 'h' and err later
        assert fast[1:] <= contextual[1:]


def _glued(tokens, text):
    """True when a token starts right after a letter, digit or '_' (a word was split)."""
    lines = text.split("\n")
    return any(
        col > 1 and (lines[line - 1][col - 2].isalnum() or lines[line - 1][col - 2] == "_")
        for _, value, line, col, _, _ in tokens
        if value[:1].isidentifier()
    )


def test_make_equals_validated_construction():
    span = make(Span, {"file": "f", "line": 1, "column": 2, "end_line": 1, "end_column": 5})
    assert span == Span(file="f", line=1, column=2, end_line=1, end_column=5) and str(span) == "f:1:2"
    atom = make(Atom, {"left": "h", "right": "o", "negated": False, "span": span})
    assert atom == Atom(left="o", right="h") and hash(atom) == hash(Atom(left="h", right="o"))
    assert atom.model_dump()["left"] == "h" and atom.note is None and atom.parts == ()
    copy = atom.model_copy(update={"note": "n"})
    assert copy == atom and copy.note == "n"
    oac = make(
        Oac, {"name": "f", "params": (Param(name="h", cls="Hand"),), "effect": (atom,), "skill": "place"}
    )
    assert oac == Oac(name="f", params=(Param(name="h", cls="Hand"),), effect=(atom,), skill="place")
    assert oac.pre == () and oac.steps is None and oac.kind == "oac"
    inst = make(Instance, {"name": "a", "classes": ("Cup",)})
    assert inst == Instance(name="a", classes=("Cup",)) and inst.markers == () and not inst.environment
    with pytest.raises(Exception, match="frozen"):
        inst.name = "b"  # type: ignore[misc]


def test_parts_locate_names():
    from oacdsl.compiler import parse_text

    oac = parse_text(
        "oac f(h: Hand = left_hand) {\n  effect h <-> nothing\n  execute place\n}", "p.oac"
    ).decls[0]
    assert str(oac.params[0].part("default")) == "p.oac:1:17"
    assert str(oac.part("effect")) == "p.oac:2:3" and oac.part("missing") == oac.span
    assert re.fullmatch(r"p\.oac:3:11", str(oac.part("skill")))


def test_compiling_restores_the_garbage_collector_state():
    import gc

    from oacdsl.compiler import compile_sources

    assert gc.isenabled()
    compile_sources({"a.oac": "class A"})
    assert gc.isenabled()
    gc.disable()
    try:
        compile_sources({"a.oac": "class A : B"})
        assert not gc.isenabled()
    finally:
        gc.enable()
