"""Atomic file output: write next to the target, then rename over it.

Readers of a file written here see the old content or the new, never half of
it, and a failed or interrupted write leaves no stray temporary file. A new
file gets the permissions any new file would get (``0o666`` less the umask,
not ``mkstemp``'s ``0o600``); a replaced file keeps its own.

A process killed between writing and renaming (``kill -9``) does leave its
temporary file, ``.NAME.PID.XXXXXXXX.tmp``; :func:`remove_stale_temporaries`
removes those whose process ``PID`` is gone.

What a rename would damage is refused before anything is written
(:func:`check_target`, an :class:`~oacdsl.errors.InputError`, exit status 2): a FIFO,
a device or a socket (it would become a regular file), a folder, a read-only file
(no write bit in its mode, also for root), a file with several hard links (the rename
would split them), another user's file (it would become the caller's; root keeps its
owner), and a file name longer than :data:`NAME_MAX` bytes. ``unchanged_since``
refuses to replace a file whose content changed while the new one was being made
(``oacc fmt`` and an editor saving at the same time).
"""

from __future__ import annotations

import os
import re
import stat
import tempfile
import time
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

from oacdsl.errors import InputError

__all__ = ["NAME_MAX", "atomic_path", "check_target", "pid_alive", "remove_stale_temporaries", "write_atomic"]

#: The longest file name (one path component) common file systems take, bytes.
NAME_MAX = 255
_KINDS = [
    (stat.S_ISCHR, "a character device"),
    (stat.S_ISBLK, "a block device"),
    (stat.S_ISFIFO, "a FIFO (named pipe)"),
    (stat.S_ISSOCK, "a socket"),
]

#: Age after which a temporary file without a process id in its name is stale, seconds.
STALE_AFTER_S = 3600.0
_TEMP_NAME = re.compile(r"^\..+?\.(?:(\d+)\.)?[A-Za-z0-9_]{8}\.tmp(?:\.[A-Za-z0-9]+)?$")


def _new_file_mode() -> int:
    umask = os.umask(0)
    os.umask(umask)
    return 0o666 & ~umask


def check_target(path: str | os.PathLike[str]) -> os.stat_result | None:
    """Refuse a ``path`` that replacing by rename would damage (see the module docstring);
    return its status, None when it does not exist yet."""
    target = Path(path)
    where = str(target)
    size = len(os.fsencode(target.name))
    if size > NAME_MAX:
        raise InputError(f"the file name is {size} bytes, longer than the {NAME_MAX} a file system takes",
                         location=where[:80] + "…")
    try:
        info = os.stat(target)
    except FileNotFoundError:
        return None
    except NotADirectoryError:
        raise InputError("cannot write: a parent of this path is not a folder", location=where) from None
    except OSError as error:
        raise InputError(f"cannot write: {error.strerror or error}", location=where) from None
    mode = info.st_mode
    if stat.S_ISDIR(mode):
        raise InputError("is a folder; give a file path", location=where)
    if not stat.S_ISREG(mode):
        kind = next((name for test, name in _KINDS if test(mode)), "a special file")
        raise InputError(f"is {kind}; not replaced by a regular file (give a file path)", location=where)
    if not mode & 0o222:
        raise InputError(f"read-only (mode {stat.S_IMODE(mode):04o}); not replaced", location=where)
    if info.st_nlink > 1:
        raise InputError(f"has {info.st_nlink} hard links; replacing it would split them (not replaced)",
                         location=where)
    if info.st_uid != os.geteuid() and os.geteuid() != 0:
        raise InputError(f"owned by another user (uid {info.st_uid}); replacing it would make it yours"
                         " (not replaced)", location=where)
    return info


def _temp_prefix(name: str) -> str:
    """``.NAME.PID.`` with NAME shortened so that the temporary name fits :data:`NAME_MAX`."""
    room = NAME_MAX - 40  # the process id, mkstemp's 8 characters and a suffix such as ".tmp.png"
    raw = os.fsencode(name)
    short = raw[:room].decode("utf-8", errors="ignore") if len(raw) > room else name
    return f".{short}.{os.getpid()}."


