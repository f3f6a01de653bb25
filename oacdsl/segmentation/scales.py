"""The demonstration's own scales: how large its demonstrator is and how fast it moves.

The adaptive detector's constants (distances, speeds, durations; :class:`AasParams`,
:class:`~oacdsl.segmentation.comotion.AdaptiveSettings`) are written for a *reference*
demonstration: the KIT bimanual development clips' (an adult's hands, everyday pace).
Another take of the same demonstration — the scene 15 % larger, the motion twice as slow —
must give the same keyframes, so :func:`measure` finds the recording's scales and
:func:`scale_params` / :func:`scale_settings` rescale every constant by them:

- **length** factor: the agents' (hands') size — per hand with at least
  :data:`SIZE_MIN_MARKERS` markers the median over frames of its largest marker distance, the
  median of those — over the reference's (:data:`REFERENCE_SIZE_M`); 1 without such a hand.
  It stays under rotation, mirroring, translation, resampling and gaps, and grows with the
  scene's scale. (Object sizes differ too much between scenes to be a scale: the development
  clips' objects span 94–335 mm.)
- **speed** factor: the demonstration's pace — the :data:`PACE_QUANTILE` quantile over
  frames of the fastest agent's median marker speed (over :data:`PACE_LAG_S`) — over the
  reference's (:data:`REFERENCE_PACE_M_S`). It halves on a take twice as slow and grows
  with the scale.
- **time** factor: length / speed (durations).

Speeds are multiplied by the speed factor, durations by the time factor; ratios (``margin``,
``rigid_ratio``) stay. Of the distances ``d`` (``AasParams.distance_m``, the *largest*
contact distance, a cap) follows the length factor, and only upwards: a larger demonstrator in a
larger scene holds a tool farther from its target's markers (a take 15 % larger put Pour's carton
and Mix's spoon beyond 150 mm of the cup's and the bowl's markers), while a smaller one needs no
tighter cap (the hands' size measures the demonstrator, not the objects: on the KIT Scoop clip,
whose subject's hands are 5 % smaller, a 5 % shorter reach found the ladle in the cup 0.3 s late
and changed the composed OAC). The per-pair distances are learned; the static one
(``static_distance_m``, between two objects that never move together) follows the length factor
both ways (a fork lying 84 mm beside KIT Mix's bowl is 71 mm from it in a take 15 % smaller).
The tool rule's reach between two objects (:func:`tool_reach_m`) is a contact distance and also
shrinks, for a length factor below :data:`SUBJECT_BAND` (the
development clips' subjects differ by 0.95-1.06, and a 5 % shorter reach already moves Cut's
keyframes): ``d`` × factor / band, at least :data:`MIN_REACH_FACTOR` × ``d``. So a scene 15 %
smaller has its tools reach 10 % less far (at 150 mm Pour's carton "reached" the cup 0.5 s before
it was grasped in a take ×0.85; Scoop's and the dough's alike). Per-pair reaches from the objects'
own sizes were measured and do not fit the development clips (docs/segmentation.md, *Measured:
variations beyond the standard takes*). The length factor also serves the time factor: a take
15 % larger is 15 % faster, not quicker. The factors are clamped to
[:data:`MIN_FACTOR`, :data:`MAX_FACTOR`] so that a recording without motion or markers cannot
make a constant vanish.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from oacdsl.segmentation.comotion import AdaptiveSettings
from oacdsl.segmentation.medians import nanmedian0
from oacdsl.segmentation.params import AasParams
from oacdsl.segmentation.recording import Recording, column_index

__all__ = [
    "MAX_FACTOR",
    "MEASURE_FRAMES",
    "MIN_FACTOR",
    "MIN_REACH_FACTOR",
    "PACE_LAG_S",
    "PACE_QUANTILE",
    "REFERENCE_PACE_M_S",
    "REFERENCE_SIZE_M",
    "SIZE_MIN_MARKERS",
    "SUBJECT_BAND",
    "DemoScale",
    "measure",
    "scale_params",
    "scale_settings",
    "tool_reach_m",
]

#: The reference demonstration's hand size, metres: the median of the six KIT development
#: clips' (each the median of its two hands' largest marker distance).
REFERENCE_SIZE_M = 0.162
#: Fewest markers of a hand that measure its size (wrist to finger tips, as the KIT set's five);
#: a smaller set (three on the back of the hand) says where the markers are, not how large the
#: hand is, and leaves the length factor at 1.
SIZE_MIN_MARKERS = 4
#: The reference demonstration's pace, m/s: the median of the six KIT development clips'.
REFERENCE_PACE_M_S = 0.5
#: Quantile of the fastest agent's speed over frames that is the demonstration's pace.
PACE_QUANTILE = 0.9
#: Seconds over which a marker's speed is measured for the pace (at least one frame).
PACE_LAG_S = 0.1
#: Length factors from this up to 1 tell subjects apart, not scenes: the development clips' hands
#: are 0.95-1.06 of the reference's, so below it the scene is smaller (:func:`tool_reach_m`).
SUBJECT_BAND = 0.94
#: The tool reach shrinks to at most this fraction of ``d``: four markers of a hand that do not span
#: it (a cluster on its back) measure a "hand" a third of the reference's.
MIN_REACH_FACTOR = 0.8
#: Bounds of each factor.
MIN_FACTOR, MAX_FACTOR = 0.25, 4.0
#: Most frames the factors are measured on, evenly spread (a median and a quantile over 20,000
#: frames are as good as over all of an hour's 360,000, at a twentieth of the cost).
MEASURE_FRAMES = 20_000


@dataclass(frozen=True)
class DemoScale:
    """Factors of a recording against the reference demonstration (1.0 = the reference).

    Attributes:
        length: the scene's sizes over the reference's.
        speed: the demonstration's pace over the reference's.
    """

    length: float = 1.0
    speed: float = 1.0

    @property
    def time(self) -> float:
        """Durations' factor: length / speed."""
        return self.length / self.speed

    def to_dict(self) -> dict[str, float]:
        return {"length": self.length, "speed": self.speed, "time": self.time}


