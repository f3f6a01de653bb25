"""Match every sub-action of a segmented demonstration and compose them into one OAC.

The glue between segmentation (keyframes with world states), the matcher and
the composer, used by ``oacc match`` and ``oacc compose``. It also picks the
scene of a demonstration: the library's scene whose tracked instances are the
recording's marker groups.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass
from typing import Any

from oacdsl.errors import MatchingError, did_you_mean
from oacdsl.library import Library
from oacdsl.matching.agency import Travel, by_motion
from oacdsl.matching.coincident import Joined, coincidence_window_s, join_coincident, matches_whole
from oacdsl.matching.composer import Composition, Step, compose
from oacdsl.matching.drafts import propose_draft
from oacdsl.matching.matcher import Matcher
from oacdsl.matching.results import MatchResult, Mode, change_text
from oacdsl.matching.split import Split, split_change
from oacdsl.matching.transient import TRANSIENT_S, Transient, agents_of, stable_segmentation
from oacdsl.model import Instance, Oac, Scene
from oacdsl.segmentation.result import Segmentation, SubAction
from oacdsl.world import Relation, WorldState

__all__ = [
    "Demonstration",
    "SubActionMatch",
    "compose_demonstration",
    "find_scene",
    "match_segmentation",
    "reaching",
]


def _pairs(relations: Iterable[Relation]) -> list[list[str]]:
    return [list(r) for r in sorted(relations)]


@dataclass(frozen=True)
class SubActionMatch:
    """One sub-action of a segmentation with its match result."""

    sub_action: SubAction
    result: MatchResult
    #: Transient states inside the sub-action (an object in flight), not keyframes of their own.
    transient: tuple[Transient, ...] = ()
    #: For a sub-action that matches no OAC as a whole: its parts, each matched
    #: (:mod:`oacdsl.matching.split`); None when it matched, or could not be split.
    split: Split | None = None
    #: Keyframes inside it between near-coincident independent changes whose union its OAC
    #: matches (:mod:`oacdsl.matching.coincident`), not keyframes of their own.
    joined: tuple[Joined, ...] = ()

    @property
    def matched(self) -> bool:
        """True when the sub-action matched an OAC, as a whole or split into parts."""
        return self.result.chosen is not None or self.split is not None

    def text(self) -> str:
        """The chosen call, the split (``split: together { … }, then …``) or ``no match``."""
        if self.result.chosen is not None:
            return self.result.chosen.text()
        if self.split is not None:
            return f"split: {self.split.text()}"
        return "no match"

    @property
    def index(self) -> int:
        return self.sub_action.index

    @property
    def explanation(self) -> str | None:
        """Why nothing matched, or why the chosen match won over the others (None: one match);
        for a split sub-action, what it was split into."""
        if self.split is not None:
            n = len(self.split.parts)
            change = change_text(self.result.added, self.result.removed)
            return f"no OAC matches the whole change ({change}); it is {n} sub-actions at once, each matched"
        return self.result.explanation if not self.result.matches else self.result.reason

    def to_json(self) -> dict[str, Any]:
        """One entry of ``oacc match --json``'s ``sub_actions``."""
        r = self.result
        doc: dict[str, Any] = {
            "from_frame": int(self.sub_action.start.frame),
            "to_frame": int(self.sub_action.end.frame),
            "before": _pairs(r.before.relations),
            "after": _pairs(r.after.relations),
            "matches": [{"oac": m.oac.name, "binding": m.mapping} for m in r.matches],
            "chosen": 0 if r.matches else None,
            "explanation": self.explanation,
        }
        if self.transient:
            doc["transient"] = [t.to_json() for t in self.transient]
        if self.joined:
            doc["joined"] = [j.to_json() for j in self.joined]
        if self.split is not None:
            doc["split"] = self.split.to_json()
        return doc


