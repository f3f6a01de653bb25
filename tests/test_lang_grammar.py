"""What is derived from grammar/oac.lark, and the table of syntax-error examples."""

import re

import pytest

from oacdsl.compiler import compile_sources, format_atom, parse_text, print_module
from oacdsl.compiler.grammar import grammar_text, keywords, name_pattern
from oacdsl.compiler.syntax_examples import EXAMPLES
from oacdsl.errors import LanguageError
from oacdsl.model import Atom, Module, ObjectClass

CASES = [(label, snippet) for label, snippets in EXAMPLES for snippet in snippets]


def _syntax_message(text: str) -> str:
    with pytest.raises(LanguageError) as info:
        parse_text(text)
    (diagnostic,) = info.value.diagnostics
    assert diagnostic.code in {"E001", "E002"}
    return diagnostic.message


@pytest.mark.parametrize(("label", "snippet"), CASES, ids=[s for _, s in CASES])
def test_every_example_gets_its_own_message(label, snippet):
    """As Lark's ``match_examples``: each snippet, where it fails, says what its entry says."""
    try:
        parse_text(snippet)
    except LanguageError:
        text = snippet  # fails at its end
    else:
        text = snippet + " @"  # complete: fails at the '@' that follows
    assert _syntax_message(text).endswith(f", expected {label}")


def test_the_table_is_large_and_its_labels_distinct():
    assert len(CASES) >= 180
    labels = [label for label, _ in EXAMPLES]
    assert len(set(labels)) == len(labels)


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("class Cup\nscene s { a, : Cup }", "unexpected ':', expected an instance name"),
        ("oac f(h: H) { effect h <-> nothing steps { g(h, ) } }", "unexpected ')', expected an argument"),
        ("class A : B, }", "unexpected '}', expected a class name"),
        ("scene s { a, b, c, d, }", "unexpected '}', expected an instance name"),
        ("oac f() { effect a <-> b steps { g(a, b, c, ) } }", "unexpected ')', expected an argument"),
    ],
)
def test_lists_that_share_a_parser_state_get_their_own_message(text, message):
    """Classes, instance names and step arguments are each ``NAME ("," NAME)*`` in the grammar."""
    assert _syntax_message(text) == message


def test_keywords_are_the_words_of_the_grammar():
    words = set(re.findall(r'"([A-Za-z_][A-Za-z0-9_]*)"', grammar_text()))
    assert keywords() == words
    assert {"class", "scene", "oac", "pre", "effect", "nothing", "markers", "approach"} <= keywords()


@pytest.mark.parametrize("word", sorted(keywords()))
def test_no_word_of_the_grammar_may_name_an_instance_or_a_parameter(word):
    text = (
        f"class Hand\nscene s {{ {word} : Hand }}\n"
        f"oac f({word}: Hand, o: Hand) {{ effect o <-> {word} execute reach_and_grasp }}\n"
    )
    result = compile_sources({"k.oac": text})
    e018 = [d for d in result.diagnostics if d.code == "E018"]
    assert [d.span.line for d in e018] == [2, 3], [d.header() for d in result.diagnostics]


def test_the_printer_prints_exactly_the_names_of_the_grammar():
    assert name_pattern().fullmatch("_cup2") and not name_pattern().fullmatch("2cup")
    assert format_atom(Atom(left="b", right="a", negated=True)) == "not a <-> b"
    assert print_module(Module(path="m", decls=(ObjectClass(name="Cup_2"),))) == "class Cup_2\n"
    for bad in ("2cup", "red-cup", "cup cup", "", "tasse\u00e9"):
        with pytest.raises(LanguageError, match="not a name"):
            print_module(Module(path="m", decls=(ObjectClass(name=bad),)))
        with pytest.raises(LanguageError, match="not a name"):
            format_atom(Atom(left=bad, right="zz"))
