"""Shapes posed in a recording, and the gap between two instances' surfaces frame by frame.

**Objects.** The rigid fit of an instance's markers (:func:`~oacdsl.segmentation.poses.fit_instance`:
its constellation at the reference frame, fitted in every frame) is tied to the class's object
frame by the declared ``markers`` of its :class:`~oacdsl.segmentation.shapes.ShapeModel`: the
rigid transform that maps the recorded constellation best onto the declared points, over every
assignment of recorded to declared markers (the library does not say which is which; at most
:data:`MAX_PERMUTED` markers, more are taken in order). The shape is used only when that fit is
good (:data:`MAX_FIT_FRACTION` of the shape's largest extent): the declared markers must describe
the recorded object. Two errors remain, which a contact decision allows for: the **misfit** (RMS
distance of the declared from the recorded markers: how far the model may be off the object) and
the **noise** (the rigid fit's median residual over frames: marker jitter, a marker slipping).

**Hands** (:class:`HandVolume`): a hand is not rigid and has no shape in the library; its volume
is every point within ``radius_m`` of its markers and of the segments between them (palm and
fingers: the markers sit on the back of the hand and on the fingers), ``radius_m`` =
:data:`HAND_RADIUS_FRACTION` of the hand's size (its largest marker distance).

**Gaps** (:func:`surface_gaps`): per frame, the distance between the two surfaces (negative:
they overlap), from surface samples of one shape (the one with fewer) against the other's
signed distance, or from the hand's points against the object's signed distance minus the hand's radius.
Metres; NaN where an instance's pose is unknown (fewer than three markers seen).
"""

from __future__ import annotations

import itertools
import math
import warnings
from dataclasses import dataclass
from typing import TypeAlias

import numpy as np

from oacdsl.errors import RecordingError
from oacdsl.segmentation.poses import MIN_MARKERS, fit_constellation, fit_instance, invert
from oacdsl.segmentation.recording import Recording
from oacdsl.segmentation.scales import instance_size_m
from oacdsl.segmentation.shapes import ShapeModel

__all__ = [
    "DEFAULT_HAND_SIZE_M",
    "HAND_RADIUS_FRACTION",
    "MAX_FIT_FRACTION",
    "MAX_PERMUTED",
    "HandVolume",
    "PosedShape",
    "hand_volume",
    "pose_shape",
    "surface_gaps",
]

#: Most markers whose assignment to the declared ones is searched (6! = 720 fits at once).
MAX_PERMUTED = 6
#: A shape is posed only when its declared markers fit the recorded ones within this fraction of
#: its largest extent (RMS): 10 %, a 25 cm board within 25 mm (markers on stalks, a rough model).
MAX_FIT_FRACTION = 0.10
#: A hand's volume reaches this fraction of its size around its markers (15 %: 24 mm for the
#: KIT subjects' 162 mm hands, the thickness of a hand under markers on its back).
HAND_RADIUS_FRACTION = 0.15
#: A hand's size when its markers cannot measure it (fewer than two), metres.
DEFAULT_HAND_SIZE_M = 0.16
_SEGMENT_SAMPLES = 5  # points along each segment between two hand markers, ends included
_FRAME_BLOCK = 256  # frames per block of the gap computation

Frames: TypeAlias = "slice | np.ndarray"  # frames of a recording: a range or indices


@dataclass(frozen=True)
class PosedShape:
    """An instance's shape in every frame.

    Attributes:
        instance: the instance's name.
        model: its shape.
        T_world_object: (F, 4, 4) the class's object frame in the world, metres; NaN in gaps.
        misfit_m: RMS distance of the declared from the recorded markers, metres (module doc).
        noise_m: the rigid fit's median residual over frames, metres.
        extent_m: the middle of the shape's three bounding-box sizes, metres (its size across).
    """

    instance: str
    model: ShapeModel
    T_world_object: np.ndarray
    misfit_m: float
    noise_m: float
    extent_m: float


@dataclass(frozen=True)
class HandVolume:
    """A hand: its markers (``markers_m``: (F, k, 3), world, NaN in gaps) and ``radius_m`` around
    them and the segments between them."""

    instance: str
    markers_m: np.ndarray
    radius_m: float

    @property
    def extent_m(self) -> float:
        """Its size across: twice the radius around the back of the hand and the fingers."""
        return 2 * self.radius_m

    def points(self, frames: Frames) -> np.ndarray:
        """(F', P, 3) the markers and points along the segments between them in ``frames``."""
        p = self.markers_m[frames]
        s = np.linspace(0.0, 1.0, _SEGMENT_SAMPLES)[1:-1]
        parts = [p] + [p[:, i, None, :] + s[None, :, None] * (p[:, j, None, :] - p[:, i, None, :])
                       for i, j in itertools.combinations(range(p.shape[1]), 2)]
        return np.concatenate(parts, axis=1)

    def bounds(self, frames: Frames) -> tuple[np.ndarray, np.ndarray]:
        """(F', 3) centres and (F',) radii of spheres holding the volume in ``frames``, metres."""
        p = self.markers_m[frames]
        with np.errstate(invalid="ignore"), warnings.catch_warnings():
            warnings.simplefilter("ignore", RuntimeWarning)  # a frame without markers: NaN
            centre = np.nanmean(p, axis=1)
            reach = np.nanmax(np.linalg.norm(p - centre[:, None, :], axis=2), axis=1)
        return centre, reach + self.radius_m


