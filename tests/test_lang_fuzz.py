"""Fuzzing the compiler with mutations of the standard library: deleted, duplicated and swapped
tokens, swapped braces, inserted characters (NUL, ÿ, CR, …) and truncation, generated here from a
fixed seed. Every case must end in diagnostics (a ``LanguageError``), never another exception;
a case that compiles must print and parse back to the same model. Inputs the grammar cannot nest
fail at once at the first bracket too many; undecodable bytes are a located one-line error.
Long class chains and thousands of errors cost linear time and memory
(``benchmarks/pathological.py`` measures 100,000 of each)."""

from __future__ import annotations

import random
import re
from collections import Counter
from pathlib import Path

import pytest

from oacdsl.compiler import compile_paths, parse_text, print_module
from oacdsl.compiler.checks import check_modules
from oacdsl.compiler.diagnostics import CODES, language_error
from oacdsl.compiler.parser import parse_source
from oacdsl.errors import LanguageError, OacError

ROOT = Path(__file__).resolve().parents[1]
STANDARD = sorted((ROOT / "library").glob("*.oac"))
#: How many mutated files the test compiles (a few thousand, in seconds).
CASES = 3000
SEED = 13

TOKEN = re.compile(
    r'<->|[{}(),:=]|"(?:\\.|[^"\\\n])*"|#[^\n]*|[A-Za-z_][A-Za-z0-9_]*|[+-]?[\d.]+(?:[eE][+-]?\d+)?|\s+|.'
)
BRACKETS = "{}()"
INSERTS = [
    "\x00", "\xff", "\r", "\r\n", "\n", "\t", "\x0b", "\x0c", "\u2028", "\ufeff", "\x7f", '"', "#", "{", "}",
    "(", ")", ",", ":", "=", "<->", "<", "-", ">", "not", "nothing", "class", "oac", "scene", "1e400",
    "-0.0", "é", "\U0001f600", "\\",
]


def mutate(text: str, rng: random.Random) -> tuple[str, str]:
    """``text`` with one to three random mutations; also their names, for failure messages."""
    tokens = TOKEN.findall(text)
    done = []
    for _ in range(rng.randint(1, 3)):
        kind = rng.choice(["delete", "duplicate", "swap", "bracket", "insert", "truncate"])
        done.append(kind)
        if not tokens:
            break
        i = rng.randrange(len(tokens))
        if kind == "delete":
            del tokens[i]
        elif kind == "duplicate":
            tokens.insert(i, tokens[i])
        elif kind == "swap" and i + 1 < len(tokens):
            tokens[i], tokens[i + 1] = tokens[i + 1], tokens[i]
        elif kind == "bracket":
            places = [j for j, t in enumerate(tokens) if t in BRACKETS]
            if places:
                j = rng.choice(places)
                tokens[j] = rng.choice(BRACKETS.replace(tokens[j], ""))
        elif kind == "insert":
            tokens.insert(i, rng.choice(INSERTS))
        elif kind == "truncate":
            cut = "".join(tokens)
            tokens = [cut[: rng.randrange(len(cut) + 1)]]
    return "".join(tokens), "+".join(done)


HEADER = re.compile(r"^.+:\d+:\d+: error\[E\d{3}\]: \S")


def check_case(path: str, text: str, others: list, sources: dict[str, str]) -> str:  # noqa: ANN001
    """Compile one mutated file with the other standard files; the outcome's first code or "ok"."""
    try:
        module, warnings = parse_source(text, path)
    except LanguageError as error:
        diagnostics = list(error.diagnostics)
        assert len(diagnostics) == 1 and diagnostics[0].code in ("E001", "E002"), error.rendered
    else:
        diagnostics = warnings + check_modules([*others, module])
    lines = text.replace("\r\n", "\n").replace("\r", "\n").count("\n") + 1
    for d in diagnostics:
        assert d.code in CODES and d.span is not None, d
        if d.span.file == path:
            assert 1 <= d.span.line <= lines and d.span.column >= 1, (d, lines)
    errors = [d for d in diagnostics if d.is_error]
    if errors:
        error = language_error(diagnostics, {**sources, path: text})
        assert error.exit_code == 1 and "\n" not in str(error) and HEADER.match(str(error)), str(error)
        return errors[0].code
    assert parse_text(print_module(module), path) == module  # fmt keeps the meaning
    return "ok"


def test_mutated_library_files_give_diagnostics_never_another_exception() -> None:
    rng = random.Random(SEED)
    modules = {str(p): parse_text(p.read_text(encoding="utf-8"), str(p)) for p in STANDARD}
    texts = {str(p): p.read_text(encoding="utf-8") for p in STANDARD}
    outcomes: Counter[str] = Counter()
    for n in range(CASES):
        path = rng.choice(sorted(texts))
        text, how = mutate(texts[path], rng)
        others = [m for p, m in modules.items() if p != path]
        try:
            outcomes[check_case(path, text, others, texts)] += 1
        except AssertionError:
            raise
        except Exception as error:  # noqa: BLE001
            pytest.fail(f"case {n} ({how} on {path}): {type(error).__name__}: {error}\n{text!r}")
    # the mutations reach the lexer, the parser and the semantic checks alike
    assert outcomes["E001"] > CASES // 10 and outcomes["E002"] > CASES // 50, outcomes
    assert sum(v for k, v in outcomes.items() if k not in ("E001", "E002", "ok")) > CASES // 50, outcomes


