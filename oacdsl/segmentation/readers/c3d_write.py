"""Writing a C3D file directly with numpy (no C3D library).

The layout follows the C3D specification (c3d.org), Intel processor, float storage
(``POINT:SCALE`` −1), millimetres: block 1 the header (16-bit words), block 2 on
the parameter section, then the point data, frame after frame, four float32 per
marker (x, y, z and a residual word: 0 for a valid point, −1 for a gap, whose
coordinates are stored as 0). The parameters are those ezc3d writes for the same
recording (``POINT`` with ``LABELS2``, ``LABELS3``, … beyond 255 markers, an empty
``ANALOG`` and ``FORCE_PLATFORM`` group, ``SUBJECTS`` naming the groups), so that the
file reads back the same through ezc3d; ezc3d's own ``ROTATION`` and ``EZC3D``
groups are left out. The point data is built as one float32 array and written in
one call: writing through ezc3d cost seconds for a robot recording (issue 18).
"""

from __future__ import annotations

import struct
from collections.abc import Sequence
from pathlib import Path

import numpy as np

__all__ = ["c3d_bytes_head", "write_c3d_points"]

_BLOCK = 512  # bytes
_KEY = 0x50
_INTEL = 84
_CHUNK = 255  # labels per POINT:LABELS parameter
_UINT16_MAX = 65535

_Value = tuple[int, tuple[int, ...], bytes]  # element type (-1 char, 2 int16, 4 float32), dims, data


def _int(*values: int) -> _Value:
    dims = () if len(values) == 1 else (len(values),)
    return 2, dims, struct.pack(f"<{len(values)}h", *values)


def _float(*values: float) -> _Value:
    dims = () if len(values) == 1 else (len(values),)
    return 4, dims, struct.pack(f"<{len(values)}f", *values)


def _empty(element: int, *dims: int) -> _Value:
    return element, dims, b""


def _text(text: str) -> _Value:
    raw = text.encode("utf-8")
    return -1, (len(raw),), raw


def _texts(texts: Sequence[str]) -> _Value:
    raw = [t.encode("utf-8") for t in texts]
    width = max((len(r) for r in raw), default=0)
    return -1, (width, len(raw)), b"".join(r.ljust(width, b" ") for r in raw)


def _record(name: str, group_id: int, value: _Value, locked: bool) -> bytes:
    element, dims, data = value
    if len(dims) > 7 or any(d > 255 for d in dims):
        raise ValueError(f"parameter {name} has dimensions {dims} (at most 7, each at most 255)")
    body = struct.pack("<bB", element, len(dims)) + bytes(dims) + data + b"\x00"  # no description
    label = name.encode("ascii")
    length = -len(label) if locked else len(label)
    return struct.pack("<bb", length, group_id) + label + struct.pack("<h", 2 + len(body)) + body


def _group(name: str, group_id: int) -> bytes:
    label = name.encode("ascii")
    return struct.pack("<bb", len(label), -group_id) + label + struct.pack("<h", 3) + b"\x00"


def _point_params(labels: Sequence[str], rate_hz: float, frames: int, data_start: int) -> bytes:
    chunks = [labels[i:i + _CHUNK] for i in range(0, len(labels), _CHUNK)] or [[]]
    if frames > _UINT16_MAX:  # ezc3d wrote such a file, which then read back as 65535 frames
        raise ValueError(f"{frames} frames (POINT:FRAMES holds at most {_UINT16_MAX})")
    frames_value = 2, (), struct.pack("<H", frames)  # unsigned past 32767, as ezc3d writes it
    out = [_group("POINT", 1),
           _record("USED", 1, _int(len(labels)), True),
           _record("LABELS", 1, _texts(chunks[0]), False),
           _record("DESCRIPTIONS", 1, _empty(-1, 0, len(chunks[0])), False),
           _record("SCALE", 1, _float(-1.0), True),
           _record("UNITS", 1, _text("mm"), False),
           _record("RATE", 1, _float(rate_hz), True),
           _record("DATA_START", 1, _int(data_start), True),
           _record("FRAMES", 1, frames_value, True)]
    for k, chunk in enumerate(chunks[1:], start=2):
        out += [_record(f"LABELS{k}", 1, _texts(chunk), False),
                _record(f"DESCRIPTIONS{k}", 1, _empty(-1, 0, len(chunk)), False),
                _record(f"UNITS{k}", 1, _texts(["mm"] * len(chunk)), False)]
    return b"".join(out)


