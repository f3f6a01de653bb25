"""An object's geometry estimated from its marker constellation: a box or a cylinder on the table.

The markers of a tracked object sit on its surface (corners, rims, handles), so the
smallest shape that holds them is a fair first guess of the object. For each object
with at least :data:`~oacdsl.segmentation.poses.MIN_MARKERS` markers:

* the **constellation** is its markers at its reference frame (the first frame with the
  most markers seen, :func:`~oacdsl.segmentation.poses.fit_instance`), world frame, z up;
* the **table top** is the lowest marker of all objects at the recording's first frame
  (:func:`table_height`): every object stands on the table there, and one of them has a
  marker near its base — so it is high by about that marker's height (a marker's radius,
  5–10 mm, on a recording with base markers);
* the **principal horizontal axes** are the eigenvectors of the markers' horizontal
  covariance, the larger first (x), y = z × x; given the demonstrator's forward direction
  (:mod:`oacdsl.draft.facing`), x is instead the one of the two nearer it, pointing forward, so
  that the object lies on the robot's table as in front of the demonstrator;
* a **box** spans the markers' extent along those axes (length along x, width along y)
  and reaches from the table to the highest marker (height); a **cylinder** instead when
  at least 4 markers lie on one circle around a vertical axis (rms off the circle at most
  :data:`ROUND_TOLERANCE_M` or 5 % of its radius), cover at least half of it and are not
  a rectangle's corners (which lie on a circle too: two pairs of opposite points) — markers
  on a rim; its radius is the circle's;
* the **object frame** (docs/language.md, "Geometry") has its origin at the centre of the
  shape's base, on the table, z up, x along the principal axis (or the forward one); the markers
  are given in it.

A size below :data:`MIN_SIZE_M` (markers in a line or in one plane) is raised to it, and
the estimate says so. Metres throughout.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from oacdsl.errors import InvalidRecording, RecordingError
from oacdsl.segmentation.poses import MIN_MARKERS, fit_instance
from oacdsl.segmentation.recording import Recording

__all__ = ["MIN_SIZE_M", "ROUND_TOLERANCE_M", "ShapeEstimate", "estimate_shape", "table_height"]

#: The smallest size a drafted shape gets, metres (1 cm).
MIN_SIZE_M = 0.01
#: Largest rms distance of rim markers from their circle for a cylinder, metres (3 mm).
ROUND_TOLERANCE_M = 0.003
#: Fewest markers that make a circle fit meaningful (3 points always lie on one circle).
ROUND_MIN_MARKERS = 4
#: Two markers this close to diametrically opposite count as a pair of a box's corners, radians (10°).
OPPOSITE_TOLERANCE_RAD = np.deg2rad(10.0)


@dataclass(frozen=True)
class ShapeEstimate:
    """One object's drafted geometry.

    Attributes:
        instance: the marker group.
        shape: ``"box"`` or ``"cylinder"``.
        length_m, width_m: the box's extent along the principal horizontal axes (x, y);
            for a cylinder both are its diameter. Metres.
        height_m: from the table to the highest marker, metres.
        radius_m: the cylinder's radius (0 for a box), metres.
        markers_m: (k, 3) the markers seen at the reference frame, in the object frame, metres.
        reference_frame: the frame of the constellation.
        unseen: markers of the group not seen at the reference frame (left out).
        raised: the sizes raised to :data:`MIN_SIZE_M` (``"width"``, ``"height"`` …).
        round_rms_m: rms distance of the markers from the fitted circle (NaN: no fit), metres.
        facing: x is the principal axis nearer the demonstrator's forward (not the larger spread).
        x_axis_xy: the direction of the object's x axis in the world at the reference frame
            (horizontal unit vector (x, y)).
    """

    instance: str
    shape: str
    length_m: float
    width_m: float
    height_m: float
    radius_m: float
    markers_m: np.ndarray
    reference_frame: int
    unseen: int
    raised: tuple[str, ...]
    round_rms_m: float
    facing: bool = False
    x_axis_xy: tuple[float, float] = (1.0, 0.0)

    @property
    def volume_m3(self) -> float:
        """The shape's volume, cubic metres."""
        if self.shape == "cylinder":
            return float(np.pi * self.radius_m**2 * self.height_m)
        return self.length_m * self.width_m * self.height_m


def table_height(recording: Recording, objects: list[str]) -> tuple[float, str]:
    """The table top's height (metres) and the object whose marker set it: the lowest marker of
    ``objects`` at the first frame (an object without a marker there: at its first frame with one)."""
    best: tuple[float, str] | None = None
    for name in objects:
        z = recording.group_positions(name)[..., 2]  # (F, k)
        seen = np.isfinite(z).any(axis=1)
        if not seen.any():
            continue
        low = float(np.nanmin(z[int(np.argmax(seen))]))
        if best is None or low < best[0]:
            best = (low, name)
    if best is None:
        raise InvalidRecording("no object marker is ever seen: the table height cannot be estimated",
                             location=recording.source)
    return best


