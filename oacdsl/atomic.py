"""Atomic file output: write next to the target, then rename over it.

Readers of a file written here see the old content or the new, never half of
it, and a failed or interrupted write leaves no stray temporary file. A new
file gets the permissions any new file would get (``0o666`` less the umask,
not ``mkstemp``'s ``0o600``); a replaced file keeps its own.

A process killed between writing and renaming (``kill -9``) does leave its
temporary file, ``.NAME.PID.XXXXXXXX.tmp``; :func:`remove_stale_temporaries`
removes those whose process ``PID`` is gone.
"""

from __future__ import annotations

import os
import re
import tempfile
import time
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

__all__ = ["atomic_path", "pid_alive", "remove_stale_temporaries", "write_atomic"]

#: Age after which a temporary file without a process id in its name is stale, seconds.
STALE_AFTER_S = 3600.0
_TEMP_NAME = re.compile(r"^\..+?\.(?:(\d+)\.)?[A-Za-z0-9_]{8}\.tmp(?:\.[A-Za-z0-9]+)?$")


def _new_file_mode() -> int:
    umask = os.umask(0)
    os.umask(umask)
    return 0o666 & ~umask


@contextmanager
def atomic_path(
    path: str | os.PathLike[str], *, suffix: str = ".tmp", make_parents: bool = True
) -> Iterator[Path]:
    """Yield a temporary path next to ``path``; on success rename it over ``path``.

    For writers that want a file name (matplotlib's ``savefig``, ezc3d, video
    encoders). ``suffix`` keeps a file-type suffix for writers that look at it.
    The folder is created if needed (unless ``make_parents`` is False: then a
    missing folder is an ``OSError``, as for ``open``). On any exception the temporary file is
    removed and the exception propagates; ``path`` is untouched.
    """
    target = Path(path)
    if make_parents:
        target.parent.mkdir(parents=True, exist_ok=True)
    mode = target.stat().st_mode & 0o7777 if target.exists() else _new_file_mode()
    fd, name = tempfile.mkstemp(prefix=f".{target.name}.{os.getpid()}.", suffix=suffix, dir=target.parent)
    os.close(fd)
    tmp = Path(name)
    try:
        yield tmp
        os.chmod(tmp, mode)
        os.replace(tmp, target)
    except BaseException:
        tmp.unlink(missing_ok=True)
        raise


def write_atomic(path: str | os.PathLike[str], data: bytes | str) -> Path:
    """Write ``data`` (str as UTF-8, ``\\n`` line ends) to ``path`` atomically; return the path."""
    payload = data.encode("utf-8") if isinstance(data, str) else data
    with atomic_path(path) as tmp:
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
