"""Automatic action segmentation (AAS, paper III-A): a recording → keyframes with world states.

``segment(recording, params)`` runs in chunks of frames: for each chunk it
computes the distances of the marker pairs that can matter (broad phase, see
:mod:`~oacdsl.segmentation.geometry`), asks the touch detector when each pair
starts and stops touching, and reduces that to instance pairs ("instances
touch while any pair of their markers touches", see
:mod:`~oacdsl.segmentation.instances`). The detector's state and the instance
pairs' state are carried across chunk borders, and each chunk re-reads the few
frames before it that the detector needs, so the result does not depend on the
chunk size. Memory is O(chunk × pairs), independent of the recording's length.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from itertools import pairwise

import numpy as np

from oacdsl.errors import SegmentationError
from oacdsl.segmentation import geometry
from oacdsl.segmentation.detectors import DistanceChunk, TouchDetector, make_detector
from oacdsl.segmentation.geometry import BOUND_MARGIN_M, ChunkGeometry, chunk_frames_for
from oacdsl.segmentation.instances import InstanceTouch
from oacdsl.segmentation.keyframes import keyframes_from_changes, merge_keyframes
from oacdsl.segmentation.pairs import PairTable
from oacdsl.segmentation.params import AasParams
from oacdsl.segmentation.recording import Recording
from oacdsl.segmentation.result import Segmentation
from oacdsl.segmentation.shapes import ShapeModel

__all__ = ["segment", "DEFAULT_CHUNK_FRAMES", "MAX_INSTANCES", "MAX_PAIR_FRAMES", "check_work"]

#: Frames per chunk: large enough to amortise Python overhead, small enough that
#: the broad phase stays tight and a chunk's arrays stay small (``benchmarks/segmentation.py``,
#: 10 minutes: 2048 frames 11 % less CPU time than 512 for the default detector, 12 % for the
#: paper's; 4096 no better). The result does not depend on it.
DEFAULT_CHUNK_FRAMES = 2048

Progress = Callable[[int, int], None]

#: Instances (marker groups) a segmentation takes: their pairs are examined one by one.
MAX_INSTANCES = 100
#: Cross-instance marker pairs × frames a segmentation examines: 18 times the one-hour
#: recording of benchmarks/segmentation.py (5.6e8), which a 1 GiB recording reaches only
#: with hundreds of markers.
MAX_PAIR_FRAMES = 10_000_000_000


def check_work(recording: Recording, frames: int | None = None) -> None:
    """Refuse, before any work, a segmentation beyond the bounds above or a window ``frames``
    (``n``, when given explicitly) longer than the recording."""
    where = recording.source
    if frames is not None and frames > recording.n_frames:
        raise SegmentationError(
            f"frames n = {frames} is more than the recording's {recording.n_frames} frames", location=where
        )
    hint = "group the markers (--preset, --scene) or segment a shorter part"
    if len(recording.groups) > MAX_INSTANCES:
        raise SegmentationError(
            f"{len(recording.groups)} marker groups (instances), more than the"
            f" {MAX_INSTANCES} a segmentation takes; {hint}",
            location=where,
        )
    sizes = [len(set(idx)) for idx in recording.groups.values()]
    pairs = (sum(sizes) ** 2 - sum(k * k for k in sizes)) // 2
    if pairs * recording.n_frames > MAX_PAIR_FRAMES:
        raise SegmentationError(
            f"{pairs} marker pairs × {recording.n_frames} frames is more than the"
            f" {MAX_PAIR_FRAMES:.0e} pair-frames a segmentation examines; {hint}",
            location=where,
        )


def segment(
    recording: Recording,
    params: AasParams | None = None,
    *,
    chunk_frames: int = DEFAULT_CHUNK_FRAMES,
    detector: TouchDetector | None = None,
    progress: Progress | None = None,
    shapes: Mapping[str, ShapeModel] | None = None,
) -> Segmentation:
    """Segment ``recording`` into keyframes (frame 0 = the initial world state).

    ``params`` defaults to :class:`AasParams` (the paper's mode). ``detector``
    overrides the one ``params.mode`` names (for experiments). ``progress(done,
    total)`` is called after each chunk with frame counts. The result does not
    depend on ``chunk_frames``. ``shapes`` (instance → its class's shape,
    :func:`~oacdsl.segmentation.shapes.scene_shapes`) are used with ``params.contacts ==
    "geometry"`` (:mod:`~oacdsl.segmentation.geomcontact`); without them every instance is
    measured by its markers.
    """
    given = params or AasParams()
    check_work(recording, given.frames)
    params = given.resolved(recording.rate_hz)
    if chunk_frames < 1:
        raise SegmentationError(f"chunk size must be at least 1 frame, got {chunk_frames}")
    times = np.asarray(recording.times_s, dtype=np.float64)
    if times.size > 1 and not np.all(np.diff(times) > 0):
        bad = int(np.flatnonzero(np.diff(times) <= 0)[0]) + 1
        raise SegmentationError(
            f"frame times must increase; frame {bad} is at or before frame {bad - 1}",
            location=recording.source,
        )
    det = detector if detector is not None else make_detector(params)
    if params.contacts == "geometry":
        use_shapes = getattr(det, "use_shapes", None)
        if use_shapes is None:
            raise SegmentationError(
                f"the detector {type(det).__name__} does not measure contacts from geometry"
            )
        use_shapes(dict(shapes or {}))
    effective = getattr(det, "effective_params", None)  # optional: the detector rescales them
    run = effective(recording, given) if effective is not None else params
    _fit_chunk(recording, det.history_frames, chunk_frames)  # before the pair table (history: at least)
    table = PairTable.of(recording)
    frames, which, values = _changes(recording, table, det, chunk_frames, progress)
    relations = [table.relation(q) for q in range(table.n_instance_pairs)]
    true_frames = frames - det.delay_frames
    timing = getattr(det, "change_times_s", None)  # optional: when each change happened, below the frame
    when = timing(which, true_frames, times) if timing is not None else None
    raw = keyframes_from_changes(table.instances, relations, true_frames, which, values, times, when)
    if getattr(det, "merges_connected", False):  # connected changes only, anchored by the hands
        find = getattr(det, "agents", None)  # optional: the detector's agents
        agents = frozenset(table.instances[i] for i in find(table.instances)) if find else None
        arrivals = getattr(det, "arrivals", None)  # optional: tool contacts that began by arriving
        keyframes = merge_keyframes(raw, run.merge_s, connected=True, agents=agents, arrivals=arrivals)
    else:
        keyframes = merge_keyframes(raw, run.merge_s)
    reported = params.to_dict()
    scale = getattr(det, "scale", None)
    if scale is not None:
        reported["scale"] = scale.to_dict()
    measured = getattr(det, "geometry_report", None)
    if params.contacts == "geometry" and measured is not None:
        reported["geometry"] = dict(measured)
    return Segmentation(
        recording=recording.source,
        rate_hz=float(recording.rate_hz),
        frames=recording.n_frames,
        instances=recording.instances,
        keyframes=tuple(keyframes),
        parameters=reported,
    )


def _fit_chunk(recording: Recording, history: int, wanted: int) -> int:
    """Frames per chunk whose distances (and a scratch buffer) fit the geometry's budget; refused
    when not even ``history`` output frames after the ``history`` frames a detector re-reads fit."""
    sizes = sorted(len(set(idx)) for idx in recording.groups.values())
    pairs = (sum(sizes) ** 2 - sum(k * k for k in sizes)) // 2  # cross-instance marker pairs
    per_frame = pairs + (sizes[-1] * sizes[-2] if len(sizes) > 1 else 0)  # float32 values per frame
    least = history + max(1, min(history, recording.n_frames))  # frames
    if per_frame * least * 4 > geometry.MAX_CHUNK_DISTANCE_BYTES:
        raise SegmentationError(
            f"{pairs} marker pairs × {least} frames at once ({history} before each chunk) need"
            f" {_mib(per_frame * least * 4)} of distances, more than the"
            f" {_mib(geometry.MAX_CHUNK_DISTANCE_BYTES)} a segmentation holds; group fewer markers"
            " (--preset, --scene) or choose a smaller --frames",
            location=recording.source,
        )
    return chunk_frames_for(per_frame, wanted, history)


def _mib(size: int) -> str:
    return f"{size / 2**20:.4g} MiB"


def _changes(
    recording: Recording,
    table: PairTable,
    det: TouchDetector,
    chunk_frames: int,
    progress: Progress | None,
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Causal frames, instance pairs and new states of every instance-pair change."""
    det.begin(recording, table)
    geometry = ChunkGeometry(recording, table, getattr(det, "filler", None))  # optional: rigid gaps filled
    chunk_frames = _fit_chunk(recording, det.history_frames, chunk_frames)  # the history at this rate
    tracker = InstanceTouch(table)
    n_frames, n_q = recording.n_frames, table.n_instance_pairs
    all_blocks = np.arange(n_q, dtype=np.intp)
    near_blocks = getattr(det, "near_blocks", None)  # optional: (lo, stop, touching) → blocks or None
    found: list[tuple[np.ndarray, np.ndarray, np.ndarray]] = []
    # the first chunk holds two frames at least: frame 0 borrows frame 1's distance change
    borders = [0, *range(max(2, chunk_frames), n_frames, chunk_frames), n_frames]
    width = min(n_frames, max(2, chunk_frames) + det.history_frames)  # the longest chunk, its history too
    buffer = np.empty((3, table.marker_order.size, width), dtype=np.float32)  # its coordinates, reused
    for start, stop in pairwise(borders):
        lo = max(0, start - det.history_frames)
        known = near_blocks(lo, stop, tracker.touching) if near_blocks is not None else None
        boxes = None
        if known is not None:  # the detector already knows which pairs come within reach: their markers
            blocks = known
            needed = np.zeros(len(table.instances), dtype=bool)
            needed[table.instance_pairs[blocks].reshape(-1)] = True
            x = geometry.coordinates(lo, stop, buffer[:, :, : stop - lo], needed)
        elif det.reach_m is None or n_q == 0:
            x = geometry.coordinates(lo, stop, buffer[:, :, : stop - lo])
            blocks = all_blocks
        else:
            x = geometry.coordinates(lo, stop, buffer[:, :, : stop - lo])
            boxes = geometry.marker_boxes(x)
            with np.errstate(invalid="ignore"):
                near = geometry.lower_bounds(x, boxes=boxes) <= det.reach_m + BOUND_MARGIN_M
            blocks = np.flatnonzero(near | tracker.touching)
        pair_state = getattr(det, "pair_state", None)  # optional: the marker pairs it holds touching
        if boxes is not None and pair_state is not None and det.reach_m is not None:
            pairs, dist = geometry.near_distances(x, blocks, det.reach_m + BOUND_MARGIN_M, pair_state, boxes)
        else:
            pairs, dist = geometry.distances(x, blocks)
        chunk = DistanceChunk(
            start, stop, start - lo, recording.times_s[lo:stop], pairs, dist, recording.positions_m[lo:stop]
        )
        changed = tracker.apply(det.step(chunk))
        if changed[0].size:
            found.append(changed)
        if progress is not None:
            progress(stop, n_frames)
    if not found:
        empty = np.zeros(0, dtype=np.intp)
        return empty, empty.copy(), np.zeros(0, dtype=bool)
    return (
        np.concatenate([f[0] for f in found]),
        np.concatenate([f[1] for f in found]),
        np.concatenate([f[2] for f in found]),
    )
