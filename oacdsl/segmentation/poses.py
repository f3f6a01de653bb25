"""Object poses from markers: a rigid fit (Kabsch/Umeyama without scale) per frame.

An instance with at least three markers is a rigid body. Its **constellation** is
its markers' positions at a *reference frame*: the first frame where the most of
its markers are seen (all of them on a clean recording). The **object frame** has
its origin at the constellation's centroid and the world's axes at the reference
frame, so ``T_world_object`` is ``[I | centroid]`` there; on a recording that starts
with the objects at rest on a table, the object's z axis is "up" as it stood.

Every other frame is fitted to the constellation by the least-squares rotation and
translation of its visible markers (Kabsch 1976; Umeyama 1991 without scale), for
all frames at once (one batched 3×3 SVD). A frame with fewer than three visible
markers is a **gap**: its pose is NaN. The fit's RMS residual (metres) says how
rigid the markers stayed (a hand is only roughly rigid).

numpy only; every array is vectorised over frames.
"""

from __future__ import annotations

from collections.abc import Iterable, Iterator
from dataclasses import dataclass

import numpy as np

from oacdsl.errors import RecordingError, did_you_mean
from oacdsl.segmentation.recording import Recording

__all__ = [
    "MIN_MARKERS",
    "ObjectPoses",
    "RigidFill",
    "agreement",
    "fill_rigid_gaps",
    "fit_constellation",
    "fit_instance",
    "fit_poses",
    "invert",
    "relative",
    "rotation_angle",
]

#: Fewest visible markers that fix a rigid pose (three non-collinear points).
MIN_MARKERS = 3


@dataclass(frozen=True)
class ObjectPoses:
    """The poses of one instance over a recording.

    Attributes:
        instance: the instance (marker group) name.
        times_s: (F,) frame times, seconds.
        T_world_object: (F, 4, 4) homogeneous transforms, metres; NaN in gaps.
        residual_m: (F,) RMS distance of the visible markers from the fitted constellation,
            metres; NaN in gaps.
        visible: (F,) number of markers seen in each frame.
        reference_frame: the frame whose marker positions define the constellation.
        constellation_m: (k, 3) marker positions in the object frame, metres (NaN for a
            marker not seen at the reference frame: it takes no part in the fit).
    """

    instance: str
    times_s: np.ndarray
    T_world_object: np.ndarray
    residual_m: np.ndarray
    visible: np.ndarray
    reference_frame: int
    constellation_m: np.ndarray

    @property
    def valid(self) -> np.ndarray:
        """(F,) bool: frames with a pose (not a gap)."""
        result: np.ndarray = np.isfinite(self.T_world_object[:, 0, 0])
        return result

    @property
    def gap_fraction(self) -> float:
        """Share of frames without a pose, 0..1."""
        return float(1.0 - self.valid.mean()) if self.valid.size else 1.0

    @property
    def positions_m(self) -> np.ndarray:
        """(F, 3) origin of the object frame in the world, metres."""
        result: np.ndarray = self.T_world_object[:, :3, 3]
        return result


