"""Bad inputs found by fuzzing the command line (issue 21): each is one line and an exit status.

Hangs (a FIFO), unbounded reads (``/dev/zero``), stdout on a full disk, malformed option
values, repeated options with different values, damaged run stores, a scene whose tracked
instances the demonstration lacks.
"""

from __future__ import annotations

import json
import os
import shutil
import sqlite3
import stat
import subprocess
import sys
from pathlib import Path

import pytest

from oacdsl.cli import main
from oacdsl.errors import StoreError
from oacdsl.stats import Outcome, RunStore, ensure_writable
from tests.kitchen import dough_segmentation

ROOT = Path(__file__).resolve().parents[1]
OACC = [sys.executable, "-m", "oacdsl"]


@pytest.fixture
def lib_dir(tmp_path: Path) -> Path:
    skip = shutil.ignore_patterns("learned", "drafts")
    shutil.copytree(ROOT / "library", tmp_path / "library", ignore=skip)
    return tmp_path / "library"


@pytest.fixture
def dough_json(tmp_path: Path) -> Path:
    path = tmp_path / "dough.json"
    path.write_text(json.dumps(dough_segmentation().to_json()))
    return path


def one_line_error(capsys: pytest.CaptureFixture[str], argv: list[str], code: int, *words: str) -> str:
    assert main(argv) == code
    err = capsys.readouterr().err
    assert err.startswith("oacc: error:") and len(err.strip().splitlines()) == 1, err
    for word in words:
        assert word in err, err
    return err


# -- standard output on a full disk ---------------------------------------------------------------
needs_dev_full = pytest.mark.skipif(not os.path.exists("/dev/full"), reason="needs /dev/full (Linux)")


@needs_dev_full
@pytest.mark.parametrize(
    "argv",
    [
        ["skills"],
        ["skills", "--json"],
        ["compile", "LIB"],
        ["inspect", "data/dough.c3d"],
        ["segment", "SEG", "--json"],
        ["match", "SEG", "--library", "LIB"],
        ["match", "SEG", "--library", "LIB", "--json"],
        ["compose", "SEG", "--library", "LIB", "--name", "d", "--dry-run"],
        ["stats", "--db", "DB", "--json"],
        ["--help"],
    ],
)
def test_stdout_on_a_full_disk_is_one_line_exit_2(argv, lib_dir, dough_json, tmp_path, monkeypatch, capsys):
    names = {"LIB": str(lib_dir), "SEG": str(dough_json), "DB": str(tmp_path / "none.sqlite3")}
    argv = [names.get(a, str(ROOT / a) if a.startswith("data/") else a) for a in argv]
    if argv[0] == "segment":  # segment reads a recording, not a segmentation
        argv[1] = str(ROOT / "data" / "dough.c3d")
    full = open("/dev/full", "w")  # noqa: SIM115 (closed below; main points it at /dev/null)
    monkeypatch.setattr(sys, "stdout", full)
    try:
        try:
            code = main(argv)
        except SystemExit as stop:  # --help
            code = int(stop.code or 0)
    finally:
        monkeypatch.undo()
        full.close()
    err = capsys.readouterr().err
    assert code == 2, err
    full_disk = "oacc: error: standard output: cannot write: No space left on device"
    assert err.strip().splitlines()[-1] == full_disk
    assert "Traceback" not in err


@needs_dev_full
def test_stdout_on_a_full_disk_from_the_shell(tmp_path):
    with open("/dev/full", "w") as full:
        proc = subprocess.run([*OACC, "skills"], stdout=full, stderr=subprocess.PIPE, text=True, cwd=ROOT,
                              timeout=120)
    assert proc.returncode == 2
    assert proc.stderr == "oacc: error: standard output: cannot write: No space left on device\n"


# -- documents that are not regular files ---------------------------------------------------------
@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="needs FIFOs")
@pytest.mark.parametrize("command", [["match"], ["compose", "--name", "d"], ["report"]])
def test_a_fifo_named_as_a_json_document_is_refused_not_waited_for(command, tmp_path):
    fifo = tmp_path / "seg.json"
    os.mkfifo(fifo)
    argv = [command[0], str(fifo), *command[1:]]
    proc = subprocess.run([*OACC, *argv], capture_output=True, text=True, cwd=ROOT, timeout=60)
    assert proc.returncode == 2
    assert proc.stderr.strip() == f"oacc: error: {fifo}: is a FIFO (named pipe), not a " + (
        "result document" if command[0] == "report" else "segmentation (oacc segment --json)"
    )


