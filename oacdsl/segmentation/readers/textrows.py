"""Text recordings (TSV, CSV) read in bounded memory: lines in chunks, numbers block by block.

A text file is read twice. :func:`scan_text` counts its lines in chunks of bytes and
learns its encoding (UTF-8, else Latin-1) and how it ends; the reader then allocates its
arrays from that count (an upper bound of the data rows) and :func:`read_rows` converts the
rows a block at a time (about :data:`BLOCK_FIELDS` fields) into them. Memory is the result
plus one block, never the whole file as Python strings (which took 14 times the file).

Lines end with ``\\n``, ``\\r\\n`` or ``\\r``. A file whose last line has no line end was
cut short, perhaps inside its last number (``903.1`` → ``90``): that line is an error
(:class:`~oacdsl.errors.TruncatedRecording`, naming it), or with ``allow_truncated`` it is
left out with a :class:`~oacdsl.errors.RecordingWarning`.
"""

from __future__ import annotations

import codecs
import warnings
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from oacdsl.errors import InvalidRecording, RecordingError, RecordingWarning, TruncatedRecording
from oacdsl.segmentation.readers._common import clip
from oacdsl.segmentation.readers.limits import open_regular

__all__ = ["BLOCK_FIELDS", "Lines", "TextFile", "clip", "read_rows", "scan_text"]

READ_BYTES = 1 << 20  # bytes read at a time
BLOCK_FIELDS = 1 << 18  # fields converted at a time: bounds the temporary strings (~20 MB)
_BOM = codecs.BOM_UTF8
@dataclass(frozen=True)
class TextFile:
    """What the first pass learned: encoding, lines holding more than white space, the end."""

    path: Path
    encoding: str  # "utf-8" or "latin-1"
    nonblank: int  # lines with more than ASCII white space (an upper bound of the data rows)
    last_line: int  # 1-based number of the last line (0: empty file)
    unterminated: bool  # the last line holds text but no line end

    @property
    def location(self) -> str:
        return str(self.path)


def _chunks_of_lines(path: Path) -> Iterator[tuple[list[bytes], bool]]:
    """Lists of whole lines (without line ends), read in chunks; the flag: the file's tail."""
    with open_regular(path) as fh:
        carry = b""
        while True:
            try:
                chunk = fh.read(READ_BYTES)
            except OSError as err:
                raise RecordingError(f"cannot read: {err.strerror or err}", location=str(path)) from None
            if not chunk:
                break
            data = carry + chunk
            body = data[:-1] if data.endswith(b"\r") else data  # a \r may be half of \r\n
            cut = max(body.rfind(b"\n"), body.rfind(b"\r"))
            if cut < 0:
                carry = data
                continue
            yield body[: cut + 1].splitlines(), False
            carry = data[cut + 1 :]
        if carry:
            yield carry.splitlines(), True


def scan_text(path: Path) -> TextFile:
    """First pass: encoding, line count, whether the last line ends (bounded memory)."""
    encoding = "utf-8"
    nonblank = lines = 0
    unterminated = False
    with open_regular(path) as fh:
        head = fh.read(4096)
    if b"\x00" in head:
        raise InvalidRecording("binary data in a text recording", location=str(path))
    for batch, tail in _chunks_of_lines(path):
        if encoding == "utf-8":
            try:
                b"\n".join(batch).decode("utf-8-sig" if lines == 0 else "utf-8")
            except UnicodeDecodeError:
                encoding = "latin-1"
        lines += len(batch)
        nonblank += sum(map(bool, map(bytes.strip, batch)))
        if tail:
            unterminated = bool(batch and batch[-1].strip())
    return TextFile(path, encoding, nonblank, lines, unterminated)


class Lines:
    """Second pass: the decoded lines ``(number, text)`` one at a time, with one line of look-ahead.

    The last line of an unterminated file is an error when the reader reaches it
    (before converting it), or is left out with a warning when ``allow_truncated``.
    """

    def __init__(self, text: TextFile, *, allow_truncated: bool = False) -> None:
        self.text = text
        self.allow_truncated = allow_truncated
        self._it = self._lines()
        self._ahead: tuple[int, str] | None = None
        self.dropped = 0  # lines left out (the unterminated last one, with allow_truncated)

    def _lines(self) -> Iterator[tuple[int, str]]:
        number = 0
        encoding = self.text.encoding
        for batch, _ in _chunks_of_lines(self.text.path):
            if number == 0 and batch and encoding == "utf-8" and batch[0].startswith(_BOM):
                batch[0] = batch[0][3:]
            for raw in batch:
                number += 1
                if number == self.text.last_line and self.text.unterminated:
                    self._cut_short(number)
                    return
                yield number, raw.decode(encoding)

    def _cut_short(self, number: int) -> None:
        where = f"line {number}: the file ends inside this line (no line end after it): cut short"
        if not self.allow_truncated:
            raise TruncatedRecording(
                f"{where}, perhaps inside a number; --allow-truncated reads the lines before it",
                location=self.text.location,
            )
        self.dropped = 1
        warnings.warn(f"{self.text.location}: {where}; reading the lines before it", RecordingWarning,
                      stacklevel=4)

    def peek(self) -> tuple[int, str] | None:
        """The next line without taking it (``None`` at the end)."""
        if self._ahead is None:
            self._ahead = next(self._it, None)
        return self._ahead

    def __iter__(self) -> Iterator[tuple[int, str]]:
        return self

    def __next__(self) -> tuple[int, str]:
        line = self.peek()
        if line is None:
            raise StopIteration
        self._ahead = None
        return line


