"""Tool–target contacts and cross-hand contacts (step 5 of the adaptive detector)."""

from __future__ import annotations

import numpy as np
import pytest
from _aas_helpers import path, recording, still, summary

from oacdsl.errors import SegmentationError
from oacdsl.segmentation import AasParams, segment
from oacdsl.segmentation.adaptive import AdaptiveDetector, AdaptiveSettings
from oacdsl.segmentation.pairs import PairTable
from oacdsl.segmentation.tooluse import agents_of, passes_through, tool_contacts

F = 800
CUP = np.array([[0.03, 0.03, 0.0], [-0.03, 0.03, 0.0], [0.03, -0.03, 0.05], [-0.03, -0.03, 0.05]])
SPOON = np.array([[0.0, 0.0, 0.0], [0.0, 0.0, 0.03], [0.0, 0.0, 0.06]])  # markers along the handle
HAND = np.array([[0.0, 0.0, 0.0], [0.04, 0.0, 0.0], [0.0, 0.03, 0.01]])
GRIP = np.array([0.0, 0.0, 0.10])  # hand origin above the spoon origin: 4 cm from its top marker
CUP_AT = np.array([0.5, 0.0, 0.0])


def cluster(centre: np.ndarray, layout: np.ndarray) -> np.ndarray:
    return centre[:, None, :] + layout[None, :, :]


def stir_scene(stir: bool = True) -> dict[str, np.ndarray]:
    """A hand takes a spoon (100), carries it over a cup (150–250) and stirs 3 cm circles at 2 Hz
    (250–450), 9–12 cm from the cup's markers, puts it back (450–600) and leaves (650).
    Without ``stir`` it carries the spoon across the cup at 0.8 m/s instead, and on."""
    rest, above = (0.9, 0.0, 0.0), tuple(CUP_AT + (0.0, 0.0, 0.14))
    if stir:
        spoon = path(F, [(0, rest), (150, rest), (250, above), (450, above), (600, rest)])
        t = np.arange(F) / 100.0
        active = (np.arange(F) >= 250) & (np.arange(F) < 450)
        spoon[active, 0] += 0.03 * np.cos(2 * np.pi * 2 * t[active])
        spoon[active, 1] += 0.03 * np.sin(2 * np.pi * 2 * t[active])
    else:
        spoon = path(F, [(0, rest), (150, rest), (250, (0.1, 0.0, 0.14)), (600, (0.1, 0.0, 0.14))])
    hand = spoon + GRIP
    hand[:100] = path(100, [(0, (0.9, -0.4, 0.5)), (99, tuple(hand[100]))])
    hand[650:] = path(F - 650, [(0, tuple(hand[649])), (F - 651, (0.9, -0.4, 0.5))])
    return {"cup": cluster(still(F, tuple(CUP_AT)), CUP), "spoon": cluster(spoon, SPOON),
            "right_hand": cluster(hand, HAND)}


def relations(rec, settings: AdaptiveSettings | None = None) -> set[tuple[str, str]]:
    params = AasParams(merge_s=0.0).resolved(rec.rate_hz)
    return {r for _, rs in summary(segment(rec, params, detector=AdaptiveDetector(params, settings)))
            for r in rs}


def test_a_stirring_spoon_touches_the_cup_it_oscillates_in():
    rec = recording(stir_scene())
    closest = np.linalg.norm(rec.group_positions("spoon")[:, :, None] - rec.group_positions("cup")[:, None],
                             axis=-1).min(axis=(1, 2))
    assert 0.08 < closest[250:450].min() and closest[250:450].max() < 0.15  # beyond the static 8 cm, within d
    reach = np.flatnonzero(closest < 0.15)
    params = AasParams(merge_s=0.0).resolved(rec.rate_hz)
    kfs = summary(segment(rec, params))
    on = [f for f, rs in kfs if ("cup", "spoon") in rs]
    off = [f for f, rs in kfs if on and f > on[0] and ("cup", "spoon") not in rs]
    # from when the held spoon comes within d of the cup until it leaves that reach
    assert on and off and abs(on[0] - reach[0]) <= 2 and abs(off[0] - reach[-1] - 1) <= 2, kfs
    # without agents (no instance named like a hand) the tool rule is off and the contact is missed
    assert ("cup", "spoon") not in relations(rec, AdaptiveSettings(agent_pattern="nobody"))


