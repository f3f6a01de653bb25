"""Binding an OAC's parameters to a scene's instances, and its steps to primitive OACs.

Light on purpose (no MuJoCo, no placo): the run command checks its arguments with
these functions before it builds a simulation.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

from oacdsl.errors import RuntimeFailure, did_you_mean
from oacdsl.geometry import ROLE_LIQUID, resolve_scene
from oacdsl.library import Library
from oacdsl.model import Atom, Oac, PathValue, Scene, SkillParam
from oacdsl.skills import SIGNATURES
from oacdsl.units import language_si
from oacdsl.world import NOTHING, WorldState

__all__ = [
    "Step",
    "Call",
    "bind",
    "flatten",
    "expand",
    "bound_atoms",
    "holds",
    "explain",
    "choose_scene",
    "liquid_contents",
]

_MAX_DEPTH = 16


@dataclass(frozen=True)
class Step:
    """A primitive OAC with its parameters bound to instances; ``overrides`` are the skill
    parameters written on the step that called it (``pour(h, c, l, b) { tilt 105deg }``)."""

    oac: Oac
    binding: dict[str, str]
    overrides: tuple[SkillParam, ...] = ()

    @property
    def args(self) -> tuple[str, ...]:
        """The instances the skill gets, in the order of its signature (``execute pour(h, c, l, b)``;
        without an argument list, the OAC's parameters in order)."""
        return tuple(self.binding.get(a, a) for a in self.oac.skill_arguments())

    @property
    def params(self) -> dict[str, Any]:
        """The skill's named parameters (SI): the signature's defaults, then the OAC's values,
        then the calling step's (a path: its keyframes, :meth:`PathValue.si`)."""
        sig = SIGNATURES.get(str(self.oac.skill))
        values: dict[str, Any] = dict(sig.defaults()) if sig is not None else {}
        values.update(self.given)
        return values

    @property
    def given(self) -> dict[str, Any]:
        """The parameters the OAC or the calling step set (SI), without the skill's defaults."""
        return {
            p.name: p.value.si() if isinstance(p.value, PathValue)
            else language_si(p.value.value, p.value.unit)[0]
            for p in (*self.oac.skill_params, *self.overrides)
        }


@dataclass(frozen=True)
class Call:
    """A composed OAC called with a binding: it spans the primitive steps ``first`` to
    ``last`` (0-based, inclusive) and is nested ``depth`` calls deep (the OAC run is 0)."""

    oac: Oac
    binding: dict[str, str]
    first: int
    last: int
    depth: int


def choose_scene(
    library: Library, oac: Oac, name: str | None = None, given: Mapping[str, str] | None = None
) -> Scene:
    """The scene called ``name``, else the one scene of the library, else the one scene that
    holds the instances of the OAC's defaults and of ``given`` (the ``--bind`` values)."""
    if name is not None:
        if name not in library.scenes:
            raise RuntimeFailure(f"no scene {name!r} in the library{did_you_mean(name, library.scenes)}")
        return library.scenes[name]
    if len(library.scenes) == 1:
        return next(iter(library.scenes.values()))
    defaults = {p.default for p in oac.params if p.default is not None} | set((given or {}).values())
    fitting = [s for s in library.scenes.values() if defaults and defaults <= {i.name for i in s.instances}]
    if len(fitting) == 1:
        return fitting[0]
    if not library.scenes:
        raise RuntimeFailure("the library declares no scene to run in (give one with --scene)")
    if len(fitting) > 1:  # Open and Close: the same marker groups, a scene for each
        raise RuntimeFailure(f"choose a scene with --scene: {', '.join(sorted(s.name for s in fitting))} each"
                             f" hold the instances {oac.name} names")
    raise RuntimeFailure(f"choose a scene with --scene (the library has {', '.join(sorted(library.scenes))})")


def bind(library: Library, oac: Oac, scene: Scene, given: Mapping[str, str] | None = None) -> dict[str, str]:
    """Instance per parameter: ``given`` first, then the parameter's default, then the only
    instance of the scene of the parameter's class. Classes are checked (inherited too)."""
    given = dict(given or {})
    names = [p.name for p in oac.params]
    for key in given:
        if key not in names:
            raise RuntimeFailure(
                f"--bind {key}={given[key]}: oac {oac.name} has no parameter {key!r}"
                f"{did_you_mean(key, names)}"
            )
    classes = library.instance_classes(scene)
    tracked = [i.name for i in scene.tracked()]
    binding: dict[str, str] = {}
    for p in oac.params:
        value = given.get(p.name) or p.default
        if value is None:
            candidates = [n for n in tracked if p.cls in classes[n]]
            if len(candidates) != 1:
                what = ", ".join(candidates) if candidates else "none"
                raise RuntimeFailure(
                    f"parameter {p.name}: {p.cls} of oac {oac.name} needs a binding"
                    f" (instances of {p.cls} in scene {scene.name}: {what});"
                    f" give one with --bind {p.name}=INSTANCE"
                )
            value = candidates[0]
        named = f"--bind {p.name}={value}" if p.name in given else f"parameter {p.name}"
        if value not in classes:
            raise RuntimeFailure(
                f"{named}: no instance {value!r} in scene {scene.name}{did_you_mean(value, tracked)}"
            )
        if p.cls not in classes[value]:
            raise RuntimeFailure(
                f"{named}: {value} is not a {p.cls} (it is {', '.join(sorted(classes[value]))})"
            )
        binding[p.name] = value
    return binding


def flatten(library: Library, oac: Oac, binding: Mapping[str, str]) -> list[Step]:
    """The primitive steps of ``oac`` under ``binding`` (a primitive OAC is one step)."""
    return expand(library, oac, binding)[0]


def expand(library: Library, oac: Oac, binding: Mapping[str, str]) -> tuple[list[Step], list[Call]]:
    """The primitive steps of ``oac`` under ``binding``, and every composed OAC on the way
    (``oac`` itself first when it is composed, then its composed steps, outer before inner)."""
    steps: list[Step] = []
    calls: list[Call] = []
    _expand(library, oac, dict(binding), 0, steps, calls)
    return steps, calls


def _expand(
    library: Library,
    oac: Oac,
    binding: dict[str, str],
    depth: int,
    steps: list[Step],
    calls: list[Call],
    overrides: tuple[SkillParam, ...] = (),
) -> None:
    if depth > _MAX_DEPTH:
        raise RuntimeFailure(f"oac {oac.name}: steps nest deeper than {_MAX_DEPTH} (a cycle?)")
    if not oac.composed:
        steps.append(Step(oac, binding, overrides))
        return
    index, first = len(calls), len(steps)
    calls.append(Call(oac, binding, first, first, depth))  # its last step is known below
    for call in oac.steps or ():
        callee = library.oacs.get(call.oac)
        if callee is None:
            raise RuntimeFailure(
                f"oac {oac.name} calls unknown oac {call.oac!r}{did_you_mean(call.oac, library.oacs)}"
            )
        if len(call.args) != len(callee.params):
            raise RuntimeFailure(
                f"oac {oac.name}: {call.oac} takes {len(callee.params)} arguments, {len(call.args)} given"
            )
        inner = {p.name: binding.get(a, a) for p, a in zip(callee.params, call.args, strict=True)}
        _expand(library, callee, inner, depth + 1, steps, calls, call.skill_params)
    if len(steps) == first:
        raise RuntimeFailure(f"oac {oac.name} has no steps to execute")
    for p in overrides:  # to the one step inside whose skill takes it (oacdsl/passdown.py; E047)
        found = [k for k in range(first, len(steps)) if _takes(steps[k], p.name)]
        if len(found) != 1:
            raise RuntimeFailure(
                f"oac {oac.name} is composed: a parameter on a step calling it goes to the one step"
                f" inside whose skill takes it; {len(found)} steps take {p.name!r}"
            )
        k = found[0]
        kept = tuple(o for o in steps[k].overrides if o.name != p.name)
        steps[k] = Step(steps[k].oac, steps[k].binding, (*kept, p))
    calls[index] = Call(oac, binding, first, len(steps) - 1, depth)


def _takes(step: Step, name: str) -> bool:
    sig = SIGNATURES.get(str(step.oac.skill))
    return sig is not None and any(p.name == name for p in sig.params)


def bound_atoms(atoms: tuple[Atom, ...], binding: Mapping[str, str]) -> list[tuple[str, str, bool]]:
    """``(a, b, negated)`` with variables replaced by instances (``nothing`` stays)."""
    return [(binding.get(a.left, a.left), binding.get(a.right, a.right), a.negated) for a in atoms]


def holds(state: WorldState, a: str, b: str, negated: bool) -> bool:
    """Whether ``a <-> b`` (or its negation) holds in ``state``."""
    if b == NOTHING:
        value = state.touches_nothing(a)
    elif a == NOTHING:
        value = state.touches_nothing(b)
    else:
        value = state.touches(a, b)
    return value != negated


def explain(state: WorldState, a: str, b: str, negated: bool) -> str:
    """One clause saying why ``a <-> b`` (negated or not) does not hold in ``state``."""
    atom = f"{'not ' if negated else ''}{a} <-> {b}"
    partners = sorted(state.partners(a))
    now = f"{a} touches {', '.join(partners)}" if partners else f"{a} touches nothing"
    return f"{atom} does not hold ({now})"


def liquid_contents(library: Library, scene: Scene, oac: Oac, binding: Mapping[str, str]) -> dict[str, str]:
    """Liquid → container named by the OAC's own preconditions (``l <-> c``): where the
    runtime puts each liquid before the run, as the demonstrator filled the cups. A liquid
    is an instance whose shape is ``balls``; a container one whose shape has a ``shell``."""
    shapes = {name: geo for name, geo in resolve_scene(library, scene).items() if geo is not None}
    out: dict[str, str] = {}
    for a, b, negated in bound_atoms(oac.pre, binding):
        if negated or NOTHING in (a, b) or a not in shapes or b not in shapes:
            continue
        for liquid, container in ((a, b), (b, a)):
            if shapes[liquid].role == ROLE_LIQUID and shapes[container].container and liquid not in out:
                out[liquid] = container
    return out
