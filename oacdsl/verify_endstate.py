"""End state: where each tracked object ends, and how it is turned, against the demonstration.

Per object that is not an agent (a hand), in each recording:

- **support** at the last frame: ``held`` by a hand (touching it in the final world state);
  ``in``/``on`` another tracked object x, neither a liquid nor held by a hand (touching x in
  the final world state, its centre horizontally within x's footprint — x's markers'
  horizontal radius plus ``footprint_margin_m`` — and its lowest point not below x's by more
  than 1 cm; when each of two objects could hold the other up, the wider one does: a bowl,
  not the ladle standing in it; ``in`` when x's class is an open container); else ``table``
  (its lowest marker at most ``table_band_m`` above where it was at the first frame: markers
  sit at different heights on each object), ``fell`` (more than ``fell_m`` below that and
  below the *table level*, the lowest marker of any object at the first frame), ``in``/``on``
  x when it ends higher than that and *leans on* x: touches x (not a hand, liquid or held),
  whose lowest marker is lower (a salad server left in a bowl, its handle on the rim and its
  markers outside the bowl's footprint), or ``air`` (higher, touching nothing that holds it).
- **orientation** (:mod:`oacdsl.verify_orientation`): its turn since its start (the axis
  that pointed up at the first frame, from the vertical at the end; rigid fit of ≥ 3
  markers, :mod:`oacdsl.segmentation.poses`) and, for an elongated constellation, its long
  axis from the vertical at the start and at the end.
- **moved**: its horizontal distance from start to end.

Everything is relative (heights to the table level, distances start to end, supports by
name), so a take rotated about the vertical, translated, slower or faster compares equal.
An object passes when its support matches the demonstration's (held by the same hand, or
the mapped one under ``hand_map``), its orientation matches (below), and it is not left
within ``moved_share`` of its demonstrated displacement of
its start when the demonstration moved it ``moved_min_m`` or more ("returned to its pick-up
spot"). Orientations compare by :func:`~oacdsl.verify_orientation.compare_orientation`: the
two turns since the start within ``tilt_rad`` — or, for an elongated object whose start pose
differs between the two recordings (a tool lying before the person, standing in the robot's
scene), the two end tilts of its long axis.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass

import numpy as np

from oacdsl.segmentation.poses import MIN_MARKERS, fit_constellation
from oacdsl.segmentation.recording import Recording
from oacdsl.verify_orientation import Orientation, axis_tilts, compare_orientation, orientation_name
from oacdsl.verify_tolerances import VerifyTolerances
from oacdsl.world import WorldState

__all__ = ["EndState", "ObjectEnd", "end_state", "compare_object"]

#: Frames averaged at each end (robust to one bad frame).
_ENDS = 5


@dataclass(frozen=True)
class ObjectEnd:
    """One object's end (see the module docstring); SI units."""

    support: str  # held, in, on, table, fell, air
    supporter: str | None  # the hand or object (held/in/on)
    tilt_rad: float | None  # turn since the start; None: fewer than three markers
    moved_m: float
    #: (start, end) tilt of the long axis from the vertical, rad; None: not elongated
    axis_rad: tuple[float, float] | None = None

    @property
    def orientation(self) -> str | None:
        return None if self.tilt_rad is None else orientation_name(self.tilt_rad)

    def place(self) -> str:
        return f"{self.support} {self.supporter}" if self.supporter else self.support

    def describe(self) -> str:
        turned = "" if self.tilt_rad is None else f", {self.orientation} ({math.degrees(self.tilt_rad):.0f}°)"
        return f"{self.place()}{turned}, {self.moved_m * 100:.0f} cm from its start"


@dataclass(frozen=True)
class EndState:
    objects: dict[str, ObjectEnd]
    table_level_m: float


#: Frames read at a time when looking for the first and last frames that show an instance.
_SCAN_FRAMES = 256