def find_scene(library: Library, instances: Sequence[str], name: str | None = None) -> Scene:
    """The scene called ``name``, or the one whose tracked instances are exactly ``instances``
    (leaving out the groups the scene marks ``ignored``)."""
    if name is not None:
        if name not in library.scenes:
            raise MatchingError(f"no scene {name!r} in the library{did_you_mean(name, library.scenes)}")
        return library.scenes[name]
    wanted = set(instances)

    def called(instances: Sequence[Instance]) -> set[str]:
        return {i.name for i in instances}

    scenes = library.scenes.values()
    # every group accounted for (tracked or ignored) first; else the ignored groups may be absent
    fits = [s for s in scenes if called(s.tracked()) | called(s.ignored()) == wanted] or [
        s for s in scenes if called(s.tracked()) == wanted - called(s.ignored())
    ]
    if len(fits) == 1:
        return fits[0]
    if len(fits) > 1:
        names = ", ".join(sorted(s.name for s in fits))
        raise MatchingError(
            f"several scenes have the recording's instances ({names}); choose one with --scene"
        )
    known = ", ".join(sorted(library.scenes)) or "none"
    raise MatchingError(
        f"no scene of the library has exactly the recording's instances ({', '.join(sorted(wanted))});"
        f" scenes: {known}; give one with --scene NAME or --scene FILE (oacc draft RECORDING drafts one)"
    )


def reaching(library: Library, name: str) -> frozenset[str]:
    """``name`` and every OAC of ``library`` that calls it, directly or through other OACs.

    Composing an OAC called ``name`` leaves these out of matching: an earlier composition of
    the same name (``learned/NAME.oac``), or a learned OAC that calls it, matched as a step
    would make the new OAC call itself (E019).
    """
    callers: dict[str, set[str]] = {}
    for oac in library.oacs.values():
        for call in oac.steps or ():
            callers.setdefault(call.oac, set()).add(oac.name)
    found = {name}
    todo = [name]
    while todo:
        for caller in callers.get(todo.pop(), ()):
            if caller not in found:
                found.add(caller)
                todo.append(caller)
    return frozenset(found)


def match_segmentation(
    segmentation: Segmentation, matcher: Matcher, mode: Mode | None = None, transient_s: float = TRANSIENT_S,
    unmerged: Callable[[], Segmentation] | None = None, coincident_s: float | None = None,
    travel: Travel | None = None,
) -> list[SubActionMatch]:
    """Match every sub-action of ``segmentation``, in time order.

    Keyframes of transient states (an object in flight for less than ``transient_s``
    seconds, :mod:`oacdsl.matching.transient`) delimit no sub-action; the agents are the
    matcher's instances of class ``Hand``. Two near-coincident independent changes (keyframes
    less than ``coincident_s`` apart; default: the segmentation's merge window in its own time,
    :mod:`oacdsl.matching.coincident`; 0 = off) are one sub-action when an OAC matches their
    union. A sub-action that matches no OAC is split into parts when it can be
    (:mod:`oacdsl.matching.split`); ``unmerged`` gives the recording's segmentation without the
    merge window (called only then), whose keyframes say when each changed relation changed.
    ``travel`` (:func:`oacdsl.matching.agency.hand_travel` of the recording) breaks a tie that
    the world states cannot by how far the tied matches' hands moved in the sub-action.
    """
    agents = agents_of(matcher.instance_classes)
    stable, dropped = stable_segmentation(segmentation, agents.__contains__, transient_s)
    rule = mode or matcher.mode
    untracked = matcher.untracked

    def match(b: WorldState, a: WorldState, explain: bool = True) -> MatchResult:
        result = matcher.match(b, a, mode=mode, explain=explain)
        if untracked is None:
            return result
        return dataclasses.replace(result, matches=tuple(untracked.original(m) for m in result.matches))

    def quiet(b: WorldState, a: WorldState) -> MatchResult:
        """A match for its matches only: no explanation (the parts of a split, the union of two
        near-coincident changes are tried by the many)."""
        return match(b, a, explain=False)

    raw: list[Segmentation] = []

    def split(b: WorldState, a: WorldState, sub: SubAction) -> Split | None:
        if rule != "strict":  # only the strict rule accounts for every change
            return None
        if unmerged is not None and not raw:
            raw.append(unmerged())
        times = _change_times(raw[0], sub, b, a) if raw else None
        return split_change(quiet, b, a, untracked.names if untracked is not None else frozenset(), times)

    def decided(r: MatchResult, sa: SubAction) -> MatchResult:
        return r if travel is None else by_motion(r, agents, travel, sa.start.frame, sa.end.frame)

    def run(subs: list[SubAction]) -> tuple[list[SubAction], list[tuple[MatchResult, Split | None]]]:
        if untracked is None:
            plain = []
            for sa in subs:
                r = decided(match(sa.before, sa.after), sa)
                plain.append((r, split(sa.before, sa.after, sa) if r.chosen is None else None))
            return subs, plain
        # relations of untracked instances: predicted along the way (one call per sub-action, in order)
        order = iter(subs)
        done = untracked.match_sequence([(sa.before, sa.after) for sa in subs],
                                        lambda b, a: decided(match(b, a), next(order)),
                                        lambda k, b, a: split(b, a, subs[k]))
        return [dataclasses.replace(sa, start=dataclasses.replace(sa.start, state=r.before),
                                    end=dataclasses.replace(sa.end, state=r.after))
                for sa, (r, _) in zip(subs, done, strict=True)], done

    subs, done = run(stable.sub_actions())
    window = coincidence_window_s(segmentation) if coincident_s is None else coincident_s
    joined: tuple[Joined, ...] = ()
    if window > 0 and len(subs) > 1:
        stable, joined = join_coincident(stable, matches_whole(subs, quiet, untracked), window)
        if joined:
            subs, done = run(stable.sub_actions())
    out = []
    for sa, (result, parts) in zip(subs, done, strict=True):
        inside = tuple(t for t in dropped if sa.start.frame < t.keyframe.frame < sa.end.frame)
        together = tuple(j for j in joined if sa.start.frame < j.keyframe.frame < sa.end.frame)
        out.append(SubActionMatch(sa, result, inside, parts, together))
    return out


