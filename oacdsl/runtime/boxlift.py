"""How far one set of boxes must rise to keep clear of another: separating axes, shifted in z.

A hand pouring over a cup that the other hand holds must pass that hand's palm, fingers and
thumb. Their bounding boxes (:func:`oacdsl.runtime.shapes.hand_corners`, as the hand is now)
are oriented boxes; so are the pouring hand's and its object's at a planned pose. Two convex
boxes overlap exactly when their projections overlap on each of 15 axes (the three edges of
each and their nine cross products); moving one of them up by ``dz`` moves each projection
linearly, so the heights at which a pair overlaps form one interval, and the least lift that
clears every pair is the lowest height not inside any of them. Unlike the columns over a box's
footprint, a box beside another at the same height needs no lift (metres throughout).
"""

from __future__ import annotations

import numpy as np

__all__ = ["oriented_boxes", "overlap_heights", "lift_to_clear"]

#: Below this |z| component an axis does not change with the lift (its overlap is all or nothing).
_FLAT = 1e-9


def oriented_boxes(corners: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(centres (k, 3), unit axes (k, 3, 3) one per row, half extents (k, 3)) of the k boxes whose
    corners ``corners`` (8k, 3) lists eight per box, x outermost, then y, then z, minus before
    plus (the order of :func:`~oacdsl.runtime.shapes.corners` and ``hand_corners``)."""
    c = np.asarray(corners, dtype=float).reshape(-1, 8, 3)
    edges = np.stack([c[:, 4] - c[:, 0], c[:, 2] - c[:, 0], c[:, 1] - c[:, 0]], axis=1)
    lengths = np.linalg.norm(edges, axis=2)
    axes = edges / np.maximum(lengths, 1e-12)[:, :, None]
    # a flat box (a zero edge) gets an axis normal to the other two (its projection is still right)
    for k, i in zip(*np.nonzero(lengths < 1e-12), strict=True):
        other = np.cross(axes[k, (i + 1) % 3], axes[k, (i + 2) % 3])
        axes[k, i] = other / max(float(np.linalg.norm(other)), 1e-12)
    return c.mean(axis=1), axes, lengths / 2


def overlap_heights(moving: np.ndarray, fixed: np.ndarray, margin_m: float = 0.0) -> np.ndarray:
    """(p, 2) intervals ``[lo, hi]`` of upward shifts (m) of the boxes with corners ``moving`` at
    which one of them overlaps one of the boxes ``fixed`` grown by ``margin_m`` on every side
    (only the pairs that overlap at some shift; ``-inf``/``inf`` when a pair overlaps at any)."""
    ca, ra, ha = oriented_boxes(moving)
    cb, rb, hb = oriented_boxes(fixed)
    hb = hb + margin_m
    m, n = len(ca), len(cb)
    if m == 0 or n == 0:
        return np.zeros((0, 2))
    ra_, rb_ = np.repeat(ra, n, axis=0), np.tile(rb, (m, 1, 1))  # (p, 3, 3), p = m n pairs
    ha_, hb_ = np.repeat(ha, n, axis=0), np.tile(hb, (m, 1))
    d0 = np.repeat(ca, n, axis=0) - np.tile(cb, (m, 1))  # (p, 3)
    cross = np.cross(ra_[:, :, None, :], rb_[:, None, :, :]).reshape(-1, 9, 3)
    axes = np.concatenate([ra_, rb_, cross], axis=1)  # (p, 15, 3)
    norm = np.linalg.norm(axes, axis=2)
    usable = norm > 1e-9  # parallel edges give no cross axis
    axes = axes / np.maximum(norm, 1e-12)[:, :, None]
    reach = (np.abs(np.einsum("pij,pkj->pki", ra_, axes)) * ha_[:, None, :]).sum(axis=2) + (
        np.abs(np.einsum("pij,pkj->pki", rb_, axes)) * hb_[:, None, :]).sum(axis=2)  # (p, 15)
    d = np.einsum("pj,pkj->pk", d0, axes)
    lz = axes[:, :, 2]
    flat = np.abs(lz) < _FLAT
    with np.errstate(divide="ignore", invalid="ignore"):
        a, b = (-reach - d) / lz, (reach - d) / lz
    lo = np.where(flat, np.where(np.abs(d) < reach, -np.inf, np.inf), np.minimum(a, b))
    hi = np.where(flat, np.where(np.abs(d) < reach, np.inf, -np.inf), np.maximum(a, b))
    lo = np.where(usable, lo, -np.inf).max(axis=1)
    hi = np.where(usable, hi, np.inf).min(axis=1)
    keep = lo < hi
    return np.stack([lo[keep], hi[keep]], axis=1)


def lift_to_clear(moving: np.ndarray, fixed: np.ndarray, margin_m: float = 0.0, from_m: float = 0.0) -> float:
    """The least upward shift (m), at least ``from_m``, of the boxes with corners ``moving`` after
    which none of them comes within ``margin_m`` of the boxes with corners ``fixed``."""
    spans = overlap_heights(moving, fixed, margin_m)
    dz = from_m
    moved = True
    while moved:  # the lowest height at or above from_m inside none of the intervals
        inside = (spans[:, 0] < dz) & (dz < spans[:, 1])
        moved = bool(inside.any())
        if moved:
            dz = float(spans[inside, 1].max())
    return dz
