"""Random small libraries, scenes and world states for property tests, and the
brute-force matching reference (a loop over all bindings) the matcher is checked against."""

from __future__ import annotations

import itertools
from collections.abc import Mapping

from hypothesis import strategies as st

from oacdsl.library import Library
from oacdsl.matching.conditions import apply_effects, bind_atoms, holds
from oacdsl.model import Atom, Instance, Module, Oac, ObjectClass, Param, Scene
from oacdsl.world import NOTHING, WorldState, relation

CLASS_NAMES = ["Root", "Thing", "Mid", "Sub", "Leaf", "Other"]


@st.composite
def hierarchies(draw) -> list[ObjectClass]:
    """Up to six classes, at most three levels deep, parents drawn among earlier classes."""
    classes: list[ObjectClass] = []
    level: dict[str, int] = {}
    for name in CLASS_NAMES[: draw(st.integers(2, len(CLASS_NAMES)))]:
        candidates = [c.name for c in classes if level[c.name] < 2]
        parents = draw(st.lists(st.sampled_from(candidates), max_size=2, unique=True)) if candidates else []
        level[name] = 1 + max((level[p] for p in parents), default=-1)
        classes.append(ObjectClass(name=name, parents=tuple(parents)))
    return classes


@st.composite
def scenes(draw, classes: list[ObjectClass], min_size: int = 2, max_size: int = 6) -> Scene:
    n = draw(st.integers(min_size, max_size))
    names = [c.name for c in classes]
    return Scene(name="s", instances=tuple(
        Instance(name=f"i{k}", classes=tuple(draw(st.lists(st.sampled_from(names), min_size=1, max_size=2,
                                                            unique=True))))
        for k in range(n)
    ))


@st.composite
def atoms_over(draw, variables: list[str], n_min: int = 0, n_max: int = 3) -> tuple[Atom, ...]:
    out = []
    for _ in range(draw(st.integers(n_min, n_max))):
        kind = draw(st.sampled_from(["pos", "pos", "neg", "none", "pos", "neg", "none", "some"]))
        a = draw(st.sampled_from(variables))
        if kind in ("none", "some") or len(variables) < 2:
            out.append(Atom(left=a, right=NOTHING, negated=kind == "some"))
        else:
            b = draw(st.sampled_from([v for v in variables if v != a]))
            out.append(Atom(left=a, right=b, negated=kind == "neg"))
    return tuple(out)


def consistent(atoms: tuple[Atom, ...]) -> bool:
    """True when the atoms can hold in one state."""
    keys = {(a.left, a.right, a.negated) for a in atoms}
    for x, y, neg in keys:
        if (x, y, not neg) in keys:
            return False
        if y != NOTHING and not neg and ((x, NOTHING, False) in keys or (y, NOTHING, False) in keys):
            return False
    return True


@st.composite
def oacs(draw, classes: list[ObjectClass], name: str, constants: list[str] = (),  # type: ignore[assignment]
         fit: Library | None = None, scene: Scene | None = None) -> Oac:
    """A random OAC; with ``fit`` and ``scene``, its parameters' classes are classes of
    distinct instances of the scene (so the OAC can bind)."""
    n = draw(st.sampled_from([2, 3, 1, 4]))
    class_names = [c.name for c in classes]
    if fit is not None and scene is not None:
        of = fit.instance_classes(scene)
        picked = draw(st.permutations(sorted(of)))[: n]
        params = tuple(Param(name=f"v{k}", cls=draw(st.sampled_from(sorted(of[i]))))
                       for k, i in enumerate(picked))
    else:
        params = tuple(Param(name=f"v{k}", cls=draw(st.sampled_from(class_names))) for k in range(n))
    names = [p.name for p in params]
    if constants and draw(st.booleans()):
        names = [*names, draw(st.sampled_from(list(constants)))]
    if fit is not None:  # atoms that can hold together: a usable OAC
        pre = draw(atoms_over(names, 0, 3).filter(consistent))
        effect = draw(atoms_over(names, 1, 3).filter(consistent))
    else:
        pre = draw(atoms_over(names, 0, 3))
        effect = draw(atoms_over(names, 1, 3))
    return Oac(name=name, params=params, pre=pre, effect=effect, skill="mix")