@contextmanager
def atomic_path(
    path: str | os.PathLike[str],
    *,
    suffix: str = ".tmp",
    make_parents: bool = True,
    unchanged_since: bytes | None = None,
) -> Iterator[Path]:
    """Yield a temporary path next to ``path``; on success rename it over ``path``.

    For writers that want a file name (matplotlib's ``savefig``, ezc3d, video
    encoders). ``suffix`` keeps a file-type suffix for writers that look at it.
    The folder is created if needed (unless ``make_parents`` is False: then a
    missing folder is an ``OSError``, as for ``open``). On any exception the temporary file is
    removed and the exception propagates; ``path`` is untouched. :func:`check_target` first;
    ``unchanged_since``: the bytes ``path`` held when the caller read it, checked again just
    before the rename (an :class:`~oacdsl.errors.InputError` when they differ).
    """
    target = Path(path)
    info = check_target(target)
    if make_parents:
        target.parent.mkdir(parents=True, exist_ok=True)
    mode = stat.S_IMODE(info.st_mode) if info is not None else _new_file_mode()
    fd, name = tempfile.mkstemp(prefix=_temp_prefix(target.name), suffix=suffix, dir=target.parent)
    os.close(fd)
    tmp = Path(name)
    try:
        yield tmp
        os.chmod(tmp, mode)
        if info is not None and (info.st_uid, info.st_gid) != (os.geteuid(), os.getegid()):
            try:  # keep the file's owner and group (root may; a user may choose one of its groups)
                os.chown(tmp, info.st_uid if os.geteuid() == 0 else -1, info.st_gid)
            except OSError:
                pass
        if unchanged_since is not None and _current(target) != unchanged_since:
            raise InputError("changed while it was being rewritten; not replaced (run again)",
                             location=str(target))
        os.replace(tmp, target)
    except BaseException:
        tmp.unlink(missing_ok=True)
        raise


def _current(target: Path) -> bytes | None:
    try:
        return target.read_bytes()
    except OSError:
        return None


def write_atomic(
    path: str | os.PathLike[str], data: bytes | str, *, unchanged_since: bytes | None = None
) -> Path:
    """Write ``data`` (str as UTF-8, ``\\n`` line ends) to ``path`` atomically; return the path."""
    payload = data.encode("utf-8") if isinstance(data, str) else data
    with atomic_path(path, unchanged_since=unchanged_since) as tmp:
        with open(tmp, "wb") as fh:
            fh.write(payload)
            fh.flush()
            os.fsync(fh.fileno())
    return Path(path)


def pid_alive(pid: int) -> bool:
    """True when a process ``pid`` exists on this machine (also one of another user)."""
    if pid <= 0:
        return False
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True
    except OSError:
        return False
    return True


def remove_stale_temporaries(folder: str | os.PathLike[str]) -> list[Path]:
    """Remove the temporary files of :func:`atomic_path` in ``folder`` left by processes that are gone.

    A temporary file names its process (``.NAME.PID.XXXXXXXX.tmp``): it is stale when that
    process no longer runs (or the file is a day old: the id is then another process's); one
    without a process id (older oacdsl) when it is older than :data:`STALE_AFTER_S`.
    Returns the files removed; errors are ignored (a best effort).
    """
    removed: list[Path] = []
    try:
        entries = list(os.scandir(folder))
    except OSError:
        return removed
    now = time.time()
    for entry in entries:
        m = _TEMP_NAME.match(entry.name)
        if m is None or not entry.is_file(follow_symlinks=False):
            continue
        try:
            age = now - entry.stat(follow_symlinks=False).st_mtime
            if m.group(1):  # after a day, a live process of that id is another one (ids are reused)
                stale = not pid_alive(int(m.group(1))) or age > 24 * STALE_AFTER_S
            else:
                stale = age > STALE_AFTER_S
            if stale:
                os.unlink(entry.path)
                removed.append(Path(entry.path))
        except OSError:
            continue
    return removed
