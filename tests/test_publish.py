"""Publishing a reproduce report: one whole run at any moment, even under ``kill -9``; stale
staging and temporary files of killed runs are cleaned up, those of live runs kept."""

from __future__ import annotations

import os
import subprocess
import sys
import time
from pathlib import Path

import pytest

from oacdsl.atomic import remove_stale_temporaries
from oacdsl.pipeline.publish import KEEP_RUNS, STAGING_PREFIX, clean_stale, make_staging, publish


def staged_run(out: Path, tag: str, name: str = "dough") -> Path:
    """A finished staging folder whose every entry says ``tag``."""
    staging = make_staging(out)
    (staging / "figures").mkdir()
    (staging / "figures" / "aas.png").write_text(tag)
    (staging / "result.json").write_text(tag)
    (staging / "report.html").write_text(tag)
    (staging / f"{name}.oac").write_text(tag)
    return staging


def shown(out: Path, name: str = "dough") -> set[str]:
    """What a reader of ``out`` sees in every entry (one tag when the folder is consistent)."""
    paths = [out / "report.html", out / "result.json", out / "figures" / "aas.png", out / f"{name}.oac"]
    return {p.read_text() if p.exists() else f"missing {p.name}" for p in paths}


def a_dead_pid() -> int:
    proc = subprocess.Popen([sys.executable, "-c", ""])
    proc.wait()
    return proc.pid


def test_publish_links_the_entries_to_the_current_run_and_keeps_a_few(tmp_path: Path) -> None:
    out = tmp_path / "out"
    (out).mkdir()
    (out / "notes.txt").write_text("mine")
    publish(staged_run(out, "A"), out)
    assert shown(out) == {"A"}
    assert os.readlink(out / "report.html") == "current/report.html" and (out / "current").is_symlink()
    for tag in "BCDE":
        publish(staged_run(out, tag), out)
        assert shown(out) == {tag}
    assert len(list((out / "runs").iterdir())) == KEEP_RUNS
    publish(staged_run(out, "F", name="salad"), out)  # another name: the old NAME.oac link goes
    assert shown(out, "salad") == {"F"} and not os.path.lexists(out / "dough.oac")
    assert sorted(p.name for p in out.iterdir()) == [
        ".oacdsl-report", "current", "figures", "notes.txt", "report.html", "result.json", "runs", "salad.oac"
    ]
    assert (out / "notes.txt").read_text() == "mine"


def test_a_folder_of_the_older_layout_is_adopted_as_a_run(tmp_path: Path) -> None:
    out = tmp_path / "out"
    (out / "figures").mkdir(parents=True)
    for path in ("report.html", "result.json", "figures/aas.png", "dough.oac"):
        (out / path).write_text("old")
    publish(staged_run(out, "new"), out)
    assert shown(out) == {"new"} and (out / "figures").is_symlink()
    legacy = [p for p in (out / "runs").iterdir() if p.name.startswith("legacy-")]
    assert len(legacy) == 1 and (legacy[0] / "figures" / "aas.png").read_text() == "old"


def publish_killed(out: Path, k: int, name: str = "dough") -> int:
    """Publish run "B" over ``out`` in a child process that SIGKILLs itself just before its
    ``k``-th change of the file system; the child's exit status (0: it finished first)."""
    import shutil
    import signal

    from oacdsl.pipeline import publish as module

    pid = os.fork()
    if pid == 0:  # the child: never returns into pytest
        try:
            staging = staged_run(out, "B", name)
            calls = [0]

            def fatal(fn):  # noqa: ANN001, ANN202
                def wrapped(*args, **kwargs):  # noqa: ANN002, ANN003, ANN202
                    calls[0] += 1
                    if calls[0] == k:
                        os.kill(os.getpid(), signal.SIGKILL)
                    return fn(*args, **kwargs)

                return wrapped

            for name in ("rename", "replace", "symlink", "unlink", "mkdir", "rmdir"):
                setattr(os, name, fatal(getattr(os, name)))
            module._exchange = fatal(module._exchange)  # type: ignore[method-assign]
            shutil.copy2 = fatal(shutil.copy2)
            module.publish(staging, out)
        except BaseException:
            os._exit(3)
        os._exit(0)
    return os.waitstatus_to_exitcode(os.waitpid(pid, 0)[1])


@pytest.mark.parametrize("layout, killed_name", [("runs", "dough"), ("older", "dough"), ("runs", "salad")])
def test_killed_at_any_step_the_folder_shows_one_whole_run(
    tmp_path: Path, layout: str, killed_name: str
) -> None:
    k, finished = 0, False
    while not finished:
        k += 1
        out = tmp_path / f"out{k}"
        if layout == "runs":
            publish(staged_run(out, "A"), out)
        else:  # what an older oacdsl wrote: regular files and a figures folder
            (out / "figures").mkdir(parents=True)
            for path in ("report.html", "result.json", "figures/aas.png", "dough.oac"):
                (out / path).write_text("A")
        status = publish_killed(out, k, killed_name)
        finished = status == 0
        assert finished or status == -9, status
        assert shown(out) in ({"A"}, {"B"}) or killed_name != "dough", (k, shown(out))
        # the next run cleans what the killed one left and publishes a whole run
        clean_stale(out)
        publish(staged_run(out, "C"), out)
        assert shown(out) == {"C"}
        assert not [p for p in out.iterdir() if p.name.startswith(".") and p.name != ".oacdsl-report"]
        dangling = [p.name for p in out.iterdir() if p.is_symlink() and not p.exists()]
        assert not dangling, (k, dangling)  # e.g. salad.oac of a run killed while publishing
        assert len(list((out / "runs").iterdir())) <= KEEP_RUNS
        assert k < 60, "publish takes more steps than expected"
    assert k > 5  # the kill points did cover the steps of publishing


