"""Virtual markers: per-frame 3D points on the hands and objects of a simulated run.

:class:`MarkerRecorder` is an observer of the control loop (see
:class:`~oacdsl.runtime.control.Controller`): every ``1 / rate_hz`` seconds of
simulated time it stores a few points per instance — three on each hand, three on
each object, the centre of every ball of a liquid — and :meth:`MarkerRecorder.to_recording`
turns them into a :class:`~oacdsl.segmentation.recording.Recording` with one marker
group per instance, which the segmentation can read like motion capture.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

from oacdsl.errors import RuntimeFailure
from oacdsl.runtime.simworld import SimWorld
from oacdsl.segmentation.recording import Recording

__all__ = ["ContactRecorder", "MarkerRecorder", "MARKER_RATE_HZ"]

#: Default sampling rate of the virtual markers, Hz (simulated time).
MARKER_RATE_HZ = 100.0


class MarkerRecorder:
    """Collects marker points; use as an observer of the run (``execute(..., recorder=r)``)."""

    def __init__(self, rate_hz: float = MARKER_RATE_HZ) -> None:
        self.rate_hz = rate_hz
        self.times_s: list[float] = []
        self.frames: list[dict[str, np.ndarray]] = []

    def __call__(self, world: SimWorld) -> None:
        self.times_s.append(world.time_s)
        self.frames.append({k: v.copy() for k, v in world.marker_points().items()})

    def to_recording(self, source: str = "simulation") -> Recording:
        """The recorded points as a Recording (markers named ``instance/k``, metres)."""
        if not self.frames:
            raise RuntimeFailure("the run recorded no marker frames")
        instances = sorted(self.frames[0])
        names: list[str] = []
        groups: dict[str, tuple[int, ...]] = {}
        for inst in instances:
            k = len(self.frames[0][inst])
            groups[inst] = tuple(range(len(names), len(names) + k))
            names.extend(f"{inst}/{i}" for i in range(k))
        positions = np.array([np.concatenate([f[i] for i in instances]) for f in self.frames])
        times = np.array(self.times_s) - self.times_s[0]
        return Recording(source, self.rate_hz, times, tuple(names), positions, groups)


class ContactRecorder:
    """The simulation's own touching relations, every ``1 / rate_hz`` s of simulated time.

    An observer of the run like :class:`MarkerRecorder`; it stores the set of touching
    instance pairs (MuJoCo contacts between the tracked instances' geoms,
    :meth:`~oacdsl.runtime.simworld.SimWorld.relations`) only when it changes, so a run
    costs a few hundred entries. :meth:`to_json` gives the document the verifier reads
    (:mod:`oacdsl.verify_contacts`): the relations as they come, unfiltered.

    ``regrasps``: the controller's list of regrasps internal to a step (:attr:`~oacdsl.runtime.
    control.Controller.regrasps`, read when the document is made): each becomes an *internal*
    window in which the hand's relation to the object holds although the hand let go for a
    moment (a turn continued by taking the object again is not a change of the task).
    """

    def __init__(self, rate_hz: float = MARKER_RATE_HZ,
                 regrasps: Sequence[tuple[float, float, str, str]] = ()) -> None:
        self.rate_hz = rate_hz
        self.frames = 0
        self.instances: tuple[str, ...] = ()
        #: (frame, time_s, sorted relations) whenever the set changed (the first frame too).
        self.changes: list[tuple[int, float, tuple[tuple[str, str], ...]]] = []
        self._t0: float | None = None
        self._regrasps = regrasps
        self._hands: dict[str, str] = {}  # side → hand instance

    def __call__(self, world: SimWorld) -> None:
        state = world.relations()
        if self._t0 is None:
            self._t0 = world.time_s
            self.instances = tuple(sorted(state.instances))
            layout = getattr(world, "layout", None)  # a world without hands has no regrasps
            self._hands = {side: inst for inst, side in layout.hands.items()} if layout is not None else {}
        rels = tuple(state.sorted_relations())
        if not self.changes or self.changes[-1][2] != rels:
            self.changes.append((self.frames, world.time_s - self._t0, rels))
        self.frames += 1

    def internal(self) -> list[dict[str, object]]:
        """The regrasps as windows of frames: ``[{"relation", "from_frame", "to_frame"}]`` (the
        hand and the object; the frames from the one where it let go to the one after it had
        taken the object again)."""
        t0 = self._t0 or 0.0
        return [
            {"relation": sorted((self._hands.get(side, side), obj)),
             "from_frame": max(0, math.floor((a - t0) * self.rate_hz)),
             "to_frame": math.ceil((b - t0) * self.rate_hz) + 1}
            for a, b, side, obj in self._regrasps
        ]

    def to_json(self) -> dict[str, object]:
        """``{"rate_hz", "frames", "instances", "changes": [{"frame", "time_s", "relations"}],
        "internal": [...]}`` (:meth:`internal`)."""
        return {
            "rate_hz": self.rate_hz,
            "frames": self.frames,
            "instances": list(self.instances),
            "changes": [
                {"frame": f, "time_s": round(t, 6), "relations": [list(r) for r in rels]}
                for f, t, rels in self.changes
            ],
            "internal": self.internal(),
        }
