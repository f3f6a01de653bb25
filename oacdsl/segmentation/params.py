"""Parameters of the automatic action segmentation (AAS), SI units.

The defaults, and why (``docs/segmentation.md`` has the long version):

- ``distance_m = 0.15`` (150 mm): the paper's Fig. 3. Markers sit on the back of the
  hand and on object corners, so two touching objects have markers 30–120 mm apart
  (KIT data README); 150 mm covers that with a margin.
- ``speed_m_s = 0.1`` (100 mm/s): the paper gives no value. A held object's markers
  move with the hand, so their distance changes by only a few cm/s (real Vicon data:
  hand–box while carrying 20–90 mm/s, marker jitter about 0.1 mm per frame = 10 mm/s
  at 100 Hz), while a hand approaching or passing an object closes the distance at
  0.3–1 m/s. 100 mm/s lies between the two.
- ``hold_s = 0.1`` (``n`` as a duration; ``frames = None`` = automatic): the frames in 0.1 s
  at the recording's rate, at least 2 (10 Hz → 2, 50 Hz → 5, 100 Hz → 10, 240 Hz → 24).
  ``n`` counts frames in Eq. 1/2, but what it must reject
  lasts a certain *time*: a hand passing an object at speed ``u`` and distance ``b``
  has ``|dist'| < v`` only for about ``2 v b / u²`` seconds around the closest point
  (0.02 s at 0.5 m/s and 5 cm), and a noise spike lasts a frame or two. The KIT data
  README recommends 2–3 frames at 10 Hz; three frames at 100 Hz (30 ms) would let slow
  pass-bys through.
- ``change_window_s = 0.1`` (100 ms): the default detectors (``robust``, ``adaptive``)
  estimate the distance change as the slope of a least-squares line through the distances
  of a centred window of this length (:mod:`~oacdsl.segmentation.slope`), not as the
  one-frame difference of Eq. 1/2: white jitter σ then gives a slope noise of about
  ``σ √24 / (w^1.5 √rate)`` instead of ``2 σ rate`` (0.5 mm at 240 Hz: 5 mm/s instead of
  240 mm/s). 0.1 s was chosen by the sweep in docs/segmentation.md ("Choosing the window").
  ``mode = "paper"`` ignores it (one-frame difference, as printed).
- ``merge_s = 0.3`` (300 ms): an object set down bounces for 0.1–0.2 s, while the
  demonstrated sub-actions last a second or more; the KIT labels and the distance
  crossings disagree by up to 3 frames (0.3 s) anyway.
- ``mode = "adaptive"`` is the default because it is the more accurate detector on real
  recordings: it learns per-pair contact distances from the recording (co-motion of a held
  object with the hand) and scores F1 1.00 on the KIT development clips against 0.85 for
  the paper's rule at its best fixed parameters (docs/segmentation-adaptive.md).
  ``mode = "paper"`` is Eq. 1 and Eq. 2 as printed
  (:class:`~oacdsl.segmentation.paper.PaperDetector`); the keyframe frames of
  ``data/dough.truth.json`` are where it fires (adaptive finds the same sub-actions and OACs,
  with keyframes up to 0.33 s apart), and the closed loop always segments the robot's
  on-surface virtual markers with it (:func:`oacdsl.pipeline.markers.robot_params`).
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass, replace
from typing import Any

from oacdsl.errors import SegmentationError

__all__ = [
    "AUTO_MIN_FRAMES",
    "AUTO_WINDOW_S",
    "DEFAULT_CHANGE_WINDOW_S",
    "CONTACTS",
    "DEFAULT_MODE",
    "AasParams",
    "frames_in",
]

#: The touch detector used unless one is named (see the module docstring for why).
DEFAULT_MODE = "adaptive"

#: How contacts are measured: between markers (the paper's), or between the library's shapes
#: posed by the markers (:mod:`oacdsl.segmentation.geomcontact`; mode ``adaptive`` only).
CONTACTS = ("markers", "geometry")

#: Seconds that ``frames=None`` spans at the recording's frame rate (the default ``hold_s``).
AUTO_WINDOW_S = 0.1
#: The fewest frames ``frames=None`` resolves to.
AUTO_MIN_FRAMES = 2
#: Seconds of the window over which the default detectors fit the distance change.
DEFAULT_CHANGE_WINDOW_S = 0.1


def frames_in(seconds: float, rate_hz: float) -> int:
    """Whole frames in ``seconds`` at ``rate_hz``, rounded half up (``round`` rounds 2.5 to 2)."""
    return int(math.floor(seconds * rate_hz + 0.5))


@dataclass(frozen=True)
class AasParams:
    """Thresholds of Eq. 1 and Eq. 2 and the keyframe merge window.

    Attributes:
        distance_m: ``d``, metres: markers closer than this may touch.
        speed_m_s: ``v``, metres per second: the absolute change of a marker pair's
            distance per second, ``|dist[i] - dist[i-1]| / (t[i] - t[i-1])``, must stay
            below this while touching begins; above it (or beyond ``d``) touching ends.
            ``math.inf`` switches the speed condition off.
        frames: ``n``, frames: how many consecutive frames a condition must hold;
            ``None`` = the frames in ``hold_s`` at the recording's rate, at
            least :data:`AUTO_MIN_FRAMES` (see :meth:`resolved`).
        merge_s: seconds: keyframes closer than this are merged (0 = no merging).
        mode: the touch detector, a key of
            :data:`~oacdsl.segmentation.detectors.DETECTORS` (``"adaptive"``, ``"robust"``
            or ``"paper"``).
        hold_s: seconds: ``n`` as a duration, used when ``frames`` is ``None``.
        change_window_s: seconds: the window of the least-squares slope that estimates
            the distance change (modes ``robust`` and ``adaptive``; ``paper`` uses the
            one-frame difference of Eq. 1/2).
        contacts: ``"markers"`` (marker-to-marker distances) or ``"geometry"`` (surface to
            surface where the library gives a class its shape and markers, the rest by
            markers: :mod:`~oacdsl.segmentation.geomcontact`; mode ``adaptive`` only, and
            only with the shapes given to :func:`~oacdsl.segmentation.aas.segment`).
    """

    distance_m: float = 0.15
    speed_m_s: float = 0.1
    frames: int | None = None
    merge_s: float = 0.3
    mode: str = DEFAULT_MODE
    hold_s: float = AUTO_WINDOW_S
    change_window_s: float = DEFAULT_CHANGE_WINDOW_S
    contacts: str = "markers"

    def __post_init__(self) -> None:
        if not (math.isfinite(self.distance_m) and self.distance_m > 0):
            raise SegmentationError(f"distance must be a positive length, got {self.distance_m} m")
        if not (self.speed_m_s > 0):  # inf allowed: no speed condition
            raise SegmentationError(f"speed must be a positive speed, got {self.speed_m_s} m/s")
        if self.frames is not None:
            if isinstance(self.frames, bool) or int(self.frames) != self.frames or self.frames < 1:
                raise SegmentationError(f"frames must be a whole number ≥ 1, got {self.frames}")
            object.__setattr__(self, "frames", int(self.frames))
        if not (math.isfinite(self.merge_s) and self.merge_s >= 0):
            raise SegmentationError(f"merge window must be a duration ≥ 0, got {self.merge_s} s")
        if not (math.isfinite(self.hold_s) and self.hold_s > 0):
            raise SegmentationError(f"hold must be a positive duration, got {self.hold_s} s")
        if not (math.isfinite(self.change_window_s) and self.change_window_s > 0):
            raise SegmentationError(
                f"change window must be a positive duration, got {self.change_window_s} s"
            )
        if self.contacts not in CONTACTS:
            raise SegmentationError(f"contacts must be one of {', '.join(CONTACTS)}, got {self.contacts!r}")
        if self.contacts == "geometry" and self.mode != "adaptive":
            raise SegmentationError(
                f"contacts from geometry need mode adaptive, not {self.mode!r}"
                + (" (mode paper is the paper's equations as printed)" if self.mode == "paper" else "")
            )

    def resolved(self, rate_hz: float) -> AasParams:
        """These parameters with ``frames`` fixed for a recording at ``rate_hz``."""
        if self.frames is not None:
            return self
        frames = max(AUTO_MIN_FRAMES, frames_in(self.hold_s, rate_hz))
        return replace(self, frames=frames)

    def half_window(self, rate_hz: float) -> int:
        """Frames on each side of the centre of the slope window at ``rate_hz`` (at least 1)."""
        return max(1, frames_in(self.change_window_s / 2, rate_hz))

    @property
    def n(self) -> int:
        """``frames`` of resolved parameters (an error before :meth:`resolved`)."""
        if self.frames is None:
            raise SegmentationError("frames is automatic until resolved for a frame rate")
        return self.frames

    def to_dict(self) -> dict[str, Any]:
        """The parameters as plain JSON values (the ``parameters`` of ``--json``)."""
        out = asdict(self)
        if self.contacts == "markers":  # the default: documents written before it stay the same
            del out["contacts"]
        if math.isinf(self.speed_m_s):
            out["speed_m_s"] = None  # JSON has no infinity: null = no speed condition
        return out
