"""Contacts from geometry (``AasParams.contacts = "geometry"``, a mode beyond the paper).

Where the library gives an instance's class a shape and its markers' positions, the shape is
posed by the rigid fit of the markers and two instances touch while the gap between their
surfaces (:func:`~oacdsl.segmentation.shapefit.surface_gaps`; a hand: a palm-and-finger volume
around its markers) stays within the pair's **tolerance**

    tol = CONTACT_FRACTION × min(size_a, size_b) + misfit_a + misfit_b + NOISE_FACTOR × (noise_a + noise_b)

— a fraction of the smaller object's size across (a hand: its volume's thickness), how far each
shape may be off its object (its declared markers' misfit to the recorded ones) and the
recording's measured noise (the rigid fit's residual) — not a fixed distance between markers.
A long cucumber whose markers sit at one end touches the peeler at its other end; a spoon in a bowl touches it
whatever the scene's scale (the inside of a container counts as the container); a knife
lifted off the board it lay on stops touching it.

A pair's contact is a run of frames within the tolerance, lasting ``n`` frames (``AasParams``'
hold) at least, with excursions of at most ``tool_bridge_s`` bridged; a frame without a pose
keeps the state before it. A hand that comes to an object and stays there holds it, moving or
still. A hand already within the tolerance of an object at the first frame may only rest beside
it (a demonstrator's hands rest by the objects before the task starts, and a modelled shape is
not the object): geometry cannot tell that from a hold, so that first run is left to the markers
(``GeometryContacts.undecided``). A hand that carries an object (the adaptive detector's
co-motion episodes of the pair: they move together) holds it whatever the gap: a hand's volume
is a model of the hand under the markers on its back, not of the fingers around the object,
which may close 1-2 cm beyond it (``carried`` of :func:`decided_by_geometry`).

Pairs measured this way are decided by geometry alone (:class:`AdaptiveDetector
<oacdsl.segmentation.adaptive.AdaptiveDetector>` overrides its marker rules for them; its
cross-hand rule still applies); an instance without a usable shape (none in the library, a
mesh, markers that do not fit its declared ones, fewer than three markers) is measured by its
markers as before, and so is every pair of two hands. :attr:`GeometryContacts.report` says for
each instance which it was, and why.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np

from oacdsl.segmentation.episodes import true_runs, union_spans
from oacdsl.segmentation.pairs import PairTable
from oacdsl.segmentation.recording import Recording
from oacdsl.segmentation.shapefit import HandVolume, PosedShape, hand_volume, pose_shape, surface_gaps
from oacdsl.segmentation.shapes import ShapeModel

__all__ = [
    "CONTACT_FRACTION",
    "NOISE_FACTOR",
    "GeometryContacts",
    "complement_spans",
    "decided_by_geometry",
    "geometric_contacts",
    "tolerance_m",
]

#: Fraction of the smaller instance's size across that two surfaces may stay apart and touch
#: (10 %: 8 mm for an 8 cm cup; the shapes are models, the markers sit on stalks).
CONTACT_FRACTION = 0.10
#: Multiples of the two shapes' noise (rigid-fit residual) added to the tolerance (3 σ).
NOISE_FACTOR = 3.0

Spans = list[tuple[int, int]]


@dataclass(frozen=True)
class GeometryContacts:
    """Per measured instance pair (every one, ``[]`` when they never touch), the frame intervals
    ``[a, b)`` of contact; ``undecided``: measured pair → the intervals geometry leaves to the
    markers (a hand within reach from the first frame); ``report``: instance → ``"shape"``,
    ``"hand"`` or why its markers are used; ``tolerance_m``: measured instance pair → its
    tolerance, metres."""

    spans: dict[int, Spans]
    undecided: dict[int, Spans]
    report: dict[str, str]
    tolerance_m: dict[int, float]


def tolerance_m(a: PosedShape | HandVolume, b: PosedShape | HandVolume) -> float:
    """The pair's contact tolerance, metres (module doc; a hand has neither misfit nor noise)."""
    shapes = [x for x in (a, b) if isinstance(x, PosedShape)]
    errors = sum(x.misfit_m + NOISE_FACTOR * x.noise_m for x in shapes)
    return CONTACT_FRACTION * min(a.extent_m, b.extent_m) + errors