def _other_params(groups: Sequence[str]) -> bytes:
    out = [_group("ANALOG", 2),
           _record("USED", 2, _int(0), True),
           _record("LABELS", 2, _empty(-1, 0, 0), False),
           _record("DESCRIPTIONS", 2, _empty(-1, 0, 0), False),
           _record("GEN_SCALE", 2, _float(1.0), False),
           _record("SCALE", 2, _empty(4, 0), False),
           _record("OFFSET", 2, _empty(2, 0), False),
           _record("UNITS", 2, _empty(-1, 0, 0), False),
           _record("RATE", 2, _float(0.0), True),
           _record("FORMAT", 2, _empty(-1, 0, 0), False),
           _record("BITS", 2, _empty(2, 0), False),
           _group("FORCE_PLATFORM", 3),
           _record("USED", 3, _int(0), False),
           _record("TYPE", 3, _empty(2, 0), False),
           _record("ZERO", 3, _int(1, 0), False),
           _record("CORNERS", 3, _empty(4, 0), False),
           _record("ORIGIN", 3, _empty(4, 0), False),
           _record("CHANNEL", 3, _empty(2, 0), False),
           _record("CAL_MATRIX", 3, _empty(4, 0), False)]
    if groups:
        out += [_group("SUBJECTS", 4),
                _record("USED", 4, _int(len(groups)), False),
                _record("USES_PREFIXES", 4, _int(1), False),
                _record("NAMES", 4, _texts(groups), False),
                _record("LABEL_PREFIXES", 4, _texts([f"{g}:" for g in groups]), False)]
    return b"".join(out)


def c3d_bytes_head(labels: Sequence[str], groups: Sequence[str], rate_hz: float, frames: int,
                   first_frame: int) -> bytes:
    """The header and the parameter section (whole 512-byte blocks) of a float C3D in mm."""
    rest = _other_params(groups)
    size = 4 + len(_point_params(labels, rate_hz, frames, 0)) + len(rest)
    blocks = -(-size // _BLOCK)
    if blocks > 255:
        raise ValueError(f"the parameters take {blocks} blocks (at most 255: too many markers)")
    point = _point_params(labels, rate_hz, frames, 2 + blocks)
    params = struct.pack("<BBBB", 1, _KEY, blocks, _INTEL) + point
    params = (params + rest).ljust(blocks * _BLOCK, b"\x00")
    first = first_frame + 1  # the header's frame numbers are 1-based
    header = np.zeros(_BLOCK // 2, dtype="<u2")
    header[1], header[3], header[4], header[5] = len(labels), first, min(first + frames - 1, _UINT16_MAX), 10
    header[6:8] = np.frombuffer(struct.pack("<f", -1.0), dtype="<u2")
    header[8] = 2 + blocks  # the data's first block
    header[10:12] = np.frombuffer(struct.pack("<f", rate_hz), dtype="<u2")
    header[149] = 0x3039  # events with 4-character labels
    head = bytearray(header.tobytes())
    head[0], head[1] = 2, _KEY  # the parameter section's block, the key
    return bytes(head) + params


def write_c3d_points(target: Path, labels: Sequence[str], groups: Sequence[str], rate_hz: float,
                     first_frame: int, positions_m: np.ndarray) -> None:
    """Write ``positions_m`` (frames × markers × 3, metres, NaN gaps) to ``target`` as a C3D.

    ``labels`` one a marker (``group:marker``), ``groups`` the subjects' names."""
    n_frames, n_markers = positions_m.shape[:2]
    data = np.zeros((n_frames, n_markers, 4), dtype="<f4")
    np.multiply(positions_m, 1000.0, out=data[..., :3], casting="unsafe")  # metres → mm
    data[~np.isfinite(positions_m).all(axis=-1)] = (0.0, 0.0, 0.0, -1.0)
    with open(target, "wb") as out:
        out.write(c3d_bytes_head(labels, groups, float(rate_hz), n_frames, first_frame))
        data.tofile(out)
        out.write(b"\x00" * (-data.nbytes % _BLOCK))  # the last block whole, as ezc3d writes it
