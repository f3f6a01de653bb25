"""The cycles check's reading of an execution's path (``oacdsl/verify_motion.py``), on the KIT
Mix demonstration's own mixing path: the person's circles followed by what a robot does
before its hands let go (sets the tool down a few centimetres aside and rests it there) are
still the person's circles; a path with its circles straightened is still no oscillation."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import numpy as np
from _mocap import mocap_file

from oacdsl.matching.transient import agents_of, stable_segmentation
from oacdsl.pipeline import load_inputs
from oacdsl.segmentation import AasParams, segment
from oacdsl.segmentation.motion import SubActionMotion, sub_action_motions
from oacdsl.segmentation.motionfeatures import motion_features
from oacdsl.verify_motion import moving_stretches, oscillation
from oacdsl.verify_tolerances import DEFAULT_TOLERANCES

ROOT = Path(__file__).resolve().parents[1]
MIX = "kit_bimanual/Mix_files_motions_3121_Mix1_salad_gb_parallel_08.mmm.xml"


def _mixing() -> SubActionMotion:
    """The Mix demonstration's sub-action in which the spoon circles in the bowl."""
    inputs = load_inputs(mocap_file(MIX), ROOT / "library" / "kit", None, AasParams())
    agents = agents_of(inputs.library.instance_classes(inputs.scene))
    rec = inputs.recording
    seg = stable_segmentation(segment(rec, inputs.params), agents.__contains__)[0]
    circling = [m for m in sub_action_motions(rec, seg) if m.features is not None and m.features.cycles]
    assert len(circling) == 1, [m.moved for m in circling]
    return circling[0]


def _straightened(m: SubActionMotion) -> SubActionMotion:
    """``m`` with its path straightened over the circles' span, as tests/_verify_takes.py
    corrupts a recording: a straight line at constant speed between where the circles begin and
    end, the orientation kept as it was there (turning, the pose's origin would still circle)."""
    a, b = (int(np.searchsorted(m.times_s, t)) for t in m.features.core_s)
    T = m.T_target_object.copy()
    w = np.linspace(0.0, 1.0, b - a + 1)[:, None]
    T[a : b + 1, :3, 3] = (1 - w) * T[a, :3, 3] + w * T[b, :3, 3]
    T[a : b + 1, :3, :3] = T[a, :3, :3]
    return replace(m, T_target_object=T, features=motion_features(m.times_s, T))


def _min_jerk(n: int) -> np.ndarray:
    s = np.linspace(0.0, 1.0, n + 1)[1:]
    return 10 * s**3 - 15 * s**4 + 6 * s**5


def _with_rest(m: SubActionMotion) -> tuple[np.ndarray, np.ndarray]:
    """The sub-action's path (times, T_target_object) followed by what the robot does on KIT
    Mix after its circles, before its hands let go (seed 0, measured in the bowl's frame): its
    arm stops (0.3 s), sets the server down 4.5 cm aside (1 s), holds (0.7 s), leans it 7 cm
    the other way (0.7 s) and rests it there (2.7 s)."""
    t, T = m.times_s, m.T_target_object
    dt = float(np.median(np.diff(t)))
    here = T[np.flatnonzero(np.isfinite(T[:, 0, 0]))[-1], 0, 3]
    x = [np.full(round(0.3 / dt), here)]
    for to_m, move_s, still_s in ((-0.045, 1.0, 0.7), (0.025, 0.7, 2.7)):
        n = round(move_s / dt)
        x += [x[-1][-1] + (here + to_m - x[-1][-1]) * _min_jerk(n), np.full(round(still_s / dt), here + to_m)]
    xs = np.concatenate(x)
    last = T[np.flatnonzero(np.isfinite(T[:, 0, 0]))[-1]]
    tail = np.repeat(last[None], len(xs), axis=0)
    tail[:, 0, 3] = xs
    times = np.r_[t, t[-1] + dt * np.arange(1, len(xs) + 1)]
    return times, np.concatenate([T, tail])


def test_circles_followed_by_a_rest_are_still_circles() -> None:
    m = _mixing()
    demo = m.features
    times, T = _with_rest(m)
    assert motion_features(times, T).cycles is None  # read whole: no period found
    f = oscillation(times, T, DEFAULT_TOLERANCES)
    assert f.cycles is not None and abs(f.cycles - demo.cycles) < 0.5, (f.cycles, demo.cycles)
    assert abs(f.radius_m - demo.radius_m) < 0.005
    tol = DEFAULT_TOLERANCES
    stretches = moving_stretches(times, T, tol.still_speed_m_s, tol.still_pause_s)
    assert len(stretches) == 3 and stretches[0][1] <= len(m.times_s) + 1  # circles, set down, lean


def test_a_path_read_whole_is_read_as_before() -> None:
    m = _mixing()
    assert oscillation(m.times_s, m.T_target_object, DEFAULT_TOLERANCES) == m.features


def test_straightened_circles_followed_by_a_rest_are_no_oscillation() -> None:
    m = _straightened(_mixing())
    assert m.features is not None and m.features.cycles is None
    times, T = _with_rest(m)
    assert oscillation(times, T, DEFAULT_TOLERANCES).cycles is None
    assert oscillation(m.times_s, m.T_target_object, DEFAULT_TOLERANCES).cycles is None


def test_strokes_that_stop_at_each_end_are_read_across_their_stops() -> None:
    """Four strokes of 5 cm, 0.5 s each way, stopping 0.15 s at each end (each stroke is a
    min-jerk move), then, after a stop, set down 4 cm aside and rested 3 s: no single moving
    stretch holds an oscillation, the strokes joined do."""
    dt = 0.01
    go = _min_jerk(50)
    stop = np.zeros(15)
    x = np.concatenate([np.r_[stop, 0.05 * go, stop + 0.05, 0.05 - 0.05 * go] for _ in range(4)]
                       + [stop, -0.04 * _min_jerk(60), np.full(300, -0.04)])
    times = dt * np.arange(len(x))
    T = np.repeat(np.eye(4)[None], len(x), axis=0)
    T[:, 0, 3] = x
    tol = DEFAULT_TOLERANCES
    stretches = moving_stretches(times, T, tol.still_speed_m_s, tol.still_pause_s)
    assert len(stretches) >= 8
    assert all(motion_features(times[a:b], T[a:b]).cycles is None for a, b in stretches)
    f = oscillation(times, T, tol)
    assert f.cycles is not None and f.cycles >= 3.0, f
