"""The typed model of the OAC language (pydantic, frozen, hashable).

Every node may carry the :class:`Span` of the text it came from and the comments
written before it; both are *trivia*: kept for diagnostics and for the printer,
but left out of equality and hashing, so ``parse(print(m)) == m`` compares
meaning, not layout. Collections whose order carries no meaning (parents,
preconditions, effects) are normalised to sorted, de-duplicated tuples when a
node is built, so two models that mean the same compare equal.

Units: grasp offsets are metres in the object's frame; geometry, placements and
skill parameters keep each quantity with the unit it was written in
(:class:`Quantity`; :func:`oacdsl.units.language_si` converts to SI).
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any, Literal

from pydantic import BaseModel, ConfigDict, Field, field_validator, model_validator

from oacdsl.world import NOTHING

_TRIVIA = frozenset({"span", "comments", "note", "parts"})

#: Hand shapes a ``grasp`` declaration may name (``type``).
GRASP_TYPES: tuple[str, ...] = ("handle", "pinch", "power", "precision", "rim")
#: Directions a hand may approach an object from (``approach``), in the object frame.
APPROACHES: tuple[str, ...] = ("front", "side", "top")
#: Where a scene's objects start when no ``at`` says (``layout …``).
LAYOUTS: tuple[str, ...] = ("auto", "demonstrated")
#: Most balls one liquid may have (``balls N``; each ball is a free body in the simulation).
MAX_BALLS = 40


class Span(BaseModel):
    """Where a node stands in its source: 1-based line and column, end exclusive."""

    model_config = ConfigDict(frozen=True)

    file: str
    line: int
    column: int
    end_line: int
    end_column: int

    def __str__(self) -> str:
        return f"{self.file}:{self.line}:{self.column}"


class Node(BaseModel):
    """Base of every model node: frozen, hashable, trivia outside equality.

    Trivia: ``span`` (the whole node), ``comments`` (the comment lines written
    before it, without ``#``), ``note`` (a comment at the end of its last line)
    and ``parts`` (the spans of the names inside it, keyed like ``"name"``,
    ``"cls"``, ``"parents:Cup"`` (sorted collections: by name) or ``"args.1"``
    (ordered ones: by index), for diagnostics that point at one name).
    """

    model_config = ConfigDict(frozen=True, extra="forbid")

    span: Span | None = Field(default=None, repr=False)
    comments: tuple[str, ...] = Field(default=(), repr=False)
    note: str | None = Field(default=None, repr=False)
    #: (key, line, column, end_line, end_column) of names inside the node, in ``span.file``.
    parts: tuple[tuple[str, int, int, int, int], ...] = Field(default=(), repr=False)

    def part(self, key: str) -> Span | None:
        """The span of the part ``key`` (e.g. ``"parents:Cup"``), else the node's span."""
        if self.span is not None:
            for k, line, column, end_line, end_column in self.parts:
                if k == key:
                    return Span(
                        file=self.span.file,
                        line=line,
                        column=column,
                        end_line=end_line,
                        end_column=end_column,
                    )
        return self.span

    def _key(self) -> tuple[Any, ...]:
        return tuple(v for k, v in self.__dict__.items() if k not in _TRIVIA)

    def __eq__(self, other: object) -> bool:
        return type(self) is type(other) and self._key() == other._key()  # type: ignore[attr-defined]

    def __hash__(self) -> int:
        return hash((type(self).__name__, self._key()))


class Quantity(Node):
    """A number as written with its unit as written (``4cm`` → 4.0, ``"cm"``; ``0.04`` → ``""``).

    The model keeps the text's unit so that printing gives back what was written;
    :func:`oacdsl.geometry.si` converts to SI (metres, kilograms). The compiler checks units.
    """

    value: float
    unit: str = ""


class Dim(Node):
    """A named parameter of a shape: ``radius 4cm``."""

    name: str
    value: Quantity


class Point(Node):
    """A point ``(x, y, z)`` in an object's frame (lengths, each with its unit)."""

    x: Quantity
    y: Quantity
    z: Quantity


class Shape(Node):
    """One primitive of an object's geometry: ``shell(radius 4cm, height 10cm, wall 6mm) at (0, 0, 1cm)``.

    ``primitive`` is the shape's name (``cylinder``, ``box``, ``sphere``, ``capsule``,
    ``shell``, ``mesh``, ``balls``, ``hand``, ``table``: see :mod:`oacdsl.geometry`),
    ``dims`` its named sizes in written order, ``file`` a mesh file (relative to the
    ``.oac`` file) and ``at`` where the centre of its base sits in the object frame.
    """

    primitive: str
    dims: tuple[Dim, ...] = ()
    file: str | None = None
    at: Point | None = None

    def dim(self, name: str) -> Quantity | None:
        for d in self.dims:
            if d.name == name:
                return d.value
        return None


class Geometry(Node):
    """``{ shape … mass … }`` — an object's physical description (of a class or an instance).

    Several shapes make a compound. Unset properties come from the class (for an
    instance) or the nearest parent class that sets them (for a class).
    """

    shapes: tuple[Shape, ...] = ()
    mass: Quantity | None = None
    friction: float | None = None
    colour: str | None = None
    markers: tuple[Point, ...] = ()


class ObjectClass(Node):
    """``class Cup : Graspable, Container { … }`` — a class with zero or more parents and,
    optionally, its geometry."""

    kind: Literal["class"] = "class"
    name: str
    parents: tuple[str, ...] = ()
    geometry: Geometry | None = None

    @field_validator("parents")
    @classmethod
    def _sort_parents(cls, v: tuple[str, ...]) -> tuple[str, ...]:
        return tuple(sorted(set(v)))


class Instance(Node):
    """A named object of a scene; its name is the label of its marker group.

    ``markers`` optionally lists the motion-capture marker names of the group
    (an explicit mapping); ``environment`` marks geometry that is not tracked
    (the table in the paper's scene): it takes no part in touching relations;
    ``ignored`` marks a marker group of the recording that is neither tracked nor built;
    ``untracked`` an object the recording does not track (KIT's milk: no markers) that
    is built and takes part in relations, which OAC effects predict (docs/language.md).
    ``geometry`` overrides its class's geometry property by property.
    """

    name: str
    classes: tuple[str, ...]
    markers: tuple[str, ...] = ()
    environment: bool = False
    #: A marker group nobody uses (``rack : Rack ignored``): not tracked, not built.
    ignored: bool = False
    #: Built and related, but not in the recording (``milk : Milk untracked``): its relations
    #: are predicted by OAC effects, never observed in the demonstration.
    untracked: bool = False
    geometry: Geometry | None = None

    @field_validator("classes")
    @classmethod
    def _sort_classes(cls, v: tuple[str, ...]) -> tuple[str, ...]:
        return tuple(sorted(set(v)))


class ScenePlace(Node):
    """``red_cup at (56cm, 28cm)`` — where an object starts on the robot's table.

    ``x`` is forward from the robot's platform centre, ``y`` to its left (metres).
    """

    instance: str
    x: Quantity
    y: Quantity


class SceneFill(Node):
    """``liquid_one in red_cup balls 12`` — a liquid that starts inside a container.

    ``balls`` is the number of simulated balls (None: the runtime's default).
    """

    liquid: str
    container: str
    balls: int | None = None


class Scene(Node):
    """``scene kitchen { … }`` — the instances of one demonstration setting.

    ``layout`` says where objects without an ``at`` start (``auto`` or
    ``demonstrated``; None: ``auto``); ``places`` and ``fills`` are the scene's
    initial state, sorted by instance name.
    """

    kind: Literal["scene"] = "scene"
    name: str
    instances: tuple[Instance, ...]
    layout: str | None = None
    places: tuple[ScenePlace, ...] = ()
    fills: tuple[SceneFill, ...] = ()

    @field_validator("instances")
    @classmethod
    def _sort_instances(cls, v: tuple[Instance, ...]) -> tuple[Instance, ...]:
        return tuple(sorted(v, key=lambda i: i.name))

    @field_validator("places")
    @classmethod
    def _sort_places(cls, v: tuple[ScenePlace, ...]) -> tuple[ScenePlace, ...]:
        return tuple(sorted(v, key=place_key))

    @field_validator("fills")
    @classmethod
    def _sort_fills(cls, v: tuple[SceneFill, ...]) -> tuple[SceneFill, ...]:
        return tuple(sorted(v, key=fill_key))

    def instance(self, name: str) -> Instance | None:
        """The instance called ``name``, or None."""
        for inst in self.instances:
            if inst.name == name:
                return inst
        return None

    def tracked(self) -> tuple[Instance, ...]:
        """Instances whose marker groups the recording holds: they take part in touching
        relations (neither environment, ignored nor untracked)."""
        return tuple(i for i in self.instances if not (i.environment or i.ignored or i.untracked))

    def untracked(self) -> tuple[Instance, ...]:
        """Instances marked ``untracked``: built and related, but not in the recording."""
        return tuple(i for i in self.instances if i.untracked)

    def ignored(self) -> tuple[Instance, ...]:
        """Instances marked ``ignored``: marker groups that are neither tracked nor built."""
        return tuple(i for i in self.instances if i.ignored)

    def place(self, name: str) -> ScenePlace | None:
        """The ``at`` statement of instance ``name``, or None."""
        return next((p for p in self.places if p.instance == name), None)


def place_key(p: ScenePlace) -> tuple[str, float, str, float, str]:
    """Sort key of scene placements (by instance, then position as written)."""
    return (p.instance, p.x.value, p.x.unit, p.y.value, p.y.unit)


def fill_key(f: SceneFill) -> tuple[str, str, int]:
    """Sort key of scene contents (by liquid, then container)."""
    return (f.liquid, f.container, -1 if f.balls is None else f.balls)


class Grasp(Node):
    """``grasp Cup { … }`` — how the robot grasps objects of a class.

    ``offset`` is the grasp point in the object frame, metres; ``approach`` is the
    direction the hand comes from (``side``, ``top``, ``front``); ``type`` is the
    hand shape (``power``, ``precision``, ``pinch``, ``rim``, ``handle``).
    """

    kind: Literal["grasp"] = "grasp"
    cls: str
    type: str
    approach: str
    offset: tuple[float, float, float] = (0.0, 0.0, 0.0)


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
            (v(k.time), v(k.position.x), v(k.position.y), v(k.position.z),
             v(k.rotation.x), v(k.rotation.y), v(k.rotation.z))
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


Decl = ObjectClass | Scene | Grasp | Oac


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


class Module(Node):
    """The declarations of one ``.oac`` file, in source order."""

    path: str
    decls: tuple[Decl, ...]
    #: Comments after the last declaration of the file.
    trailing: tuple[str, ...] = Field(default=(), repr=False)

    def _key(self) -> tuple[Any, ...]:
        return (self.decls,)