@st.composite
def states(draw, instances: list[str], p_max: float = 0.5) -> WorldState:
    pairs = [relation(a, b) for a, b in itertools.combinations(sorted(instances), 2)]
    chosen = draw(st.lists(st.sampled_from(pairs), unique=True, max_size=len(pairs))) if pairs else []
    return WorldState.of(instances, chosen)


@st.composite
def cases(draw, max_oacs: int = 4, constants: bool = False):
    """(library, scene, before, after)."""
    classes = draw(hierarchies())
    scene = draw(scenes(classes))
    inst = [i.name for i in scene.instances]
    n_oacs = draw(st.integers(1, max_oacs))
    lib_oacs = [draw(oacs(classes, f"o{k}", inst if constants else ())) for k in range(n_oacs)]
    library = Library([Module(path="<random>", decls=(*classes, scene, *lib_oacs))])
    before = draw(states(inst))
    how = draw(st.sampled_from(["planted", "flip", "random"]))
    planted = draw(plant(library, scene, before)) if how == "planted" else None
    if planted is not None:  # an OAC's bound pre forced before, its effects applied after
        before, after = planted
    elif how != "random":  # a small change, like a real sub-action
        pairs = [relation(a, b) for a, b in itertools.combinations(sorted(inst), 2)]
        flips = draw(st.lists(st.sampled_from(pairs), min_size=1, max_size=2, unique=True))
        after = WorldState(before.instances, before.relations.symmetric_difference(flips))
    else:
        after = draw(states(inst))
    return library, scene, before, after


@st.composite
def plant(draw, library: Library, scene: Scene, state: WorldState):
    """(before, after) where one random OAC under one random binding applies, or None."""
    classes = library.instance_classes(scene)
    oac = draw(st.sampled_from(sorted(library.oacs.values(), key=lambda o: o.name)))
    free = sorted(state.instances)
    binding: dict[str, str] = {}
    for p in oac.params:
        options = [i for i in free if p.cls in classes[i] and i not in binding.values()]
        if not options:
            return None
        binding[p.name] = draw(st.sampled_from(options))
    names = {n for a in (*oac.pre, *oac.effect) for n in (a.left, a.right)} - set(binding) - {NOTHING}
    if not names <= set(free) - set(binding.values()):
        return None
    binding |= {n: n for n in names}
    undo = [Atom(left=a.left, right=a.right, negated=not a.negated)
            for a in oac.effect if not a.about_nothing]
    before = apply_effects(apply_effects(state, bind_atoms(undo, binding)), bind_atoms(oac.pre, binding))
    return before, apply_effects(before, bind_atoms(oac.effect, binding))


def brute_force(library: Library, classes: Mapping[str, frozenset[str]], before: WorldState,
                after: WorldState, mode: str) -> set[tuple[str, tuple[tuple[str, str], ...]]]:
    """Every (OAC name, binding) that matches, by trying every injective binding."""
    found = set()
    instances = sorted(before.instances & set(classes))
    added = after.relations - before.relations
    removed = before.relations - after.relations
    for oac in library.oacs.values():
        params = [p.name for p in oac.params]
        constants = sorted({n for a in (*oac.pre, *oac.effect) for n in (a.left, a.right)}
                           - set(params) - {NOTHING})
        if any(c not in instances for c in constants):
            continue
        free = [i for i in instances if i not in constants]
        for values in itertools.permutations(free, len(params)):
            if any(p.cls not in classes[v] for p, v in zip(oac.params, values, strict=True)):
                continue
            binding = dict(zip(params, values, strict=True)) | {c: c for c in constants}
            pre, eff = bind_atoms(oac.pre, binding), bind_atoms(oac.effect, binding)
            if not all(holds(a, before) for a in pre) or not all(holds(a, after) for a in eff):
                continue
            if mode == "strict":
                pos = {relation(a.left, a.right) for a in eff
                       if not a.negated and not a.about_nothing and a.left != a.right}
                neg = {relation(a.left, a.right) for a in eff
                       if a.negated and not a.about_nothing and a.left != a.right}
                cleared = {a.left for a in eff if a.about_nothing and not a.negated}
                if not (added or removed) or not added <= pos:
                    continue
                if any(r not in neg and not cleared & set(r) for r in removed):
                    continue
                changed = {x for r in added | removed for x in r}
                if any(x not in changed for a in eff for x in (a.left, a.right) if x != NOTHING):
                    continue
            found.add((oac.name, tuple(zip(params, values, strict=True))))
    return found


