"""End-state rules on small hand-made recordings (docs/verify.md)."""

from __future__ import annotations

import math

import numpy as np

from oacdsl.segmentation.recording import Recording
from oacdsl.verify_endstate import end_state
from oacdsl.verify_tolerances import VerifyTolerances
from oacdsl.world import WorldState


def _recording(objects: dict[str, np.ndarray]) -> Recording:
    """Per object (2, k, 3): its markers at the start and at the end, each held 6 frames."""
    names, groups, blocks = [], {}, []
    for name, pts in objects.items():
        groups[name] = tuple(range(len(names), len(names) + pts.shape[1]))
        names += [f"{name}:{i}" for i in range(pts.shape[1])]
        blocks.append(np.repeat(pts, 6, axis=0))
    positions = np.concatenate(blocks, axis=1)
    return Recording("test", 10.0, np.arange(12) / 10.0, tuple(names), positions, groups)


def _ring(radius: float, z: float, k: int = 6, centre: tuple[float, float] = (0.0, 0.0)) -> np.ndarray:
    return np.array([[centre[0] + radius * math.cos(a), centre[1] + radius * math.sin(a), z]
                     for a in np.linspace(0, 2 * math.pi, k, endpoint=False)])


def test_the_wider_of_two_objects_holding_each_other_up_is_the_support() -> None:
    bowl = np.concatenate([_ring(0.12, 0.012), _ring(0.05, 0.012)])  # floor markers, 12 mm up
    ladle = np.concatenate([_ring(0.015, 0.005), _ring(0.01, 0.25)])  # stands on the floor, lower
    rec = _recording({"bowl": np.stack([bowl, bowl]), "ladle": np.stack([ladle, ladle])})
    final = WorldState.of(("bowl", "ladle"), [("bowl", "ladle")])
    ends = end_state(rec, final, lambda n: False, lambda n: n == "bowl", VerifyTolerances())
    assert (ends.objects["ladle"].support, ends.objects["ladle"].supporter) == ("in", "bowl")
    assert ends.objects["bowl"].support == "table"


def test_a_tipped_cup_and_one_off_the_table() -> None:
    cup = np.concatenate([_ring(0.04, 0.02), _ring(0.04, 0.08)])
    tipped = cup.copy()
    tipped[:, [1, 2]] = cup[:, [2, 1]]  # 90° about x: on its side
    fallen = cup - [0.0, 0.0, 0.8]
    rec = _recording({"a": np.stack([cup, tipped]), "b": np.stack([cup + [0.5, 0, 0], fallen])})
    ends = end_state(rec, WorldState.of(("a", "b"), []), lambda n: False, lambda n: True, VerifyTolerances())
    a, b = ends.objects["a"], ends.objects["b"]
    assert a.orientation == "on its side" and a.tilt_rad is not None and abs(a.tilt_rad - math.pi / 2) < 1e-6
    assert b.support == "fell" and b.orientation == "upright"
