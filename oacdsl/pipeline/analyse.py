"""The demonstration's stages: segment (AAS), match every sub-action, compose the new OAC.

Each stage is a function returning a small record with the objects later stages need
and ``doc``, its part of ``result.json`` (docs/report.md): the documents
``oacc segment --json``, ``oacc match --json`` and ``oacc compose --json`` print, plus
the fields the report shows (bound constraints, ranking notes, provenance, the text).
"""

from __future__ import annotations

import re
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from oacdsl.library import Library
from oacdsl.matching.agency import Travel
from oacdsl.matching.composer import Composition
from oacdsl.matching.demonstration import SubActionMatch
from oacdsl.matching.emit import Emitted
from oacdsl.model import Atom, Oac, Scene
from oacdsl.segmentation.params import AasParams
from oacdsl.segmentation.recording import Recording
from oacdsl.segmentation.result import Segmentation
from oacdsl.segmentation.shapes import ShapeModel
from oacdsl.world import NOTHING

__all__ = [
    "ComposeStage",
    "MatchStage",
    "SegmentStage",
    "compose_stage",
    "match_stage",
    "segment_stage",
    "steps_by_sub_action",
    "match_doc",
]


@dataclass(frozen=True)
class SegmentStage:
    recording: Recording
    segmentation: Segmentation
    doc: dict[str, Any]


def segment_stage(
    recording: Recording, params: AasParams, shapes: Mapping[str, ShapeModel] | None = None
) -> SegmentStage:
    """Segment the demonstration by the AAS; ``shapes``: the scene's, for ``params.contacts ==
    "geometry"`` (:meth:`oacdsl.pipeline.inputs.Inputs.shapes`; without them every instance is
    measured by its markers)."""
    from oacdsl.segmentation import segment

    seg = segment(recording, params, shapes=shapes)
    return SegmentStage(recording, seg, seg.to_json())


def segment_doc(stage: SegmentStage, source: str) -> dict[str, Any]:
    """The stage's document, naming the recording as the user gave it."""
    return {**stage.doc, "recording": source}


@dataclass(frozen=True)
class MatchStage:
    matches: list[SubActionMatch]
    doc: dict[str, Any]

    @property
    def unmatched(self) -> list[SubActionMatch]:
        return [m for m in self.matches if not m.matched]


def _match_note(rank: int, m: Any) -> str:
    what = f"explains {m.explained} of {m.changes} changed relations"
    if rank == 0:
        return f"chosen: {what}"
    return (f"rank {rank + 1}: {what}, class specificity {m.specificity}, {m.idle} idle effect(s),"
            f" {m.conditions} conditions")


def _primitive_steps(oac: Any, by_name: dict[str, Any]) -> int:
    """How many primitive steps running ``oac`` takes (a composed OAC: those of its steps)."""
    if not oac.steps:
        return 1
    return sum(_primitive_steps(by_name[c.oac], by_name) if c.oac in by_name else 1 for c in oac.steps)


def _executed_steps(m: SubActionMatch, by_name: dict[str, Any]) -> int:
    """How many primitive steps the robot runs for the sub-action ``m``."""
    if m.result.chosen is not None:
        return _primitive_steps(m.result.chosen.oac, by_name)
    if m.split is not None:
        return sum(_primitive_steps(p.match.oac, by_name) for p in m.split.parts)
    return 0


def match_doc(matches: Sequence[SubActionMatch], matcher: Any = None) -> dict[str, Any]:
    """The ``match`` part: ``oacc match --json`` plus bound constraints and ranking notes.

    With ``matcher``, every sub-action also lists the OACs that only the paper's rule accepts
    (preconditions before, effects after, but not accounting for the change), marked
    ``"rule": "paper"``: the runner-ups a reader of the paper's Fig. 4 expects to see.
    """
    from oacdsl.report import bound_conditions

    by_name = {o.name: o for o in matcher.oacs} if matcher is not None else {}
    subs = []
    for k, m in enumerate(matches):
        doc = m.to_json()
        for rank, (entry, match) in enumerate(zip(doc["matches"], m.result.matches, strict=True)):
            entry.update(bound_conditions(match.oac, match.mapping))
            entry["note"] = _match_note(rank, match)
            entry["rule"] = m.result.mode
        if matcher is not None and m.result.mode == "strict":
            seen = {(x.oac.name, x.binding) for x in m.result.matches}
            paper = matcher.match(m.result.before, m.result.after, mode="paper", explain=False)
            for x in paper.matches:
                if (x.oac.name, x.binding) in seen:
                    continue
                entry = {"oac": x.oac.name, "binding": x.mapping, **bound_conditions(x.oac, x.mapping)}
                entry["note"] = (
                    f"only by the paper's rule: its conditions hold, but it explains"
                    f" {x.explained} of {x.changes} changed relations (not strict)"
                )
                entry["rule"] = "paper"
                doc["matches"].append(entry)
        if m.matched:  # a composed OAC of the library runs as several steps, a split one as its parts
            doc["step"] = sum(_executed_steps(x, by_name) for x in matches[:k])
        subs.append(doc)
    return {"sub_actions": subs}


