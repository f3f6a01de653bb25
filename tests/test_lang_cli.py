"""``oacc compile`` and ``oacc fmt`` through a real subprocess: exit codes, output, no tracebacks."""

import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def oacc(*args, cwd=None, stdin=None):
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    out = subprocess.run(
        [sys.executable, "-m", "oacdsl", *map(str, args)],
        capture_output=True,
        text=True,
        cwd=cwd or ROOT,
        env=env,
        input=stdin,
    )
    assert "Traceback" not in out.stderr, out.stderr
    return out


def copy_library(tmp_path):
    lib = tmp_path / "library"
    ignore = shutil.ignore_patterns("learned", "drafts", "kit", "examples")  # libraries of their own
    shutil.copytree(ROOT / "library", lib, ignore=ignore)
    return lib


#: The hand-written standard library (learned/ holds what oacc reproduce and oacc compose wrote).
STANDARD = [str(p.relative_to(ROOT)) for p in sorted((ROOT / "library").glob("*.oac"))]


def test_compile_clean_library():
    out = oacc("compile", *STANDARD)
    assert out.returncode == 0, out.stderr
    assert out.stdout.startswith("ok: 4 files") and "5 OACs" in out.stdout
    assert out.stderr == ""


def test_a_typo_in_kitchen_points_at_the_exact_spot(tmp_path):
    lib = copy_library(tmp_path)
    kitchen = lib / "kitchen.oac"
    kitchen.write_text(kitchen.read_text(encoding="utf-8").replace(": Liquid", ": Lquid"), encoding="utf-8")
    out = oacc("compile", lib)
    assert out.returncode == 1
    lines = out.stderr.splitlines()
    assert lines[0] == f"{kitchen}:7:30: error[E003]: unknown class 'Lquid' (did you mean 'Liquid'?)"
    assert lines[1].endswith("liquid_one, liquid_two : Lquid")
    assert lines[2].endswith(" " * 25 + "^^^^^")
    assert lines[3].endswith("note: class 'Liquid' is defined here")
    assert lines[-1] == "1 error, 0 warnings"


def test_compile_json(tmp_path):
    bad = tmp_path / "bad.oac"
    bad.write_text("class Mug : Cupp\nclass Mug\n", encoding="utf-8")
    out = oacc("compile", *STANDARD, bad, "--format", "json")
    assert out.returncode == 1
    doc = json.loads(out.stdout)
    assert doc["ok"] is False and doc["errors"] == 2
    assert [(d["code"], d["line"], d["column"]) for d in doc["diagnostics"]] == [
        ("E003", 1, 13),
        ("E006", 2, 7),
    ]
    clean = json.loads(oacc("compile", *STANDARD, "--format", "json").stdout)
    assert clean["ok"] is True and clean["diagnostics"] == [] and clean["declarations"]["OACs"] == 5


def test_warnings_pass_unless_strict(tmp_path):
    lib = copy_library(tmp_path)
    (lib / "spoon.oac").write_text(
        "class Spoon : Graspable { shape capsule(radius 1cm, height 18cm) }\n"
        "scene drawer { spoon : Spoon }\n",
        encoding="utf-8",
    )
    out = oacc("compile", lib)
    assert out.returncode == 0 and "warning[W004]" in out.stderr and "(0 errors, 1 warning)" in out.stdout
    assert oacc("compile", "--strict", lib).returncode == 1


def test_io_errors_exit_2_with_one_line(tmp_path):
    missing = oacc("compile", tmp_path / "nope.oac")
    assert (
        missing.returncode == 2
        and missing.stderr.strip() == f"oacc: error: {tmp_path / 'nope.oac'}: no such file or folder"
    )
    (tmp_path / "empty").mkdir()
    empty = oacc("compile", tmp_path / "empty")
    assert empty.returncode == 2 and "contains no .oac files" in empty.stderr
    binary = tmp_path / "binary.oac"
    binary.write_bytes(b"class A\n\xff\xfe\x00")
    undecodable = oacc("compile", binary)
    assert undecodable.returncode == 2 and "not UTF-8 text (byte 0xff on line 2)" in undecodable.stderr
    usage = oacc("compile")
    assert usage.returncode == 2 and "usage:" in usage.stderr


