"""A realistic, hand-made result of `oacc reproduce` on the dough demonstration (for report tests).

The parts mirror the JSON documents the issues define: `oacc segment --json`, `oacc match --json`,
`oacc compose --json`, `oacc run --json`, the verification and `oacc stats --json`. Pictures are
placeholders drawn here with matplotlib and written under `out/figures/`.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from oacdsl.report.figures import marker_snapshot_png, save_png
from oacdsl.segmentation.recording import Recording
from oacdsl.stats import summarise
from oacdsl.verify import verify
from oacdsl.world import WorldState

INSTANCES = ["left_hand", "right_hand", "red_cup", "green_cup", "liquid_one", "liquid_two", "orange_bowl",
             "mixer"]
INITIAL = [["liquid_one", "red_cup"], ["green_cup", "liquid_two"]]
HAND = {"h": "left_hand"}

# (oac, binding, added, removed, time_s) per sub-action of the demonstration.
STEPS = [
    ("grasp", {"h": "left_hand", "o": "red_cup"}, [["left_hand", "red_cup"]], [], 1.32),
    ("pour", {"h": "left_hand", "c": "red_cup", "l": "liquid_one", "b": "orange_bowl"},
     [["liquid_one", "orange_bowl"]], [["liquid_one", "red_cup"]], 3.05),
    ("place", {"h": "left_hand", "o": "red_cup"}, [], [["left_hand", "red_cup"]], 4.71),
    ("grasp", {"h": "right_hand", "o": "green_cup"}, [["green_cup", "right_hand"]], [], 6.02),
    ("pour", {"h": "right_hand", "c": "green_cup", "l": "liquid_two", "b": "orange_bowl"},
     [["liquid_two", "orange_bowl"]], [["green_cup", "liquid_two"]], 7.88),
    ("place", {"h": "right_hand", "o": "green_cup"}, [], [["green_cup", "right_hand"]], 9.40),
    ("grasp", {"h": "right_hand", "o": "mixer"}, [["mixer", "right_hand"]], [], 10.65),
    ("mix", {"h": "right_hand", "m": "mixer", "b": "orange_bowl"}, [["mixer", "orange_bowl"]], [], 12.10),
]
RATE_HZ = 100.0

OAC_TEXT = """\
# composed from dough.c3d by oacc compose
oac dough(h1: Hand = left_hand, h2: Hand = right_hand, c1: Cup = red_cup, c2: Cup = green_cup,
          l1: Liquid = liquid_one, l2: Liquid = liquid_two, b: Bowl = orange_bowl, m: Mixer = mixer) {
    pre     h1 <-> nothing,   # step 1 grasp, K0
            h2 <-> nothing,   # step 4 grasp, K3
            l1 <-> c1,        # step 2 pour, K1
            l2 <-> c2         # step 5 pour, K4
    effect  h2 <-> m,         # step 7 grasp, K7
            l1 <-> b,         # step 2 pour, K2
            l2 <-> b,         # step 5 pour, K5
            m <-> b,          # step 8 mix, K8
            not l1 <-> c1,    # step 2 pour, K2
            not l2 <-> c2     # step 5 pour, K5
    steps {
        grasp(h1, c1)  pour(h1, c1, l1, b)  place(h1, c1)
        grasp(h2, c2)  pour(h2, c2, l2, b)  place(h2, c2)
        grasp(h2, m)   mix(h2, m, b)
    }
}
"""


def _sorted(pairs):
    return sorted(sorted(p) for p in pairs)


def keyframe_relations():
    state = {tuple(sorted(p)) for p in INITIAL}
    out = [_sorted(state)]
    for _, _, added, removed, _ in STEPS:
        state = (state - {tuple(sorted(p)) for p in removed}) | {tuple(sorted(p)) for p in added}
        out.append(_sorted(state))
    return out


def _figure(width, height):
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    fig = Figure(figsize=(width, height))
    FigureCanvasAgg(fig)
    return fig


def _png(fig):
    import io

    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=90)
    return buf.getvalue()


def distance_plot_png(times):
    fig = _figure(10, 3.2)
    ax = fig.add_subplot(1, 1, 1)
    t = np.linspace(0, 13, 1300)
    for k, t0 in enumerate(times[:4]):
        ax.plot(t, 0.45 - 0.38 * np.exp(-((t - t0 - 0.8) / 0.9) ** 2) + 0.01 * k, lw=1.2, label=f"pair {k}")
    ax.axhline(0.15, color="k", ls=":", lw=1)
    for t0 in times:
        ax.axvline(t0, color="k", ls=":", lw=0.8)
    ax.set_xlabel("time (s)")
    ax.set_ylabel("distance (m)")
    ax.legend(fontsize=7, loc="upper right")
    fig.tight_layout()
    return _png(fig)


def robot_frame_png(text, colour="#8fb3d9"):
    fig = _figure(3.2, 2.4)
    ax = fig.add_axes((0, 0, 1, 1))
    ax.set_facecolor("#e9edf2")
    from matplotlib.patches import Circle, Rectangle

    ax.add_patch(Rectangle((0.1, 0.1), 0.8, 0.12, color="#a07850"))
    ax.add_patch(Circle((0.5, 0.62), 0.16, color=colour))
    ax.text(0.5, 0.9, text, ha="center", fontsize=10)
    ax.set_xlim(0, 1)
    ax.set_ylim(0, 1)
    ax.set_xticks([])
    ax.set_yticks([])
    return _png(fig)


def synthetic_recording(times):
    """Markers of the eight instances drifting over a table, enough for a snapshot picture."""
    n = int(13 * RATE_HZ)
    rng = np.random.default_rng(0)
    names, groups, base = [], {}, []
    centres = {"left_hand": (-0.45, -0.3, 1.05), "right_hand": (0.45, -0.3, 1.05),
               "red_cup": (-0.3, 0.05, 0.85), "green_cup": (0.3, 0.05, 0.85),
               "liquid_one": (-0.3, 0.05, 0.92), "liquid_two": (0.3, 0.05, 0.92),
               "orange_bowl": (0.0, 0.2, 0.82), "mixer": (0.5, 0.3, 0.85)}
    for inst in INSTANCES:
        centre = np.array(centres[inst])
        idx = []
        for k in range(3):
            idx.append(len(names))
            names.append(f"{inst}_{k}")
            base.append(centre + rng.normal(0, 0.02, 3))
        groups[inst] = tuple(idx)
    t = np.arange(n) / RATE_HZ
    pos = np.repeat(np.array(base)[None], n, axis=0)
    pos[:, :6, 2] += 0.1 * np.sin(t)[:, None]
    return Recording("dough.c3d", RATE_HZ, t, tuple(names), pos, groups)


def dough_result(out: Path, *, with_pictures: bool = True) -> dict:
    """The result dict, with pictures written under ``out / "figures"`` (paths relative to ``out``)."""
    rels = keyframe_relations()
    times = [0.0] + [s[4] for s in STEPS]
    fig_dir = out / "figures"
    pic = {}
    if with_pictures:
        rec = synthetic_recording(times)
        pic["plot"] = "figures/distances.png"
        save_png(distance_plot_png(times[1:]), out / pic["plot"])
        for i, t in enumerate(times):
            snapshot = marker_snapshot_png(rec, int(t * RATE_HZ), instances=INSTANCES)
            save_png(snapshot, fig_dir / f"keyframe_{i}.png")
            save_png(robot_frame_png(f"step {i}" if i else "start"), fig_dir / f"robot_{i}.png")
    keyframes = [
        {"frame": int(round(t * RATE_HZ)), "time_s": t, "relations": r,
         **({"image": f"figures/keyframe_{i}.png"} if with_pictures else {})}
        for i, (t, r) in enumerate(zip(times, rels, strict=True))
    ]
    segment = {"recording": "dough.c3d", "rate_hz": RATE_HZ, "frames": 1300,
               "parameters": {"distance_m": 0.15, "speed_m_s": 0.05, "frames": 3, "merge_s": 0.3,
                              "mode": "adaptive"},
               "instances": INSTANCES, "keyframes": keyframes, "plot": pic.get("plot")}
    sub_actions = []
    for i, (oac, binding, _added, _removed, _) in enumerate(STEPS):
        h = binding["h"]
        match = {"oac": oac, "binding": binding, "note": "strict: explains every change"}
        if oac == "grasp":
            match |= {"pre": [[h, "nothing"]], "effect": [sorted([h, binding["o"]])]}
        elif oac == "place":
            match |= {"pre": [sorted([h, binding["o"]])], "effect": [[h, "nothing"]]}
        elif oac == "pour":
            match |= {"pre": _sorted([[h, binding["c"]], [binding["l"], binding["c"]]]),
                      "effect": [sorted([binding["l"], binding["b"]])],
                      "effect_not": [sorted([binding["l"], binding["c"]])]}
        else:
            match |= {"pre": [sorted([h, binding["m"]])], "effect": [sorted([binding["m"], binding["b"]])]}
        matches = [match]
        if oac == "mix":
            matches.append({"oac": "wipe", "binding": {"h": h, "s": "mixer", "t": "orange_bowl"},
                            "note": "also explains the change (mixer is a Sponge in this library)"})
        sub_actions.append({"from_frame": keyframes[i]["frame"], "to_frame": keyframes[i + 1]["frame"],
                            "before": rels[i], "after": rels[i + 1], "matches": matches, "chosen": 0,
                            "explanation": None})
    compose = {
        "name": "dough",
        "pre": [["left_hand", "nothing"], ["right_hand", "nothing"], ["liquid_one", "red_cup"],
                ["green_cup", "liquid_two"]],
        "effect": [["mixer", "right_hand"], ["liquid_one", "orange_bowl"], ["liquid_two", "orange_bowl"],
                   ["mixer", "orange_bowl"]],
        "ended": [["liquid_one", "red_cup"], ["green_cup", "liquid_two"]],
        "steps": [{"oac": s[0], "binding": s[1]} for s in STEPS],
        "file": "library/learned/dough.oac",
        "text": OAC_TEXT,
        "provenance": [
            {"kind": "pre", "relation": ["left_hand", "nothing"], "step": 0, "keyframe": 0},
            {"kind": "pre", "relation": ["right_hand", "nothing"], "step": 3, "keyframe": 3},
            {"kind": "pre", "relation": ["liquid_one", "red_cup"], "step": 1, "keyframe": 1},
            {"kind": "pre", "relation": ["green_cup", "liquid_two"], "step": 4, "keyframe": 4},
            {"kind": "effect", "relation": ["mixer", "right_hand"], "step": 6, "keyframe": 7},
            {"kind": "effect", "relation": ["liquid_one", "orange_bowl"], "step": 1, "keyframe": 2},
            {"kind": "effect", "relation": ["liquid_two", "orange_bowl"], "step": 4, "keyframe": 5},
            {"kind": "effect", "relation": ["mixer", "orange_bowl"], "step": 7, "keyframe": 8,
             "note": "last writer"},
            {"kind": "ended", "relation": ["liquid_one", "red_cup"], "step": 1, "keyframe": 2},
            {"kind": "ended", "relation": ["green_cup", "liquid_two"], "step": 4, "keyframe": 5},
        ],
    }
    run_steps = []
    for i, (oac, binding, added, removed, _) in enumerate(STEPS):
        run_steps.append({"oac": oac, "binding": binding, "success": True, "duration_s": 2.1 + 0.3 * (i % 3),
                          "predicted": added or [[binding["h"], "nothing"]], "predicted_not": removed,
                          "observed": rels[i + 1], "error": None,
                          **({"frame": f"figures/robot_{i + 1}.png"} if with_pictures else {})})
    run = {"oac": "dough", "success": True, "steps": run_steps,
           "metrics": {"balls_total": 20, "balls_in_bowl": 19, "sim_time_s": 19.6, "wall_time_s": 1.7},
           "initial": rels[0], "grasp": "weld", **({"frame": "figures/robot_0.png"} if with_pictures else {})}
    states = [WorldState.of(INSTANCES, r) for r in rels]
    verification = verify(states, states, demonstration_frames=[k["frame"] for k in keyframes],
                          robot_frames=[k["frame"] + 40 for k in keyframes],
                          demonstration_times_s=times, robot_times_s=[t * 1.5 for t in times]).to_json()
    rows = [{"oac": s["oac"], "success": True, "duration_s": s["duration_s"], "error": None, "time_utc": "t"}
            for s in run_steps]
    rows += [{"oac": "pour", "success": False, "duration_s": 3.3,
              "error": "only 12 of 20 balls reached the bowl", "time_utc": "2025-05-01T10:00:00.000Z"}]
    reliability = {"db": "/home/user/.local/share/oacdsl/runs.sqlite3",
                   "oacs": [r.to_json() for r in summarise(rows)]}
    stages = [("segment", 0.41), ("match", 0.05), ("compose", 0.03), ("execute", 21.8), ("verify", 0.6),
              ("report", 1.2)]
    return {
        "schema_version": 1,
        "created_utc": "2025-05-02T09:30:00Z",
        "oacdsl_version": "0.1.0",
        "demonstration": {"recording": "dough.c3d", "title": "Dough: pour two liquids into a bowl and mix",
                          "scene": "kitchen", "library": ["library/"], "seed": 0,
                          "command": "oacc reproduce dough.c3d --out out/"},
        "verdict": {"success": True, "summary": "The robot poured both liquids and mixed; its own execution"
                    " gives the demonstration's 8 world-state changes."},
        "stages": [{"name": n, "status": "ok", "duration_s": d} for n, d in stages],
        "segment": segment,
        "match": {"sub_actions": sub_actions},
        "compose": compose,
        "run": run,
        "verification": verification,
        "reliability": reliability,
    }