@pytest.mark.parametrize(
    ("text", "where"),
    [
        ("{" * 200_000, "1:1"),
        ("oac g(" + "(" * 200_000, "1:7"),
        ("scene s {" + "{" * 100_000 + "}" * 100_000 + "}", "1:10"),
        ("oac g(h: Hand) {\n  pre " + "(" * 100_000 + "h <-> nothing" + ")" * 100_000 + "\n}", "2:7"),
        ("oac g(h: Hand) {\n  steps { " + "grasp(" * 50_000 + ")" * 50_000 + " }\n}", "2:22"),
        ("class A\n" + "# " + "{" * 100_000 + "\n" + "class B : A\n" * 1000, None),
    ],
)
def test_deeply_nested_text_fails_at_once_with_a_located_error(text: str, where: str | None) -> None:
    try:
        parse_text(text, "deep.oac")
    except LanguageError as error:
        assert where is not None and str(error).startswith(f"deep.oac:{where}: error[E001]"), str(error)
    else:
        assert where is None  # nesting in a comment is just text


@pytest.mark.parametrize(
    "data", [b"class A\n\xff\n", b"\x00\x00\xfe\xff", b"class A\r\xc3(\n", b"\xef\xbb\xbf\xff"]
)
def test_undecodable_bytes_are_a_located_one_line_error(tmp_path: Path, data: bytes) -> None:
    path = tmp_path / "bad.oac"
    path.write_bytes(data)
    with pytest.raises(OacError) as error:
        result = compile_paths([path])
        if not result.ok:
            raise result.error()
    assert str(error.value).startswith(str(path)) and "\n" not in str(error.value)
    assert error.value.exit_code in (1, 2)


def test_ancestors_of_a_long_chain_are_computed_when_asked_not_for_every_class() -> None:
    from oacdsl.library import Library
    from oacdsl.model import Module, ObjectClass

    n = 50_000  # a set per class would hold n²/2 = 1.25e9 names
    chain = (ObjectClass(name=f"C{i}", parents=(f"C{i - 1}",)) for i in range(1, n))
    decls = (ObjectClass(name="C0"), *chain)
    lib = Library([Module(path="chain.oac", decls=decls)])
    assert lib.ancestors(f"C{n - 1}") == frozenset(f"C{i}" for i in range(n))
    assert lib.is_subclass(f"C{n - 1}", "C0") and not lib.is_subclass("C0", "C1")
    assert len(lib._ancestors) == 2  # only what was asked


def test_many_errors_in_one_file_split_its_text_once() -> None:
    from oacdsl.compiler import compile_sources, diagnostics

    result = compile_sources({"dup.oac": "class A\n" * 3000})
    assert len(result.errors) == 2999
    before = diagnostics._lines.cache_info().misses
    rendered = result.error().rendered
    assert diagnostics._lines.cache_info().misses - before <= 1
    assert rendered.count("error[E006]") == diagnostics.MAX_RENDERED
    assert rendered.endswith("2999 errors, 0 warnings")
    assert f"… {2999 - diagnostics.MAX_RENDERED} more not shown (" in rendered


COMPOSED_WITH_PARAMS = """oac dough(h: Hand = left_hand, c: Cup = red_cup, l: Liquid = liquid_one,
          b: Bowl = orange_bowl, r: Hand = right_hand, m: Mixer = mixer) {
    pre     h <-> nothing, r <-> nothing, c <-> l
    effect  l <-> b, m <-> b, r <-> m, not c <-> l
    steps {
        grasp(h, c) { lift 8cm }
        # demonstrated tilt 110deg over 0.65 s (10-90 %)
        pour(h, c, l, b) { duration 0.81s  tilt 110deg }
        place(h, c)
        grasp(r, m)
        mix(r, m, b) { period 0.9s  radius 3cm  turns 3 }
    }
}
"""


def test_mutated_step_parameters_give_diagnostics_never_another_exception() -> None:
    # steps with skill parameters (what the composer writes): the new syntax and its checks
    rng = random.Random(SEED + 1)
    path = str(ROOT / "library" / "learned_dough.oac")
    modules = [parse_text(p.read_text(encoding="utf-8"), str(p)) for p in STANDARD]
    texts = {str(p): p.read_text(encoding="utf-8") for p in STANDARD}
    assert check_case(path, COMPOSED_WITH_PARAMS, modules, texts) == "ok"
    outcomes: Counter[str] = Counter()
    for n in range(400):
        text, how = mutate(COMPOSED_WITH_PARAMS, rng)
        try:
            outcomes[check_case(path, text, modules, texts)] += 1
        except AssertionError:
            raise
        except Exception as error:  # noqa: BLE001
            pytest.fail(f"case {n} ({how}): {type(error).__name__}: {error}\n{text!r}")
    assert outcomes["E001"] > 40, outcomes
    # the step parameters' own checks are reached (unknown name, unit, range, twice)
    assert sum(outcomes[c] for c in ("E042", "E043", "E044", "E006")) > 0, outcomes