def _contact_spans(gap: np.ndarray, tol: float, hold: int, bridge: int, hand: bool) -> tuple[Spans, Spans]:
    """Runs of ``gap ≤ tol`` (NaN: the state before), bridged and at least ``hold`` frames long,
    and the frames left undecided (a hand's run from the first frame, module doc)."""
    known = np.isfinite(gap)
    within = np.zeros(gap.size, dtype=bool)
    within[known] = gap[known] <= tol
    if not known.all():  # a frame without a pose keeps the state before it
        last = np.maximum.accumulate(np.where(known, np.arange(gap.size), -1))
        within = np.where(last >= 0, within[np.maximum(last, 0)], False)
    spans: Spans = []
    for a, b in true_runs(within):
        if spans and a - spans[-1][1] <= bridge:
            spans[-1] = (spans[-1][0], b)
        else:
            spans.append((a, b))
    undecided = [spans.pop(0)] if hand and spans and spans[0][0] == 0 else []
    return [(a, b) for a, b in spans if b - a >= hold], undecided


def geometric_contacts(
    recording: Recording,
    table: PairTable,
    shapes: Mapping[str, ShapeModel],
    agents: Sequence[int],
    hold_frames: int,
    bridge_s: float,
) -> GeometryContacts:
    """Contacts of every pair measured by geometry (module doc). ``shapes``: instance → its
    class's shape; ``agents``: the hands (table indices); ``hold_frames``: ``n``; ``bridge_s``:
    seconds beyond the tolerance that do not end a contact."""
    bodies: dict[int, PosedShape | HandVolume] = {}
    report: dict[str, str] = {}
    for i, name in enumerate(table.instances):
        if i in agents:
            bodies[i] = hand_volume(recording, name)
            report[name] = "hand"
            continue
        model = shapes.get(name)
        if model is None:
            report[name] = "markers: no measurable shape in the library"
            continue
        posed, why = pose_shape(recording, name, model)
        if posed is None:
            report[name] = f"markers: {why}"
            continue
        bodies[i] = posed
        report[name] = "shape"
    bridge = round(bridge_s * recording.rate_hz)
    spans: dict[int, Spans] = {}
    undecided: dict[int, Spans] = {}
    tolerances: dict[int, float] = {}
    for q, (a, b) in enumerate(table.instance_pairs.tolist()):
        if a not in bodies or b not in bodies or (a in agents and b in agents):  # two hands: markers
            continue
        tol = tolerance_m(bodies[a], bodies[b])
        gap = surface_gaps(bodies[a], bodies[b], within_m=tol)
        hand = a in agents or b in agents
        spans[q], undecided[q] = _contact_spans(gap, tol, hold_frames, bridge, hand)
        tolerances[q] = tol
    return GeometryContacts(spans, undecided, report, tolerances)



def complement_spans(spans: Spans, n_frames: int) -> Spans:
    """The frames of ``[0, n_frames)`` outside the sorted, disjoint ``spans``."""
    out: Spans = []
    at = 0
    for a, b in spans:
        if a > at:
            out.append((at, a))
        at = max(at, b)
    if at < n_frames:
        out.append((at, n_frames))
    return out


def decided_by_geometry(geo: GeometryContacts, added: Mapping[int, Spans], removed: Mapping[int, Spans],
                        n_frames: int, carried: Mapping[int, Spans] | None = None
                        ) -> tuple[dict[int, Spans], dict[int, Spans]]:
    """The adaptive detector's contacts ``added`` and ``removed`` (instance pair → intervals) with
    every pair of ``geo`` decided by geometry: added where it touches, removed elsewhere but where
    it leaves the pair to the markers (a removal the detector had, the cross-hand rule's, stays)
    and where a hand carries the object (``carried``: hand–object pair → its co-motion episodes,
    which the detector's episodes keep as contacts; module doc)."""
    new_added, new_removed = dict(added), dict(removed)
    for q, spans in geo.spans.items():
        undecided = geo.undecided.get(q, [])
        new_added[q] = union_spans([*added.get(q, []), *spans]) if undecided else list(spans)
        kept = (carried or {}).get(q, [])
        outside = complement_spans(union_spans([*spans, *undecided, *kept]), n_frames)
        new_removed[q] = union_spans([*removed.get(q, []), *outside])
    return new_added, new_removed