def _edge_frames(recording: Recording, name: str, need: int,
                 shown: Callable[[np.ndarray], np.ndarray]) -> tuple[np.ndarray, np.ndarray]:
    """The first and the last ``need`` frame indices (increasing) whose (k, 3) positions of
    ``name``'s markers are ``shown`` (a per-frame bool of (F, k, 3) blocks), read a block of
    frames at a time from either end, not the whole recording's positions of the instance."""
    idx = list(recording.groups[name])
    n = recording.n_frames

    def scan(starts: range) -> list[int]:
        found: list[int] = []
        for lo in starts:
            frames = np.flatnonzero(shown(recording.positions_m[lo : lo + _SCAN_FRAMES, idx])) + lo
            found += frames.tolist()
            if len(found) >= need:
                break
        return found

    first = scan(range(0, n, _SCAN_FRAMES))[:need]
    backwards = range((n - 1) // _SCAN_FRAMES * _SCAN_FRAMES, -1, -_SCAN_FRAMES)
    last = sorted(scan(backwards))[-need:] if first else []
    return np.asarray(first, dtype=np.intp), np.asarray(last, dtype=np.intp)


def _all_seen(x: np.ndarray) -> np.ndarray:
    result: np.ndarray = np.isfinite(x).all(axis=(1, 2))
    return result


def _ends(recording: Recording, name: str) -> tuple[np.ndarray, np.ndarray]:
    """(first, last): the median over the first/last few frames that show every marker of
    ``name``, per marker ((k, 3) each; NaN when no frame shows them all)."""
    first, last = _edge_frames(recording, name, _ENDS, _all_seen)
    if first.size == 0:
        nan = np.full((len(recording.groups[name]), 3), np.nan)
        return nan, nan
    idx = list(recording.groups[name])
    return (np.median(recording.positions_m[first][:, idx], axis=0),
            np.median(recording.positions_m[last][:, idx], axis=0))


def _tilt(recording: Recording, name: str) -> float | None:
    """Angle between the start's up axis and the vertical at the end, radians: the rigid fit
    (:func:`~oacdsl.segmentation.poses.fit_constellation`) of the last frame that shows three
    of its markers to the first such frame's constellation."""
    if len(recording.groups[name]) < MIN_MARKERS:
        return None
    first, last = _edge_frames(recording, name, 1,
                               lambda x: np.isfinite(x).all(axis=2).sum(axis=1) >= MIN_MARKERS)
    if first.size == 0 or first[0] == last[-1]:
        return None
    idx = list(recording.groups[name])
    pts = recording.positions_m[[int(first[0]), int(last[-1])]][:, idx]
    seen = np.isfinite(pts).all(axis=2)
    start = np.where(seen[0][:, None], pts[0], np.nan)
    constellation = start - np.nanmean(start, axis=0)
    T, _ = fit_constellation(constellation, pts[1:])
    if not np.isfinite(T[0, 2, 2]):
        return None
    return float(np.arccos(np.clip(T[0, 2, 2], -1.0, 1.0)))  # the start's up axis is the world's z


def _radius(pts: np.ndarray) -> float:
    """Horizontal radius of an object's markers about their centre, metres (its footprint)."""
    c = np.nanmean(pts, axis=0)
    return float(np.nanmax(np.linalg.norm(pts[:, :2] - c[:2], axis=1)))


def _holds_up(x: str, o: str, end: Mapping[str, np.ndarray], final: WorldState,
              is_agent: Callable[[str], bool], is_liquid: Callable[[str], bool],
              tolerances: VerifyTolerances) -> bool:
    """Whether ``x`` may hold ``o`` up at the end (module docstring)."""
    if is_liquid(x) or not final.touches(o, x) or not np.isfinite(end[x]).any():
        return False
    if any(final.touches(h, x) for h in final.instances if is_agent(h)):
        return False  # held up by a hand: it holds nothing up
    pts = end[o]
    centre, low = np.nanmean(pts, axis=0), float(np.nanmin(pts[:, 2]))
    xc, x_low = np.nanmean(end[x], axis=0), float(np.nanmin(end[x][:, 2]))
    inside = np.linalg.norm(centre[:2] - xc[:2]) <= _radius(end[x]) + tolerances.footprint_margin_m
    return bool(inside and low >= x_low - 0.01 and centre[2] > x_low)


def _leans_on(o: str, objects: list[str], end: Mapping[str, np.ndarray], start: Mapping[str, np.ndarray],
              final: WorldState, is_agent: Callable[[str], bool], is_liquid: Callable[[str], bool],
              tolerances: VerifyTolerances) -> list[tuple[float, str]]:
    """(lowest marker height, x) of each object ``x`` that ``o`` leans on: ``o`` ends above
    the table band, no hand holds it, and it touches ``x`` (neither a hand, nor a liquid, nor
    held by a hand) whose lowest marker is below ``o``'s. Nothing stays above the table
    untouched by a hand unless what it touches holds it up: a salad spoon left in a bowl with
    its handle on the rim, whose markers (on the handle) are outside the bowl's footprint."""
    low = float(np.nanmin(end[o][:, 2]))
    if low <= float(np.nanmin(start[o][:, 2])) + tolerances.table_band_m:
        return []
    out = []
    for x in objects:
        if x == o or is_liquid(x) or not final.touches(o, x) or not np.isfinite(end[x]).any():
            continue
        if any(final.touches(h, x) for h in final.instances if is_agent(h)):
            continue
        x_low = float(np.nanmin(end[x][:, 2]))
        if x_low < low:
            out.append((x_low, x))
    return out


def end_state(
    recording: Recording,
    final: WorldState,
    is_agent: Callable[[str], bool],
    is_container: Callable[[str], bool],
    tolerances: VerifyTolerances,
    is_liquid: Callable[[str], bool] = lambda _: False,
) -> EndState:
    """Every non-agent instance's end (module docstring); ``final``: the last world state."""
    start: dict[str, np.ndarray] = {}
    end: dict[str, np.ndarray] = {}
    for name in recording.instances:
        start[name], end[name] = _ends(recording, name)  # (k, 3) each
    objects = [n for n in recording.instances if not is_agent(n)]
    lows = [float(np.nanmin(start[n][:, 2])) for n in objects if np.isfinite(start[n]).any()]
    table = min(lows) if lows else 0.0
    out: dict[str, ObjectEnd] = {}
    for o in objects:
        pts = end[o]
        if not np.isfinite(pts).any():
            continue
        low = float(np.nanmin(pts[:, 2]))
        moved = float(np.linalg.norm(np.nanmean(end[o], axis=0)[:2] - np.nanmean(start[o], axis=0)[:2]))
        hands = sorted(h for h in final.instances if is_agent(h) and final.touches(h, o))
        support, by = "", None
        if hands:
            support, by = "held", hands[0]
        else:
            under = [(float(np.nanmin(end[x][:, 2])), x) for x in objects
                     if x != o and _holds_up(x, o, end, final, is_agent, is_liquid, tolerances)
                     and not (_radius(end[o]) > _radius(end[x])
                              and _holds_up(o, x, end, final, is_agent, is_liquid, tolerances))]
            leans = [] if under else _leans_on(o, objects, end, start, final, is_agent, is_liquid, tolerances)
            if under or leans:
                by = max(under)[1] if under else max(leans)[1]
                support = "in" if is_container(by) else "on"
            else:
                # its own lowest marker as it stood at the start: markers sit at different
                # heights on each object (the table level is the lowest of them all)
                ref = float(np.nanmin(start[o][:, 2]))
                if low < min(ref, table) - tolerances.fell_m:
                    support = "fell"
                elif low <= ref + tolerances.table_band_m:
                    support = "table"
                else:
                    support = "air"
        axis = axis_tilts(start[o], end[o], tolerances.elongated_ratio)
        out[o] = ObjectEnd(support, by, _tilt(recording, o), moved, axis)
    return EndState(out, table)


def compare_object(
    name: str,
    demo: ObjectEnd,
    run: ObjectEnd,
    tolerances: VerifyTolerances,
    hand_map: Mapping[str, str],
) -> list[tuple[str, bool, str, str, str, str]]:
    """The checks of one object: (aspect, passed, demonstration, execution, tolerance, detail)."""
    out = []
    want = demo.supporter
    if demo.support == "held" and want is not None:
        want = hand_map.get(want, want)
    same_kind = {demo.support, run.support} <= {"in", "on"} or demo.support == run.support
    ok = same_kind and (want == run.supporter)
    detail = "" if ok else f"{name} ends {run.place()}, the demonstration's {demo.place()}"
    if not ok and run.support == "fell":
        detail = f"{name} fell: it ends below the table, the demonstration's {demo.place()}"
    out.append(("support", ok, demo.place(), run.place(), "same support", detail))
    turned = compare_orientation(name, Orientation(demo.tilt_rad, demo.axis_rad),
                                 Orientation(run.tilt_rad, run.axis_rad), tolerances)
    if turned is not None:
        out.append(("orientation", *turned))
    if demo.moved_m >= tolerances.moved_min_m and demo.support != "held":
        least = tolerances.moved_share * demo.moved_m
        ok = run.moved_m >= least
        detail = "" if ok else (
            f"{name} ends {run.moved_m * 100:.0f} cm from where it started (back at its pick-up spot);"
            f" the demonstration put it {demo.moved_m * 100:.0f} cm away"
        )
        out.append(("placed", ok, f"{demo.moved_m:.3f} m", f"{run.moved_m:.3f} m",
                    f">= {tolerances.moved_share:g} x demonstrated", detail))
    return out