def test_stale_staging_goes_and_a_live_runs_stays(tmp_path: Path) -> None:
    out = tmp_path / "out"
    live = make_staging(out)  # owned by this (live) process
    dead = make_staging(out)
    (dead / ".owner").write_text(f"{a_dead_pid()}\n")
    orphan_old, orphan_new = out / f"{STAGING_PREFIX}old1", out / f"{STAGING_PREFIX}new1"
    orphan_old.mkdir()
    orphan_new.mkdir()
    week_ago = time.time() - 7 * 86400
    os.utime(orphan_old, (week_ago, week_ago))
    reused = make_staging(out)  # this process's id, but written two days ago: a reused id
    two_days_ago = time.time() - 2 * 86400
    os.utime(reused, (two_days_ago, two_days_ago))
    removed = clean_stale(out)
    assert sorted(removed) == sorted([dead, orphan_old, reused])
    assert live.is_dir() and orphan_new.is_dir() and not dead.exists()


def test_stale_temporaries_of_atomic_writes_go(tmp_path: Path) -> None:
    dead, alive = a_dead_pid(), os.getpid()
    names = {
        f".dough.oac.{dead}.abcd_123.tmp": False,
        f".dough.oac.{alive}.abcd_123.tmp": True,
        ".dough.oac.zyxw9876.tmp": True,  # older oacdsl, no pid: kept while fresh
        ".salad.oac.zyxw9876.tmp": False,  # … and removed when old
        "dough.oac": True,
        f".bread.oac.{alive}.abcd_123.tmp": False,  # a live id, but two days old: reused
    }
    for name in names:
        (tmp_path / name).write_text("x")
    week_ago = time.time() - 7 * 86400
    os.utime(tmp_path / ".salad.oac.zyxw9876.tmp", (week_ago, week_ago))
    os.utime(tmp_path / f".bread.oac.{alive}.abcd_123.tmp", (week_ago, week_ago))
    remove_stale_temporaries(tmp_path)
    assert {n: (tmp_path / n).exists() for n in names} == names


@pytest.mark.parametrize("round_", range(6))  # a race: several rounds to meet it
def test_concurrent_runs_on_one_folder_leave_one_whole_run_and_no_dangling_link(
    tmp_path: Path, round_: int
) -> None:
    out = tmp_path / "out"
    publish(staged_run(out, "A"), out)
    stagings = [staged_run(out, f"R{i}", f"name{i}") for i in range(4)]
    go = tmp_path / "go"
    pids = []
    for staging in stagings:
        pid = os.fork()
        if pid == 0:  # a child: publish as soon as all are ready
            try:
                while not go.exists():
                    time.sleep(0.001)
                publish(staging, out)
            except BaseException:
                os._exit(3)
            os._exit(0)
        pids.append(pid)
    go.touch()
    assert [os.waitstatus_to_exitcode(os.waitpid(pid, 0)[1]) for pid in pids] == [0, 0, 0, 0]
    winner = os.readlink(out / "current")
    tag = next(p.read_text() for p in (out / winner).glob("*.oac"))
    assert shown(out, f"name{tag[1:]}") == {tag}  # every entry of the current run, linked
    links = [p for p in out.iterdir() if p.is_symlink()]
    assert all(p.exists() for p in links), [p.name for p in links if not p.exists()]
    assert sorted(p.name for p in out.glob("*.oac")) == [f"name{tag[1:]}.oac"]


def test_a_published_run_can_be_read_by_others(tmp_path: Path) -> None:
    out = tmp_path / "out"
    old = os.umask(0o022)
    try:
        publish(staged_run(out, "A"), out)
    finally:
        os.umask(old)
    run = out / os.readlink(out / "current")
    assert run.stat().st_mode & 0o777 == 0o755


def test_a_report_folder_inside_a_library_is_not_part_of_it(tmp_path: Path) -> None:
    from oacdsl.compiler.loader import oac_files

    library = tmp_path / "lib"
    library.mkdir()
    (library / "a.oac").write_text("class A {}\n")
    out = library / "out"
    publish(staged_run(out, "class B {}\n"), out)
    assert (out / "dough.oac").read_text() == "class B {}\n"
    assert oac_files(library) == [library / "a.oac"]
    (out / ".oacdsl-report").unlink()  # a folder of an older oacdsl: recognised by its layout
    assert oac_files(library) == [library / "a.oac"]
