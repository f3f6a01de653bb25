"""Object-Action Complexes: touching statements (:class:`Atom`), typed parameters, skill
parameters and paths, the steps of a composed OAC (:class:`Call`) and :class:`Oac` itself (see
:mod:`oacdsl.model`)."""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any, Literal

from pydantic import field_validator, model_validator

from oacdsl.model.node import Node, Point, Quantity
from oacdsl.world import NOTHING

__all__ = [
    "Atom",
    "Call",
    "KeyPose",
    "Oac",
    "Param",
    "PathValue",
    "SkillParam",
    "atom_text",
    "canonical_steps",
    "pair_order",
    "sorted_skill_params",
    "step_groups",
]


class Atom(Node):
    """A touching statement ``a <-> b``, ``a <-> nothing`` or its negation.

    ``left``/``right`` are variable names (or instance names); the pair is
    stored sorted unless ``right`` is :data:`~oacdsl.world.NOTHING`, which always
    stays on the right. ``note`` is a trailing comment (the composer's provenance).
    """

    left: str
    right: str
    negated: bool = False

    @model_validator(mode="before")
    @classmethod
    def _canonical(cls, data: Any) -> Any:
        if isinstance(data, dict):
            left, right = data.get("left"), data.get("right")
            if isinstance(left, str) and isinstance(right, str) and pair_order(left, right) != (left, right):
                data = {**data, "left": right, "right": left}
        return data

    @property
    def about_nothing(self) -> bool:
        """True for ``x <-> nothing``."""
        return self.right == NOTHING

    def sort_key(self) -> tuple[str, str, bool]:
        return (self.left, self.right, self.negated)


def pair_order(left: str, right: str) -> tuple[str, str]:
    """The order an atom stores its two names in: sorted, ``nothing`` always on the right."""
    if right == NOTHING or (left != NOTHING and left <= right):
        return left, right
    return right, left


def atom_text(atom: Atom, order: tuple[str, str] | None = None) -> str:
    """The atom as written in ``.oac``: ``not a <-> b``, ``x <-> nothing``.

    ``order`` writes the pair in another order than the stored one (the printer
    puts the earlier parameter first). No check that the names are names: for
    messages; :func:`oacdsl.compiler.printer.format_atom` checks them.
    """
    left, right = order if order is not None else (atom.left, atom.right)
    return f"not {left} <-> {right}" if atom.negated else f"{left} <-> {right}"


def _atoms(v: tuple[Atom, ...]) -> tuple[Atom, ...]:
    unique: dict[Atom, Atom] = {}
    for atom in v:
        unique.setdefault(atom, atom)
    return tuple(sorted(unique.values(), key=Atom.sort_key))


class Param(Node):
    """A typed variable (wildcard) ``h: Hand``; ``default`` is an instance name."""

    name: str
    cls: str
    default: str | None = None


class KeyPose(Node):
    """One keyframe of a path: ``0.4s (12mm, -3mm, 95mm) (0deg, 5deg, 0deg)`` — its time, a
    position and a rotation vector (axis × angle), as written (docs/language.md)."""

    time: Quantity
    position: Point
    rotation: Point


class PathValue(Node):
    """A skill parameter's path: ``[ KEYPOSE, KEYPOSE, … ]`` (``follow``'s demonstrated motion)."""

    poses: tuple[KeyPose, ...]

    def si(self) -> tuple[tuple[float, ...], ...]:
        """One ``(t_s, x_m, y_m, z_m, rx_rad, ry_rad, rz_rad)`` per keyframe."""
        from oacdsl.units import language_si

        def v(q: Quantity) -> float:
            return language_si(q.value, q.unit)[0]

        return tuple(
            (
                v(k.time),
                v(k.position.x),
                v(k.position.y),
                v(k.position.z),
                v(k.rotation.x),
                v(k.rotation.y),
                v(k.rotation.z),
            )
            for k in self.poses
        )