def test_a_tool_carried_past_an_object_does_not_touch_it():
    rec = recording(stir_scene(stir=False))
    closest = np.linalg.norm(rec.group_positions("spoon")[:, :, None] - rec.group_positions("cup")[:, None],
                             axis=-1).min(axis=(1, 2))
    assert (closest < 0.15).sum() >= 20  # within reach for a moment (0.2 s and more)
    # the dwell as written, 0.5 s: the pass (0.44 s) is too short. The default detector reads the
    # dwell in the demonstration's pace, here the carry itself (0.8 m/s, 1.6 times the reference's):
    # 0.31 s, shorter than the pass; the pass is told apart by its path: straight through the reach
    fixed = relations(rec, AdaptiveSettings(rescale=False))
    assert ("cup", "spoon") not in fixed and ("right_hand", "spoon") in fixed
    found = relations(rec)
    assert ("cup", "spoon") not in found and ("right_hand", "spoon") in found
    # the tool rule alone, with a dwell shorter than the pass: the path decides, not the dwell
    found = relations(rec, AdaptiveSettings(rescale=False, tool_dwell_s=0.1))
    assert ("cup", "spoon") not in found and ("right_hand", "spoon") in found


def test_a_tool_going_straight_through_a_reach_passes_by_one_going_to_it_or_back_and_forth_does_not():
    t = np.linspace(0.0, 1.0, 41)[:, None]
    target = np.zeros((41, 3))
    through = np.hstack([-0.15 + 0.3 * t, np.full_like(t, 0.05), np.zeros_like(t)])  # 30 cm across
    assert passes_through(through, target, 4, 0.15)
    assert not passes_through(through * 0.4, target, 4, 0.15)  # 12 cm, straight to it: placed there
    onto = np.hstack([-0.25 + 0.24 * t, np.full_like(t, 0.01), np.zeros_like(t)])  # 24 cm, onto it
    assert not passes_through(onto, target, 4, 0.15)
    stir = np.hstack([0.05 * np.cos(12 * t), 0.05 * np.sin(12 * t), np.zeros_like(t)])
    assert not passes_through(stir, target, 4, 0.15)
    jitter = through + np.random.default_rng(0).normal(0.0, 0.0005, through.shape)
    assert passes_through(jitter, target, 4, 0.15)  # sampled every few frames: jitter adds no length
    gaps = through.copy()
    gaps[10:20] = np.nan
    assert passes_through(gaps, target, 4, 0.15)


def table_of(names: list[str]) -> PairTable:
    return PairTable.of(recording({n: still(4, (i, 0.0, 0.0)) for i, n in enumerate(names)}))


def test_tool_contact_through_the_hand_holding_the_target_and_cross_hand_veto():
    table = table_of(["cup", "jug", "left_hand", "right_hand"])
    q = {table.relation(k): k for k in range(table.n_instance_pairs)}
    n = 100
    held = {q[("cup", "left_hand")]: [(10, 90)], q[("jug", "right_hand")]: [(20, 80)]}
    far = np.full(n, 0.3)
    jug_cup, jug_hand = far.copy(), far.copy()
    jug_cup[30:40] = 0.12   # the jug near the cup for 1 s …
    jug_hand[40:60] = 0.10  # … then near the hand holding it (the cup's far side) for 2 s
    closest = {q[("cup", "jug")]: jug_cup, q[("jug", "left_hand")]: jug_hand}
    agents = agents_of(table.instances, "*hand*")
    assert [table.instances[i] for i in agents] == ["left_hand", "right_hand"]
    found = tool_contacts(table, n, 10.0, held, closest, agents, 0.15, 0.5, 0.2)
    assert found.added == {q[("cup", "jug")]: [(30, 60)]}
    # each hand holds its own object: neither touches the other's while both hold
    assert found.removed == {q[("jug", "left_hand")]: [(20, 80)], q[("cup", "right_hand")]: [(20, 80)]}
    # a shorter stay than the dwell (0.5 s = 5 frames) is passing by; a short excursion is bridged
    jug_cup[:] = 0.3
    jug_cup[30:34] = 0.12
    assert tool_contacts(table, n, 10.0, held, closest | {q[("cup", "jug")]: jug_cup}, [], 0.15, 0.5, 0.2) \
        .added == {}
    jug_hand[:] = 0.3
    jug_hand[40:43] = jug_hand[45:48] = 0.1
    short = tool_contacts(table, n, 10.0, held, {q[("jug", "left_hand")]: jug_hand}, agents, 0.15, 0.5, 0.2)
    assert short.added == {q[("cup", "jug")]: [(40, 48)]}
    # a gap (NaN) of any length inside a contact does not end it; beyond its ends it starts nothing
    jug_hand[:] = 0.3
    jug_hand[40:60] = 0.1
    jug_hand[45:55] = jug_hand[60:70] = np.nan
    gap = tool_contacts(table, n, 10.0, held, {q[("jug", "left_hand")]: jug_hand}, agents, 0.15, 0.5, 0.2)
    assert gap.added == {q[("cup", "jug")]: [(40, 60)]}
    # without agents there is nothing to do
    assert tool_contacts(table, n, 10.0, held, closest, (), 0.15, 0.5, 0.2).added == {}


def test_tool_settings_are_checked():
    with pytest.raises(SegmentationError, match="tool_dwell_s must be positive"):
        AdaptiveSettings(tool_dwell_s=0)
    with pytest.raises(SegmentationError, match="tool_bridge_s"):
        AdaptiveSettings(tool_bridge_s=-1)
