"""The pictures: Fig. 4 edge styles, Fig. 3 content, atomic writing."""

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402
from _aas_helpers import path, recording, still  # noqa: E402

from oacdsl.errors import InputError  # noqa: E402
from oacdsl.segmentation import AasParams, segment  # noqa: E402
from oacdsl.segmentation.plots import (  # noqa: E402
    change_labels,
    draw_world_state,
    plot_distances,
    save_figure,
    world_state_layout,
)
from oacdsl.world import WorldState  # noqa: E402


def _edges(ax):
    """(colour, dashed?, number of segments) of each drawn edge collection."""
    out = []
    for coll in ax.collections:
        if coll.__class__.__name__ != "LineCollection" or not len(coll.get_segments()):
            continue
        rgba = tuple(np.round(coll.get_edgecolor()[0][:3], 2))
        dashes = coll.get_linestyle()[0][1]
        out.append((rgba, dashes is not None, len(coll.get_segments())))
    return sorted(out)


def test_world_state_graph_marks_new_and_ended_relations():
    prev = WorldState.of(["hand", "cup", "bowl", "liquid"], [("hand", "cup"), ("liquid", "cup")])
    cur = WorldState.of(["hand", "cup", "bowl", "liquid"], [("hand", "cup"), ("liquid", "bowl")])
    fig, ax = plt.subplots()
    draw_world_state(prev, cur, ax, title="k")
    red, black, grey = (1.0, 0.0, 0.0), (0.0, 0.0, 0.0), (0.35, 0.35, 0.35)
    assert _edges(ax) == sorted([(black, False, 1), (red, False, 1), (grey, True, 1)])
    labels = {t.get_text() for t in ax.texts}
    assert {"hand", "cup", "bowl", "liquid"} <= labels
    plt.close(fig)


def test_initial_state_draws_everything_as_existing():
    cur = WorldState.of(["a", "b", "c"], [("a", "b"), ("b", "c")])
    fig, ax = plt.subplots()
    draw_world_state(None, cur, ax)
    assert _edges(ax) == [((0.0, 0.0, 0.0), False, 2)]
    plt.close(fig)


def test_layout_is_stable_and_change_labels():
    assert world_state_layout(["b", "a"]) == world_state_layout(["a", "b"])
    prev = WorldState.of(["a", "b", "c"], [("a", "b")])
    cur = WorldState.of(["a", "b", "c"], [("b", "c")])
    assert change_labels(prev, cur) == ["+ b <-> c", "- a <-> b"]


def test_distance_plot_shows_near_pairs_thresholds_and_keyframes():
    F = 300
    hand = path(F, [(0, (0.5, 0, 0)), (100, (0.05, 0, 0)), (200, (0.05, 0, 0)), (250, (0.5, 0, 0))])
    rec = recording({"hand": hand, "cup": still(F, (0, 0, 0)), "far": still(F, (5, 5, 5))})
    seg = segment(rec, AasParams(frames=3, mode="paper"))
    fig = plt.figure()
    plot_distances(rec, seg, fig)
    ax_d, ax_v = fig.axes[:2]
    labels = [line.get_label() for line in ax_d.get_lines()]
    assert "cup – hand" in labels and not any("far" in label for label in labels)
    assert "d = 150 mm" in labels
    assert any(line.get_label() == "v = 100 mm/s" for line in ax_v.get_lines())
    vertical = [line for line in ax_d.get_lines()
                if np.ptp(line.get_xdata()) == 0 and line.get_linestyle() == ":"]
    assert sorted(float(line.get_xdata()[0]) for line in vertical) == pytest.approx([0.0, 1.01, 2.01])
    texts = [t.get_text() for t in ax_d.texts]
    assert "+ cup <-> hand" in texts and "- cup <-> hand" in texts
    closest = next(line for line in ax_d.get_lines() if line.get_label() == "cup – hand")
    assert float(np.min(closest.get_ydata())) == pytest.approx(50.0, abs=0.01)  # millimetres
    plt.close(fig)


def test_save_figure_is_atomic_and_checks_the_suffix(tmp_path):
    fig, ax = plt.subplots()
    ax.plot([0, 1])
    out = save_figure(fig, tmp_path / "x.svg")
    assert out.read_text(encoding="utf-8").lstrip().startswith("<?xml")
    with pytest.raises(InputError, match="use .png, .pdf or .svg"):
        save_figure(fig, tmp_path / "x.gif")
    with pytest.raises(InputError, match="cannot write the picture"):
        save_figure(fig, tmp_path / "missing" / "x.png")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["x.svg"]
    plt.close(fig)
