"""Atomic file output: write next to the target, then rename over it.

Readers of a file written here see the old content or the new, never half of
it, and a failed or interrupted write leaves no stray temporary file. A new
file gets the permissions any new file would get (``0o666`` less the umask,
not ``mkstemp``'s ``0o600``); a replaced file keeps its own.
"""

from __future__ import annotations

import os
import tempfile
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

__all__ = ["atomic_path", "write_atomic"]


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
    fd, name = tempfile.mkstemp(prefix=f".{target.name}.", suffix=suffix, dir=target.parent)
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