class SkillParam(Node):
    """A named parameter of a skill call: ``tilt 110deg`` (the value as written; SI via
    :func:`oacdsl.units.language_si`), or a path ``path [ … ]``."""

    name: str
    value: Quantity | PathValue


def _param_key(s: SkillParam) -> tuple[str, float, str]:
    v = s.value
    return (s.name, v.value, v.unit) if isinstance(v, Quantity) else (s.name, float(len(v.poses)), "path")


def sorted_skill_params(v: tuple[SkillParam, ...]) -> tuple[SkillParam, ...]:
    """Skill parameters in canonical order: by name, then value as written."""
    return tuple(sorted(v, key=_param_key))


class Call(Node):
    """One step of a composed OAC: ``grasp(h1, c1)`` — arguments are variable names.

    ``skill_params`` (``pour(h, c, l, b) { tilt 105deg }``, sorted by name) override the
    named parameters of the called OAC's skill for this step (docs/language.md).
    ``together``: the step may run together with the step before it (both are in one
    ``together { … }`` block; the first step of a block has it False).
    """

    oac: str
    args: tuple[str, ...]
    skill_params: tuple[SkillParam, ...] = ()
    together: bool = False

    @field_validator("skill_params")
    @classmethod
    def _sort_skill_params(cls, v: tuple[SkillParam, ...]) -> tuple[SkillParam, ...]:
        return sorted_skill_params(v)


class Oac(Node):
    """An Object-Action Complex: typed parameters, preconditions, effects, execution.

    Exactly one of ``skill`` (a runtime skill by name) and ``steps`` (an ordered
    list of OAC calls, for a composed OAC) is set. ``skill_args`` are the skill's
    arguments when written (``execute pour(h, c, l, b)``; None: the OAC's
    parameters in order) and ``skill_params`` its named parameters
    (``{ tilt 110deg }``), sorted by name.
    """

    kind: Literal["oac"] = "oac"
    name: str
    params: tuple[Param, ...]
    pre: tuple[Atom, ...] = ()
    effect: tuple[Atom, ...] = ()
    skill: str | None = None
    steps: tuple[Call, ...] | None = None
    skill_args: tuple[str, ...] | None = None
    skill_params: tuple[SkillParam, ...] = ()

    @field_validator("pre", "effect")
    @classmethod
    def _normalise_atoms(cls, v: tuple[Atom, ...]) -> tuple[Atom, ...]:
        return _atoms(v)

    @field_validator("steps")
    @classmethod
    def _together_flags(cls, v: tuple[Call, ...] | None) -> tuple[Call, ...] | None:
        return canonical_steps(v) if v is not None else None

    @field_validator("skill_params")
    @classmethod
    def _sort_skill_params(cls, v: tuple[SkillParam, ...]) -> tuple[SkillParam, ...]:
        return sorted_skill_params(v)

    def skill_arguments(self) -> tuple[str, ...]:
        """The names passed to the skill: ``skill_args`` when written, else the parameters."""
        return self.skill_args if self.skill_args is not None else tuple(p.name for p in self.params)

    @property
    def composed(self) -> bool:
        return self.steps is not None

    def param(self, name: str) -> Param | None:
        for p in self.params:
            if p.name == name:
                return p
        return None


def step_groups(steps: Sequence[Call]) -> list[list[Call]]:
    """The steps in groups: a ``together { … }`` block is one group, any other step one of its own."""
    out: list[list[Call]] = []
    for call in steps:
        if call.together and out:
            out[-1].append(call)
        else:
            out.append([call])
    return out


def canonical_steps(steps: Sequence[Call]) -> tuple[Call, ...]:
    """``steps`` with the ``together`` flags of every block normalised: the first step of a
    block False, the others True. The order is kept: the runtime runs a block's steps one after
    the other as written, and the composer writes them in the order they were demonstrated."""
    out: list[Call] = []
    for group in step_groups(steps):
        for k, call in enumerate(group):
            if call.together != (k > 0):
                call = call.model_copy(update={"together": k > 0})
            out.append(call)
    return tuple(out)