@pytest.mark.skipif(not os.path.exists("/dev/zero"), reason="needs /dev/zero")
@pytest.mark.parametrize("command", ["match", "report"])
def test_dev_zero_as_a_json_document_is_refused_unread(command, tmp_path, capsys):
    link = tmp_path / "zero.json"
    link.symlink_to("/dev/zero")
    one_line_error(capsys, [command, str(link)], 2, "is a character device")


def test_a_folder_as_a_result_is_refused(tmp_path, capsys):
    (tmp_path / "r.json").mkdir()
    one_line_error(capsys, ["report", str(tmp_path / "r.json")], 2, "is a folder")


# -- option values ---------------------------------------------------------------------------------
@pytest.mark.parametrize("value", ["liquid_one=red_cup:²", "liquid_one=red_cup:٣", "liquid_one=red_cup:0x3"])
def test_ball_counts_are_ascii_whole_numbers(value, capsys):
    one_line_error(capsys, ["run", "dough", "--fill", value], 2, "the number of balls is a whole number")


@pytest.mark.parametrize(
    "argv, what",
    [
        (["run", "x", "--bind", "h=left_hand", "--bind", "h=right_hand"], "--bind h: given twice"),
        (["run", "x", "--place", "red_cup=60cm,0", "--place", "red_cup=50cm,0"], "--place red_cup: given"),
        (["reproduce", "--fill", "liquid_one=red_cup", "--fill", "liquid_one=green_cup"], "--fill liquid_"),
    ],
)
def test_a_key_given_twice_with_different_values_is_refused(argv, what, capsys):
    one_line_error(capsys, argv, 2, what)


def test_a_single_option_given_twice_with_different_values_is_refused(capsys, tmp_path):
    with pytest.raises(SystemExit) as stop:
        main(["stats", "--db", str(tmp_path / "a"), "--db", str(tmp_path / "b")])
    assert stop.value.code == 2
    assert "argument --db: given twice with different values" in capsys.readouterr().err
    same = str(tmp_path / "a")
    assert main(["stats", "--db", same, "--db", same, "--json"]) == 0  # the same value twice: fine


# -- the run store ----------------------------------------------------------------------------------
@pytest.fixture
def store(tmp_path: Path) -> Path:
    path = tmp_path / "runs.sqlite3"
    with RunStore(path) as s:
        for _ in range(40):
            s.record(Outcome("dough", {"h": "left_hand" * 20}, True, 1.0), [Outcome("grasp", {}, True, 1.0)])
    conn = sqlite3.connect(path)
    conn.execute("PRAGMA wal_checkpoint(TRUNCATE)")
    conn.close()
    return path


def _malformed(path: Path) -> None:
    data = bytearray(path.read_bytes())
    page = 4096
    assert len(data) > 3 * page
    data[2 * page] = 0x77  # not a b-tree page type
    data[2 * page + 3 : 2 * page + 5] = b"\xff\xff"
    path.write_bytes(bytes(data))


def _no_table(path: Path) -> None:
    conn = sqlite3.connect(path)
    conn.execute("DROP VIEW outcome_rows")
    conn.execute("DROP TABLE outcomes")
    conn.commit()
    conn.close()


def _bad_binding(path: Path) -> None:
    conn = sqlite3.connect(path)
    conn.execute("UPDATE outcomes SET binding = '{not json' WHERE position = 1")
    conn.commit()
    conn.close()


@pytest.mark.parametrize(
    "damage, words",
    [
        (_malformed, "malformed"),
        (_no_table, "no outcome_rows, outcomes"),
        (_bad_binding, "binding is not a JSON"),
    ],
)
def test_a_damaged_store_is_one_line_in_stats_and_refused_before_a_run(damage, words, store, capsys):
    damage(store)
    one_line_error(capsys, ["stats", "--db", str(store)], 2, "damaged run database", words)
    with pytest.raises(StoreError, match="damaged run database"):
        ensure_writable(store)


def test_a_read_only_store_is_refused_before_a_run(store):
    store.chmod(0o444)
    with pytest.raises(StoreError, match=r"read-only \(mode 0444\)"):
        ensure_writable(store)


def test_an_immutable_store_is_refused_before_a_run(store):
    if shutil.which("chattr") is None or subprocess.run(["chattr", "+i", str(store)]).returncode != 0:
        pytest.skip("chattr +i is not available here (needs root and a file system that has it)")
    try:
        with pytest.raises(StoreError, match="cannot record runs here|not writable"):
            ensure_writable(store)
    finally:
        subprocess.run(["chattr", "-i", str(store)], check=True)


