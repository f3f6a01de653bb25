"""What a tool contact means around it (oacdsl.segmentation.toolroles), on the KIT development clips.

Each clip's keyframes are written down from its labels and its objects' heights (see
docs/segmentation-adaptive.md, "Tool roles"); every rule of toolroles breaks one of them.
"""

from __future__ import annotations

import numpy as np
import pytest
from _mocap import mocap_file

from oacdsl.segmentation import AasParams, segment
from oacdsl.segmentation.grouping import recognise_preset
from oacdsl.segmentation.readers import read_recording

FORK, SPOON, BOWL = "salad_fork", "salad_spoon", "mixing_bowl_green"
L, R = "left_hand", "right_hand"

#: clip → [(frame, relations made, relations broken)] of the default (adaptive) segmentation.
EXPECTED: dict[str, list[tuple[int, set[tuple[str, str]], set[tuple[str, str]]]]] = {
    "Mix": [  # the servers are taken, mix in the bowl and are left in it (rules 1, 2, 3, 5)
        (10, {(L, FORK)}, set()),  # the two hands' changes keep their own frames (connected merging)
        (12, {(R, SPOON)}, set()),
        (24, {(BOWL, FORK), (BOWL, SPOON)}, set()),
        (56, set(), {(L, FORK)}),
        (58, set(), {(R, SPOON)}),
    ],
    "Wipe": [  # the plate is put into the draining rack and stays there (rule 2)
        (11, {(L, "plate_dish")}, set()),
        (16, {(R, "sponge_small")}, set()),
        (20, {("plate_dish", "sponge_small")}, set()),
        (39, set(), {("plate_dish", "sponge_small")}),
        (42, {("draining_rack", "plate_dish")}, set()),
        (48, set(), {(L, "plate_dish")}),
        (54, set(), {(R, "sponge_small")}),
    ],
    "Scoop": [  # the cup is held by the bowl, not on it (rule 4); the ladle goes back in (rule 2)
        (17, {("cup_small", L)}, set()),
        (21, {("ladle", BOWL), ("ladle", R)}, set()),  # a group stands at its hand's change
        (35, {("cup_small", "ladle")}, {("ladle", BOWL)}),
        (52, {("ladle", BOWL)}, {("cup_small", "ladle")}),
        (63, set(), {("ladle", R)}),
        (66, set(), {("cup_small", L)}),
    ],
    "Cut": [  # the knife cuts the cucumber held on the board, not the board (rules 4, 5)
        (12, {("cucumber_attachment", L)}, set()),
        (19, {("knife_black", R)}, set()),
        (22, {("cucumber_attachment", "cutting_board_small")}, set()),
        (28, {("cucumber_attachment", "knife_black")}, set()),
        (71, set(), {("cucumber_attachment", "cutting_board_small"), ("cucumber_attachment", "knife_black")}),
        (83, set(), {("cucumber_attachment", L)}),
        (87, set(), {("knife_black", R)}),
    ],
}


def changes(action: str) -> list[tuple[int, set[tuple[str, str]], set[tuple[str, str]]]]:
    xml = next(mocap_file("kit_bimanual").glob(f"{action}_*.mmm.xml"))
    recording, _ = recognise_preset(read_recording(xml))
    result = segment(recording, AasParams().resolved(recording.rate_hz))
    assert not result.keyframes[0].state.relations  # nothing touches at the start
    out = []
    for before, after in zip(result.keyframes, result.keyframes[1:], strict=False):
        was, now = before.state.relations, after.state.relations
        made, broken = now - was, was - now
        out.append((after.frame, set(made), set(broken)))
    return out


@pytest.mark.parametrize("action", sorted(EXPECTED))
def test_development_clip_keyframes_are_what_the_labels_say(action):
    assert changes(action) == EXPECTED[action]


def test_pour_and_stir_keep_their_keyframes():
    """Both objects held: nothing is left behind when they are set down (rule 2 does not apply)."""
    pour = changes("Pour")
    assert [f for f, _, _ in pour] == [14, 20, 54]  # the carton grasped, then reaching the cup: one group
    assert ("cup_small", "milk_small") in pour[-1][2]
    assert [f for f, _, _ in changes("Stir")] == [19, 21, 27, 48, 55, 56]


def test_at_rest_is_within_rest_m_between_the_quartiles():
    """A held object rests on another when their distance varies by at most REST_M between its
    quartiles (Cut's cucumber held on the board: 0.7 mm). A spoon stirring in a bowl varies by
    12 mm at 10 Hz, and by 9.5 mm when the same stirring is seen in a 10 Hz take at double speed
    (every other moment): not at rest (with twice REST_M it was, and Mix's fork, not the spoon,
    became the spoon's target)."""
    import numpy as np

    from oacdsl.segmentation.toolroles import REST_M, _rests

    held = 0.12 + np.array([0.0, 0.0007, 0.0003, -0.0002, 0.0005, 0.0001])
    assert _rests(held, REST_M)
    stirring = 0.13 + np.array([-0.00475, 0.00475] * 4)
    lo, hi = np.percentile(stirring, [25, 75])
    assert hi - lo == pytest.approx(0.0095) and not _rests(stirring, REST_M)


def test_mix_at_double_speed_keeps_the_servers_in_the_bowl():
    """KIT Mix as a 10 Hz take at twice the speed: both servers touch the bowl, not each other."""
    from oacdsl.segmentation.takes import stretched

    xml = next(mocap_file("kit_bimanual").glob("Mix_*.mmm.xml"))
    recording, _ = recognise_preset(read_recording(xml))
    take = stretched(recording, 0.5)
    result = segment(take, AasParams().resolved(take.rate_hz))
    seen = {frozenset(r) for k in result.keyframes for r in k.state.relations}
    assert frozenset((FORK, BOWL)) in seen and frozenset((SPOON, BOWL)) in seen
    assert frozenset((FORK, SPOON)) not in seen


def test_first_not_is_the_per_frame_walk() -> None:
    """_first_not (rules 2 and 5's walk onwards) stops where the frame-by-frame loop stops."""
    from oacdsl.segmentation.toolroles import _first_not

    rng = np.random.default_rng(4)
    for _ in range(300):
        n = int(rng.integers(1, 400))
        d = rng.random(n) * 0.2
        d[rng.random(n) < 0.05] = np.nan
        held_i, held_j = rng.random(n) < 0.01, rng.random(n) < 0.01
        b = int(rng.integers(0, n + 1))
        e = b
        while e < n and d[e] < 0.19 and not (held_i[e] or held_j[e]):
            e += 1
        assert _first_not(d, 0.19, b, n, held_i, held_j) == e
        near = d < 0.15
        e = b
        while e < n and near[e]:
            e += 1
        assert _first_not(near, None, b, n) == e
