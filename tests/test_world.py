import pytest

from oacdsl.world import WorldState, relation


def test_relation_is_sorted_and_rejects_self():
    assert relation("b", "a") == ("a", "b")
    with pytest.raises(ValueError):
        relation("a", "a")


def test_world_state_queries():
    w = WorldState.of(["cup", "hand", "bowl"], [("hand", "cup")])
    assert w.touches("cup", "hand") and w.touches("hand", "cup")
    assert not w.touches("cup", "bowl")
    assert w.partners("hand") == {"cup"}
    assert w.touches_nothing("bowl") and not w.touches_nothing("cup")
    assert not w.touches_nothing("ghost")  # unknown is not "touching nothing"
    assert w == WorldState.of(["bowl", "hand", "cup"], [("cup", "hand")])
    assert hash(w) == hash(WorldState.of(["bowl", "hand", "cup"], [("cup", "hand")]))


def test_world_state_changes_and_unknown_instance():
    w = WorldState.of(["a", "b", "c"], [("a", "b")])
    w2 = w.with_changes(added=[("c", "b")], removed=[("b", "a")])
    assert w2.sorted_relations() == [("b", "c")]
    with pytest.raises(ValueError, match="unknown instance 'z'"):
        WorldState.of(["a"], [("a", "z")])
