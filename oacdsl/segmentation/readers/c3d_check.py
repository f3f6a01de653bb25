"""Structural checks of a C3D file before ezc3d parses it.

ezc3d reads a truncated data section without complaint (it returns the frames
that are there) and can crash the interpreter on a garbled parameter section
(for example a parameter with 217 dimensions). These checks walk the header and
the parameter records with plain ``struct`` reads, so a corrupt file becomes a
one-line :class:`~oacdsl.errors.InvalidRecording` instead.

The layout follows the C3D specification (c3d.org): 512-byte blocks; block 1 is
the header (16-bit words); the parameter section starts at the block named by
header byte 0 and declares its own length in blocks and the processor type
(84 Intel, 85 DEC, 86 MIPS — the last one big-endian).
"""

from __future__ import annotations

import struct
import warnings
from dataclasses import dataclass
from pathlib import Path

from oacdsl.errors import InvalidRecording, RecordingWarning, TruncatedRecording
from oacdsl.segmentation.readers.c3d_agree import Param as _Param
from oacdsl.segmentation.readers.c3d_agree import check_agreement
from oacdsl.segmentation.readers.limits import check_size

__all__ = ["C3dLayout", "RecordingWarning", "check_c3d_structure", "check_c3d_data_size"]

_BLOCK = 512  # bytes
_KEY = 0x50  # the C3D key byte
_PROCESSORS = {84: "<", 85: "<", 86: ">"}  # Intel, DEC, MIPS
_ELEMENT_SIZES = {-1, 1, 2, 4}
_MAX_DIMENSIONS = 7  # the specification's limit
_MAX_RECORDS = 100_000  # far more parameters than any writer produces


@dataclass(frozen=True)
class C3dLayout:
    """What the raw header says (before any library interprets it)."""

    points: int  # 3D points per frame: POINT:USED when present (what ezc3d reads), else the header
    analog_per_frame: int  # analog samples per 3D frame (all channels)
    first_frame: int  # 1-based, as stored
    last_frame: int  # 1-based, as stored
    data_start_block: int  # 1-based block number
    endian: str  # "<" or ">"
    float_storage: bool  # POINT:SCALE < 0: 4-byte floats, else scaled 16-bit integers
    point_frames: int | None = None  # POINT:FRAMES as stored, when present

    @property
    def n_frames(self) -> int:
        """Frames the file declares: POINT:FRAMES when present (ezc3d reads that many), else the header."""
        if self.point_frames:
            return self.point_frames
        return self.last_frame - self.first_frame + 1


def _fail(path: Path, what: str) -> InvalidRecording:
    return InvalidRecording(f"not a valid C3D file: {what}", location=str(path))


def check_c3d_structure(path: Path, data: bytes) -> C3dLayout:
    """Validate the header and walk every parameter record; return the header layout."""
    if len(data) < 2 * _BLOCK:
        raise _fail(path, f"file is {len(data)} bytes, shorter than a header and a parameter block")
    param_block = data[0]
    if data[1] != _KEY:
        raise _fail(path, f"header key byte is {data[1]:#04x}, expected 0x50")
    if param_block < 2:
        raise _fail(path, f"parameter section starts at block {param_block}")
    start = (param_block - 1) * _BLOCK
    if start + 4 > len(data):
        raise _fail(path, f"truncated before the parameter section (block {param_block})")
    n_blocks, processor = data[start + 2], data[start + 3]
    if processor not in _PROCESSORS:
        raise _fail(path, f"unknown processor type {processor} (expected 84, 85 or 86)")
    endian = _PROCESSORS[processor]
    end = start + n_blocks * _BLOCK
    if n_blocks == 0:
        raise _fail(path, "the parameter section declares 0 blocks")
    if end > len(data):
        raise _fail(path, f"truncated inside the parameter section ({len(data)} of {end} bytes)")
    params = _walk_parameters(path, data, start + 4, end, endian)
    _check_required(path, params, endian)
    scale = params.get(("POINT", "SCALE"))
    scale_raw = scale.raw if scale is not None and scale.element == 4 and len(scale.raw) >= 4 else data[12:16]
    frames = params.get(("POINT", "FRAMES"))
    point_frames = _frames_value(frames.raw, frames.element, endian) if frames and not frames.dims else None
    used = params.get(("POINT", "USED"))
    point_used = _int_value(used, endian) if used is not None and not used.dims else None

    words = struct.unpack(endian + "12H", data[:24])
    layout = C3dLayout(
        points=words[1] if point_used is None else point_used,  # ezc3d reads POINT:USED points
        analog_per_frame=words[2],
        first_frame=words[3],
        last_frame=words[4],
        data_start_block=words[8],
        endian=endian,
        float_storage=_negative(scale_raw, processor),
        point_frames=point_frames,
    )
    check_agreement(path, data, params, processor, endian, end, point_frames)
    return layout


