"""Where the demonstration sets each object down, mapped onto the robot's table.

``layout demonstrated`` puts the objects where the recording's first frame has them
(:mod:`oacdsl.runtime.demo_layout`). A person who moves an object somewhere else (a mug handed
over and set down on the other side, a lid taken off a bottle and laid on the table) leaves
it at a *set-down place*: the object stands still there (its markers' mean moving slower than
:data:`STILL_M_S` for :data:`REST_S` or longer), no higher than where it started plus
:data:`LEVEL_M` (held still up in the air is no place), let go of (at some moment of that
stillness no hand is within :data:`RELEASED_M` of it: a tool held still on a board is not set
down), at least :data:`MOVED_M` from where it stood before (its start or its previous
set-down place). :func:`set_down_places` lists them in
order, per object.

:func:`mapped_set_downs` brings them onto the robot's table in the layout's own frame and
scale (:class:`~oacdsl.runtime.demo_layout.TableMap`), relative to the object whose
first-frame place is nearest in the demonstration (the object itself, when it went nowhere
near another): the place's offset from that object's start is scaled and turned as the
layout is, and added to where that object stands on the robot's table (after the seed's
shift and the layout's pushing apart). ``place`` takes the k-th of an object's places for
its k-th set-down on the table (:mod:`oacdsl.runtime.skills.place`).

Units: metres and seconds; the motion capture's z axis is up.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np

from oacdsl.library import Library
from oacdsl.model import Scene
from oacdsl.runtime.demo_layout import TableMap, table_map
from oacdsl.segmentation.episodes import true_runs
from oacdsl.segmentation.recording import Recording

__all__ = [
    "STILL_M_S", "REST_S", "LEVEL_M", "MOVED_M", "RELEASED_M",
    "set_down_places", "mapped_set_downs", "set_downs_on_table", "scene_hands",
]

#: Speed (of the markers' mean, m/s) below which an object stands still.
STILL_M_S = 0.02
#: How long it must stand still to be set down there, s.
REST_S = 0.3
#: How much higher than where it started a set-down place may be, m (what is held up is not set down).
LEVEL_M = 0.03
#: How far from where it stood before a place must be to be another one, m.
MOVED_M = 0.05
#: No hand (its markers' mean) this near an object (its markers' mean): let go of, m.
RELEASED_M = 0.15
#: The window over which speeds are taken, s (half on each side).
_WINDOW_S = 0.2


def set_down_places(
    recording: Recording, names: Sequence[str], hands: Sequence[str] = ()
) -> dict[str, list[np.ndarray]]:
    """Each named marker group's set-down places (module docstring) in the order they are
    reached: the median of its markers' mean (m) over each still stretch. Objects never
    moved elsewhere are left out; ``hands`` (marker groups) are no objects, and without
    any in the recording every still stretch counts as let go of."""
    out: dict[str, list[np.ndarray]] = {}
    half = max(1, int(round(0.5 * _WINDOW_S * recording.rate_hz)))
    least = max(1, int(round(REST_S * recording.rate_hz)))
    hand_paths = [_mean_path(recording, h) for h in hands if h in recording.groups]
    for name in names:
        if name not in recording.groups or name in hands:
            continue
        pos = _mean_path(recording, name)  # (frames, 3)
        seen = np.flatnonzero(np.isfinite(pos).all(axis=1))
        if seen.size < 2 * half + least:
            continue
        pos = pos[seen[0]:]
        near = np.zeros(len(pos), dtype=bool)  # a hand near it (unseen: not known to be away)
        for path in hand_paths:
            gap = np.linalg.norm(path[seen[0]:] - pos, axis=1)
            near |= ~(gap > RELEASED_M)
        speed = np.full(len(pos), np.inf)
        span_s = 2 * half / recording.rate_hz
        speed[half:-half] = np.linalg.norm(pos[2 * half:] - pos[:-2 * half], axis=1) / span_s
        still = np.isfinite(speed) & (speed < STILL_M_S)
        start = pos[0]
        before = start
        places: list[np.ndarray] = []
        for a, b in true_runs(still.astype(bool)):
            if b - a < least:
                continue
            here = np.median(pos[a:b], axis=0)
            if here[2] > start[2] + LEVEL_M or (hand_paths and near[a:b].all()):
                continue  # held up, or held still
            if float(np.linalg.norm(here[:2] - before[:2])) < MOVED_M:
                continue
            places.append(here)
            before = here
        if places:
            out[name] = places
    return out


def mapped_set_downs(
    places: Mapping[str, Sequence[np.ndarray]],
    first: Mapping[str, np.ndarray],
    mapping: TableMap,
    placed: Mapping[str, tuple[float, float]],
) -> dict[str, tuple[tuple[float, float], ...]]:
    """Robot-table (x, y) of each object's set-down places (``places``, demonstration m),
    relative to the object of ``first`` (first-frame positions, m) whose start is nearest,
    among those ``placed`` (robot-table x, y, m) as demonstrated (module docstring)."""
    out: dict[str, tuple[tuple[float, float], ...]] = {}
    refs = [n for n in sorted(first) if n in placed]
    for name, ps in places.items():
        if name not in placed or not refs:
            continue
        xys = []
        for p in ps:
            gaps = {n: float(np.linalg.norm(np.asarray(first[n])[:2] - p[:2])) for n in refs}
            ref = min(refs, key=lambda n: (gaps[n], n != name))  # on a tie, the object itself
            xy = np.asarray(placed[ref], float) + mapping(p) - mapping(first[ref])
            xys.append((float(xy[0]), float(xy[1])))
        out[name] = tuple(xys)
    return out


def set_downs_on_table(
    set_downs: Mapping[str, Sequence[np.ndarray]],
    first: Mapping[str, np.ndarray],
    hands: Mapping[str, np.ndarray],
    radii: Mapping[str, float],
    placed: Mapping[str, tuple[float, float]],
    stacks: Mapping[str, str],
) -> dict[str, tuple[tuple[float, float], ...]]:
    """:func:`mapped_set_downs` for a layout: ``radii`` names the objects laid out as
    demonstrated (footprints, m), ``stacks`` those of them standing on another at the start
    (not in the layout's own :func:`~oacdsl.runtime.demo_layout.table_map`), ``hands`` the
    demonstrator's hands (``"r"``/``"l"`` → first-frame position, m)."""
    laid = {n: np.asarray(first[n], float) for n in radii if n in first}
    unstacked = {n: p for n, p in laid.items() if n not in stacks}
    if not unstacked:
        return {}
    mapping = table_map(unstacked, hands, {n: radii[n] for n in unstacked})
    places = {n: p for n, p in set_downs.items() if n in laid}
    return mapped_set_downs(places, laid, mapping, {n: placed[n] for n in laid})


def scene_hands(library: Library, scene: Scene) -> list[str]:
    """The instances of ``scene`` whose geometry is a hand (their marker groups are no objects;
    ``ignored`` instances are not built and left out)."""
    from oacdsl.geometry import ROLE_HAND
    from oacdsl.runtime.bodies import bodies_for_scene

    built = scene.model_copy(update={"instances": tuple(i for i in scene.instances if not i.ignored)})
    return sorted(n for n, b in bodies_for_scene(library, built).items() if b.role == ROLE_HAND)


def _mean_path(recording: Recording, name: str) -> np.ndarray:
    """(frames, 3) mean of the group's markers seen at each frame (NaN where none is), m."""
    pos = recording.group_positions(name)
    seen = np.isfinite(pos).all(axis=2)
    count = seen.sum(axis=1)
    total = np.where(seen[..., None], pos, 0.0).sum(axis=1)
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.where(count[:, None] > 0, total / count[:, None], np.nan)