def match_stage(
    segmentation: Segmentation, library: Library, scene: Scene, name: str | None = None,
    unmerged: Callable[[], Segmentation] | None = None, travel: Travel | None = None,
) -> MatchStage:
    """Match every sub-action with the strict rule (the effects account for every change);
    ``name``: the OAC about to be composed, which (like every OAC calling it) is no step of it;
    ``unmerged``: the recording segmented without merging, for split keyframes
    (:func:`~oacdsl.matching.demonstration.match_segmentation`); ``travel``: how far the hands
    moved, for a tie the world states cannot break."""
    from oacdsl.matching import Matcher
    from oacdsl.matching.demonstration import match_segmentation, reaching

    matcher = Matcher.from_library(library, scene, exclude=reaching(library, name) if name else ())
    matches = match_segmentation(segmentation, matcher, unmerged=unmerged, travel=travel)
    return MatchStage(matches, match_doc(matches, matcher))


@dataclass(frozen=True)
class ComposeStage:
    composition: Composition
    #: The OAC to execute: parameters default to the demonstration's instances.
    oac: Oac
    emitted: Emitted
    warnings: tuple[str, ...]
    doc: dict[str, Any]


_NOTE = re.compile(r"step (\d+) \w+, keyframe (\d+)")


def _pair(atom: Atom) -> list[str]:
    return [atom.left, atom.right] if NOTHING in (atom.left, atom.right) else sorted([atom.left, atom.right])


def provenance(comp: Composition) -> list[dict[str, Any]]:
    """Where every precondition, effect and ended relation came from (step and keyframe)."""
    position = {s.index: k for k, s in enumerate(comp.steps)}

    def entry(kind: str, atom: Atom) -> dict[str, Any]:
        out: dict[str, Any] = {"kind": kind, "relation": _pair(atom)}
        found = _NOTE.search(atom.note or "")
        if found:
            out["step"] = position.get(int(found.group(1)) - 1)
            out["keyframe"] = int(found.group(2))
        if atom.note:
            out["note"] = atom.note
        return out

    rows = [entry("pre", a) for a in comp.pre if not a.negated]
    effects = {tuple(_pair(a)): a for a in comp.effect if not a.negated}
    ended = {tuple(_pair(a)): a for a in comp.effect if a.negated}
    for kind, relations, atoms in (("effect", comp.added, effects), ("ended", comp.ended, ended)):
        for r in relations:
            atom = atoms.get(tuple(r))
            rows.append(
                entry(kind, atom)
                if atom is not None
                else {"kind": kind, "relation": list(r), "note": "world-state change"}
            )
    return rows


def compose_stage(
    name: str,
    matches: Sequence[SubActionMatch],
    library: Library,
    library_path: Path,
    scene: Scene,
    *,
    source: str,
    outside_scene: Path | None = None,
    force: bool = False,
    recording: Recording | None = None,
    also: Sequence[Path] = (),
) -> ComposeStage:
    """Compose the matched sub-actions (Algorithm 1) and write the new OAC into
    ``LIBRARY/learned/NAME.oac`` as ``oacc compose`` does (unchanged when it is already there).
    ``recording``: the steps carry the skill parameters of its demonstrated motion
    (:mod:`oacdsl.matching.demoparams`; None: the paper's plain steps). ``also``: the files of
    the other libraries given (``--library`` repeated), which the new OAC is checked with."""
    from oacdsl.matching.demonstration import compose_demonstration
    from oacdsl.matching.emit import LEARNED, emit

    comp = compose_demonstration(name, matches, library, scene).composition
    if recording is not None:
        from oacdsl.matching.composedparams import with_demo_params
        from oacdsl.matching.demoparams import demonstrated_motions

        motions = demonstrated_motions(recording, [m.sub_action for m in matches])
        comp = with_demo_params(comp, motions, library, scene)
    written = comp.oac
    warnings = list(comp.warnings)
    if outside_scene is not None:  # defaults would name instances the library does not know
        written = written.model_copy(
            update={"params": tuple(p.model_copy(update={"default": None}) for p in written.params)}
        )
        warnings.append(
            f"the scene comes from {outside_scene}, outside the library: the OAC written to the"
            " library carries no default binding"
        )
    root = library_path if library_path.is_dir() else library_path.parent
    header = [
        f"Composed by oacc reproduce from {source} (strict matching, {len(comp.steps)} steps,"
        f" scene {scene.name})."
    ]
    emitted = emit(
        [written], root / LEARNED / f"{name}.oac", library=library_path, header=header, force=force, also=also
    )
    doc = comp.to_json(str(emitted.path))
    doc["text"] = emitted.text
    doc["provenance"] = provenance(comp)
    doc["emitted"] = emitted.status
    if warnings:
        doc["warnings"] = warnings
    return ComposeStage(comp, comp.oac, emitted, tuple(warnings), doc)


def steps_by_sub_action(stage: ComposeStage) -> list[dict[str, Any]]:
    """``compose.steps`` of the document, one per sub-action: a split sub-action (several steps
    from one keyframe, :mod:`oacdsl.matching.split`) by its first step."""
    docs = stage.doc.get("steps", [])
    first: dict[int, int] = {}
    for k, step in enumerate(stage.composition.steps):
        first.setdefault(step.start_keyframe, k)
    last = max(first, default=-1)
    return [docs[first[i]] if i in first and first[i] < len(docs) else {} for i in range(last + 1)]