def test_fmt_check_lists_files_and_fmt_rewrites_them(tmp_path):
    lib = copy_library(tmp_path)
    actions = lib / "actions.oac"
    canonical = actions.read_text(encoding="utf-8")
    messy = canonical.replace("    pre     h <-> nothing", "  pre h<->nothing  ")
    actions.write_text(messy, encoding="utf-8")
    check = oacc("fmt", "--check", lib)
    assert check.returncode == 1 and check.stdout.strip() == str(actions)
    assert "1 of 4 files would be reformatted" in check.stderr
    assert actions.read_text(encoding="utf-8") == messy  # --check writes nothing
    diff = oacc("fmt", "--check", "--diff", actions)
    assert diff.returncode == 1 and "+    pre     h <-> nothing" in diff.stdout
    done = oacc("fmt", lib)
    assert done.returncode == 0 and done.stdout.strip() == f"formatted {actions}"
    assert actions.read_text(encoding="utf-8") == canonical
    assert oacc("fmt", "--check", lib).returncode == 0
    assert sorted(p.name for p in lib.iterdir()) == [
        "actions.oac",
        "classes.oac",
        "kitchen.oac",
        "wiping.oac",
    ]


def test_fmt_refuses_files_with_syntax_errors(tmp_path):
    bad = tmp_path / "bad.oac"
    bad.write_text("class A :\n", encoding="utf-8")
    out = oacc("fmt", bad)
    assert out.returncode == 1 and "error[E001]" in out.stderr
    assert bad.read_text(encoding="utf-8") == "class A :\n"


def test_fmt_stdin():
    out = oacc("fmt", "-", stdin="class Cup:Graspable,Container\n")
    assert out.returncode == 0 and out.stdout == "class Cup : Container, Graspable\n"


def test_fmt_stdin_that_is_not_utf8_is_e024_as_a_file_is():
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    out = subprocess.run([sys.executable, "-m", "oacdsl", "fmt", "-"], input=b"class A\n\xff\xfe oac",
                         capture_output=True, cwd=ROOT, env=env)
    assert out.returncode == 2 and out.stdout == b""
    expected = "oacc: error: <stdin>:2:1: error[E024]: not UTF-8 text (byte 0xff on line 2)\n"
    assert out.stderr.decode() == expected


def test_fmt_formats_a_symlinks_target_once_and_keeps_the_link(tmp_path):
    lib = copy_library(tmp_path)
    actions = lib / "actions.oac"
    canonical = actions.read_text(encoding="utf-8")
    elsewhere = tmp_path / "shared" / "actions.oac"
    elsewhere.parent.mkdir()
    messy = canonical.replace("    pre     h <-> nothing", "  pre h<->nothing  ")
    elsewhere.write_text(messy, encoding="utf-8")
    actions.unlink()
    actions.symlink_to(elsewhere)
    (lib / "again.oac").symlink_to(elsewhere)  # the same target twice in one folder
    done = oacc("fmt", lib)
    assert done.returncode == 0, done.stderr
    assert done.stdout.count("formatted") == 1
    assert actions.is_symlink() and (lib / "again.oac").is_symlink()
    assert elsewhere.read_text(encoding="utf-8") == canonical
    assert oacc("fmt", "--check", lib).returncode == 0


def test_cr_and_mixed_line_ends_keep_every_declaration(tmp_path):
    lib = copy_library(tmp_path)
    actions = lib / "actions.oac"
    lf = actions.read_text(encoding="utf-8")
    assert "#" in lf  # a comment that a CR-only file would stretch over the rest of it
    lines = lf.split("\n")
    mixed = "".join(line + ("\r\n", "\r", "\n")[i % 3] for i, line in enumerate(lines[:-1]))
    for variant in (lf.replace("\n", "\r"), mixed):
        actions.write_bytes(variant.encode("utf-8"))
        out = oacc("compile", lib, "--format", "json")
        assert out.returncode == 0, out.stderr
        assert json.loads(out.stdout)["declarations"]["OACs"] == 5
    # an error in a CR-only file is located on the line an editor shows
    actions.write_bytes(lf.replace("<->", "<=>", 1).replace("\n", "\r").encode("utf-8"))
    out = oacc("compile", lib)
    bad_line = next(i for i, line in enumerate(lines, 1) if "<->" in line)
    assert out.returncode == 1 and f"{actions}:{bad_line}:" in out.stderr.splitlines()[0]
    actions.write_bytes(lf.replace("\n", "\r").encode("utf-8"))
    done = oacc("fmt", actions)
    assert done.returncode == 0 and actions.read_text(encoding="utf-8") == lf
