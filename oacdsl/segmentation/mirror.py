"""A mirrored take: the demonstration as a left-handed person would do it (and vice versa).

Every position is reflected across the demonstrator's **sagittal plane**, a vertical plane
(the mirrored person stands on the same floor), found in this order:

1. the plane given by the caller (a point and a normal);
2. the subject's torso markers (KIT/Vicon marker set): the normal is the median over
   frames of the horizontal direction from the right to the left member of the pairs
   ``RSHO``/``LSHO``, ``RASI``/``LASI``, ``RPSI``/``LPSI`` (or, without any pair, the
   horizontal perpendicular of ``C7`` → ``CLAV``); the plane passes through the median over
   frames of the midline markers ``CLAV``, ``STRN``, ``C7``, ``T10`` and the pairs' midpoints;
3. without torso markers (e.g. the synthetic ``data/dough.c3d``): the plane halfway between
   the two hands' mean positions (groups ``left_hand``/``right_hand``, or the KIT hand
   markers), perpendicular to the horizontal line between them.

Otherwise the take cannot be made (:class:`RecordingError`). Medians over frames make the
plane robust to a few bad frames, and the reflection of a mirrored take across its own
plane gives back the original: :func:`mirrored` is an involution.

Then left and right are exchanged: a marker whose label has a mirror label in the recording
(``LHPS`` ↔ ``RHPS``, ``left_hand:LHTS`` ↔ ``right_hand:RHTS``: a leading ``L``/``R`` and
the words ``left``/``right`` exchanged) takes its partner's reflected trajectory, so labels
and groups stay as they are and the original right hand now appears as the left hand.
Groups named for a side whose markers have no such partners (``left_gripper`` with ``a``,
``b``) exchange their names instead. Objects are reflected too: their marker layouts are the
mirror images of the originals.
"""

from __future__ import annotations

import re
from collections.abc import Sequence

import numpy as np

from oacdsl.errors import RecordingError
from oacdsl.segmentation.grouping import KIT_HANDS
from oacdsl.segmentation.recording import Recording

__all__ = [
    "HANDS",
    "TORSO_PAIRS",
    "MIDLINE",
    "hand_indices",
    "mirror_label",
    "mirrored",
    "sagittal_plane",
    "subject_indices",
]

#: The instances that are the demonstrator's hands.
HANDS = ("left_hand", "right_hand")
#: Torso marker pairs (left, right) whose difference is the sagittal plane's normal.
TORSO_PAIRS = (("LSHO", "RSHO"), ("LASI", "RASI"), ("LPSI", "RPSI"))
#: Torso markers on the sagittal plane.
MIDLINE = ("CLAV", "STRN", "C7", "T10")

_WORD = re.compile(r"(?i)(?<![a-z])(left|right)(?![a-z])")


def _bare(label: str) -> str:
    return label.rsplit(":", 1)[-1]


def _swap_word(text: str) -> str:
    def swap(m: re.Match[str]) -> str:
        word = m.group(1)
        new = "right" if word.lower() == "left" else "left"
        return new.upper() if word.isupper() else new.capitalize() if word[0].isupper() else new

    return _WORD.sub(swap, text)


def mirror_label(label: str) -> str:
    """The label of the marker on the other side: ``LSHO`` → ``RSHO``, ``left_hand:LHTS`` →
    ``right_hand:RHTS`` (a leading L/R of the marker's own name, the words left/right)."""
    head, sep, tail = label.rpartition(":")
    if len(tail) > 1 and tail[0] in "LR" and (tail[1].isupper() or tail[1].isdigit()):
        tail = ("R" if tail[0] == "L" else "L") + tail[1:]
    else:
        tail = _swap_word(tail)
    return f"{_swap_word(head)}{sep}{tail}"


def _by_bare(rec: Recording, names: Sequence[str]) -> dict[str, int]:
    """Index of each of ``names`` found as a marker's own name (the first such marker)."""
    found: dict[str, int] = {}
    for i, label in enumerate(rec.marker_names):
        bare = _bare(label)
        if bare in names and bare not in found:
            found[bare] = i
    return found


def subject_indices(rec: Recording) -> list[int]:
    """Markers of the subject's body (torso and KIT hand markers found in the recording)."""
    names = [
        *MIDLINE,
        *(n for pair in TORSO_PAIRS for n in pair),
        *(n for h in KIT_HANDS.values() for n in h),
    ]
    return sorted(_by_bare(rec, names).values())


def hand_indices(rec: Recording, side: str) -> list[int]:
    """The markers of hand ``side`` (``left_hand``/``right_hand``): its group, else the KIT hand markers."""
    if side in rec.groups:
        return list(rec.groups[side])
    return list(_by_bare(rec, KIT_HANDS[side]).values())


def _horizontal_unit(v: np.ndarray) -> np.ndarray:
    """(F, 3) → (F, 3) horizontal unit vectors (NaN where undefined)."""
    h = v.copy()
    h[..., 2] = 0.0
    n = np.linalg.norm(h, axis=-1, keepdims=True)
    with np.errstate(all="ignore"):
        return np.where(n > 1e-9, h / n, np.nan)


