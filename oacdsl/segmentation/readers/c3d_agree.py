"""A C3D file's header and its parameters must agree (checked before ezc3d reads the data).

The C3D header repeats what the ``POINT`` and ``ANALOG`` parameters say: points per
frame (``POINT:USED``), frames (``POINT:FRAMES``), where the data starts
(``POINT:DATA_START``), the scale (``POINT:SCALE``) and the analog values per frame
(``ANALOG:USED`` × ``ANALOG:RATE`` / ``POINT:RATE``). ezc3d takes some of these from the
header and some from the parameters; when the two disagree it reads a frame size that
is not the file's and returns wrong coordinates without complaint (every marker at
one point, 100 % gaps, one frame of forty). Such a file is refused here, naming the
parameter and what the header says (:class:`~oacdsl.errors.InvalidRecording`, exit 1).

Allowed: a header that counts 0 points (the parameter is read), and a header whose
last frame is saturated at 65535 (a file of more frames than a 16-bit word holds).
"""

from __future__ import annotations

import math
import struct
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path

from oacdsl.errors import InvalidRecording

__all__ = ["Param", "check_agreement", "param_float", "param_int"]

_BLOCK = 512  # bytes
_SATURATED = 0xFFFF  # a 16-bit header word that cannot hold the frame count


@dataclass(frozen=True)
class Param:
    """One parameter record as stored: element size, dimensions, raw value bytes."""

    element: int  # -1 char, 1 byte, 2 int16, 4 float
    dims: tuple[int, ...]
    raw: bytes

    @property
    def count(self) -> int:
        n = 1
        for d in self.dims:
            n *= d
        return n


def param_float(raw: bytes, processor: int) -> float:
    """A stored 4-byte float: Intel (84), DEC (85: words swapped, exponent bias 2 more) or MIPS (86)."""
    if processor == 85:
        return struct.unpack("<f", raw[2:4] + raw[0:2])[0] / 4.0
    return struct.unpack((">" if processor == 86 else "<") + "f", raw[:4])[0]


def param_int(param: Param | None, endian: str) -> int | None:
    """An unsigned integer parameter (int16 or byte), or ``None`` when absent or not one."""
    if param is None or param.dims:
        return None
    if param.element == 2 and len(param.raw) >= 2:
        return int(struct.unpack(endian + "H", param.raw[:2])[0])
    if param.element == 1 and param.raw:
        return int(param.raw[0])
    return None


def _scalar_float(param: Param | None, processor: int) -> float | None:
    if param is None or param.element != 4 or len(param.raw) < 4:
        return None
    return param_float(param.raw, processor)


def _fail(path: Path, what: str) -> InvalidRecording:
    return InvalidRecording(f"C3D header and parameters disagree: {what}", location=str(path))


def check_agreement(
    path: Path,
    data: bytes,
    params: Mapping[tuple[str, str], Param],
    processor: int,
    endian: str,
    parameters_end: int,
    point_frames: int | None,
) -> None:
    """Refuse a header that contradicts its parameters (see the module docstring).

    ``data`` is the file's bytes, ``parameters_end`` the byte where the parameter
    section ends, ``point_frames`` the decoded ``POINT:FRAMES`` (``None`` when absent).
    """
    words: Sequence[int] = struct.unpack(endian + "12H", data[:24])
    _check_data_start(path, words[8], params, endian, parameters_end)
    used = param_int(params.get(("POINT", "USED")), endian)
    if used is not None and words[1] and used != words[1]:
        raise _fail(path, f"POINT:USED is {used} but the header (word 2) says {words[1]} points per frame")
    first, last = words[3], words[4]
    header_frames = last - first + 1
    if point_frames is not None and point_frames != header_frames and last != _SATURATED:
        raise _fail(
            path,
            f"POINT:FRAMES is {point_frames} but the header says frames {first}..{last}"
            f" ({max(header_frames, 0)} frames)",
        )
    scale_param = _scalar_float(params.get(("POINT", "SCALE")), processor)
    scale = scale_param if scale_param is not None else param_float(data[12:16], processor)
    name = "POINT:SCALE" if scale_param is not None else "the header's scale (words 7-8)"
    if not math.isfinite(scale):
        raise InvalidRecording(
            f"{name} is {scale:g}; it must be a finite number (negative: float storage)", location=str(path)
        )
    if scale == 0 and not math.copysign(1.0, scale) < 0:
        raise InvalidRecording(
            f"{name} is 0: integer coordinates scaled by 0 would all read as 0 (gaps)", location=str(path)
        )
    _check_analog(path, words, params, processor, endian, param_float(data[20:24], processor))


def _check_data_start(
    path: Path, start_block: int, params: Mapping[tuple[str, str], Param], endian: str, parameters_end: int
) -> None:
    first_free = -(-parameters_end // _BLOCK) + 1  # 1-based block after the parameters
    if start_block < first_free:
        raise InvalidRecording(
            f"not a valid C3D file: the header (word 9) puts the data at block {start_block}, inside the"
            f" header or the parameters (the data may start at block {first_free})",
            location=str(path),
        )
    declared = param_int(params.get(("POINT", "DATA_START")), endian)
    if declared is not None and declared != start_block:
        raise _fail(path, f"POINT:DATA_START is {declared} but the header (word 9) says block {start_block}")


def _check_analog(
    path: Path,
    words: Sequence[int],
    params: Mapping[tuple[str, str], Param],
    processor: int,
    endian: str,
    header_rate: float,
) -> None:
    """ANALOG:USED × ANALOG:RATE / POINT:RATE analog values per frame, as the header (word 3) says."""
    channels = param_int(params.get(("ANALOG", "USED")), endian)
    analog_rate = _scalar_float(params.get(("ANALOG", "RATE")), processor)
    point_rate = _scalar_float(params.get(("POINT", "RATE")), processor)
    if point_rate is None:
        point_rate = header_rate
    if channels is None or analog_rate is None or not (math.isfinite(point_rate) and point_rate > 0):
        return  # nothing to compare (a bad POINT:RATE is refused with the frame rate)
    if channels == 0 and words[2] == 0:
        return
    per_frame = channels * analog_rate / point_rate if math.isfinite(analog_rate) else math.nan
    if per_frame != words[2]:
        raise _fail(
            path,
            f"ANALOG:RATE is {analog_rate:g} Hz: ANALOG:USED = {channels} channels at that rate and"
            f" POINT:RATE {point_rate:g} Hz make {per_frame:g} analog values per frame, the header"
            f" (word 3) says {words[2]}",
        )