def _walk_parameters(
    path: Path, data: bytes, pos: int, end: int, endian: str
) -> dict[tuple[str, str], _Param]:
    """Check every record; return the parameters by (GROUP, NAME) upper-case."""
    group_names: dict[int, str] = {}
    by_id: list[tuple[int, str, _Param]] = []
    for _ in range(_MAX_RECORDS):
        if pos + 2 > end:
            raise _fail(path, f"parameter record at byte {pos} runs past the section end")
        n_chars, ident = struct.unpack("bb", data[pos : pos + 2])
        if n_chars == 0:
            break
        name_end = pos + 2 + abs(n_chars)
        if name_end + 2 > end:
            raise _fail(path, f"parameter record at byte {pos} runs past the section end")
        name = data[pos + 2 : name_end].decode("latin-1", "replace").upper()
        (offset,) = struct.unpack(endian + "h", data[name_end : name_end + 2])
        q = name_end + 2
        if ident < 0:
            group_names[-ident] = name
        elif ident > 0:  # a parameter (groups have negative ids)
            if q + 2 > end:
                raise _fail(path, f"parameter {name!r} runs past the section end")
            element, n_dims = struct.unpack("bB", data[q : q + 2])
            if element not in _ELEMENT_SIZES:
                raise _fail(path, f"parameter {name!r} has element size {element}")
            if n_dims > _MAX_DIMENSIONS:
                raise _fail(path, f"parameter {name!r} has {n_dims} dimensions (at most 7)")
            dims = tuple(data[q + 2 : q + 2 + n_dims])
            value_at = q + 2 + n_dims
            q = value_at + abs(element) * _Param(element, dims, b"").count
            by_id.append((ident, name, _Param(element, dims, data[value_at : min(q, end)])))
        if q + 1 > end or q + 1 + data[q] > end:
            raise _fail(path, f"parameter record {name!r} at byte {pos} runs past the section end")
        record_end = q + 1 + data[q]
        if offset == 0:
            break
        following = name_end + offset
        if following != record_end or following > end:
            raise _fail(path, f"parameter record {name!r} at byte {pos}: its contents do not fit its length")
        pos = following
    else:
        raise _fail(path, "too many parameter records")
    return {(group_names.get(ident, "?"), name): param for ident, name, param in by_id}


def _check_required(path: Path, params: dict[tuple[str, str], _Param], endian: str) -> None:
    """Parameters ezc3d needs (it crashes without them)."""
    used = params.get(("ANALOG", "USED"))
    n_analog = _int_value(used, endian) if used is not None else 0
    if n_analog:
        for name in ("SCALE", "OFFSET"):
            param = params.get(("ANALOG", name))
            if param is None or param.count < n_analog:
                raise _fail(path, f"ANALOG:{name} is missing or shorter than ANALOG:USED = {n_analog}")


def _int_value(param: _Param, endian: str) -> int:
    if param.element == 2 and len(param.raw) >= 2:
        return int(struct.unpack(endian + "H", param.raw[:2])[0])
    if param.element == 1 and param.raw:
        return int(param.raw[0])
    return 0


def _negative(raw: bytes, processor: int) -> bool:
    """The sign bit of a stored 4-byte float: IEEE little-endian, DEC (word-swapped) or big-endian."""
    sign_byte = {84: 3, 85: 1, 86: 0}[processor]
    return bool(raw[sign_byte] & 0x80)


def _frames_value(raw: bytes, element: int, endian: str) -> int | None:
    if len(raw) < abs(element):
        return None
    if element == 2:
        return int(struct.unpack(endian + "H", raw)[0])  # unsigned: files with > 32767 frames
    if element == 4 and endian == ">":
        return int(struct.unpack(">f", raw)[0])
    if element == 4:  # Intel float; DEC floats are not decoded here (rare for FRAMES)
        value = struct.unpack("<f", raw)[0]
        return int(value) if 0 < value < 1e9 else None
    return None


def check_c3d_data_size(path: Path, size: int, layout: C3dLayout, *, allow_truncated: bool = False) -> int:
    """Frames the data section holds (all declared ones unless ``allow_truncated``); checked sizes.

    A file that ends before its declared frames are complete (inside a frame or at a
    frame boundary: the ``Optotrak.c3d`` sample declares 1149 frames and holds 29) is a
    :class:`~oacdsl.errors.TruncatedRecording` naming the frames lost; with
    ``allow_truncated`` a :class:`RecordingWarning` and the number of complete frames
    (ezc3d reads those). The positions (and analog samples) those frames need are
    bounded (:func:`~oacdsl.segmentation.readers.limits.check_size`) before anything
    allocates them.
    """
    word = 4 if layout.float_storage else 2  # bytes per stored value
    frame_bytes = (4 * layout.points + layout.analog_per_frame) * word
    start = (layout.data_start_block - 1) * _BLOCK
    declared = layout.n_frames
    location = str(path)
    if declared <= 0:
        raise InvalidRecording(
            f"the recording has no frames (header frames {layout.first_frame}..{layout.last_frame})",
            location=location,
        )
    if not frame_bytes or start + declared * frame_bytes <= size:
        check_size(declared, layout.points, location, extra_values=declared * layout.analog_per_frame)
        return declared
    present, rest = divmod(max(0, size - start), frame_bytes)
    where = f"it ends at byte {size}, inside frame {present + 1}" if rest else f"it holds {present}"
    lost = f"frame {declared}" if present + 1 == declared else f"frames {present + 1}..{declared}"
    if present == 0 or not allow_truncated:
        plural = "s" * (present > 1)
        hint = f"; --allow-truncated reads the {present} complete frame{plural}" if present else ""
        raise TruncatedRecording(
            f"truncated C3D file: {where} of {declared} frames; {lost} lost{hint}",
            location=location,
            declared=declared,
            complete=present,
        )
    check_size(present, layout.points, location, extra_values=present * layout.analog_per_frame)
    warnings.warn(
        f"{path}: truncated C3D file: {lost} of {declared} lost; reading the {present} complete frames",
        RecordingWarning,
        stacklevel=3,
    )
    return int(present)
