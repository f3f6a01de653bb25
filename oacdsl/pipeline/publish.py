"""Publishing a report folder in one atomic step, and cleaning what killed runs left behind.

``oacc reproduce --out OUT`` builds each run in a hidden staging folder
``OUT/.reproduce-XXXX/`` (its owner's process id in ``.owner``), then:

1. renames the finished folder to ``OUT/runs/<id>/`` (``<id>``: UTC time and a random tag);
2. replaces the symbolic link ``OUT/current`` by one to ``runs/<id>`` — a single
   ``rename``, the one step that publishes the run;
3. makes sure ``OUT/report.html``, ``OUT/result.json``, ``OUT/figures`` and
   ``OUT/NAME.oac`` are links to ``current/…`` (created once; they never change).

Whoever reads ``OUT`` — a browser, ``oacc report``, a script — sees every entry of one
whole run, the previous or the new one, whenever the process is killed (``kill -9``
included). The newest :data:`KEEP_RUNS` runs stay in ``OUT/runs/``; older ones are removed.

A folder written by an older oacdsl (regular ``report.html``, ``result.json``,
``figures/`` in ``OUT``) is first turned into a run of its own, ``runs/legacy-…``, by
copying; each entry is then replaced by its link, which shows the same content.

At the start of a run, :func:`clean_stale` removes staging folders and temporary links
whose owner process is gone (or, without an owner file, older than :data:`STALE_AFTER_S`;
with an owner whose process id another process reuses, older than a day).

``OUT/.oacdsl-report`` marks the folder as a report folder (a library search leaves it
out: :data:`oacdsl.compiler.loader.REPORT_MARK`) and is the lock that publishing holds
(``flock``), so concurrent runs on one ``OUT`` publish one after the other; a killed
holder's lock is released by the system. Under the lock, every link ``OUT/X → current/X``
that no longer leads anywhere (an entry of an older run, or of a run killed between
linking and switching) is removed. A run folder gets the permissions of a new folder
(``0777`` less the umask), so whoever may read ``OUT`` may read its report.
"""

from __future__ import annotations

import fcntl
import os
import re
import secrets
import shutil
import time
from collections.abc import Iterable, Iterator
from contextlib import contextmanager
from datetime import datetime, timezone
from pathlib import Path

from oacdsl.atomic import pid_alive
from oacdsl.compiler.loader import REPORT_MARK

__all__ = [
    "ENTRIES",
    "KEEP_RUNS",
    "STAGING_PREFIX",
    "STALE_AFTER_S",
    "clean_stale",
    "make_staging",
    "publish",
]

#: The fixed entries of a report folder (the composed ``NAME.oac`` is linked too).
ENTRIES = ("report.html", "result.json", "figures", "execution.c3d", "execution.contacts.json")
#: How many runs ``OUT/runs/`` keeps (the current one always).
KEEP_RUNS = 3
#: Prefix of a staging folder inside ``OUT``.
STAGING_PREFIX = ".reproduce-"
#: Age after which leftovers without an owner file are stale, seconds.
STALE_AFTER_S = 600.0
#: Age after which leftovers are stale even though their owner's process id is in use (reused), s.
REUSED_PID_AFTER_S = 86_400.0
_OWNER = ".owner"
_CURRENT = "current"
_RUNS = "runs"
_TEMP_LINK = re.compile(r"^\.(?:current|link)-(\d+)-[0-9a-f]+$")
_ASIDE = re.compile(r"^\.reproduce-old-(\d+)-")


def make_staging(out: Path) -> Path:
    """Create ``out/.reproduce-XXXX/`` owned by this process (``out`` is created if needed and
    marked as a report folder)."""
    import tempfile

    out.mkdir(parents=True, exist_ok=True)
    (out / REPORT_MARK).touch()
    staging = Path(tempfile.mkdtemp(prefix=STAGING_PREFIX, dir=out))
    (staging / _OWNER).write_text(f"{os.getpid()}\n", encoding="ascii")
    return staging