def fit_constellation(constellation_m: np.ndarray, points_m: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The rigid transforms that best map ``constellation_m`` onto ``points_m``, per frame.

    ``constellation_m``: (k, 3) marker positions in the object frame, metres (NaN: unused
    marker); ``points_m``: (F, k, 3) observed positions, metres, NaN where a marker is
    missing. Returns ``(T, residual)``: (F, 4, 4) transforms ``T_world_object`` and (F,)
    RMS residuals, metres; frames with fewer than :data:`MIN_MARKERS` usable markers
    are NaN. Minimises ``Σ |R c_i + t − p_i|²`` over the visible markers (Kabsch).
    """
    ref = np.asarray(constellation_m, dtype=np.float64)
    pts = np.asarray(points_m, dtype=np.float64)
    usable = np.asarray(np.isfinite(ref).all(axis=1))
    seen = np.isfinite(pts).all(axis=2) & usable[None, :]  # (F, k)
    if seen.all() and ref.shape[0] >= MIN_MARKERS:  # every marker in every frame (virtual markers)
        w: np.ndarray | None = None
        n = np.full(len(pts), float(ref.shape[0]))
        ok = np.ones(len(pts), dtype=bool)
        safe_n = n
        ref0, pts0 = ref, pts
        c_ref = np.broadcast_to(ref.mean(axis=0), (len(pts), 3))
        c_pts = pts.mean(axis=1)
        centred = ref - c_ref[0]
        # (F, 3, 3) cross-covariance Σ centred_i (p_i − c)ᵀ, without a centred copy of every frame
        h = np.matmul(centred.T, pts) - centred.sum(axis=0)[None, :, None] * c_pts[:, None, :]
    else:
        w = seen.astype(np.float64)
        n = w.sum(axis=1)  # (F,)
        ok = n >= MIN_MARKERS
        safe_n = np.where(ok, n, 1.0)
        ref0 = np.where(np.isfinite(ref), ref, 0.0)
        pts0 = np.where(seen[..., None], pts, 0.0)
        c_ref = (w @ ref0) / safe_n[:, None]  # (F, 3) centroid of the constellation's visible markers
        c_pts = np.matmul(w[:, None, :], pts0)[:, 0] / safe_n[:, None]  # batched matmul: einsum is slower
        a = (ref0[None, :, :] - c_ref[:, None, :]) * w[..., None]  # (F, k, 3)
        b = (pts0 - c_pts[:, None, :]) * w[..., None]
        h = np.matmul(np.swapaxes(a, 1, 2), b)  # (F, 3, 3) cross-covariance
    u, _, vt = np.linalg.svd(h)
    v = np.swapaxes(vt, 1, 2)
    d = np.sign(np.linalg.det(v @ np.swapaxes(u, 1, 2)))
    d = np.where(d == 0, 1.0, d)
    fix = np.ones((len(d), 3))
    fix[:, 2] = d  # no reflection
    rot = (v * fix[:, None, :]) @ np.swapaxes(u, 1, 2)  # (F, 3, 3)
    trans = c_pts - np.einsum("fij,fj->fi", rot, c_ref)
    T = np.zeros((len(pts), 4, 4))
    T[:, :3, :3] = rot
    T[:, :3, 3] = trans
    T[:, 3, 3] = 1.0
    mapped = np.matmul(ref0, np.swapaxes(rot, 1, 2)) + trans[:, None, :]
    sq = ((mapped - pts0) ** 2).sum(axis=2)
    if w is not None:
        sq *= w
    residual = np.sqrt(sq.sum(axis=1) / safe_n)
    T[~ok] = np.nan
    residual[~ok] = np.nan
    return T, residual


def fit_instance(recording: Recording, instance: str) -> ObjectPoses:
    """The poses of ``instance`` by a rigid fit of its markers (see the module doc)."""
    if instance not in recording.groups:
        raise RecordingError(
            f"no marker group {instance!r}{did_you_mean(instance, recording.groups)}",
            location=recording.source,
        )
    pts = recording.group_positions(instance)
    k = pts.shape[1]
    if k < MIN_MARKERS:
        raise RecordingError(
            f"instance {instance!r} has {k} marker(s); a pose needs at least {MIN_MARKERS}",
            location=recording.source,
        )
    seen = np.isfinite(pts).all(axis=2)
    visible = seen.sum(axis=1)
    reference = int(np.argmax(visible))  # the first frame with the most markers seen
    if visible[reference] < MIN_MARKERS:
        raise RecordingError(
            f"instance {instance!r}: no frame shows {MIN_MARKERS} of its markers at once",
            location=recording.source,
        )
    ref_pts = np.where(seen[reference][:, None], pts[reference], np.nan)
    centroid = np.nanmean(ref_pts, axis=0)
    constellation = ref_pts - centroid  # world axes at the reference frame
    T, residual = fit_constellation(constellation, pts)
    return ObjectPoses(
        instance,
        np.asarray(recording.times_s, dtype=np.float64),
        T,
        residual,
        visible.astype(np.int64),
        reference,
        constellation,
    )


def fit_poses(recording: Recording, instances: Iterable[str] | None = None) -> dict[str, ObjectPoses]:
    """Poses of every instance with ≥ :data:`MIN_MARKERS` markers (or of ``instances``)."""
    names = recording.instances if instances is None else tuple(instances)
    out: dict[str, ObjectPoses] = {}
    for name in names:
        if len(recording.groups.get(name, ())) >= MIN_MARKERS or instances is not None:
            try:
                out[name] = fit_instance(recording, name)
            except RecordingError:
                if instances is not None:
                    raise
    return out


def invert(T: np.ndarray) -> np.ndarray:
    """Inverse of rigid transforms (..., 4, 4) (NaN stays NaN)."""
    rot_t = np.swapaxes(T[..., :3, :3], -1, -2)
    out = np.zeros_like(T)
    out[..., :3, :3] = rot_t
    out[..., :3, 3] = -np.einsum("...ij,...j->...i", rot_t, T[..., :3, 3])
    out[..., 3, 3] = 1.0
    return out


def relative(T_world_target: np.ndarray, T_world_object: np.ndarray) -> np.ndarray:
    """``T_target_object = T_world_target⁻¹ · T_world_object``, frame by frame (..., 4, 4)."""
    result: np.ndarray = invert(T_world_target) @ T_world_object
    return result


def rotation_angle(rot: np.ndarray) -> np.ndarray:
    """Angle of rotation matrices (..., 3, 3), radians in [0, π]."""
    trace = np.einsum("...ii->...", rot)
    result: np.ndarray = np.arccos(np.clip((trace - 1.0) / 2.0, -1.0, 1.0))
    return result


def agreement(poses: ObjectPoses, T_world_model: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """How far a rigid fit strays from another pose source of the same body (e.g. MMM ``ModelPose``).

    ``T_world_model``: (F, 4, 4), the other source on the same frames. The two frames
    differ by a constant offset, taken at the fit's reference frame; returns per frame
    the distance between the fitted origin and the one the other source predicts
    (metres) and the angle between the two orientations (radians); NaN in gaps.
    """
    T_fit = poses.T_world_object
    ref = poses.reference_frame
    T_model_object = invert(T_world_model[ref]) @ T_fit[ref]  # constant offset between the frames
    predicted = T_world_model @ T_model_object
    position = np.linalg.norm(predicted[:, :3, 3] - T_fit[:, :3, 3], axis=1)
    angle = rotation_angle(np.swapaxes(predicted[:, :3, :3], 1, 2) @ T_fit[:, :3, :3])
    return position, angle



class RigidFill:
    """Fills, frame range by frame range, the gaps of rigid instances' markers from their fit.

    For each of ``instances`` with more than :data:`MIN_MARKERS` markers: a missing marker at a
    frame where at least :data:`MIN_MARKERS` of them are seen is put where the rigid fit
    (:func:`fit_constellation`) of the constellation of its first frame with every marker seen
    places it. Memory O(gap frames); :meth:`rows` copies only a range that has something to fill.
    """

    def __init__(self, recording: Recording, instances: Iterable[str]) -> None:
        self.recording = recording
        # per instance: marker indices, frames to fill (sorted), (R, k, 3) positions there (NaN: seen)
        self._items: list[tuple[np.ndarray, np.ndarray, np.ndarray]] = []
        groups = [np.asarray(recording.groups.get(name, ()), dtype=np.intp) for name in instances]
        groups = [idx for idx in groups if idx.size > MIN_MARKERS]
        # (F, M) a marker's gap, NaN in every coordinate: one pass over the recording for all groups
        gap = np.isnan(recording.positions_m[:, :, 0]) if groups else np.zeros((0, 0), dtype=bool)
        for idx in groups:
            seen = ~gap[:, idx]
            count = seen.sum(axis=1)
            frames = np.flatnonzero((count >= MIN_MARKERS) & (count < idx.size))
            full = np.flatnonzero(count == idx.size)
            if frames.size == 0 or full.size == 0:
                continue
            ref = recording.positions_m[full[0], idx, :]
            ref = ref - ref.mean(axis=0)
            pts = recording.positions_m[frames[:, None], idx]  # (R, k, 3)
            T, _ = fit_constellation(ref, pts)
            placed = np.einsum("fij,kj->fki", T[:, :3, :3], ref) + T[:, None, :3, 3]
            placed[seen[frames]] = np.nan
            self._items.append((idx, frames, placed))
        # every item's frames in one sorted array, item k's shifted by k × (F + 1): one search finds
        # each item's range of a frame range (cells() is called for every slab of every chunk)
        self._stride = recording.n_frames + 1
        shifts = np.arange(len(self._items), dtype=np.int64) * self._stride
        self._keys = np.concatenate([frames.astype(np.int64) + shift
                                     for (_, frames, _), shift in zip(self._items, shifts, strict=True)]
                                    + [np.zeros(0, dtype=np.int64)])
        self._shifts = shifts
        self._offsets = np.cumsum([0] + [frames.size for _, frames, _ in self._items])[:-1]

    @property
    def empty(self) -> bool:
        """Nothing to fill anywhere."""
        return not self._items

    def rows(self, lo: int, hi: int) -> np.ndarray:
        """(hi - lo, M, 3) positions of frames ``lo:hi``, metres, gaps filled (a view when none is)."""
        out = self.recording.positions_m[lo:hi]
        copied = False
        for frames, idx, values in self.cells(lo, hi):
            if not copied:
                out, copied = out.copy(), True
            cells = (frames[:, None], idx)
            out[cells] = np.where(np.isnan(values), out[cells], values)
        return out

    def cells(self, lo: int, hi: int) -> Iterator[tuple[np.ndarray, np.ndarray, np.ndarray]]:
        """What :meth:`rows` fills in frames ``lo:hi``, per instance with something to fill:
        ``(frames, markers, values)``: (R,) frames counted from ``lo``, (k,) the instance's marker
        indices, (R, k, 3) their positions there, metres (NaN: seen, kept as it is)."""
        if not self._items:
            return
        first = (self._keys.searchsorted(self._shifts + lo) - self._offsets).tolist()
        last = (self._keys.searchsorted(self._shifts + hi) - self._offsets).tolist()
        for (idx, frames, placed), a, b in zip(self._items, first, last, strict=True):
            if a < b:
                yield frames[a:b] - lo, idx, placed[a:b]

def fill_rigid_gaps(recording: Recording, instances: Iterable[str]) -> Recording:
    """``recording`` with the gaps of ``instances``' markers filled as :class:`RigidFill` does
    (the same object when nothing is filled; else a copy: the segmenter fills chunk by chunk).

    A marker hidden for a moment does not move the object: without this the closest marker
    distance of its pairs jumps to the next marker's for the length of the gap.
    """
    filler = RigidFill(recording, instances)
    if filler.empty:
        return recording
    return Recording(recording.source, recording.rate_hz, recording.times_s, recording.marker_names,
                     filler.rows(0, recording.n_frames), recording.groups, recording.first_frame)
