"""Motion-capture readers: one module per file format, one :class:`Recording` out.

:func:`read_recording` picks the reader by extension (``.c3d``; ``.xml`` and
``.mmm.xml``; ``.tsv``; ``.csv``) unless ``fmt`` names it. Every reader returns
positions in metres with NaN in gaps, frame times from 0 at the file's first
frame, and ``first_frame`` = the file's own number of that frame.
"""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

from oacdsl.errors import RecordingError, did_you_mean
from oacdsl.segmentation.readers.c3d import read_c3d, write_c3d
from oacdsl.segmentation.readers.limits import check_regular, clip
from oacdsl.segmentation.recording import Recording

__all__ = ["FORMATS", "WRITABLE", "read_recording", "read_c3d", "write_c3d", "write_recording", "format_of"]

#: Formats :func:`write_recording` writes.
WRITABLE = ("c3d", "mmm")

#: Format names accepted by ``fmt`` and the extensions that select them.
FORMATS: dict[str, tuple[str, ...]] = {
    "c3d": (".c3d",),
    "mmm": (".mmm.xml", ".xml"),
    "tsv": (".tsv",),
    "csv": (".csv",),
}


def format_of(path: str | Path) -> str:
    """The format name for ``path``'s extension, or a :class:`RecordingError`."""
    name = Path(path).name.lower()
    for fmt, extensions in FORMATS.items():
        if name.endswith(extensions):
            return fmt
    known = ", ".join(e for exts in FORMATS.values() for e in exts)
    raise RecordingError(
        f"unknown recording format (extensions: {known}; or give the format)", location=str(path)
    )


def _reader(fmt: str) -> Callable[..., Recording]:
    if fmt == "c3d":
        return read_c3d
    if fmt == "mmm":
        from oacdsl.segmentation.readers.mmm import read_mmm

        return read_mmm
    if fmt == "tsv":
        from oacdsl.segmentation.readers.qualisys_tsv import read_tsv

        return read_tsv
    from oacdsl.segmentation.readers.plain_csv import read_csv

    return read_csv


def read_recording(
    path: str | Path, fmt: str | None = None, *, units: str | None = None, allow_truncated: bool = False
) -> Recording:
    """Read a recording; ``fmt`` (c3d, mmm, tsv, csv) overrides the extension.

    ``units`` overrides the length unit of a TSV or CSV file (mm, cm, m); C3D and
    MMM files declare their own. A C3D file that ends before its declared frames, or a
    TSV or CSV file whose last line has no line end (cut short), is a
    :class:`~oacdsl.errors.TruncatedRecording` unless ``allow_truncated`` (then a
    :class:`~oacdsl.errors.RecordingWarning` and its complete frames). Every reader
    checks the limits of :mod:`~oacdsl.segmentation.readers.limits`: a bad file is an
    :class:`~oacdsl.errors.InvalidRecording` (exit 1), a missing or special file
    (``/dev/zero``, a FIFO) a :class:`~oacdsl.errors.RecordingError` (exit 2).
    """
    path = Path(path)
    if fmt is None:
        fmt = format_of(path)
    elif fmt not in FORMATS:
        raise RecordingError(
            f"unknown recording format {clip(fmt)}{did_you_mean(fmt, FORMATS)}", location=str(path)
        )
    check_regular(path)  # before anything opens it: /dev/zero or a FIFO would be read for ever
    if units is not None and fmt not in ("tsv", "csv"):
        raise RecordingError(
            f"{fmt} files declare their own units; drop the units option", location=str(path)
        )
    if fmt == "c3d":
        return read_c3d(path, allow_truncated=allow_truncated)
    if fmt == "mmm":
        return _reader(fmt)(path)
    if units is not None:
        return _reader(fmt)(path, units=units, allow_truncated=allow_truncated)
    return _reader(fmt)(path, allow_truncated=allow_truncated)


def write_recording(recording: Recording, path: str | Path, fmt: str | None = None) -> Path:
    """Write ``recording`` as C3D or MMM XML (markers only), chosen by ``fmt`` or ``path``'s
    extension, atomically; :func:`read_recording` reads it back (same markers, groups, times)."""
    path = Path(path)
    fmt = fmt or format_of(path)
    if fmt == "c3d":
        return write_c3d(recording, path)
    if fmt == "mmm":
        from oacdsl.segmentation.readers.mmm_write import write_mmm

        return write_mmm(recording, path)
    raise RecordingError(
        f"cannot write {fmt} files; write {' or '.join(WRITABLE)} (.c3d, .mmm.xml)", location=str(path)
    )
