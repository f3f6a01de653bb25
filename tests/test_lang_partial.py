"""A broken file (syntax error, not UTF-8) does not hide the other files' problems."""

import json
import subprocess
import sys

import pytest

from oacdsl.compiler import compile_sources, load_library
from oacdsl.compiler.parser import read_source
from oacdsl.errors import LanguageError, SourceEncodingError

GOOD = "class Hand\nclass Cup\n"
# E006 (a duplicate), E008 (an object with itself) and W001 (unused) need no other file
SEMANTIC = (
    "class Hand\n"
    "oac g(h: Hand, o: Hand) {\n  pre h <-> nothing effect h <-> h\n  execute place\n}\n"
    "oac uses_broken(h: Hand, c: Bowl) {\n  effect h <-> c\n  execute place\n}\n"
)
SYNTAX = "class Bowl\nclass ( \n"


def _codes(result):
    return [(d.code, str(d.span)) for d in result.diagnostics]


def test_semantic_errors_of_files_that_parsed_are_reported_beside_a_syntax_error():
    result = compile_sources({"good.oac": GOOD, "semantic.oac": SEMANTIC, "syntax.oac": SYNTAX})
    assert _codes(result) == [
        ("E006", "semantic.oac:1:7"),  # class Hand, also in good.oac
        ("W001", "semantic.oac:2:16"),  # o is never used
        ("E008", "semantic.oac:3:28"),
        ("E001", "syntax.oac:2:7"),
    ]
    # 'Bowl' is defined in the file that did not parse: no "unknown class" error for it
    assert "E003" not in {d.code for d in result.diagnostics}
    # once the broken file parses, the same library reports the same checks, and no more
    fixed = compile_sources({"good.oac": GOOD, "semantic.oac": SEMANTIC, "syntax.oac": "class Bowl\n"})
    assert _codes(fixed) == _codes(result)[:3]


def test_unknown_names_are_reported_when_every_file_parsed():
    result = compile_sources({"good.oac": GOOD, "semantic.oac": SEMANTIC})
    assert ("E003", "semantic.oac:6:29") in _codes(result)


def test_a_file_that_is_not_utf8_is_a_diagnostic_at_its_bad_byte(tmp_path):
    latin1 = tmp_path / "latin1.oac"
    latin1.write_bytes("class Hand\n\n# Tasse für Kaffee\nclass Cup\n".encode("latin-1"))
    with pytest.raises(SourceEncodingError) as info:
        read_source(latin1)
    assert str(info.value) == f"{latin1}:3:10: error[E024]: not UTF-8 text (byte 0xfc on line 3)"
    assert info.value.exit_code == 2 and isinstance(info.value, LanguageError)
    assert info.value.rendered.splitlines()[1:3] == ["  3 | # Tasse f\ufffdr Kaffee", "    |          ^"]
    with pytest.raises(SourceEncodingError):
        load_library([latin1])
    bom = tmp_path / "bom.oac"
    bom.write_bytes(b"\xef\xbb\xbfclass \xff")
    with pytest.raises(SourceEncodingError, match=r"bom.oac:1:7: error\[E024\]"):
        read_source(bom)  # the byte-order mark is no column


def oacc(*args):
    return subprocess.run([sys.executable, "-m", "oacdsl", *map(str, args)], capture_output=True, text=True)


def test_oacc_compile_reports_every_file_and_exits_2_for_a_file_that_is_not_text(tmp_path):
    (tmp_path / "good.oac").write_text(GOOD, encoding="utf-8")
    (tmp_path / "semantic.oac").write_text(SEMANTIC, encoding="utf-8")
    (tmp_path / "syntax.oac").write_text(SYNTAX, encoding="utf-8")
    broken = oacc("compile", tmp_path)
    assert broken.returncode == 1 and "Traceback" not in broken.stderr
    headers = [line for line in broken.stderr.splitlines() if "error[" in line or "warning[" in line]
    assert [h.split(": ", 1)[1].split(":")[0] for h in headers] == [
        "error[E006]", "warning[W001]", "error[E008]", "error[E001]",
    ]
    assert broken.stderr.rstrip().endswith("3 errors, 1 warning")
    (tmp_path / "binary.oac").write_bytes(b"class A\n\x00\xfe")
    undecodable = oacc("compile", "--format", "json", tmp_path)
    assert undecodable.returncode == 2
    doc = json.loads(undecodable.stdout)
    assert [(d["code"], d["line"], d["column"]) for d in doc["diagnostics"]][:1] == [("E024", 2, 2)]
    assert {d["code"] for d in doc["diagnostics"]} == {"E024", "E006", "E008", "W001", "E001"}
