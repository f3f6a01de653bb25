"""End-state rules on small hand-made recordings (docs/verify.md)."""

from __future__ import annotations

import math
from pathlib import Path

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


def test_an_object_left_leaning_on_another_is_supported_by_it() -> None:
    # a server left in a bowl, its handle over the rim: its markers (on the handle) end
    # outside the bowl's footprint and 10 cm above the table, touching only the bowl
    bowl = np.concatenate([_ring(0.12, 0.12), _ring(0.0, 0.0, k=1)])
    lying = np.array([[0.10 + 0.05 * i, 0.3, 0.0] for i in range(4)])
    leaning = np.array([[0.10 + 0.04 * i, 0.0, 0.10 + 0.03 * i] for i in range(4)])
    rec = _recording({"bowl": np.stack([bowl, bowl]), "spoon": np.stack([lying, leaning]),
                      "hand": np.stack([lying + [0, 0.3, 0], lying + [0, 0.3, 0.3]])})
    agent = lambda n: n == "hand"  # noqa: E731
    ends = end_state(rec, WorldState.of(("bowl", "spoon", "hand"), [("bowl", "spoon")]), agent,
                     lambda n: n == "bowl", VerifyTolerances())
    assert (ends.objects["spoon"].support, ends.objects["spoon"].supporter) == ("in", "bowl")
    # touching nothing, or only what a hand holds up, it is in the air
    for pairs in ([], [("bowl", "spoon"), ("bowl", "hand")]):
        ends = end_state(rec, WorldState.of(("bowl", "spoon", "hand"), pairs), agent,
                         lambda n: n == "bowl", VerifyTolerances())
        assert ends.objects["spoon"].support == "air"


def test_the_mix_demonstration_leaves_both_servers_leaning_in_the_bowl() -> None:
    from _mocap import mocap_file

    from oacdsl.pipeline import load_inputs
    from oacdsl.segmentation import AasParams
    from oacdsl.verify_execution import verify_execution

    i = load_inputs(mocap_file("kit_bimanual/Mix_files_motions_3121_Mix1_salad_gb_parallel_08.mmm.xml"),
                    Path(__file__).resolve().parents[1] / "library" / "kit", None, AasParams())
    rec = i.recording
    # the spoon's markers end 10 cm above the table, their centre outside the bowl's rim ...
    pts, bowl = rec.group_positions("salad_spoon")[-1], rec.group_positions("mixing_bowl_green")[-1]
    out = np.linalg.norm(pts.mean(axis=0)[:2] - bowl.mean(axis=0)[:2])
    assert out > np.linalg.norm(bowl[:, :2] - bowl.mean(axis=0)[:2], axis=1).max() + 0.03
    assert pts[:, 2].min() - rec.group_positions("salad_spoon")[0][:, 2].min() > 0.08
    # ... leaning on its side and touching the bowl only (no hand): it is in the bowl, as the fork
    o = verify_execution(rec, rec, scene=i.scene, library=i.library, params=i.params)
    demo = {c.name: c.demonstration for c in o.checks}
    assert demo["end_state.salad_spoon.support"] == "in mixing_bowl_green"
    assert demo["end_state.salad_spoon.orientation"].startswith("on its side")
    assert demo["end_state.salad_fork.support"] == "in mixing_bowl_green"


def test_the_mix_servers_start_lying_and_end_leaning_along_their_long_axes() -> None:
    """The physical reason for judging an elongated tool by its long axis's end tilt when its
    start differs (oacdsl/verify_orientation.py): the person's servers lie on the table and
    end leaning in the bowl, 31° and 48° from the vertical; the robot's (library/kit) stand."""
    from _mocap import mocap_file

    from oacdsl.pipeline import load_inputs
    from oacdsl.segmentation import AasParams

    i = load_inputs(mocap_file("kit_bimanual/Mix_files_motions_3121_Mix1_salad_gb_parallel_08.mmm.xml"),
                    Path(__file__).resolve().parents[1] / "library" / "kit", None, AasParams())
    final = WorldState.of(tuple(i.recording.instances), [])
    ends = end_state(i.recording, final, lambda n: n.endswith("hand"), lambda n: False, VerifyTolerances())
    for server, lean in (("salad_fork", 31.0), ("salad_spoon", 48.0)):
        axis = ends.objects[server].axis_rad
        assert axis is not None
        assert math.degrees(axis[0]) > 85.0  # lying
        assert abs(math.degrees(axis[1]) - lean) < 2.0
    for other in ("mixing_bowl_green",):  # no long axis
        assert ends.objects[other].axis_rad is None