def _clamp(x: float) -> float:
    return float(min(MAX_FACTOR, max(MIN_FACTOR, x))) if np.isfinite(x) and x > 0 else 1.0


def instance_size_m(points_m: np.ndarray) -> float:
    """Median over frames of the largest distance between two visible markers, metres
    (``points_m``: (F, k, 3), NaN in gaps); NaN with fewer than two markers."""
    k = points_m.shape[1]
    if k < 2:
        return float("nan")
    largest = np.full(points_m.shape[0], np.nan)
    with np.errstate(invalid="ignore"):
        for i in range(k):
            for j in range(i + 1, k):
                d = np.linalg.norm(points_m[:, i] - points_m[:, j], axis=1)
                largest = np.fmax(largest, d)
    if not np.isfinite(largest).any():
        return float("nan")
    return float(np.nanmedian(largest))


def _rows(n_frames: int, start: int = 0) -> np.ndarray:
    """Frames ``start … n_frames - 1``, at most :data:`MEASURE_FRAMES` of them, evenly spread."""
    if n_frames - start <= MEASURE_FRAMES:
        return np.arange(start, n_frames)
    return np.unique(np.linspace(start, n_frames - 1, MEASURE_FRAMES).astype(np.intp))


def _points(recording: Recording, name: str, rows: np.ndarray) -> np.ndarray:
    """(len(rows), k, 3) positions of instance ``name``'s markers at ``rows``, metres."""
    columns = column_index(np.asarray(recording.groups[name], dtype=np.intp))
    if isinstance(columns, slice):  # rows of a strided view: no fancy indexing of both axes
        return recording.positions_m[rows, columns]
    return recording.positions_m[np.ix_(rows, columns)]