def _owner_pid(folder: Path) -> int | None:
    try:
        return int((folder / _OWNER).read_text(encoding="ascii").strip())
    except (OSError, ValueError):
        return None


def _is_stale(path: Path, pid: int | None, now: float) -> bool:
    try:
        age = now - path.lstat().st_mtime
    except OSError:
        return False
    if pid is not None:  # a run lasts minutes: after a day, a live pid is another process's
        return not pid_alive(pid) or age > REUSED_PID_AFTER_S
    return age > STALE_AFTER_S


def clean_stale(out: Path) -> list[Path]:
    """Remove from ``out`` the staging folders and temporary links of runs that are gone.

    A staging folder is stale when the process named in its ``.owner`` file no longer
    runs, or it has no readable owner and is older than :data:`STALE_AFTER_S`. Returns what
    was removed. A live run's staging is never touched.
    """
    removed: list[Path] = []
    if not out.is_dir():
        return removed
    now = time.time()
    try:
        entries = list(out.iterdir())
    except OSError:
        return removed
    for path in entries:
        name = path.name
        if (m := _ASIDE.match(name)) is not None:  # an older layout's folder, swapped for its link
            if _is_stale(path, int(m.group(1)), now):
                if path.is_symlink() or not path.is_dir():
                    path.unlink(missing_ok=True)
                else:
                    shutil.rmtree(path, ignore_errors=True)
                removed.append(path)
        elif name.startswith(STAGING_PREFIX) and path.is_dir() and not path.is_symlink():
            if _is_stale(path, _owner_pid(path), now):
                shutil.rmtree(path, ignore_errors=True)
                removed.append(path)
        elif (m := _TEMP_LINK.match(name)) is not None and path.is_symlink():
            if _is_stale(path, int(m.group(1)), now):
                path.unlink(missing_ok=True)
                removed.append(path)
    return removed


def _run_id() -> str:
    return datetime.now(timezone.utc).strftime("%Y%m%dT%H%M%S.%fZ") + "-" + secrets.token_hex(3)


def _replace_link(link: Path, target: str) -> None:
    """Point ``link`` at ``target`` in one rename (a new link beside it, renamed over it)."""
    tmp = link.with_name(f".link-{os.getpid()}-{secrets.token_hex(4)}")
    if link.name == _CURRENT:
        tmp = link.with_name(f".current-{os.getpid()}-{secrets.token_hex(4)}")
    os.symlink(target, tmp)
    try:
        os.replace(tmp, link)
    except BaseException:
        tmp.unlink(missing_ok=True)
        raise


def _entry_names(run: Path) -> list[str]:
    fixed = [name for name in ENTRIES if (run / name).exists()]
    return fixed + sorted(p.name for p in run.glob("*.oac"))


def _links_ok(out: Path, names: Iterable[str]) -> bool:
    return all(os.path.islink(out / n) and os.readlink(out / n) == f"{_CURRENT}/{n}" for n in names)


def _adopt_legacy(out: Path) -> None:
    """Turn regular entries of an older layout into a run of their own, pointed at by ``current``."""
    names = [n for n in ENTRIES if (out / n).exists() and not (out / n).is_symlink()]
    names += sorted(p.name for p in out.glob("*.oac") if not p.is_symlink() and p.is_file())
    if not names or (out / _CURRENT).is_symlink():
        return
    staging = make_staging(out)
    for n in names:
        if (out / n).is_dir():
            shutil.copytree(out / n, staging / n, symlinks=True)
        else:
            shutil.copy2(out / n, staging / n)
    run = out / _RUNS / f"legacy-{_run_id()}"
    run.parent.mkdir(exist_ok=True)
    os.rename(staging, run)
    (run / _OWNER).unlink()
    _replace_link(out / _CURRENT, f"{_RUNS}/{run.name}")


