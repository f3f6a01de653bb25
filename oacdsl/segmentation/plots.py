"""Pictures of a segmentation: the paper's Fig. 3 (distances over time) and Fig. 4 (world-state graphs).

matplotlib and networkx are imported inside the functions, and the Agg backend
is selected only by the ``save_*``/``write_*`` functions, so importing this module
costs nothing and never touches a display. Every file is written to a temporary
name in its folder and renamed into place.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from oacdsl.atomic import atomic_path
from oacdsl.errors import InputError
from oacdsl.segmentation.geometry import BOUND_MARGIN_M, ChunkGeometry, chunk_frames_for
from oacdsl.segmentation.pairs import PairTable
from oacdsl.segmentation.params import frames_in
from oacdsl.segmentation.recording import Recording
from oacdsl.segmentation.result import Keyframe, Segmentation
from oacdsl.segmentation.slope import windowed_slope
from oacdsl.world import WorldState

__all__ = [
    "change_labels",
    "closest_distances",
    "draw_world_state",
    "plot_distances",
    "save_distance_plot",
    "save_figure",
    "world_state_layout",
    "write_graphs",
]

#: Most points per curve; longer recordings are reduced bin by bin (closest distance per bin).
MAX_POINTS = 4000
#: Instance pairs whose closest distance stays above this many times ``d`` are not drawn.
NEAR_FACTOR = 1.5


def change_labels(prev: WorldState | None, cur: WorldState) -> list[str]:
    """``["+ a <-> b", "- c <-> d"]``: what changed from ``prev`` to ``cur``."""
    before = prev.relations if prev is not None else frozenset()
    added = sorted(cur.relations - before)
    removed = sorted(before - cur.relations)
    return [f"+ {a} <-> {b}" for a, b in added] + [f"- {a} <-> {b}" for a, b in removed]


def plot_distances(recording: Recording, segmentation: Segmentation, fig: Any, *, max_pairs: int = 8) -> None:
    """Draw the paper's Fig. 3 for ``recording`` into the matplotlib figure ``fig``.

    Top: per instance pair that ever comes near (closest marker distance below
    1.5 d; relations found first, at most ``max_pairs``), the closest marker
    distance over time, the threshold ``d`` dotted. Bottom: the change of that
    distance per second with ``v`` dotted — the one-frame difference in mode ``paper``,
    else the slope over the change window that the detector compares with ``v``.
    Keyframes: vertical dotted lines, labelled with the relations they add (+) and remove (−).
    """
    params = segmentation.parameters
    d_mm = 1000.0 * float(params.get("distance_m", 0.15))
    v = params.get("speed_m_s")
    table, dist = closest_distances(recording, reach_m=3 * d_mm / 1000.0)  # the y-axis ends at 3 d
    times = np.asarray(recording.times_s, dtype=np.float64)
    related = {r for k in segmentation.keyframes for r in k.state.relations}
    closest = np.fmin.reduce(dist, axis=1)  # NaN only for a pair never visible
    candidates = [
        q
        for q in range(table.n_instance_pairs)
        if table.relation(q) in related or closest[q] * 1000.0 < NEAR_FACTOR * d_mm
    ]
    order = np.nan_to_num(closest, nan=np.inf)
    candidates.sort(key=lambda q: (table.relation(q) not in related, float(order[q])))
    shown, hidden = candidates[:max_pairs], len(candidates) - max_pairs

    ax_d, ax_v = fig.subplots(2, 1, sharex=True, gridspec_kw={"height_ratios": [2, 1]})
    t_plot, step = _bins(times)
    half = None
    if params.get("mode", "paper") != "paper" and "change_window_s" in params:
        half = max(1, frames_in(float(params["change_window_s"]) / 2, recording.rate_hz))
    for q in shown:
        a, b = table.relation(q)
        mm = dist[q].astype(np.float64) * 1000.0
        change = np.full_like(mm, np.nan)
        if half is None:
            change[1:] = np.abs(np.diff(mm)) / np.diff(times)
        else:
            change = np.abs(windowed_slope(dist[q][None, :], times, half)[0]).astype(np.float64) * 1000.0
        line = ax_d.plot(t_plot, _reduce(mm, step, np.fmin), lw=1.2, label=f"{a} – {b}")[0]
        ax_v.plot(t_plot, _reduce(change, step, np.fmax), lw=0.8, color=line.get_color())
    ax_d.axhline(d_mm, color="k", ls=":", lw=1.2, label=f"d = {d_mm:g} mm")
    if v is not None:
        ax_v.axhline(1000.0 * float(v), color="k", ls=":", lw=1.2, label=f"v = {1000.0 * float(v):g} mm/s")
        ax_v.set_ylim(0, 5000.0 * float(v))
    ax_d.set_ylim(0, max(3 * d_mm, 1.0))
    ax_d.set_ylabel("closest marker distance [mm]")
    ax_v.set_ylabel("|distance change| [mm/s]")
    ax_v.set_xlabel("time [s]")
    title = f"{Path(recording.source).name}: AAS (mode {params.get('mode', 'paper')})"
    if hidden > 0:
        title += f" — {hidden} more near pair(s) not shown"
    ax_d.set_title(title, fontsize=10)
    prev: WorldState | None = None
    for k in segmentation.keyframes:
        for ax in (ax_d, ax_v):
            ax.axvline(k.time_s, color="k", ls=":", lw=0.8)
        labels = change_labels(prev, k.state) if prev is not None else ["initial"]
        ax_d.annotate(
            "\n".join(labels),
            (k.time_s, 1.0),
            xycoords=("data", "axes fraction"),
            xytext=(2, -2),
            textcoords="offset points",
            va="top",
            ha="left",
            fontsize=6.5,
            rotation=90,
        )
        prev = k.state
    if shown:
        ax_d.legend(loc="center left", bbox_to_anchor=(1.01, 0.5), fontsize=7, frameon=False)
    if v is not None:
        ax_v.legend(loc="center left", bbox_to_anchor=(1.01, 0.5), fontsize=7, frameon=False)
    ax_d.set_xlim(float(times[0]), float(times[-1]) if times.size > 1 else float(times[0]) + 1.0)


def save_distance_plot(recording: Recording, segmentation: Segmentation, out: str | Path) -> Path:
    """Write :func:`plot_distances` to ``out`` (.png, .pdf or .svg), atomically."""
    plt = _pyplot()
    fig = plt.figure(figsize=(11, 6.5), layout="constrained")
    try:
        plot_distances(recording, segmentation, fig)
        return save_figure(fig, out)
    finally:
        plt.close(fig)


def world_state_layout(instances: Sequence[str]) -> dict[str, tuple[float, float]]:
    """Fixed node positions: instances on a circle in name order (same for every keyframe)."""
    names = sorted(instances)
    n = max(len(names), 1)
    return {
        name: (math.cos(math.pi / 2 - 2 * math.pi * i / n), math.sin(math.pi / 2 - 2 * math.pi * i / n))
        for i, name in enumerate(names)
    }


def draw_world_state(
    prev: WorldState | None,
    cur: WorldState,
    ax: Any,
    *,
    layout: Mapping[str, tuple[float, float]] | None = None,
    title: str | None = None,
) -> None:
    """The paper's Fig. 4 graph: nodes = instances, edges = touching.

    Relations that exist in both states are black, new ones red and solid, ended
    ones grey and dotted. ``prev=None`` draws every relation as existing.
    """
    import networkx as nx

    pos = dict(layout) if layout is not None else world_state_layout(sorted(cur.instances))
    before = prev.relations if prev is not None else cur.relations
    kept = sorted(cur.relations & before)
    new = sorted(cur.relations - before)
    ended = sorted(before - cur.relations)
    graph = nx.Graph()
    graph.add_nodes_from(sorted(cur.instances))
    graph.add_edges_from(kept + new + ended)
    margin = 1800  # node "size" that keeps edge ends clear of the name boxes
    nx.draw_networkx_edges(graph, pos, ax=ax, edgelist=kept, edge_color="black", width=2.0, node_size=margin)
    nx.draw_networkx_edges(graph, pos, ax=ax, edgelist=new, edge_color="red", width=2.5, node_size=margin)
    nx.draw_networkx_edges(
        graph, pos, ax=ax, edgelist=ended, edge_color="0.35", width=2.0, style=":", node_size=margin
    )
    nx.draw_networkx_labels(
        graph, pos, ax=ax, font_size=8, bbox={"boxstyle": "round,pad=0.4", "fc": "#dde6f0", "ec": "#4a5a70"}
    )
    from matplotlib.lines import Line2D

    handles = [
        Line2D([], [], color="black", lw=2, label="touching"),
        Line2D([], [], color="red", lw=2.5, label="new"),
        Line2D([], [], color="0.35", lw=2, ls=":", label="ended"),
    ]
    ax.legend(
        handles=handles, loc="lower center", bbox_to_anchor=(0.5, -0.02), ncol=3, fontsize=7, frameon=False
    )
    ax.set_xlim(-1.45, 1.45)
    ax.set_ylim(-1.35, 1.25)
    ax.set_aspect("equal")
    ax.axis("off")
    if title:
        ax.set_title(title, fontsize=8.5)


def write_graphs(segmentation: Segmentation, directory: str | Path) -> list[Path]:
    """One PNG per keyframe in ``directory`` (created): ``keyframe_000_frame_000000.png``, …"""
    plt = _pyplot()
    folder = Path(directory)
    try:
        folder.mkdir(parents=True, exist_ok=True)
    except OSError as error:
        raise InputError(f"cannot create the folder: {error.strerror}", location=str(folder)) from error
    layout = world_state_layout(segmentation.instances)
    written: list[Path] = []
    prev: Keyframe | None = None
    for i, k in enumerate(segmentation.keyframes):
        fig, ax = plt.subplots(figsize=(5.2, 5.2), layout="constrained")
        try:
            changes = "\n".join(change_labels(prev.state, k.state)) if prev is not None else "initial state"
            draw_world_state(
                prev.state if prev is not None else None,
                k.state,
                ax,
                layout=layout,
                title=f"keyframe {i}: frame {k.frame}, {k.time_s:.2f} s\n{changes}",
            )
            written.append(save_figure(fig, folder / f"keyframe_{i:03d}_frame_{k.frame:06d}.png"))
        finally:
            plt.close(fig)
        prev = k
    return written


def save_figure(fig: Any, out: str | Path) -> Path:
    """Save a matplotlib figure atomically; the format follows the suffix (.png .pdf .svg)."""
    path = Path(out)
    fmt = path.suffix.lower().lstrip(".")
    if fmt not in ("png", "pdf", "svg"):
        raise InputError(
            f"cannot write a {path.suffix or 'suffix-less'} picture; use .png, .pdf or .svg",
            location=str(path),
        )
    try:
        with atomic_path(path, suffix=f".tmp.{fmt}", make_parents=False) as tmp:
            fig.savefig(tmp, format=fmt, dpi=150)
    except OSError as error:
        raise InputError(f"cannot write the picture: {error.strerror}", location=str(path)) from error
    return path


def _pyplot() -> Any:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def _bins(times: np.ndarray) -> tuple[np.ndarray, int]:
    step = max(1, math.ceil(times.size / MAX_POINTS))
    return times[::step], step


def _reduce(values: np.ndarray, step: int, ufunc: Any) -> np.ndarray:
    if step == 1:
        return values
    out: np.ndarray = ufunc.reduceat(values, np.arange(0, values.size, step))
    return out


def closest_distances(
    recording: Recording,
    table: PairTable | None = None,
    chunk_frames: int = 4096,
    reach_m: float | None = None,
) -> tuple[PairTable, np.ndarray]:
    """Per instance pair and frame, the smallest marker-pair distance, metres.

    Returns the pair table and a (Q, F) float32 array, NaN where no marker pair of
    the two instances is visible, and (with ``reach_m``) in chunks where the pair
    stays farther apart than ``reach_m``. Memory O(Q × F); for plots and reports.
    """
    table = table or PairTable.of(recording)
    geometry = ChunkGeometry(recording, table)
    n_q = table.n_instance_pairs
    out = np.full((n_q, recording.n_frames), np.nan, dtype=np.float32)
    if n_q == 0:
        return table, out
    blocks = np.arange(n_q, dtype=np.intp)
    chunk_frames = chunk_frames_for(table.n_pairs + geometry.max_block_pairs, chunk_frames)
    for lo in range(0, recording.n_frames, chunk_frames):
        hi = min(recording.n_frames, lo + chunk_frames)
        x = geometry.coordinates(lo, hi)
        if reach_m is not None:
            with np.errstate(invalid="ignore"):
                blocks = np.flatnonzero(geometry.lower_bounds(x) <= reach_m + BOUND_MARGIN_M)
        if blocks.size == 0:
            continue
        pairs, dist = geometry.distances(x, blocks)
        heads = np.flatnonzero(np.r_[True, table.block[pairs[1:]] != table.block[pairs[:-1]]])
        out[blocks, lo:hi] = np.fmin.reduceat(dist, heads, axis=0)
    return table, out