@st.composite
def demonstrations(draw, max_steps: int = 5):
    """(library, scene, steps): a random library and a chain of real (strict) matches.

    Each step is an OAC under an injective binding whose bound preconditions hold in
    the current state and whose bound effects hold in the state they produce.
    """
    from oacdsl.matching.composer import Step

    classes = draw(hierarchies())
    scene = draw(scenes(classes, 3, 6))
    inst = [i.name for i in scene.instances]
    n_oacs = draw(st.integers(1, 4))
    base = Library([Module(path="<random>", decls=(*classes, scene))])
    lib_oacs = [draw(oacs(classes, f"o{k}", fit=base, scene=scene)) for k in range(n_oacs)]
    library = Library([Module(path="<random>", decls=(*classes, scene, *lib_oacs))])
    cls = library.instance_classes(scene)
    options = {o.name: [v for v in itertools.permutations(inst, len(o.params))
                        if all(p.cls in cls[i] for p, i in zip(o.params, v, strict=True))] for o in lib_oacs}
    usable = [o for o in lib_oacs if options[o.name]]
    steps: list[Step] = []
    current = draw(states(inst))
    for _ in range(12 if usable else 0):  # a first step, its preconditions forced into the first state
        oac = draw(st.sampled_from(usable))
        values = draw(st.sampled_from(options[oac.name]))
        binding = dict(zip([p.name for p in oac.params], values, strict=True))
        pre, eff = bind_atoms(oac.pre, binding), bind_atoms(oac.effect, binding)
        undo = [Atom(left=a.left, right=a.right, negated=not a.negated)
                for a in eff if not a.about_nothing]
        start = apply_effects(apply_effects(current, undo), pre)
        after = apply_effects(start, eff)
        if all(holds(a, start) for a in pre) and all(holds(a, after) for a in eff) and after != start:
            steps.append(Step(oac, tuple(binding.items()), start, after, 0))
            current = after
            break
    # Later steps: any OAC and binding whose preconditions hold now (found by a pre-only matcher).
    from oacdsl.matching import Matcher

    pre_only = Matcher([o.model_copy(update={"effect": ()}) for o in lib_oacs], cls)
    for k in range(1, draw(st.integers(2, max_steps)) if steps else 0):
        valid = []
        found = pre_only.raw_matches(current, current, "paper")
        for co, b in sorted(found, key=lambda x: (x[0].index, x[1])):
            oac = lib_oacs[co.index]
            binding = dict(zip(co.names, b, strict=True))
            eff = bind_atoms(oac.effect, binding)
            after = apply_effects(current, eff)
            if after != current and all(holds(a, after) for a in eff):
                valid.append((oac, tuple((p.name, binding[p.name]) for p in oac.params), after))
        if not valid:
            break
        oac, binding_items, after = draw(st.sampled_from(valid))
        steps.append(Step(oac, binding_items, current, after, k))
        current = after
    return library, scene, steps


@st.composite
def states_satisfying(draw, instances: list[str], atoms: tuple[Atom, ...]):
    """A random state in which the bound ``atoms`` hold (None when they cannot be forced)."""
    s = apply_effects(draw(states(instances)), atoms)
    return s if all(holds(a, s) for a in atoms) else None
