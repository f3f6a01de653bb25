"""Ties on the ranking's criteria 1-4: an OAC that runs the other as one of its steps goes first
(oacdsl/matching/results.py, callers_first), whatever the names."""

from __future__ import annotations

from pathlib import Path

import pytest

from oacdsl.compiler import load_library
from oacdsl.matching import Matcher
from oacdsl.world import WorldState

ROOT = Path(__file__).resolve().parents[1]


@pytest.fixture(scope="module")
def kit():
    return load_library([ROOT / "library" / "kit"])


def _onto_board(kit):
    tracked = sorted(i.name for i in kit.scenes["kit_cut"].tracked())
    held = ("left_hand", "cucumber_attachment")
    return (WorldState.of(tracked, [held]),
            WorldState.of(tracked, [held, ("cucumber_attachment", "cutting_board_small")]))


def _matcher(kit, oacs):
    return Matcher(oacs, kit.instance_classes(kit.scenes["kit_cut"]), ancestors=kit.ancestors)


def test_an_oac_that_runs_the_other_as_a_step_goes_first_whatever_its_name(kit):
    # KIT Cut: hold_on_board (steps onto_board, keep) and onto_board state the same conditions
    hold = kit.oacs["hold_on_board"].model_copy(update={"name": "zz_hold"})
    oacs = [o for n, o in kit.oacs.items() if n != "hold_on_board"] + [hold]
    result = _matcher(kit, oacs).match(*_onto_board(kit))
    assert [m.oac.name for m in result.matches] == ["zz_hold", "onto_board"]
    assert not result.ambiguous
    assert "it runs onto_board(h=left_hand, c=cucumber_attachment, b=cutting_board_small) as one of its" \
           " steps (onto_board, keep)" in result.reason


def test_a_tie_with_an_oac_it_does_not_call_stays_ambiguous(kit):
    twin = kit.oacs["onto_board"].model_copy(update={"name": "aa_onto"})
    result = _matcher(kit, [*kit.oacs.values(), twin]).match(*_onto_board(kit))
    assert [m.oac.name for m in result.matches] == ["hold_on_board", "aa_onto", "onto_board"]
    assert result.ambiguous and "ambiguous" in result.reason
