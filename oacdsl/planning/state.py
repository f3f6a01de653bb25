"""World states and goals for planning: a scene's initial state, atoms typed on the command line.

A scene's *planning state* is the matcher's :class:`~oacdsl.world.WorldState` over the
instances that take part in touching relations (tracked and untracked, neither environment
nor ignored), with the scene's ``in`` statements as relations (a liquid touches its
container); every other instance touches nothing, as the robot's objects stand on the
table, which is environment. Goals and stated relations (``--goal``, ``--state``) are
written in the language's atom syntax (``liquid_one <-> orange_bowl, not mixer <-> nothing``)
and parsed by :mod:`oacdsl.planning.atoms`.
"""

from __future__ import annotations

import json
from collections.abc import Iterable, Sequence
from pathlib import Path
from typing import Any

from oacdsl.errors import InputError, UsageError, did_you_mean
from oacdsl.library import Library
from oacdsl.matching.conditions import apply_effects, holds
from oacdsl.model import Atom, Scene
from oacdsl.planning.atoms import parse_atoms
from oacdsl.world import NOTHING, WorldState, relation

__all__ = [
    "check_atoms",
    "instance_classes",
    "parse_atoms",
    "scene_state",
    "state_as_setup",
    "state_from_result",
    "stated",
]

def scene_state(scene: Scene) -> WorldState:
    """The scene's initial state: its related instances, each liquid in the container its
    ``in`` statement names."""
    names = {i.name for i in scene.instances if not (i.environment or i.ignored)}
    pairs = [(f.liquid, f.container) for f in scene.fills if f.liquid in names and f.container in names]
    return WorldState.of(names, pairs)


def _column(atom: Atom) -> int:
    return atom.span.column if atom.span is not None else 1


def check_atoms(atoms: Iterable[Atom], instances: Iterable[str], what: str = "--goal") -> None:
    """UsageError (one line, with a did-you-mean) for an atom naming an unknown instance."""
    known = sorted(instances)
    for atom in atoms:
        for name in (atom.left, atom.right):
            if name != NOTHING and name not in known:
                raise UsageError(
                    f"{what}:1:{_column(atom)}: no instance {name!r} in the scene{did_you_mean(name, known)}"
                )
        if atom.left == atom.right:
            raise UsageError(f"{what}:1:{_column(atom)}: an instance cannot touch itself ({atom.left})")


def stated(state: WorldState, atoms: Sequence[Atom], what: str = "--state") -> WorldState:
    """``state`` with the stated relations made true (``a <-> b`` added, ``not a <-> b`` and
    ``x <-> nothing`` removed), as an OAC's effects would; checked against its instances."""
    check_atoms(atoms, state.instances, what)
    after = apply_effects(state, atoms)
    for atom in atoms:
        if not holds(atom, after):
            raise UsageError(f"{what}:1:{_column(atom)}: the stated relations contradict each other")
    return after


def _pairs_of(doc: Any, path: str) -> list[list[str]]:
    """The last observed relations of an ``oacc run --json`` document or a result.json."""
    run = doc.get("execution", doc) if isinstance(doc, dict) else None
    steps = run.get("steps") if isinstance(run, dict) else None
    if not isinstance(steps, list) or not steps or not isinstance(steps[-1], dict):
        raise InputError("no executed steps to take the world state from", location=path)
    observed = steps[-1].get("observed")
    if not isinstance(observed, list):
        raise InputError("the last step has no observed relations", location=path)
    return observed


def state_from_result(path: str, instances: Iterable[str]) -> WorldState:
    """The world state where a run ended: the last step's observed relations of ``path``
    (``oacc run --json`` output or ``result.json``), over ``instances``."""
    try:
        doc = json.loads(Path(path).read_text(encoding="utf-8"))
    except FileNotFoundError:
        raise UsageError(f"{path}: no such file") from None
    except (OSError, UnicodeDecodeError) as error:
        raise InputError(f"cannot read: {error}", location=path) from None
    except json.JSONDecodeError as error:
        raise InputError(f"not JSON: {error.msg}", location=f"{path}:{error.lineno}:{error.colno}") from None
    except RecursionError:
        raise InputError("nested too deeply; not a run document", location=path) from None
    known = frozenset(instances)
    pairs = []
    for index, pair in enumerate(_pairs_of(doc, path)):
        if not (isinstance(pair, list) and len(pair) == 2 and all(isinstance(x, str) for x in pair)):
            raise InputError(f"observed relation {index}: expected a pair of names", location=path)
        a, b = pair
        if NOTHING in (a, b):
            continue
        for name in (a, b):
            if name not in known:
                raise InputError(
                    f"observed relation {index}: no instance {name!r} in the scene", location=path
                )
        if a != b:
            pairs.append(relation(a, b))
    return WorldState.of(known, pairs)


def instance_classes(library: Library, scene: Scene) -> dict[str, frozenset[str]]:
    """Each related instance's classes, inherited included."""
    every = library.instance_classes(scene)
    return {i.name: every[i.name] for i in scene.instances if not (i.environment or i.ignored)}


def state_as_setup(library: Any, scene: Any, text: str) -> tuple[dict[str, str], dict[str, str]]:
    """``oacc run --state`` / ``oacc reproduce --state``: stated relations the simulation can set
    up before a run: ``(fills, held)`` — a liquid in a container (as ``--fill``) and a hand
    holding an object that stands on the table (hand → object; the hand grasps it before the
    run starts). UsageError, located, for any other relation."""
    from oacdsl.geometry import ROLE_HAND, ROLE_LIQUID, ROLE_OBJECT, resolve_scene

    atoms = parse_atoms(text, "--state")
    check_atoms(atoms, scene_state(scene).instances, "--state")
    shapes = {name: geo for name, geo in resolve_scene(library, scene).items() if geo is not None}
    fills: dict[str, str] = {}
    held: dict[str, str] = {}
    for atom in atoms:
        col = _column(atom)
        pair = (atom.left, atom.right)
        roles = {n: shapes[n].role for n in pair if n in shapes}
        done = False
        for first, second in (pair, pair[::-1]):
            if atom.negated or first not in roles or second not in roles:
                continue
            if roles[first] == ROLE_LIQUID and shapes[second].container:
                fills[first] = second
                done = True
            elif roles[first] == ROLE_HAND and roles[second] == ROLE_OBJECT:
                if first in held or second in held.values():
                    raise UsageError(f"--state:1:{col}: a hand holds one object, an object one hand")
                held[first] = second
                done = True
            if done:
                break
        if not done:
            raise UsageError(
                f"--state:1:{col}: the simulation can start a liquid in a container ('liquid_one <->"
                " orange_bowl') or a hand holding an object ('mixer <-> right_hand'); other relations"
                " are not set up before a run"
            )
    return fills, held
