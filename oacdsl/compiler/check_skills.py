"""Checks of a skill call, ``execute pour(h, c, l, b) { tilt 110deg }``, against its signature.

The signatures are :data:`oacdsl.skills.SIGNATURES` (light: no runtime import).
Without an argument list the skill gets the OAC's parameters in order. Every
argument must have the class the signature names (inherited classes count), when
the library defines that class;
every named parameter must exist, carry a unit of its kind (a bare number is
SI; a count is bare and whole) and lie in its range. A step of a composed OAC may
carry parameters for the skill of the OAC it calls (``pour(h, c, l, b) { tilt 105deg }``):
the same checks, against that skill's signature.
"""

from __future__ import annotations

import math
from collections.abc import Callable

from oacdsl.compiler.context import Context
from oacdsl.compiler.diagnostics import Note
from oacdsl.errors import did_you_mean
from oacdsl.model import Call, Node, Oac, PathValue, Quantity, SkillParam
from oacdsl.skills import PATH, SIGNATURES, SkillParamSpec, SkillSignature, format_value
from oacdsl.units import language_si, unit_kind

__all__ = ["check_quantity_unit", "check_skill_call", "check_skill_params", "check_step_params", "written"]

#: Bare numbers beyond these are probably written in another unit (W040): radians, metres.
PLAUSIBLE_BARE = {"rad": 2 * math.pi, "m": 2.0}

Resolve = Callable[[str, Node, str], "list[frozenset[str]] | None"]


def written(q: Quantity) -> str:
    """``56cm`` — the quantity as written."""
    return f"{q.value:g}{q.unit}"


def check_quantity_unit(ctx: Context, q: Quantity, unit: str, what: str) -> bool:
    """E043 when ``q`` is not of SI ``unit`` (a bare number is); W040 for an implausible
    bare number. True when the unit fits."""
    value, si = language_si(q.value, q.unit)
    if q.unit and si != unit:
        known = si in ("m", "rad", "s", "N", "m/s")
        kind = unit_kind(si).split(" (")[0].removeprefix("a ").removeprefix("an ")
        why = f"a unit of {kind}" if known else f"an unknown unit '{q.unit}'"
        ctx.add("E043", f"{what} is {unit_kind(unit)}, but '{written(q)}' has {why}", q.span)
        return False
    if not q.unit and unit in PLAUSIBLE_BARE and abs(q.value) > PLAUSIBLE_BARE[unit]:
        example = format_value(q.value * (math.pi / 180 if unit == "rad" else 0.001), unit)
        ctx.add(
            "W040",
            f"{what} '{written(q)}' has no unit and is read as {q.value:g} {unit}"
            f" ({'radians' if unit == 'rad' else 'metres'}); write the unit, e.g. {example}",
            q.span,
        )
    return True


def _check_param(ctx: Context, sig: SkillSignature, given: SkillParam) -> None:
    spec = sig.param(given.name)
    if spec is None:
        names = [p.name for p in sig.params]
        valid = ", ".join(names) if names else "none"
        ctx.add(
            "E042",
            f"skill '{sig.name}' has no parameter '{given.name}'{did_you_mean(given.name, names)}",
            given.part("name"),
            Note(f"the parameters of '{sig.name}': {valid} (see 'oacc skills')"),
        )
        return
    what = f"'{spec.name}' of skill '{sig.name}'"
    if isinstance(given.value, PathValue) or spec.unit == PATH:
        _check_path(ctx, what, spec, given)
        return
    _check_value(ctx, sig, spec, given.value)


def _check_path(ctx: Context, what: str, spec: SkillParamSpec, given: SkillParam) -> None:
    """A path (``path [ … ]``) given where the signature wants one: units of every keyframe
    (E043), at least two keyframes and strictly increasing times from 0 on (E044)."""
    path = given.value
    if not isinstance(path, PathValue):
        ctx.add("E043", f"{what} is a path ('[ 0s (x, y, z) (rx, ry, rz), … ]'), not '{written(path)}'",
                path.span)
        return
    if spec.unit != PATH:
        ctx.add("E043", f"{what} is {unit_kind(spec.unit)}, not a path", path.span)
        return
    if len(path.poses) < 2:
        ctx.add("E044", f"{what} needs at least two keyframes, not {len(path.poses)}", path.span)
    last = -math.inf
    for k in path.poses:
        fine = check_quantity_unit(ctx, k.time, "s", f"the time of a keyframe of {what}")
        for q in (k.position.x, k.position.y, k.position.z):
            fine &= check_quantity_unit(ctx, q, "m", f"a position in {what}")
        for q in (k.rotation.x, k.rotation.y, k.rotation.z):
            fine &= check_quantity_unit(ctx, q, "rad", f"a rotation in {what}")
        t = language_si(k.time.value, k.time.unit)[0]
        if fine and (t < 0 if last == -math.inf else t <= last):
            ctx.add("E044", f"the keyframes of {what} must have increasing times from 0s on:"
                    f" {written(k.time)} after {last:g}s", k.time.span)
        last = max(last, t)