def _median_direction(units: np.ndarray) -> np.ndarray | None:
    """The median horizontal direction of (K, 3) unit vectors: the median angle about their
    circular mean (so that reflecting the vectors reflects the result)."""
    units = units[np.all(np.isfinite(units), axis=1)]
    if units.shape[0] == 0:
        return None
    ref = np.arctan2(units[:, 1].sum(), units[:, 0].sum())
    dev = np.angle(np.exp(1j * (np.arctan2(units[:, 1], units[:, 0]) - ref)))
    a = ref + float(np.median(dev))
    return np.array([np.cos(a), np.sin(a), 0.0])


def _torso_plane(rec: Recording) -> tuple[np.ndarray, np.ndarray] | None:
    p = rec.positions_m
    found = _by_bare(rec, [*MIDLINE, *(n for pair in TORSO_PAIRS for n in pair)])
    pairs = [(found[a], found[b]) for a, b in TORSO_PAIRS if a in found and b in found]
    if pairs:
        units = np.concatenate([_horizontal_unit(p[:, a] - p[:, b]) for a, b in pairs])
    elif "CLAV" in found and "C7" in found:  # front minus back, turned a quarter to the left
        front = _horizontal_unit(p[:, found["CLAV"]] - p[:, found["C7"]])
        units = np.stack([-front[:, 1], front[:, 0], np.zeros(len(front))], axis=1)
    else:
        return None
    normal = _median_direction(units)
    if normal is None:
        return None
    points = [p[:, found[m]] for m in MIDLINE if m in found] + [(p[:, a] + p[:, b]) / 2 for a, b in pairs]
    offsets = np.stack(points, axis=1) @ normal  # (F, K)
    rows = np.isfinite(offsets).any(axis=1)
    if not rows.any():
        return None
    d = float(np.median(np.nanmedian(offsets[rows], axis=1)))
    return normal * d, normal


def _hands_plane(rec: Recording) -> tuple[np.ndarray, np.ndarray] | None:
    means = []
    for side in HANDS:
        idx = hand_indices(rec, side)
        if not idx:
            return None
        xyz = rec.positions_m[:, idx].reshape(-1, 3)
        xyz = xyz[np.all(np.isfinite(xyz), axis=1)]
        if xyz.size == 0:
            return None
        means.append(xyz.mean(axis=0))
    normal = _horizontal_unit((means[0] - means[1])[None])[0]
    if not np.all(np.isfinite(normal)):
        return None
    return (means[0] + means[1]) / 2, normal


def sagittal_plane(
    rec: Recording, plane: tuple[Sequence[float], Sequence[float]] | None = None
) -> tuple[np.ndarray, np.ndarray, str]:
    """(a point on the plane, its unit normal, how it was found: ``given``, ``torso`` or
    ``hands``); see the module docstring. :class:`RecordingError` when none can be found."""
    if plane is not None:
        point, normal = (np.asarray(v, dtype=np.float64).ravel() for v in plane)
        length = float(np.linalg.norm(normal)) if normal.shape == (3,) else 0.0
        if point.shape != (3,) or not np.all(np.isfinite(point)) or not length > 1e-12:
            raise RecordingError(
                "a mirror plane is a point (x, y, z) and a non-zero normal (x, y, z)", location=rec.source
            )
        return point, normal / length, "given"
    for how, find in (("torso", _torso_plane), ("hands", _hands_plane)):
        found = find(rec)
        if found is not None:
            return found[0], found[1], how
    raise RecordingError(
        "cannot mirror: no sagittal plane (no torso markers such as LSHO/RSHO, LASI/RASI,"
        " CLAV/C7, and no left_hand and right_hand; give a plane)",
        location=rec.source,
    )


def _exchange(rec: Recording) -> tuple[np.ndarray, dict[str, tuple[int, ...]], dict[str, str]]:
    """The column permutation that exchanges left and right, the groups and the group map."""
    index = {n: i for i, n in enumerate(rec.marker_names)}
    order = np.arange(len(rec.marker_names))
    for i, label in enumerate(rec.marker_names):
        j = index.get(mirror_label(label))
        if j is not None and mirror_label(rec.marker_names[j]) == label:
            order[i] = j
    groups = dict(rec.groups)
    exchanged: dict[str, str] = {}
    for g, idx in rec.groups.items():
        other = _swap_word(g)
        if other == g:
            continue
        if other in rec.groups:
            exchanged[g] = other
            if sorted(order[list(idx)]) != sorted(rec.groups[other]):  # markers not paired: swap the names
                groups[g] = rec.groups[other]
    return order, groups, exchanged


def mirrored(
    rec: Recording, plane: tuple[Sequence[float], Sequence[float]] | None = None
) -> tuple[Recording, dict[str, str]]:
    """The recording reflected across the demonstrator's sagittal plane (or ``plane``: a point
    and a normal, metres), left and right exchanged; see the module docstring.

    Returns the take and the hand map: instance of the original → the instance that plays
    its part in the take (``{"left_hand": "right_hand", "right_hand": "left_hand"}`` and any
    other group named for a side)."""
    point, normal, how = sagittal_plane(rec, plane)
    p = rec.positions_m
    reflected = p - 2.0 * ((p - point) @ normal)[..., None] * normal
    order, groups, exchanged = _exchange(rec)
    hand_map = {"left_hand": "right_hand", "right_hand": "left_hand", **exchanged}
    take = Recording(
        f"{rec.source} (mirrored, {how} plane)",
        rec.rate_hz,
        rec.times_s.copy(),
        rec.marker_names,
        reflected[:, order],
        groups,
        rec.first_frame,
    )
    return take, hand_map