def test_reproduce_refuses_a_damaged_store_before_reading_the_recording(store, tmp_path, capsys):
    _no_table(store)
    missing = tmp_path / "nothing-here.c3d"  # never read: the store is refused first
    one_line_error(capsys, ["reproduce", str(missing), "--db", str(store), "--out", str(tmp_path / "o")],
                   2, "damaged run database")
    assert not (tmp_path / "o").exists()


@pytest.mark.parametrize("kind", ["folder", "fifo", "under a file"])
def test_stats_of_a_path_that_cannot_be_a_store_is_an_error(kind, tmp_path, capsys):
    path = tmp_path / "db"
    if kind == "folder":
        path.mkdir()
    elif kind == "fifo":
        os.mkfifo(path)
    else:
        path.write_text("x")
        path = path / "runs.sqlite3"
    err = one_line_error(capsys, ["stats", "--db", str(path)], 2)
    assert "No runs recorded" not in err


# -- the scene and the demonstration --------------------------------------------------------------
def test_a_tracked_scene_instance_the_demonstration_lacks_is_refused(lib_dir, dough_json, tmp_path, capsys):
    text = (lib_dir / "kitchen.oac").read_text()
    scene = text[text.index("scene kitchen {") : text.index("}", text.index("scene kitchen {")) + 1]
    extra = tmp_path / "extra.oac"
    extra.write_text(scene.replace("scene kitchen {", "scene kitchen2 {\n    spoon : Mixer"))
    for command in (["match"], ["compose", "--name", "d", "--dry-run"]):
        argv = [command[0], str(dough_json), "--library", str(lib_dir), "--scene", str(extra), *command[1:]]
        one_line_error(capsys, argv, 2, "tracked instance spoon not among")


# -- .oac line ends --------------------------------------------------------------------------------
@pytest.mark.parametrize("end", ["\x0b", "\x0c", "\x85", "\u2028", "\u2029"])
def test_a_line_end_other_than_lf_or_cr_is_a_located_error_not_a_comment(end, tmp_path, capsys):
    path = tmp_path / "odd.oac"
    path.write_text(f"# a comment{end}class Cup {{}}{end}class Bowl {{}}\n", encoding="utf-8")
    assert main(["compile", str(path)]) == 1
    out = capsys.readouterr()
    first = (out.out + out.err).strip().splitlines()[0]
    assert first.startswith(f"{path}:1:12: error[E002]:") and "is not a line end" in first
    assert main(["fmt", "--check", str(path)]) == 1  # not "canonical"
    assert "E002" in capsys.readouterr().err
    assert main(["fmt", str(path)]) == 1
    assert path.read_text(encoding="utf-8").startswith(f"# a comment{end}")  # left alone


# -- output paths -----------------------------------------------------------------------------------
@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="needs FIFOs")
def test_compose_to_a_fifo_is_refused_before_reading_it(dough_json, lib_dir, tmp_path):
    fifo = tmp_path / "out.oac"
    os.mkfifo(fifo)
    argv = ["compose", str(dough_json), "--library", str(lib_dir), "--name", "d", "-o", str(fifo)]
    proc = subprocess.run([*OACC, *argv], capture_output=True, text=True, cwd=ROOT, timeout=60)
    assert proc.returncode == 2
    why = "is a FIFO (named pipe); not replaced by a regular file (give a file path)"
    assert proc.stderr.strip() == f"oacc: error: {fifo}: {why}"
    assert fifo.is_fifo()


def a_device(tmp_path: Path) -> Path:
    """A character device of the test's own (a null device made in ``tmp_path`` as root): code
    that replaces its target must never be pointed at the system's ``/dev/null``."""
    if os.geteuid() != 0:
        return Path(os.devnull)  # not root: /dev cannot be written, /dev/null cannot be replaced
    node = tmp_path / "null-device"
    try:
        os.mknod(node, 0o666 | stat.S_IFCHR, os.makedev(1, 3))
    except OSError as error:
        pytest.skip(f"cannot make a device node here: {error}")
    return node


