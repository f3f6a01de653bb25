"""Which recordings a mining job covers: files, folders and glob patterns, each with a stable id.

A folder contributes every recording file under it (recursively) whose name ends in one of
:data:`SUFFIXES`; a pattern with ``*``, ``?`` or ``[`` is expanded (``**`` recursive); a
file is taken as it is, whatever its suffix (a reader then says what is wrong with it).
The list is sorted and free of duplicates. A recording's **id** is a digest of its resolved
path, size and modification time: a job run again skips the ids its table holds, and a file
changed since is analysed again.
"""

from __future__ import annotations

import glob
import hashlib
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

from oacdsl.errors import InputError, UsageError

__all__ = ["SUFFIXES", "RecordingFile", "expand_recordings"]

#: Name endings of recording files a folder is searched for (case-insensitive).
SUFFIXES = (".c3d", ".mmm.xml", ".xml", ".tsv", ".csv")


@dataclass(frozen=True)
class RecordingFile:
    """One recording of the job: ``path`` as found, ``id`` (see the module doc), ``size_bytes``."""

    path: str
    id: str
    size_bytes: int


def _is_recording(path: Path) -> bool:
    name = path.name.lower()
    return path.is_file() and name.endswith(SUFFIXES) and not name.endswith((".labels.csv", ".segments.csv"))


def _identify(path: Path) -> RecordingFile:
    try:
        st = path.stat()
    except OSError as error:
        raise InputError(f"cannot read: {error.strerror or error}", location=str(path)) from None
    key = f"{path.resolve()}\0{st.st_size}\0{st.st_mtime_ns}".encode()
    return RecordingFile(str(path), hashlib.sha256(key).hexdigest()[:20], st.st_size)


def expand_recordings(items: Sequence[str]) -> list[RecordingFile]:
    """The recordings named by ``items`` (module doc); a name that matches nothing is a UsageError."""
    found: dict[str, Path] = {}
    for item in items:
        if any(c in item for c in "*?["):
            hits = [Path(p) for p in sorted(glob.glob(item, recursive=True))]
            paths = [p for p in hits if p.is_file()]
            if not paths:
                raise UsageError(f"{item}: no file matches this pattern")
        elif Path(item).is_dir():
            paths = sorted(p for p in Path(item).rglob("*") if _is_recording(p))
            if not paths:
                raise UsageError(f"{item}: no recording ({', '.join(SUFFIXES)}) in this folder")
        elif Path(item).exists():
            paths = [Path(item)]
        else:
            raise UsageError(f"{item}: no such file or folder")
        for p in paths:
            found.setdefault(str(p.resolve()), p)
    return [_identify(found[k]) for k in sorted(found)]