def pace_m_s(recording: Recording, instances: tuple[str, ...]) -> float:
    """The :data:`PACE_QUANTILE` quantile over frames (at most :data:`MEASURE_FRAMES`) of the
    fastest of ``instances``' median marker speed over :data:`PACE_LAG_S`, m/s (NaN without two
    frames)."""
    n = recording.n_frames
    lag = max(1, round(PACE_LAG_S * recording.rate_hz))
    if n <= lag or not instances:
        return float("nan")
    t = np.asarray(recording.times_s, dtype=np.float64)
    rows = _rows(n, lag)
    dt = t[rows] - t[rows - lag]
    fastest = np.full(rows.size, np.nan)
    with np.errstate(invalid="ignore"):
        for name in instances:
            step = np.linalg.norm(_points(recording, name, rows) - _points(recording, name, rows - lag),
                                  axis=2)  # (R, k)
            if np.isnan(step).all():
                continue
            # np.nanmedian(…, axis=1)'s values without its masked arrays (medians.nanmedian0)
            speed = nanmedian0(np.where(np.isnan(step).all(axis=1, keepdims=True), 0.0, step).T)
            speed[np.isnan(step).all(axis=1)] = np.nan
            fastest = np.fmax(fastest, speed / dt)
    if not np.isfinite(fastest).any():
        return float("nan")
    return float(np.nanquantile(fastest, PACE_QUANTILE))


def measure(recording: Recording, agents: tuple[str, ...] = ()) -> DemoScale:
    """The recording's factors (module doc); ``agents``: the hands' instance names (without
    them both factors are 1)."""
    if not agents:  # the pace is the hands': without them the constants stay as they are
        return DemoScale()
    names = agents
    spanning = [g for g in agents if len(recording.groups[g]) >= SIZE_MIN_MARKERS]
    rows = _rows(recording.n_frames)
    sizes = [instance_size_m(_points(recording, g, rows)) for g in spanning]
    sizes = [s for s in sizes if np.isfinite(s)]
    length = _clamp(float(np.median(sizes)) / REFERENCE_SIZE_M) if sizes else 1.0
    speed = _clamp(pace_m_s(recording, names) / REFERENCE_PACE_M_S)
    return DemoScale(length, speed)


def scale_params(params: AasParams, scale: DemoScale) -> AasParams:
    """``params`` for a recording of ``scale``: speeds and durations rescaled, ``d`` grown by a
    length factor above 1 (never shrunk: module doc); an explicit ``frames`` count is kept."""
    return replace(
        params,
        distance_m=params.distance_m * max(1.0, scale.length),
        speed_m_s=params.speed_m_s * scale.speed,
        hold_s=params.hold_s * scale.time,
        change_window_s=params.change_window_s * scale.time,
        merge_s=params.merge_s * scale.time,
    )


def tool_reach_m(params: AasParams, scale: DemoScale) -> float:
    """The tool rule's reach between two objects for a recording of ``scale``, metres: ``d`` grown
    by a length factor above 1 as :func:`scale_params` grows it, and shrunk below
    :data:`SUBJECT_BAND` by the factor over it, at least :data:`MIN_REACH_FACTOR` × ``d``
    (module doc)."""
    length = scale.length
    if length >= SUBJECT_BAND:
        return params.distance_m * max(1.0, length)
    return params.distance_m * max(MIN_REACH_FACTOR, length / SUBJECT_BAND)


def scale_settings(settings: AdaptiveSettings, scale: DemoScale) -> AdaptiveSettings:
    """``settings`` for a recording of ``scale``: speeds and durations rescaled, and the static
    distance (between two objects that never move together) in the scene's length."""
    return replace(
        settings,
        static_distance_m=settings.static_distance_m * scale.length,
        move_speed_m_s=settings.move_speed_m_s * scale.speed,
        lag_s=settings.lag_s * scale.time,
        min_episode_s=settings.min_episode_s * scale.time,
        tool_dwell_s=settings.tool_dwell_s * scale.time,
        tool_bridge_s=settings.tool_bridge_s * scale.time,
    )