def _change_times(
    raw: Segmentation, sub: SubAction, before: WorldState, after: WorldState
) -> dict[Relation, float]:
    """When each relation that changed in ``sub`` first changed, by the keyframes of ``raw``
    (the recording segmented without merging) inside the sub-action (a set-down cup that
    bounces: when it was first let go)."""
    times: dict[Relation, float] = {}
    previous: WorldState | None = None
    for kf in raw.keyframes:
        if kf.frame > sub.end.frame:
            break
        if previous is not None and kf.frame > sub.start.frame:
            for r in (after.relations ^ before.relations) & (kf.state.relations ^ previous.relations):
                times.setdefault(r, kf.time_s)
        previous = kf.state
    return times


@dataclass(frozen=True)
class Demonstration:
    """A composition and the drafts proposed on the way (``propose=True``)."""

    composition: Composition
    #: (sub-action index, draft OAC) for every sub-action that matched no OAC.
    drafts: tuple[tuple[int, Oac], ...] = ()


def compose_demonstration(
    name: str,
    matches: Sequence[SubActionMatch],
    library: Library,
    scene: Scene,
    *,
    propose: bool = False,
    paper_effects: bool = False,
) -> Demonstration:
    """Compose the chosen matches into a new OAC called ``name``.

    A sub-action without a match stops the composition with its explanation,
    unless ``propose``: then a draft OAC (:func:`~oacdsl.matching.drafts.propose_draft`)
    stands for it and the composition goes on.
    """
    classes = library.instance_classes(scene)
    steps: list[Step] = []
    drafts: list[tuple[int, Oac]] = []
    taken = set(library.oacs) | {name}
    for m in matches:
        sa, chosen = m.sub_action, m.result.chosen
        if chosen is None and m.split is not None:  # several sub-actions at once: one step each
            for part in m.split.parts:
                steps.append(Step(part.match.oac, part.match.binding, part.before, part.after, len(steps),
                                  sa.start.frame, sa.end.frame, keyframe=sa.index, together=part.together))
            continue
        if chosen is not None:
            oac, binding = chosen.oac, chosen.binding
        elif not propose:
            raise MatchingError(
                f"sub-action {sa.index + 1} (frames {sa.start.frame}–{sa.end.frame}) matches no OAC: "
                f"{m.result.explanation}; write an OAC for it, or pass --propose for a draft"
            )
        else:
            draft_name = f"{name}_step{sa.index + 1}"
            while draft_name in taken:
                draft_name += "_"
            taken.add(draft_name)
            note = (
                f"DRAFT proposed by oacc compose for {name}: sub-action {sa.index + 1},"
                f" frames {sa.start.frame}–{sa.end.frame}, matched no OAC.",
                "Review pre and effect, replace 'execute TODO' by a skill (oacc skills),",
                "then move this file out of drafts/.",
            )
            oac, mapping = propose_draft(
                draft_name, sa.before, sa.after, classes, library.ancestors, comments=note
            )
            binding = tuple((p.name, mapping[p.name]) for p in oac.params)
            drafts.append((sa.index, oac))
        steps.append(Step(oac, binding, sa.before, sa.after, len(steps), sa.start.frame, sa.end.frame,
                          keyframe=sa.index))
    composition = compose(name, steps, library, scene, paper_effects=paper_effects)
    return Demonstration(composition, tuple(drafts))
