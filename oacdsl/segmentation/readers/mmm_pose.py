"""The ``ModelPose`` sensor of KIT MMM XML motions: each motion's root pose over time.

Layout read: ``MMM/Motion[@name]/Sensors/Sensor[@type="ModelPose"]/Data/
Measurement[@timestep]`` with ``RootPosition`` (``"x y z"``, millimetres, world
frame) and ``RootRotation`` (``"rx ry rz"``, radians: roll, pitch, yaw about the
fixed world axes, ``R = Rz(rz) · Ry(ry) · Rx(rx)``). That convention is the one
under which a KIT object's markers stay put in its model frame (on the Stir and
Pour clips their model-frame coordinates vary by ≤ 2.5 mm; the intrinsic order
``Rx · Ry · Rz`` gives up to 93 mm). Motions are named as
:func:`~oacdsl.segmentation.readers.mmm.read_mmm` names their marker groups
(``true_cup_small`` → ``cup_small``), so the poses line up with the instances.
Read like the marker reader: expat in chunks, a document type declaration refused,
values checked (finite; positions within the readers' coordinate limit).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from oacdsl.segmentation.readers.limits import MAX_COORDINATE_M, clip
from oacdsl.segmentation.readers.safexml import SafeXmlReader

__all__ = ["ModelPoses", "read_model_poses", "rpy_matrix"]

_MM_TO_M = 1e-3


@dataclass(frozen=True)
class ModelPoses:
    """One motion's ``ModelPose``: ``times_s`` (F,) seconds from the file's first
    timestep, ``T_world_model`` (F, 4, 4), metres."""

    name: str
    times_s: np.ndarray
    T_world_model: np.ndarray


def rpy_matrix(rpy_rad: np.ndarray) -> np.ndarray:
    """Rotation matrices ``Rz(z) · Ry(y) · Rx(x)`` for (..., 3) angles in radians."""
    x, y, z = (np.asarray(rpy_rad, dtype=np.float64)[..., i] for i in range(3))
    cx, sx, cy, sy, cz, sz = np.cos(x), np.sin(x), np.cos(y), np.sin(y), np.cos(z), np.sin(z)
    return np.stack(
        [
            np.stack([cz * cy, cz * sy * sx - sz * cx, cz * sy * cx + sz * sx], axis=-1),
            np.stack([sz * cy, sz * sy * sx + cz * cx, sz * sy * cx - cz * sx], axis=-1),
            np.stack([-sy, cy * sx, cy * cx], axis=-1),
        ],
        axis=-2,
    )


class _PoseParser(SafeXmlReader):
    """Expat callbacks that collect each motion's ``ModelPose`` measurements.

    As in :mod:`~oacdsl.segmentation.readers.mmm`, a document type declaration is
    refused, so no entity is ever expanded.
    """

    def __init__(self, location: str) -> None:
        super().__init__(location)
        self.rows: dict[str, list[tuple[float, list[float], list[float]]]] = {}
        self.subjects: set[str] = set()
        self.motion: str | None = None
        self.sensor: str | None = None
        self.timestep: str | None = None
        self.field: str | None = None
        self.values: dict[str, str] = {}
        self.text: list[str] = []

    def start(self, tag: str, attrs: dict[str, str]) -> None:
        if tag == "Motion":
            self.motion = attrs.get("name") or f"motion{len(self.rows) + 1}"
        elif tag == "Sensor":
            self.sensor = attrs.get("type")
            if self.sensor == "Kinematic" and self.motion:
                self.subjects.add(self.motion)
        elif tag == "Measurement" and self.sensor == "ModelPose":
            self.timestep, self.values = attrs.get("timestep"), {}
        elif tag in ("RootPosition", "RootRotation") and self.timestep is not None:
            self.field, self.text = tag, []

    def characters(self, data: str) -> None:
        if self.field is not None:
            self.text.append(data)

    def end(self, tag: str) -> None:
        if tag == self.field:
            self.values[tag] = "".join(self.text)
            self.field = None
        elif tag == "Measurement" and self.timestep is not None and self.motion is not None:
            self.rows.setdefault(self.motion, []).append(self.measurement())
            self.timestep = None
        elif tag == "Sensor":
            self.sensor = None
        elif tag == "Motion":
            self.motion = None

    def measurement(self) -> tuple[float, list[float], list[float]]:
        where = f"motion {clip(self.motion or '')}, timestep {clip(self.timestep or '', quoted=False)}"
        try:
            time = float(self.timestep or "")
        except ValueError:
            time = math.nan
        if not math.isfinite(time):
            where = f"motion {clip(self.motion or '')}"
            raise self.fail(f"{where}: ModelPose timestep {clip(self.timestep or '')} is not a number")
        out = []
        for what, limit in (("RootPosition", MAX_COORDINATE_M / _MM_TO_M), ("RootRotation", 1e3)):
            text = self.values.get(what)
            try:
                numbers = [float(v) for v in (text or "").split()]
            except ValueError:
                numbers = []
            if len(numbers) != 3 or not all(abs(v) <= limit for v in numbers):
                raise self.fail(f"{where}: {what} is {clip(text or '')}, expected three finite numbers")
            out.append(numbers)
        return time, out[0], out[1]


def read_model_poses(path: str | Path) -> dict[str, ModelPoses]:
    """Every motion's ``ModelPose`` in an MMM file, by group name (motions without one are left out)."""
    location = str(path)
    parser = _PoseParser(location)
    parser.feed_file(Path(path))
    rows, subjects = parser.rows, parser.subjects
    if not rows:
        return {}
    t0 = min(r[0] for measurements in rows.values() for r in measurements)
    out: dict[str, ModelPoses] = {}
    for name, measurements in rows.items():
        measurements.sort(key=lambda r: r[0])
        times = np.array([r[0] for r in measurements]) - t0
        T = np.zeros((len(measurements), 4, 4))
        T[:, :3, :3] = rpy_matrix(np.array([r[2] for r in measurements]))
        T[:, :3, 3] = np.array([r[1] for r in measurements]) * _MM_TO_M
        T[:, 3, 3] = 1.0
        base = name[5:] if name.startswith("true_") and len(name) > 5 else name
        group = f"subject_{base}" if name in subjects and base[:1].isdigit() else base
        out[group] = ModelPoses(group, times, T)
    return out