@pytest.mark.parametrize(
    "argv",
    [
        ["segment", "DOUGH", "--plot", "DEV"],
        ["synth", "dough", "-o", "TMP/x.c3d", "--truth", "DEV"],
        ["compose", "SEG", "--library", "LIB", "--name", "d", "-o", "DEV"],
        ["take", "DOUGH", "-o", "DEV.c3d", "--speed", "0.5"],
    ],
)
def test_a_device_as_an_output_file_is_refused_and_kept(argv, dough_json, lib_dir, tmp_path, capsys):
    device = a_device(tmp_path)
    link = tmp_path / "dev.c3d"
    link.symlink_to(device)
    names = {"DEV": str(device), "DEV.c3d": str(link), "SEG": str(dough_json), "LIB": str(lib_dir),
             "DOUGH": str(ROOT / "data" / "dough.c3d")}
    argv = [names.get(a, a.replace("TMP", str(tmp_path))) for a in argv]
    one_line_error(capsys, argv, 2, "is a character device; not replaced")
    assert device.is_char_device()


def test_a_file_name_longer_than_255_bytes_is_one_line(dough_json, lib_dir, tmp_path, capsys):
    long = "a" * 300
    one_line_error(capsys, ["compose", str(dough_json), "--library", str(lib_dir), "--name", long], 2,
                   "a name of 300 characters; at most 251")
    one_line_error(capsys, ["reproduce", "--name", long, "--no-record"], 2, "at most 251")
    out = tmp_path / f"{'é' * 130}.oac"  # 264 bytes
    argv = ["compose", str(dough_json), "--library", str(lib_dir), "--name", "d", "-o", str(out)]
    one_line_error(capsys, argv, 2, "the file name is 264 bytes, longer than the 255")


def test_a_name_of_251_characters_is_written(dough_json, lib_dir, capsys):
    name = "n" * 251
    assert main(["compose", str(dough_json), "--library", str(lib_dir), "--name", name]) == 0
    assert (lib_dir / "learned" / f"{name}.oac").is_file()


@pytest.mark.parametrize("file_name", ["Crêpe-1.c3d", "日本.c3d", "Ünïcode test.mmm.xml", f"{'x' * 300}.c3d"])
def test_the_default_name_of_any_recording_file_name_is_a_valid_oac_name(file_name):
    from oacdsl.cli import check_oac_name
    from oacdsl.pipeline.inputs import default_name

    name = default_name(file_name)
    assert check_oac_name(name) == name and name.isascii()


# -- oacc fmt ---------------------------------------------------------------------------------------
UGLY = "class   Cup{}\n"


def test_fmt_leaves_a_read_only_file_alone(tmp_path, capsys):
    path = tmp_path / "a.oac"
    path.write_text(UGLY)
    other = tmp_path / "b.oac"
    other.write_text(UGLY)
    path.chmod(0o444)
    assert main(["fmt", str(tmp_path)]) == 2
    err = capsys.readouterr().err
    assert f"oacc: error: {path}: read-only (mode 0444); not replaced" in err
    assert path.read_text() == UGLY and other.read_text() != UGLY  # the others are formatted


def test_fmt_keeps_hard_links_together(tmp_path, capsys):
    path = tmp_path / "a.oac"
    path.write_text(UGLY)
    os.link(path, tmp_path / "linked.oac.bak")
    assert main(["fmt", str(path)]) == 2
    assert "has 2 hard links; replacing it would split them" in capsys.readouterr().err
    assert path.read_text() == UGLY and path.stat().st_nlink == 2


def test_fmt_does_not_take_another_users_file(tmp_path, capsys, monkeypatch):
    path = tmp_path / "a.oac"
    path.write_text(UGLY)
    mine = os.geteuid()
    monkeypatch.setattr(os, "geteuid", lambda: mine + 4242)  # as if the file were someone else's
    assert main(["fmt", str(path)]) == 2
    assert "owned by another user" in capsys.readouterr().err
    assert path.read_text() == UGLY


@pytest.mark.skipif(os.geteuid() != 0, reason="needs root to give a file to another user")
def test_fmt_as_root_keeps_the_files_owner(tmp_path, capsys):
    path = tmp_path / "a.oac"
    path.write_text(UGLY)
    os.chown(path, 4242, 4343)
    assert main(["fmt", str(path)]) == 0
    assert path.read_text() != UGLY and (path.stat().st_uid, path.stat().st_gid) == (4242, 4343)


def test_fmt_does_not_overwrite_an_edit_made_while_it_ran(tmp_path, capsys, monkeypatch):
    import oacdsl.compiler.printer as printer

    path = tmp_path / "a.oac"
    path.write_text(UGLY)
    real = printer.print_module

    def slow_print(module):  # the user saves the file while fmt formats it
        path.write_text("class Bowl {}\n")
        return real(module)

    monkeypatch.setattr(printer, "print_module", slow_print)
    assert main(["fmt", str(path)]) == 2
    assert "changed while it was being rewritten" in capsys.readouterr().err
    assert path.read_text() == "class Bowl {}\n"


