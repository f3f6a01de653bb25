"""KIT MMM XML motions (the KIT Whole-Body Human Motion Database format).

Layout read: ``MMM/Motion[@name]/Sensors/Sensor[@type="MoCapMarker"]/Data/
Measurement[@timestep]/MarkerPosition[@name]`` with text ``"x y z"`` in
millimetres (world frame, z up). Other sensors (``ModelPose``, ``Kinematic``) are
skipped. The file is read with a streaming parser, element by element.

Groups: one per motion that carries markers, named after the motion without its
``true_`` prefix (``true_cup_small`` → ``cup_small``). The subject (a motion with
a ``Kinematic`` sensor or a ``ModelProcessorConfig``) whose name is a number is
called ``subject_<n>``. A marker name used by two motions is qualified as
``group:marker``. Motions are aligned on their timesteps; a marker missing from
a measurement is a gap. The rate is the inverse of the median timestep.
"""

from __future__ import annotations

import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np

from oacdsl.errors import RecordingError
from oacdsl.segmentation.readers._common import rate_from_times
from oacdsl.segmentation.recording import Recording

__all__ = ["read_mmm"]

_MM_TO_M = 1e-3
_TIME_DECIMALS = 6  # timesteps equal to a microsecond are the same frame


class _Motion:
    def __init__(self, name: str) -> None:
        self.name = name
        self.subject = False
        self.frames: dict[float, dict[str, tuple[float, float, float]]] = {}
        self.markers: dict[str, None] = {}  # insertion-ordered set

    @property
    def group(self) -> str:
        base = self.name[5:] if self.name.startswith("true_") and len(self.name) > 5 else self.name
        if self.subject and base[:1].isdigit():
            return f"subject_{base}"
        return base


def _parse(path: Path) -> list[_Motion]:
    location = str(path)
    motions: list[_Motion] = []
    motion: _Motion | None = None
    sensor: str | None = None
    timestep: float | None = None
    depth = 0
    try:
        for event, elem in ET.iterparse(str(path), events=("start", "end")):
            tag = elem.tag
            if event == "start":
                depth += 1
                if depth == 1 and tag != "MMM":
                    raise RecordingError(f"not an MMM motion file: the root element is <{tag}>, not <MMM>",
                                         location=location)
                if tag == "Motion" and depth == 2:
                    motion = _Motion(elem.get("name") or f"motion{len(motions) + 1}")
                    motions.append(motion)
                elif tag == "Sensor" and motion is not None:
                    sensor = elem.get("type")
                    if sensor == "Kinematic":
                        motion.subject = True
                elif tag == "ModelProcessorConfig" and motion is not None:
                    motion.subject = True
                elif tag == "Measurement" and sensor == "MoCapMarker":
                    timestep = _timestep(elem.get("timestep"), motion, location)
                continue
            depth -= 1
            if tag == "MarkerPosition" and timestep is not None and motion is not None:
                name = elem.get("name") or ""
                motion.markers.setdefault(name)
                xyz = _xyz(elem.text, name, timestep, motion, location)
                motion.frames.setdefault(timestep, {})[name] = xyz
            elif tag == "Measurement":
                timestep = None
                elem.clear()
            elif tag == "Sensor":
                sensor = None
                elem.clear()
            elif tag == "Motion":
                motion = None
                elem.clear()
    except ET.ParseError as err:
        line, column = err.position
        raise RecordingError(f"not well-formed XML at line {line}, column {column + 1}",
                             location=location) from None
    except OSError as err:
        raise RecordingError(f"cannot read: {err.strerror or err}", location=location) from None
    return motions


def _timestep(text: str | None, motion: _Motion | None, location: str) -> float:
    try:
        value = float(text or "")
    except ValueError:
        value = float("nan")
    if not np.isfinite(value):
        where = f"motion {motion.name!r}: " if motion else ""
        raise RecordingError(f"{where}Measurement timestep {text!r} is not a number", location=location)
    return round(value, _TIME_DECIMALS)


def _xyz(text: str | None, name: str, t: float, motion: _Motion, location: str) -> tuple[float, float, float]:
    parts = (text or "").split()
    try:
        if len(parts) == 3:
            return (float(parts[0]), float(parts[1]), float(parts[2]))
    except ValueError:
        pass
    raise RecordingError(
        f"motion {motion.name!r}, timestep {t:g}: MarkerPosition {name!r} is {text!r},"
        " expected three numbers (mm)",
        location=location,
    )


def read_mmm(path: str | Path) -> Recording:
    """Read the marker trajectories of an MMM XML file into a :class:`Recording`."""
    path = Path(path)
    location = str(path)
    motions = [m for m in _parse(path) if m.frames]
    if not motions:
        raise RecordingError("the MMM file has no MoCapMarker measurements (no frames)", location=location)
    times = np.array(sorted({t for m in motions for t in m.frames}), dtype=np.float64)
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
    rate = rate_from_times(times, location)
    return Recording(location, rate, times - times[0], tuple(names), positions * _MM_TO_M, groups, 0)
