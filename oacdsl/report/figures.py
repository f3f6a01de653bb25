"""Pictures for the report, drawn with matplotlib's object API (no pyplot, no global state).

Each function returns PNG bytes. :func:`world_state_png` and :func:`relation_timeline_png`
draw from the result's data alone (the page uses them when the result gives no picture);
:func:`marker_snapshot_png` draws a recording's markers at one frame, for the pipeline to put
into ``segment.keyframes[i].image``. :func:`save_png` writes bytes atomically.
"""

from __future__ import annotations

import functools
import io
import math
import os
from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

from oacdsl.atomic import write_atomic

if TYPE_CHECKING:
    from oacdsl.segmentation.recording import Recording

__all__ = ["instance_colour", "marker_snapshot_png", "relation_timeline_png", "save_png", "world_state_png"]

_PALETTE = [
    "#1f77b4",
    "#ff7f0e",
    "#2ca02c",
    "#d62728",
    "#9467bd",
    "#8c564b",
    "#e377c2",
    "#7f7f7f",
    "#bcbd22",
    "#17becf",
]
NEW = "#d62728"
ENDED = "#9a9a9a"
KEPT = "#222222"

Pair = tuple[str, str]


def instance_colour(instances: Sequence[str], name: str) -> str:
    """A colour per instance, stable across all pictures of one report."""
    idx = list(instances).index(name) if name in instances else len(instances)
    return _PALETTE[idx % len(_PALETTE)]


def _figure(width_in: float, height_in: float) -> Any:
    from matplotlib.figure import Figure

    fig = Figure(figsize=(width_in, height_in))
    fig.patch.set_facecolor("white")
    return fig


def _png(fig: Any, dpi: int = 110) -> bytes:
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    FigureCanvasAgg(fig)
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=dpi, metadata={"Software": None})
    return buf.getvalue()


def _key(pair: Sequence[str]) -> Pair:
    a, b = pair[0], pair[1]
    return (a, b) if a <= b else (b, a)


def world_state_png(
    instances: Sequence[str],
    after: Sequence[Sequence[str]],
    before: Sequence[Sequence[str]] | None = None,
    *,
    title: str | None = None,
) -> bytes:
    """The world state as a graph (the paper's Fig. 4, middle column).

    Nodes are the instances on a fixed ellipse (same place in every picture of one report),
    edges the touching relations: black = held on from ``before``, red = new, grey dashed =
    ended. With ``before=None`` every relation is drawn black.
    """
    now = frozenset(_key(p) for p in after)
    old = None if before is None else frozenset(_key(p) for p in before)
    return _world_state(tuple(instances), now, old, title)


@functools.lru_cache(maxsize=128)
def _world_state(
    instances: tuple[str, ...], now: frozenset[Pair], old: frozenset[Pair] | None, title: str | None
) -> bytes:
    """Cached: a report draws the same graphs again when it is re-rendered."""
    if old is None:
        old = now
    n = max(len(instances), 1)
    pos = {}
    for i, name in enumerate(instances):
        angle = math.pi / 2 - 2 * math.pi * i / n
        pos[name] = (1.2 * math.cos(angle), math.sin(angle))
    fig = _figure(3.4, 2.75 if not title else 2.95)
    ax = fig.add_axes((0.0, 0.0, 1.0, 0.93 if title else 1.0))
    ax.set_xlim(-2.1, 2.1)
    ax.set_ylim(-1.45, 1.45)
    ax.set_aspect("equal")
    ax.axis("off")
    for pair in sorted(now | old):
        if pair[0] not in pos or pair[1] not in pos:
            continue
        (x0, y0), (x1, y1) = pos[pair[0]], pos[pair[1]]
        if pair in now and pair in old:
            ax.plot([x0, x1], [y0, y1], color=KEPT, lw=1.8, zorder=1, solid_capstyle="round")
        elif pair in now:
            ax.plot([x0, x1], [y0, y1], color=NEW, lw=3.0, zorder=1, solid_capstyle="round")
        else:
            ax.plot([x0, x1], [y0, y1], color=ENDED, lw=1.8, ls=(0, (2, 2)), zorder=1)
    for name, (x, y) in pos.items():
        touching = any(name in p for p in now)
        ax.scatter(
            [x],
            [y],
            s=150,
            color=instance_colour(instances, name),
            zorder=2,
            edgecolors=KEPT if touching else "white",
            linewidths=1.4,
        )
        r = math.hypot(x, y) or 1.0
        lx, ly = x + 0.2 * x / r, y + 0.2 * y / r
        ha = "center" if abs(x) < 0.3 else ("left" if x > 0 else "right")
        va = "center" if abs(x) >= 0.3 else ("bottom" if y > 0 else "top")
        ax.text(
            lx,
            ly,
            name.replace("_", "\n", 1),
            ha=ha,
            va=va,
            fontsize=8.5,
            color="#333333",
            zorder=3,
            linespacing=0.95,
        )
    if title:
        fig.suptitle(title, fontsize=9, y=0.985)
    return _png(fig)


def relation_timeline_png(
    keyframes: Sequence[tuple[float, Sequence[Sequence[str]]]],
    end_s: float,
    *,
    labels: Sequence[str] | None = None,
    title: str | None = None,
) -> bytes:
    """When each relation held: one row per relation, bars between keyframes (times in s).

    ``keyframes`` are (time_s, relations) in time order; ``end_s`` is the recording's end.
    Keyframes are dotted vertical lines, labelled ``labels`` (default K0, K1, …).
    """
    frozen = tuple((float(t), tuple(_key(p) for p in rels)) for t, rels in keyframes)
    return _timeline(frozen, float(end_s), tuple(labels) if labels else None, title)