def _link_entry(out: Path, name: str) -> None:
    """Make ``out/name`` the link ``current/name`` (a regular entry of the same content is replaced)."""
    entry, target = out / name, f"{_CURRENT}/{name}"
    if entry.is_symlink():
        if os.readlink(entry) != target:
            _replace_link(entry, target)
    elif entry.is_dir():  # a folder of the older layout, already copied into the current run
        aside = out / f"{STAGING_PREFIX}old-{os.getpid()}-{name}-{secrets.token_hex(3)}"
        os.symlink(target, aside)
        if not _exchange(aside, entry):  # no atomic swap here: a moment without the folder
            os.unlink(aside)
            os.rename(entry, aside)
            os.symlink(target, entry)
        shutil.rmtree(aside, ignore_errors=True)
    else:
        _replace_link(entry, target)


def _exchange(a: Path, b: Path) -> bool:
    """Swap two names atomically (Linux ``renameat2(RENAME_EXCHANGE)``); False where unsupported."""
    import ctypes
    import sys

    if not sys.platform.startswith("linux"):
        return False
    try:
        libc = ctypes.CDLL(None, use_errno=True)
        renameat2 = libc.renameat2
    except (OSError, AttributeError):
        return False
    at_fdcwd, rename_exchange = -100, 2
    return renameat2(at_fdcwd, os.fsencode(a), at_fdcwd, os.fsencode(b), rename_exchange) == 0


@contextmanager
def _locked(out: Path) -> Iterator[None]:
    """Hold the exclusive lock of ``out`` (its :data:`REPORT_MARK` file) for the block."""
    fd = os.open(out / REPORT_MARK, os.O_RDWR | os.O_CREAT, 0o666)
    try:
        fcntl.flock(fd, fcntl.LOCK_EX)
        yield
    finally:
        os.close(fd)  # releases the lock


def _folder_mode() -> int:
    umask = os.umask(0)
    os.umask(umask)
    return 0o777 & ~umask


def publish(staging: Path, out: Path, *, keep: int = KEEP_RUNS) -> list[Path]:
    """Publish the finished run in ``staging`` as ``out``'s current run; return its entries.

    See the module docstring for the layout and why each step is safe to interrupt.
    """
    os.chmod(staging, _folder_mode())  # mkdtemp's 0700 would hide the report from everyone else
    with _locked(out):
        return _publish(staging, out, keep)


def _publish(staging: Path, out: Path, keep: int) -> list[Path]:
    _adopt_legacy(out)
    current = out / _CURRENT
    old_names = set(_entry_names(current)) if current.is_dir() else set()
    runs = out / _RUNS
    runs.mkdir(exist_ok=True)
    run = runs / _run_id()
    os.rename(staging, run)  # owner file and all: a staging folder never lacks its owner
    (run / _OWNER).unlink(missing_ok=True)
    names = _entry_names(run)
    for name in names:  # links to current/NAME: before the switch they show the old run's entry
        if not _links_ok(out, [name]):
            if name not in old_names and (out / name).exists() and not (out / name).is_symlink():
                continue  # a file of the user's that is not a report entry: left alone
            _link_entry(out, name)
    _replace_link(current, f"{_RUNS}/{run.name}")
    _remove_dangling(out)  # entries of older runs only (another NAME.oac), also of killed ones
    _prune(runs, keep, run.name)
    return [out / name for name in names]


def _remove_dangling(out: Path) -> None:
    """Remove the links ``out/X → current/X`` that lead nowhere (under the lock: no run is
    between linking its entries and switching ``current``)."""
    for entry in out.iterdir():
        try:
            if entry.is_symlink() and os.readlink(entry).startswith(f"{_CURRENT}/") and not entry.exists():
                entry.unlink()
        except OSError:
            continue


def _prune(runs: Path, keep: int, newest: str) -> None:
    """Remove all but the ``keep`` newest runs (by name) and never ``newest``."""
    names = sorted(
        (p.name for p in runs.iterdir() if p.is_dir() and not p.is_symlink()),
        key=lambda n: n.removeprefix("legacy-"),
    )
    for name in names[: max(0, len(names) - keep)]:
        if name != newest:
            shutil.rmtree(runs / name, ignore_errors=True)
