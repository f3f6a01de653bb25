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
"""

from __future__ import annotations

import xml.etree.ElementTree as ET
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from oacdsl.errors import RecordingError

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
    return np.stack([
        np.stack([cz * cy, cz * sy * sx - sz * cx, cz * sy * cx + sz * sx], axis=-1),
        np.stack([sz * cy, sz * sy * sx + cz * cx, sz * sy * cx - cz * sx], axis=-1),
        np.stack([-sy, cy * sx, cy * cx], axis=-1),
    ], axis=-2)


def _numbers(text: str | None, what: str, motion: str, t: str | None, location: str) -> list[float]:
    parts = (text or "").split()
    try:
        if len(parts) == 3:
            return [float(p) for p in parts]
    except ValueError:
        pass
    raise RecordingError(f"motion {motion!r}, timestep {t}: {what} is {text!r}, expected three numbers",
                         location=location)


def read_model_poses(path: str | Path) -> dict[str, ModelPoses]:
    """Every motion's ``ModelPose`` in an MMM file, by group name (motions without one are left out)."""
    location = str(path)
    rows: dict[str, list[tuple[float, list[float], list[float]]]] = {}
    subjects: set[str] = set()
    motion: str | None = None
    sensor: str | None = None
    try:
        for event, elem in ET.iterparse(str(path), events=("start", "end")):
            if event == "start":
                if elem.tag == "Motion":
                    motion = elem.get("name") or f"motion{len(rows) + 1}"
                elif elem.tag == "Sensor":
                    sensor = elem.get("type")
                    if sensor == "Kinematic" and motion:
                        subjects.add(motion)
                continue
            if elem.tag == "Measurement" and sensor == "ModelPose" and motion is not None:
                t = elem.get("timestep")
                try:
                    time = float(t or "")
                except ValueError:
                    raise RecordingError(f"motion {motion!r}: ModelPose timestep {t!r} is not a number",
                                         location=location) from None
                pos = _numbers(elem.findtext("RootPosition"), "RootPosition", motion, t, location)
                rot = _numbers(elem.findtext("RootRotation"), "RootRotation", motion, t, location)
                rows.setdefault(motion, []).append((time, pos, rot))
                elem.clear()
            elif elem.tag == "Sensor":
                sensor = None
            elif elem.tag == "Motion":
                motion = None
                elem.clear()
    except ET.ParseError as err:
        line, column = err.position
        raise RecordingError(f"not well-formed XML at line {line}, column {column + 1}",
                             location=location) from None
    except OSError as err:
        raise RecordingError(f"cannot read: {err.strerror or err}", location=location) from None
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