def _check_value(ctx: Context, sig: SkillSignature, spec: SkillParamSpec, q: Quantity) -> None:
    what = f"'{spec.name}' of skill '{sig.name}'"
    if spec.whole:
        if q.unit:
            ctx.add("E043", f"{what} is a count (a whole number without unit), not '{written(q)}'", q.span)
            return
        if not float(q.value).is_integer():
            ctx.add("E044", f"{what} is a count: '{written(q)}' is not a whole number", q.span)
            return
    elif not check_quantity_unit(ctx, q, spec.unit, what):
        return
    value = language_si(q.value, q.unit)[0]
    # a bound written in its own unit ('tilt 30deg') is SI rounded to 12 digits: within 1e-11
    slack = 1e-11 * max(1.0, abs(spec.low), abs(spec.high))
    if not spec.low - slack <= value <= spec.high + slack:
        ctx.add(
            "E044",
            f"{what} must lie between {format_value(spec.low, spec.unit)} and"
            f" {format_value(spec.high, spec.unit)}, not {written(q)}",
            q.span,
        )


def check_skill_call(ctx: Context, oac: Oac, resolve: Resolve, declared: Callable[[str], str]) -> None:
    """Arity, argument classes and named parameters of ``oac``'s ``execute`` (a known skill).

    ``resolve(name, node, key)`` gives the class sets a name may have (reporting unknown
    names); ``declared(name)`` the class a name is declared with, for messages.
    """
    sig = SIGNATURES[str(oac.skill)]
    signature = ", ".join(f"{a.name}: {a.cls}" for a in sig.args)
    note = Note(f"skill '{sig.name}({signature})' (see 'oacc skills')")
    explicit = oac.skill_args is not None
    args = oac.skill_arguments()
    if len(args) != len(sig.args):
        n = len(sig.args)
        takes = f"skill '{sig.name}' takes {n} argument{'s' if n != 1 else ''}"
        if explicit:
            ctx.add("E040", f"{takes}, {len(args)} given", oac.part("skill_call"), note)
        else:
            ctx.add(
                "E040",
                f"{takes}, but '{oac.name}' passes its {len(args)} parameter{'s' if len(args) != 1 else ''};"
                f" write the arguments: 'execute {sig.name}({', '.join(a.name for a in sig.args)})'"
                " with names of this OAC",
                oac.part("skill"),
                note,
            )
    for i, name in enumerate(args):
        key = f"skill_args.{i}" if explicit else "skill"
        kinds = resolve(name, oac, key) if explicit else _param_kinds(ctx, oac, name)
        if kinds is None or len(args) != len(sig.args):  # classes by position only when the count fits
            continue
        wanted = sig.args[i]
        if wanted.cls not in ctx.library.classes:  # a library of its own classes: not checked
            continue
        if not any(wanted.cls in k for k in kinds):
            where = oac.part(key) if explicit else (oac.param(name) or oac).part("cls")
            ctx.add(
                "E041",
                f"argument '{name}' is a {declared(name)}, but skill '{sig.name}' expects a"
                f" {wanted.cls} for '{wanted.name}'",
                where,
                note,
            )
    check_skill_params(ctx, sig, oac.skill_params)


def check_skill_params(ctx: Context, sig: SkillSignature, params: tuple[SkillParam, ...]) -> None:
    """Every named parameter of a call of skill ``sig``: given once (E006), known (E042), of its
    unit (E043), in its range (E044)."""
    seen: dict[str, SkillParam] = {}
    for given in sorted(params, key=_position):
        if given.name in seen:
            ctx.add(
                "E006",
                f"skill parameter '{given.name}' is given twice",
                given.part("name"),
                Note("first given here", seen[given.name].part("name")),
            )
            continue
        seen[given.name] = given
        _check_param(ctx, sig, given)


def check_step_params(ctx: Context, call: Call, callee: Oac) -> None:
    """The skill parameters of a step ``call`` of ``callee`` (docs/language.md): checked against
    the signature of the skill ``callee`` executes; on a step calling a composed ``callee``, each
    goes to the one step inside it whose skill takes a parameter of that name
    (:mod:`oacdsl.passdown`) and is checked against that skill's signature; none or several
    such steps is an error (E047)."""
    if not call.skill_params:
        return
    if callee.skill is not None:
        if callee.skill in SIGNATURES:  # an unknown skill is reported at the callee (E016)
            check_skill_params(ctx, SIGNATURES[callee.skill], call.skill_params)
        return
    from oacdsl.passdown import receivers

    by_skill: dict[str, list[SkillParam]] = {}
    for given in call.skill_params:
        found = receivers(ctx.library.oacs, callee, given.name)
        if len(found) == 1:
            by_skill.setdefault(str(found[0].oac.skill), []).append(given)
            continue
        if found:
            where = ", ".join(f"'{s.oac.skill}' of '{s.oac.name}'" for s in found)
            text = (f"'{callee.name}' is a composed OAC and more than one step inside it executes a skill"
                    f" that takes '{given.name}' ({where}); write it on the step inside '{callee.name}'"
                    " that should take it")
        else:
            text = (f"'{callee.name}' is a composed OAC and no step inside it executes a skill that takes"
                    f" '{given.name}'; a parameter on a step calling it goes to the one step inside"
                    " whose skill takes it")
        note = Note(f"'{callee.name}' is defined here", callee.part("name"))
        ctx.add("E047", text, given.part("name"), note)
    for skill, params in by_skill.items():
        check_skill_params(ctx, SIGNATURES[skill], tuple(params))


def _param_kinds(ctx: Context, oac: Oac, name: str) -> list[frozenset[str]] | None:
    param = oac.param(name)
    if param is None or param.cls not in ctx.library.classes:
        return None
    return [ctx.library.ancestors(param.cls)]


def _position(node: Node) -> tuple[int, int]:
    return (node.span.line, node.span.column) if node.span is not None else (0, 0)