def _principal_axes(xy: np.ndarray) -> np.ndarray:
    """(2, 2) rows x, y: the horizontal principal axes (x the larger spread, pointing to +x world)."""
    centred = xy - xy.mean(axis=0)
    _, vectors = np.linalg.eigh(centred.T @ centred)
    x = vectors[:, 1]
    if abs(x[0]) < 1e-9:
        x = x if x[1] > 0 else -x
    elif x[0] < 0:
        x = -x
    return np.array([x, [-x[1], x[0]]])


def _facing(axes: np.ndarray, forward_xy: np.ndarray) -> np.ndarray:
    """(2, 2) rows x, y: of the principal ``axes``, the one nearer ``forward_xy`` as x, pointing
    along it, and y = z × x."""
    along = axes @ np.asarray(forward_xy, float)
    i = int(np.argmax(np.abs(along)))
    x = axes[i] * (1.0 if along[i] >= 0 else -1.0)
    return np.array([x, [-x[1], x[0]]])


def _circle(xy: np.ndarray) -> tuple[np.ndarray, float, float, float]:
    """Least-squares circle through horizontal points (Kåsa): centre, radius, rms off it, metres,
    and the largest angular gap between neighbouring points around it, radians."""
    a = np.column_stack([2 * xy, np.ones(len(xy))])
    b = (xy**2).sum(axis=1)
    (cx, cy, c), *_ = np.linalg.lstsq(a, b, rcond=None)
    centre = np.array([cx, cy])
    radius = float(np.sqrt(max(c + cx**2 + cy**2, 0.0)))
    off = np.linalg.norm(xy - centre, axis=1) - radius
    angles = np.sort(np.arctan2(xy[:, 1] - cy, xy[:, 0] - cx))
    gaps = np.diff(np.append(angles, angles[0] + 2 * np.pi))
    return centre, radius, float(np.sqrt(np.mean(off**2))), float(gaps.max())


def _opposite_pairs(xy: np.ndarray, centre: np.ndarray) -> int:
    """How many disjoint pairs of points lie opposite each other about ``centre`` (within
    :data:`OPPOSITE_TOLERANCE_RAD`): a box's corners form two such pairs, rim markers rarely do."""
    angles = np.arctan2(xy[:, 1] - centre[1], xy[:, 0] - centre[0])
    free, pairs = set(range(len(xy))), 0
    for i in range(len(xy)):
        for j in sorted(free - {i}):
            off = abs((angles[j] - angles[i]) % (2 * np.pi) - np.pi)
            if i in free and off <= OPPOSITE_TOLERANCE_RAD:
                free -= {i, j}
                pairs += 1
    return pairs


def estimate_shape(recording: Recording, instance: str, table_z_m: float,
                   forward_xy: np.ndarray | None = None) -> ShapeEstimate:
    """The box or cylinder of ``instance`` standing on a table at ``table_z_m`` (module doc);
    ``forward_xy``: the demonstrator's forward direction, which the object's x axis then takes."""
    poses = fit_instance(recording, instance)
    ref = poses.reference_frame
    pts = poses.constellation_m + poses.T_world_object[ref, :3, 3]  # world, at the reference frame
    seen = np.isfinite(pts).all(axis=1)
    pts = pts[seen]
    if len(pts) < MIN_MARKERS:  # fit_instance guarantees it; kept for a clear message
        raise RecordingError(f"instance {instance!r}: fewer than {MIN_MARKERS} markers seen at once",
                             location=recording.source)
    xy = pts[:, :2]
    axes = _principal_axes(xy)
    if forward_xy is not None:
        axes = _facing(axes, forward_xy)
    raised: list[str] = []

    def at_least(value: float, what: str) -> float:
        if value < MIN_SIZE_M:
            raised.append(what)
            return MIN_SIZE_M
        return value

    height = at_least(float(pts[:, 2].max()) - table_z_m, "height")
    shape, radius, rms = "box", 0.0, float("nan")
    if len(pts) >= ROUND_MIN_MARKERS:
        centre, r, rms, gap = _circle(xy)
        if (r < 0.5 and rms <= max(ROUND_TOLERANCE_M, 0.05 * r) and gap <= np.pi + 1e-9
                and _opposite_pairs(xy, centre) < 2):
            shape, radius = "cylinder", at_least(r, "radius")
    if shape == "cylinder":
        origin_xy = centre
        length = width = 2 * radius
    else:
        local = (xy - xy.mean(axis=0)) @ axes.T
        low, high = local.min(axis=0), local.max(axis=0)
        origin_xy = xy.mean(axis=0) + ((low + high) / 2) @ axes
        length = at_least(float(high[0] - low[0]), "length")
        width = at_least(float(high[1] - low[1]), "width")
    rot = np.eye(3)
    rot[:2, :2] = axes  # rows: the object's x and y in world coordinates
    origin = np.array([origin_xy[0], origin_xy[1], table_z_m])
    markers = (pts - origin) @ rot.T
    return ShapeEstimate(instance, shape, length, width, height, radius, markers, ref,
                         int((~seen).sum()), tuple(raised), rms, forward_xy is not None,
                         (float(axes[0, 0]), float(axes[0, 1])))