def pose_shape(recording: Recording, instance: str, model: ShapeModel) -> tuple[PosedShape | None, str]:
    """``instance``'s shape posed by its markers, or None and why not (module doc)."""
    declared = model.markers_m
    k = len(recording.groups.get(instance, ()))
    if declared.shape[0] != k or k < MIN_MARKERS:
        return None, f"{declared.shape[0]} declared markers for {k} recorded"
    try:
        poses = fit_instance(recording, instance)
    except RecordingError as error:
        return None, str(error)
    real = poses.constellation_m  # (k, 3) fit frame, NaN: not seen at the reference frame
    seen = np.isfinite(real).all(axis=1)
    if k <= MAX_PERMUTED:
        perms = np.array(list(itertools.permutations(range(k))), dtype=np.intp)
    else:
        perms = np.arange(k, dtype=np.intp)[None, :]
    targets = declared[perms]  # (P, k, 3): declared marker perm[i] is recorded marker i
    targets[:, ~seen] = np.nan
    T_class_fit, misfit = fit_constellation(real, targets)
    best = int(np.nanargmin(misfit))
    extents = model.extents_m
    if not misfit[best] <= MAX_FIT_FRACTION * extents[2]:
        return None, (f"declared markers fit the recorded ones within {misfit[best] * 1000:.0f} mm,"
                      f" more than {MAX_FIT_FRACTION:.0%} of its {extents[2] * 1000:.0f} mm")
    T_world = poses.T_world_object @ invert(T_class_fit[best])
    residual = float(np.nanmedian(poses.residual_m)) if np.isfinite(poses.residual_m).any() else 0.0
    return PosedShape(instance, model, T_world, float(misfit[best]), residual, extents[1]), "posed"


def hand_volume(recording: Recording, instance: str) -> HandVolume:
    """``instance`` (a hand) as a :class:`HandVolume`."""
    p = recording.group_positions(instance)  # (F, k, 3)
    size = instance_size_m(p)
    radius = HAND_RADIUS_FRACTION * (size if math.isfinite(size) else DEFAULT_HAND_SIZE_M)
    return HandVolume(instance, p, radius)


def _shape_bounds(shape: PosedShape, frames: Frames) -> tuple[np.ndarray, np.ndarray]:
    """(F', 3) centres and (F',) radii of spheres holding ``shape`` in ``frames``, metres."""
    pts = shape.model.surface_points()
    mid = (pts.min(axis=0) + pts.max(axis=0)) / 2
    T = shape.T_world_object[frames]
    centre = np.einsum("fij,j->fi", T[:, :3, :3], mid) + T[:, :3, 3]
    return centre, np.full(len(centre), float(np.linalg.norm(pts - mid, axis=1).max()))


def _to_object(T_world_object: np.ndarray, points_world: np.ndarray) -> np.ndarray:
    """(F, P, 3) world points in the object frame of each frame's ``T_world_object`` (F, 4, 4):
    ``R^T (p - t)``, as rows ``(p - t) R``."""
    return np.asarray(np.matmul(points_world - T_world_object[:, None, :3, 3], T_world_object[:, :3, :3]))


def _posed_surface(shape: PosedShape, frames: Frames) -> np.ndarray:
    """(F', P, 3) world points of ``shape``'s surface in ``frames``."""
    T = shape.T_world_object[frames]
    rotated = np.matmul(shape.model.surface_points()[None], np.swapaxes(T[:, :3, :3], 1, 2))
    return np.asarray(rotated + T[:, None, :3, 3])


def _min_sdf(shape: PosedShape, points_world: np.ndarray, frames: Frames) -> np.ndarray:
    """(F',) the smallest signed distance of (F', P, 3) world points to ``shape``, NaN in gaps."""
    local = _to_object(shape.T_world_object[frames], points_world)
    with np.errstate(invalid="ignore"):
        sdf = shape.model.signed_distance(local)
    out = np.fmin.reduce(sdf, axis=1) if sdf.shape[1] else np.full(sdf.shape[0], np.nan)
    return np.asarray(out)


def surface_gaps(a: PosedShape | HandVolume, b: PosedShape | HandVolume,
                 within_m: float = math.inf) -> np.ndarray:
    """(F,) gap between the surfaces of ``a`` and ``b``, metres (module doc); a pair of two hands
    is not measured (an error). Frames where spheres around the two are farther apart than
    ``within_m`` get that lower bound of the gap instead (the broad phase: a long recording's
    pairs are far apart in most frames)."""
    if isinstance(a, HandVolume) and isinstance(b, HandVolume):
        raise ValueError("two hands have no surface gap: they are measured by their markers")
    if isinstance(a, HandVolume):
        a, b = b, a
    if not isinstance(a, PosedShape):  # for the type checker: a is the object now
        raise TypeError(a)
    n = a.T_world_object.shape[0]
    out = np.full(n, np.nan)
    for lo in range(0, n, _FRAME_BLOCK):
        block = slice(lo, min(n, lo + _FRAME_BLOCK))
        ca, ra = _shape_bounds(a, block)
        cb, rb = b.bounds(block) if isinstance(b, HandVolume) else _shape_bounds(b, block)
        bound = np.linalg.norm(ca - cb, axis=1) - ra - rb
        with np.errstate(invalid="ignore"):
            far = bound > within_m  # NaN (a gap): measured, NaN again
        out[block] = bound
        f = np.flatnonzero(~far) + lo
        if f.size == 0:
            continue
        if isinstance(b, HandVolume):
            out[f] = _min_sdf(a, b.points(f), f) - b.radius_m
        else:  # the surface with fewer samples against the other one's signed distance
            small, large = sorted((a, b), key=lambda x: len(x.model.surface_points()))
            out[f] = _min_sdf(large, _posed_surface(small, f), f)
    return out
