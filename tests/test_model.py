from oacdsl.library import Library
from oacdsl.model import Atom, Module, Oac, ObjectClass, Param, Span


def test_atoms_are_canonical_and_trivia_is_outside_equality():
    a = Atom(left="o", right="h", span=Span(file="x", line=1, column=1, end_line=1, end_column=2))
    b = Atom(left="h", right="o", note="from step 1")
    assert (a.left, a.right) == ("h", "o")
    assert a == b and hash(a) == hash(b)
    n = Atom(left="nothing", right="h")
    assert (n.left, n.right) == ("h", "nothing") and n.about_nothing


def test_oac_pre_and_effect_are_sets():
    p = (Param(name="h", cls="Hand"), Param(name="o", cls="Graspable"))
    o1 = Oac(name="grasp", params=p, pre=(Atom(left="h", right="nothing"),),
             effect=(Atom(left="o", right="h"), Atom(left="h", right="o")), skill="reach_and_grasp")
    o2 = Oac(name="grasp", params=p, pre=(Atom(left="h", right="nothing"),),
             effect=(Atom(left="h", right="o"),), skill="reach_and_grasp")
    assert o1 == o2 and len(o1.effect) == 1
    assert o1 != o2.model_copy(update={"skill": "place"})


def test_library_class_hierarchy():
    mod = Module(path="m.oac", decls=(
        ObjectClass(name="Graspable"), ObjectClass(name="Container"),
        ObjectClass(name="Cup", parents=("Graspable", "Container")),
        ObjectClass(name="TeaCup", parents=("Cup",)),
    ))
    lib = Library([mod])
    assert lib.is_subclass("TeaCup", "Container")
    assert not lib.is_subclass("Container", "Cup")
    assert lib.ancestors("TeaCup") == {"TeaCup", "Cup", "Graspable", "Container"}