@functools.lru_cache(maxsize=16)
def _timeline(
    keyframes: tuple[tuple[float, tuple[Pair, ...]], ...],
    end_s: float,
    labels: tuple[str, ...] | None,
    title: str | None,
) -> bytes:
    rows: list[Pair] = []
    for _, rels in keyframes:
        for p in rels:
            k = _key(p)
            if k not in rows:
                rows.append(k)
    fig = _figure(9.6, 0.9 + 0.28 * max(len(rows), 1))
    ax = fig.add_subplot(1, 1, 1)
    times = [t for t, _ in keyframes] + [max(end_s, keyframes[-1][0] if keyframes else 0.0)]
    for i, (t, rels) in enumerate(keyframes):
        held = {_key(p) for p in rels}
        for r, pair in enumerate(rows):
            if pair in held:
                ax.barh(r, times[i + 1] - t, left=t, height=0.62, color="#4c78a8", edgecolor="none")
    for i, (t, _) in enumerate(keyframes):
        ax.axvline(t, color="#555555", lw=0.8, ls=":")
        lab = labels[i] if labels and i < len(labels) else f"K{i}"
        ax.text(t, len(rows) - 0.3, lab, fontsize=7, ha="center", va="bottom", color="#555555")
    ax.set_yticks(range(len(rows)), [f"{a} ↔ {b}" for a, b in rows], fontsize=8)
    ax.set_ylim(-0.6, len(rows) + 0.3)
    ax.invert_yaxis()
    ax.set_xlim(0, times[-1] or 1.0)
    ax.set_xlabel("time (s)", fontsize=8)
    ax.tick_params(axis="x", labelsize=8)
    for side in ("top", "right"):
        ax.spines[side].set_visible(False)
    if title:
        ax.set_title(title, fontsize=9, loc="left")
    fig.tight_layout()
    return _png(fig)


def marker_snapshot_png(
    recording: Recording, frame: int, *, instances: Sequence[str] | None = None, title: str | None = None
) -> bytes:
    """The recording's markers at ``frame`` seen from above (x right, y up; z is up in the world).

    Markers are coloured by instance (the colours of the world-state graphs); instances closer
    than 6 cm (a liquid in its cup) share one label. Pass the segmentation's ``instances`` to get
    the same colours as the world-state graphs (default: the recording's instances, sorted).
    """
    import numpy as np

    if not 0 <= frame < recording.n_frames:
        raise ValueError(f"frame {frame} is outside the recording (0..{recording.n_frames - 1})")
    names = list(instances) if instances is not None else list(recording.instances)
    fig = _figure(2.7, 2.2)
    ax = fig.add_axes((0.02, 0.02, 0.96, 0.88 if title else 0.96))
    ax.set_aspect("equal")
    ax.axis("off")
    groups = {}
    for name in recording.instances:
        pts = recording.group_positions(name)[frame]
        pts = pts[~np.isnan(pts).any(axis=1)]
        if len(pts):
            groups[name] = pts
    labels: list[tuple[np.ndarray, list[str]]] = []
    for name, pts in groups.items():
        ax.scatter(pts[:, 0], pts[:, 1], s=10, color=instance_colour(names, name), zorder=2)
        c = pts.mean(axis=0)
        near = next((lab for lab in labels if np.linalg.norm(lab[0][:2] - c[:2]) < 0.06), None)
        if near is None:
            labels.append((c, [name]))
        else:
            near[1].append(name)
    for c, group in labels:
        ax.annotate(
            "\n".join(n.replace("_", " ") for n in group),
            (c[0], c[1]),
            xytext=(0, 6),
            textcoords="offset points",
            fontsize=7,
            ha="center",
            va="bottom",
            color="#333333",
            linespacing=0.95,
            zorder=3,
        )
    if groups:
        allp = np.concatenate(list(groups.values()))
        lo, hi = allp.min(axis=0), allp.max(axis=0)
        pad = 0.12 * max(float(hi[0] - lo[0]), float(hi[1] - lo[1]), 0.2)
        ax.set_xlim(lo[0] - pad, hi[0] + pad)
        ax.set_ylim(lo[1] - pad / 2, hi[1] + 1.6 * pad)
        ax.add_patch(_rounded_box(ax, lo, hi, pad))
    if title:
        fig.suptitle(title, fontsize=9, y=0.99)
    return _png(fig)


def _rounded_box(ax: Any, lo: Any, hi: Any, pad: float) -> Any:
    from matplotlib.patches import FancyBboxPatch

    return FancyBboxPatch(
        (lo[0] - pad / 2, lo[1] - pad / 3),
        hi[0] - lo[0] + pad,
        hi[1] - lo[1] + pad,
        boxstyle=f"round,pad=0,rounding_size={pad / 2}",
        facecolor="#f4f6f9",
        edgecolor="#dde2e8",
        zorder=0,
    )


def save_png(data: bytes, path: str | os.PathLike[str]) -> Path:
    """Write PNG bytes to ``path`` atomically (temporary file in the same folder, then rename)."""
    return write_atomic(path, data)
