"""The pictures of a reproduction, written into the report's ``figures/`` folder.

- ``aas.png``: the demonstration's distances over time with thresholds and keyframes
  (the paper's Fig. 3), drawn by :func:`oacdsl.segmentation.plots.plot_distances`;
- ``keyframe_NN.png``: the demonstration's markers at every keyframe, seen from above;
- ``robot_aas.png``: the same plot for the robot's virtual markers (verification), drawn
  from every k-th frame (at most :data:`PLOT_FRAMES`): hundreds of markers make the
  closest-distance curves costly, and the keyframes come from the full-rate segmentation.

The rendered frames of the robot (``robot_NN.png``) are written by the execute stage.
The world-state graphs are drawn by the report page from ``result.json`` itself.
Paths returned are relative to the report's folder, as ``result.json`` names images.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

from oacdsl.segmentation.recording import Recording
from oacdsl.segmentation.result import Segmentation

__all__ = ["FIGURES", "distance_plot", "keyframe_snapshots"]

#: The folder of the pictures, inside the report's folder.
FIGURES = "figures"
#: Resolution of the distance plots, dots per inch (11 × 6.5 in).
PLOT_DPI = 100
#: The robot's distance plot is drawn from at most this many frames of its recording.
PLOT_FRAMES = 1000
#: Markers per instance in the plot of the robot's recording (every j-th of its group).
PLOT_MARKERS = 16


def distance_plot(recording: Recording, segmentation: Segmentation, folder: Path, name: str) -> str:
    """Write the Fig.-3 plot as ``folder/name``; return its path relative to ``folder.parent``.

    Drawn by :func:`oacdsl.segmentation.plots.plot_distances` on a plain matplotlib figure
    (no pyplot: faster to import, no global state), 100 dpi.
    """
    import io

    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    from oacdsl.report.figures import save_png
    from oacdsl.segmentation.plots import plot_distances

    fig = Figure(figsize=(11, 6.5), layout="constrained")
    FigureCanvasAgg(fig)
    plot_distances(recording, segmentation, fig)
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=PLOT_DPI)
    save_png(buf.getvalue(), folder / name)
    return f"{FIGURES}/{name}"


def decimated(
    recording: Recording, max_frames: int = PLOT_FRAMES, max_markers: int | None = None
) -> Recording:
    """Every k-th frame of ``recording`` so that at most ``max_frames`` remain (for plots only:
    the closest-distance curves of a recording with hundreds of markers cost seconds); with
    ``max_markers``, also every j-th marker of each group so that at most that many remain
    per group (the robot's virtual markers: about 490, 94 per hand)."""
    from dataclasses import replace

    step = max(1, -(-recording.n_frames // max_frames))
    groups = dict(recording.groups)
    if max_markers is not None:
        groups = {g: idx[:: max(1, -(-len(idx) // max_markers))] for g, idx in groups.items()}
    if step == 1 and groups == dict(recording.groups):
        return recording
    return replace(
        recording,
        rate_hz=recording.rate_hz / step,
        times_s=recording.times_s[::step],
        positions_m=recording.positions_m[::step],
        groups=groups,
    )


def keyframe_snapshots(recording: Recording, segmentation: Segmentation, folder: Path) -> list[str]:
    """The markers at every keyframe (``keyframe_NN.png``); relative paths, one per keyframe."""
    from oacdsl.report.figures import marker_snapshot_png, save_png

    out = []
    for i, k in enumerate(segmentation.keyframes):
        png = marker_snapshot_png(
            recording, k.frame, instances=segmentation.instances, title=f"K{i} · {k.time_s:.2f} s"
        )
        save_png(png, folder / f"keyframe_{i:02d}.png")
        out.append(f"{FIGURES}/keyframe_{i:02d}.png")
    return out


def relative(path: Path, base: Path) -> str:
    """``path`` relative to ``base`` as result.json names pictures."""
    return path.relative_to(base).as_posix()


def attach_frames(run_doc: dict[str, Any], frames: dict[str, Path], base: Path) -> None:
    """Put the rendered frames into the run document: ``frame`` before the run, per step
    ``frame`` after it and ``moment`` when its predicted effects first held."""
    if "robot_00" in frames:
        run_doc["frame"] = relative(frames["robot_00"], base)
    for i, step in enumerate(run_doc.get("steps", [])):
        for key, name in (("frame", f"robot_{i + 1:02d}"), ("moment", f"robot_{i + 1:02d}_moment")):
            if name in frames:
                step[key] = relative(frames[name], base)