# -- pictures of any group name ---------------------------------------------------------------------
def test_group_names_with_tex_characters_are_drawn_as_text(tmp_path, capsys):
    import numpy as np

    from oacdsl.segmentation.readers import write_c3d
    from oacdsl.segmentation.recording import Recording

    n = 100
    t = np.arange(n) / 50.0
    pos = np.zeros((n, 2, 3))
    pos[:, :, 2] = 0.5
    pos[:, 1, 0] = np.where((t > 0.6) & (t < 1.4), 0.02, 1.0)  # b touches a for 0.8 s
    rec = Recording("m.c3d", 50.0, t, ["$x^$:m1", "b_{y}:m1"], pos, {"$x^$": (0,), "b_{y}": (1,)}, 0)
    path = write_c3d(rec, tmp_path / "m.c3d")
    argv = ["segment", str(path), "--plot", str(tmp_path / "p.png"), "--graphs", str(tmp_path / "g"),
            "--plot-motion", str(tmp_path / "m.png")]
    assert main(argv) == 0, capsys.readouterr().err
    assert "+ $x^$ <-> b_{y}" in capsys.readouterr().out
    assert (tmp_path / "p.png").is_file() and (tmp_path / "m.png").is_file()
    assert len(list((tmp_path / "g").glob("*.png"))) == 3


# -- reproduce: the report folder ------------------------------------------------------------------
def test_sigterm_during_a_run_removes_its_staging_folder(tmp_path, monkeypatch, capsys):
    import signal
    import time

    import oacdsl.pipeline.run as pipeline_run

    def terminated(*args, **kwargs):  # the run is under way: its staging folder exists
        assert [p for p in (tmp_path / "out").iterdir() if p.name.startswith(".reproduce-")]
        os.kill(os.getpid(), signal.SIGTERM)
        time.sleep(5)
        raise AssertionError("SIGTERM did not stop the run")

    monkeypatch.setattr(pipeline_run, "run_stages", terminated)
    code = main(["reproduce", "--out", str(tmp_path / "out"), "--no-record", "--no-render", "--quiet"])
    assert code == 143
    assert capsys.readouterr().err.strip().endswith("oacc: terminated")
    assert not [p for p in (tmp_path / "out").iterdir() if p.name.startswith(".reproduce-")]
    assert signal.getsignal(signal.SIGTERM) is signal.SIG_DFL  # restored after the command


def test_out_as_a_symbolic_link_is_refused(tmp_path, capsys):
    (tmp_path / "real").mkdir()
    (tmp_path / "out").symlink_to(tmp_path / "real")
    one_line_error(capsys, ["reproduce", "--out", str(tmp_path / "out"), "--no-record"], 2,
                   "--out is a symbolic link")
    assert not list((tmp_path / "real").iterdir())


# -- --place and --fill, checked before any work ---------------------------------------------------
@pytest.mark.parametrize(
    "flags, words",
    [
        (["--place", "nosuch=60cm,0"], "--place nosuch: not an object on the table of scene kitchen"),
        (["--place", "red_cup=2m,0"], "is off the table"),
        (["--fill", "liquid_one=mixer"], "--fill liquid_one=mixer: not a container"),
        (["--fill", "nope=red_cup"], "--fill nope: not a liquid"),
        (["--place", "red_cup=64cm,2cm"], "overlaps orange_bowl at (0.64, 0.00) m (the scene's 'at')"),
        (["--place", "red_cup=1m,40cm", "--place", "mixer=1m,41cm"],
         "--place mixer: at (1.00, 0.41) m it overlaps red_cup at (1.00, 0.40) m (--place)"),
    ],
)
def test_reproduce_refuses_bad_places_and_fills_before_writing_anything(flags, words, tmp_path, capsys):
    out = tmp_path / "out"
    one_line_error(capsys, ["reproduce", "--out", str(out), "--no-record", "--no-render", *flags], 2, words)
    assert not out.exists()


def test_run_refuses_overlapping_places(capsys):
    argv = ["run", "grasp", "--scene", "kitchen", "--no-record", "--place", "red_cup=60cm,0",
            "--place", "green_cup=62cm,1cm"]
    one_line_error(capsys, argv, 2, "overlaps")
