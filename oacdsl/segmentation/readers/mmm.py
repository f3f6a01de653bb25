"""KIT MMM XML motions (the KIT Whole-Body Human Motion Database format).

Layout read: ``MMM/Motion[@name]/Sensors/Sensor[@type="MoCapMarker"]/Data/
Measurement[@timestep]/MarkerPosition[@name]`` with text ``"x y z"`` in
millimetres (world frame, z up). Other sensors (``ModelPose``, ``Kinematic``) are
skipped. The file is read with a streaming parser (expat, in chunks), element by
element; a document type declaration is refused, so no entity is ever expanded
(billion laughs, external entities).

Groups: one per motion that carries markers, named after the motion without its
``true_`` prefix (``true_cup_small`` → ``cup_small``). The subject (a motion with
a ``Kinematic`` sensor or a ``ModelProcessorConfig``) whose name is a number is
called ``subject_<n>``. A marker name used by two motions is qualified as
``group:marker``. Motions are aligned on their timesteps; a marker missing from
a measurement is a gap. The rate is the inverse of the median timestep.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from oacdsl.errors import InvalidRecording
from oacdsl.segmentation.readers._common import rate_from_times
from oacdsl.segmentation.readers.limits import MAX_COORDINATE_M, MAX_POSITION_BYTES, check_size, clip
from oacdsl.segmentation.readers.safexml import SafeXmlReader
from oacdsl.segmentation.recording import Recording

__all__ = ["read_mmm"]

_MM_TO_M = 1e-3
_TIME_DECIMALS = 6  # timesteps equal to a microsecond are the same frame
_MAX_POINTS = MAX_POSITION_BYTES // 24  # marker positions (3 float64 each) the file may hold


class _Motion:
    def __init__(self, name: str) -> None:
        self.name = name
        self.subject = False
        self.frames: dict[float, dict[str, tuple[float, float, float]]] = {}
        self.markers: dict[str, None] = {}  # insertion-ordered set
        self.lines: dict[float, int] = {}  # timestep → line of its Measurement, in the current sensor

    @property
    def group(self) -> str:
        base = self.name[5:] if self.name.startswith("true_") and len(self.name) > 5 else self.name
        if self.subject and base[:1].isdigit():
            return f"subject_{base}"
        return base


class _Parser(SafeXmlReader):
    """Expat callbacks that collect the motions' marker positions, element by element.

    A document type declaration is refused (an MMM file has none): no entity can be
    declared, so neither an entity bomb nor an external entity can be expanded.
    """

    def __init__(self, location: str) -> None:
        super().__init__(location)
        self.motions: list[_Motion] = []
        self.motion: _Motion | None = None
        self.sensor: str | None = None
        self.timestep: float | None = None
        self.marker: str | None = None
        self.text: list[str] = []
        self.depth = 0
        self.points = 0

    def start(self, tag: str, attrs: dict[str, str]) -> None:
        self.depth += 1
        if self.depth == 1 and tag != "MMM":
            raise InvalidRecording(
                f"not an MMM motion file: the root element is <{clip(tag, quoted=False)}>, not <MMM>",
                location=self.location,
            )
        if tag == "Motion" and self.depth == 2:
            self.motion = _Motion(attrs.get("name") or f"motion{len(self.motions) + 1}")
            self.motions.append(self.motion)
        elif tag == "Sensor" and self.motion is not None:
            self.sensor = attrs.get("type")
            self.motion.lines = {}
            if self.sensor == "Kinematic":
                self.motion.subject = True
        elif tag == "ModelProcessorConfig" and self.motion is not None:
            self.motion.subject = True
        elif tag == "Measurement" and self.sensor == "MoCapMarker" and self.motion is not None:
            self.timestep = self.parse_timestep(attrs.get("timestep"))
            if self.timestep in self.motion.lines:  # one would overwrite the other's markers
                raise self.fail(
                    f"motion {clip(self.motion.name)}: Measurement timestep {self.timestep:g} repeats the"
                    f" one at line {self.motion.lines[self.timestep]} (timesteps within 1 µs are one frame)"
                )
            self.motion.lines[self.timestep] = self.expat.CurrentLineNumber
        elif tag == "MarkerPosition" and self.timestep is not None and self.motion is not None:
            self.marker = attrs.get("name") or ""
            self.text = []

    def characters(self, data: str) -> None:
        if self.marker is not None:
            self.text.append(data)

    def end(self, tag: str) -> None:
        self.depth -= 1
        if tag == "MarkerPosition" and self.marker is not None and self.motion is not None:
            name, motion, t = self.marker, self.motion, self.timestep or 0.0
            motion.markers.setdefault(name)
            frame = motion.frames.setdefault(t, {})
            if name in frame:
                where = f"motion {clip(motion.name)}, timestep {t:g}"
                raise self.fail(f"{where}: MarkerPosition {clip(name)} twice")
            frame[name] = self.parse_xyz("".join(self.text), name, t, motion)
            self.marker = None
            self.points += 1
            if self.points > _MAX_POINTS:
                check_size(self.points, 1, self.location)  # raises: more positions than the limit
        elif tag == "Measurement":
            self.timestep = None
        elif tag == "Sensor":
            self.sensor = None
        elif tag == "Motion":
            self.motion = None

    def parse_timestep(self, text: str | None) -> float:
        try:
            value = float(text or "")
        except ValueError:
            value = float("nan")
        if not math.isfinite(value):
            where = f"motion {clip(self.motion.name)}: " if self.motion else ""
            raise self.fail(f"{where}Measurement timestep {clip(text or '')} is not a number")
        return round(value, _TIME_DECIMALS)

    def parse_xyz(self, text: str, name: str, t: float, motion: _Motion) -> tuple[float, float, float]:
        where = f"motion {clip(motion.name)}, timestep {t:g}: MarkerPosition {clip(name)}"
        parts = text.split()
        try:
            x, y, z = (float(v) for v in parts)
        except ValueError:
            raise self.fail(f"{where} is {clip(text)}, expected three numbers (mm)") from None
        for axis, v in zip("xyz", (x, y, z), strict=True):
            if not (abs(v) * _MM_TO_M <= MAX_COORDINATE_M or math.isnan(v)):
                raise self.fail(
                    f"{where} has {axis} = {v:g} mm; a coordinate must be finite and within"
                    f" ±{MAX_COORDINATE_M:g} m (NaN is a gap)"
                )
        return (x, y, z)


def _parse(path: Path) -> list[_Motion]:
    """The motions of the MMM file ``path``, read in chunks (bounded memory per chunk)."""
    parser = _Parser(str(path))
    parser.feed_file(path)
    return parser.motions


def read_mmm(path: str | Path) -> Recording:
    """Read the marker trajectories of an MMM XML file into a :class:`Recording` (limits.py checked)."""
    path = Path(path)
    location = str(path)
    motions = [m for m in _parse(path) if m.frames]
    if not motions:
        raise InvalidRecording("the MMM file has no MoCapMarker measurements (no frames)", location=location)
    times = np.array(sorted({t for m in motions for t in m.frames}), dtype=np.float64)
    check_size(len(times), sum(len(m.markers) for m in motions), location)
    row = {t: i for i, t in enumerate(times.tolist())}
    seen: dict[str, int] = {}
    for m in motions:
        for name in m.markers:
            seen[name] = seen.get(name, 0) + 1
    names: list[str] = []
    groups: dict[str, tuple[int, ...]] = {}
    positions = np.full((len(times), sum(len(m.markers) for m in motions), 3), np.nan)
    for m in motions:
        start = len(names)
        names += [f"{m.group}:{n}" if seen[n] > 1 else n for n in m.markers]
        column = {n: start + k for k, n in enumerate(m.markers)}
        for t, markers in m.frames.items():
            for n, xyz in markers.items():
                positions[row[t], column[n]] = xyz
        group = m.group
        while group in groups:
            group += "_"
        groups[group] = tuple(range(start, len(names)))
    rate = rate_from_times(times, location, lambda i: f"timestep {times[i]:g}")
    return Recording(location, rate, times - times[0], tuple(names), positions * _MM_TO_M, groups, 0)