Take = Callable[[int, np.ndarray, np.ndarray], None]


def read_rows(
    lines: Lines,
    split: Callable[[str, int], list[str]],
    width: int,
    capacity: int,
    take: Take,
    *,
    sep: str,
    trailing_sep: bool = False,
) -> int:
    """Convert the remaining non-blank lines to numbers, a block at a time; the number of rows.

    Each row has ``width`` fields separated by ``sep`` (one more ``sep`` at the end is
    dropped when ``trailing_sep``); ``split(text, line_number)`` gives a line's fields where
    that is not enough (quotes). ``take(first_row, line_numbers (k,), values (k, width)
    float64)`` receives each block (an empty field or ``nan`` is NaN); at most ``capacity``
    rows (the caller's arrays). A row of another width or a field that is not a number is
    an error naming its line.
    """
    block_rows = max(1, BLOCK_FIELDS // max(width, 1))
    block: list[tuple[int, str]] = []
    row = 0
    for line in lines:
        if line[1].strip():
            block.append(line)
            if len(block) == block_rows:
                row = _flush(lines.text.location, block, split, width, sep, trailing_sep, row, capacity, take)
    if block:
        row = _flush(lines.text.location, block, split, width, sep, trailing_sep, row, capacity, take)
    return row


def _flush(
    location: str,
    block: list[tuple[int, str]],
    split: Callable[[str, int], list[str]],
    width: int,
    sep: str,
    trailing_sep: bool,
    row: int,
    capacity: int,
    take: Take,
) -> int:
    k = len(block)
    if row + k > capacity:  # the first pass counted fewer lines: the file changed while read
        raise RecordingError("the file changed while it was read", location=location)
    values = _fast(block, width, sep, trailing_sep)
    if values is None:  # quotes, white space in a field, or something wrong: field by field
        values = _slow(location, block, split, width)
    take(row, np.fromiter((n for n, _ in block), dtype=np.int64, count=k), values)
    block.clear()
    return row + k


def _fill_empty(text: str, sep: str) -> str:
    """``text`` (lines joined by newlines) with ``nan`` in every empty field."""
    twice = sep + sep
    if twice in text:
        text = text.replace(twice, f"{sep}nan{sep}").replace(twice, f"{sep}nan{sep}")  # ",,," needs two
    text = text.replace(f"\n{sep}", f"\nnan{sep}").replace(f"{sep}\n", f"{sep}nan\n")
    if text.startswith(sep):
        text = "nan" + text
    return text + "nan" if text.endswith(sep) else text


def _fast(block: list[tuple[int, str]], width: int, sep: str, trailing_sep: bool) -> np.ndarray | None:
    """(k, width) numbers through numpy's C parser, or ``None`` when it cannot tell them (then
    :func:`_slow` decides and names the line)."""
    texts = [t[:-1] if t.endswith(sep) else t for _, t in block] if trailing_sep else [t for _, t in block]
    joined = _fill_empty("\n".join(texts), sep)
    if '"' in joined or "#" in joined:
        return None
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            values = np.loadtxt(
                joined.split("\n"), delimiter=sep, dtype=np.float64, comments=None, ndmin=2, quotechar=None
            )
    except ValueError:
        return None
    return values if values.shape == (len(block), width) else None


def _slow(
    location: str, block: list[tuple[int, str]], split: Callable[[str, int], list[str]], width: int
) -> np.ndarray:
    flat: list[str] = []
    for line_no, text in block:
        fields = split(text, line_no)
        if len(fields) != width:
            raise InvalidRecording(
                f"line {line_no}: {len(fields)} fields, expected {width}", location=location
            )
        flat.extend([f.strip() or "nan" for f in fields])
    try:
        return np.array(flat, dtype=np.float64).reshape(len(block), width)
    except ValueError:
        for i, (line_no, _) in enumerate(block):  # find the culprit for the message
            for text in flat[i * width : (i + 1) * width]:
                try:
                    float(text)
                except ValueError:
                    raise InvalidRecording(
                        f"line {line_no}: value {clip(text)} is not a number", location=location
                    ) from None
        raise InvalidRecording(f"line {block[0][0]}: unreadable numbers", location=location) from None
