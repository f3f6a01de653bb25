"""A picture of the demonstrated motion: one panel per sub-action, the object's path in the target's frame.

Each panel shows the moved object's origin in the target's frame (or the world's,
when it works on nothing), in millimetres, on the plane of the target's axes where
its core (see :mod:`~oacdsl.segmentation.motionfeatures`) spreads most (x–y seen from
above, x–z or y–z from the side). The colour runs
from the span's start (dark) to its end (light); the dwelling core (where periods
are measured) is drawn thicker; ``+`` marks the target's origin and a star the frame of
the largest tilt (30° or more). matplotlib is
imported inside the function, with a ``Figure`` of its own (no pyplot, no backend
switch), and the file is written atomically.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np

from oacdsl.segmentation.motion import SubActionMotion
from oacdsl.segmentation.plots import save_figure

__all__ = ["draw_motion", "save_motion_plot", "view_plane"]

_AXES = ("x", "y", "z")
_M_TO_MM = 1000.0


def view_plane(points: np.ndarray) -> tuple[int, int]:
    """The two coordinate axes (indices) of (N, 3) ``points`` with the largest spread
    (median absolute deviation: a single step into or out of the target does not decide)."""
    ok = np.isfinite(points).all(axis=1)
    inner = points[ok]
    spread = np.median(np.abs(inner - np.median(inner, axis=0)), axis=0) if ok.any() else np.zeros(3)
    first, second = sorted(int(i) for i in np.argsort(spread)[::-1][:2])
    return first, second


def _caption(m: SubActionMotion) -> str:
    what = f"{m.moved} → {m.target or 'world'}" + (f" ({m.relation})" if m.relation else "")
    lines = [f"#{m.index}  {what}", f"{m.times_s[0]:.1f}–{m.times_s[-1]:.1f} s"]
    f = m.features
    if f is not None:
        extra = [f"path {f.path_length_m * _M_TO_MM:.0f} mm"]
        if f.period_s is not None:
            extra.append(f"period {f.period_s:.2f} s × {f.cycles:.1f}")
        if f.tilt_max_rad >= math.radians(30):
            extra.append(f"tilt {math.degrees(f.tilt_max_rad):.0f}°")
        lines[1] += ", " + ", ".join(extra)
    return "\n".join(lines)


def save_motion_plot(motions: Sequence[SubActionMotion], out: str | Path, *, title: str = "") -> Path:
    """Draw every sub-action that has a moved object into one picture (.png, .pdf, .svg)."""
    from matplotlib.figure import Figure

    shown = [m for m in motions if m.moved is not None]
    n = max(len(shown), 1)
    cols = min(n, 3)
    rows = math.ceil(n / cols)
    fig = Figure(figsize=(4.2 * cols, 3.9 * rows + 0.4), layout="constrained")
    if title:
        fig.suptitle(title, fontsize=9)
    if not shown:
        ax = fig.add_subplot(1, 1, 1)
        ax.text(0.5, 0.5, "no sub-action moves an object with ≥ 3 markers", ha="center", va="center")
        ax.set_axis_off()
        return save_figure(fig, out)
    for k, m in enumerate(shown):
        draw_motion(fig.add_subplot(rows, cols, k + 1), m)
    return save_figure(fig, out)


def draw_motion(ax: Any, m: SubActionMotion, title: str | None = None) -> None:
    """One panel: ``m``'s path in its target's frame on a matplotlib axis (module doc);
    ``title`` replaces the caption."""
    pos = m.T_target_object[:, :3, 3] * _M_TO_MM
    core = m.features.core_s if m.features is not None else (0.0, 0.0)
    in_core = (m.times_s >= core[0]) & (m.times_s <= core[1])
    i, j = view_plane(pos[in_core] if in_core.sum() >= 3 else pos)
    u, v = pos[:, i], pos[:, j]
    shade = np.linspace(0.0, 1.0, len(u))
    ax.plot(u, v, color="0.75", linewidth=0.8, zorder=1)
    ax.plot(np.where(in_core, u, np.nan), np.where(in_core, v, np.nan), color="0.35", linewidth=1.8,
            zorder=2)
    ax.scatter(u, v, c=shade, cmap="viridis", s=14, zorder=3)
    finite = np.flatnonzero(np.isfinite(u) & np.isfinite(v))
    if finite.size:
        ax.plot(u[finite[0]], v[finite[0]], "o", mfc="none", mec="k", ms=8, zorder=4, label="start")
        ax.plot(u[finite[-1]], v[finite[-1]], "s", mfc="none", mec="k", ms=8, zorder=4, label="end")
    tilt = np.arccos(np.clip(m.T_target_object[:, 2, 2], -1.0, 1.0))
    if np.isfinite(tilt).any() and np.nanmax(tilt) >= math.radians(30):
        top = int(np.nanargmax(tilt))
        ax.plot(u[top], v[top], "*", color="darkorange", ms=13, zorder=4,
                label=f"largest tilt ({math.degrees(tilt[top]):.0f}°)")
    if m.target is not None:
        ax.plot(0.0, 0.0, "+", color="crimson", ms=12, mew=2, zorder=5, label=f"{m.target} origin")
    ax.set_xlabel(f"{_AXES[i]} in {m.frame_name} [mm]", fontsize=8)
    ax.set_ylabel(f"{_AXES[j]} in {m.frame_name} [mm]", fontsize=8)
    ax.set_aspect("equal", adjustable="datalim")
    ax.tick_params(labelsize=7)
    ax.grid(True, linewidth=0.3)
    ax.set_title(title if title is not None else _caption(m), fontsize=8)
    ax.legend(fontsize=6, loc="upper right")  # "best" searches every point: seconds per panel
