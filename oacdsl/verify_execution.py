"""``oacc verify``: judge an execution by its physical outcome against the demonstration.

Three checks (docs/verify.md), each with the demonstration's value, the execution's and the
tolerance (:class:`~oacdsl.verify_tolerances.VerifyTolerances`):

1. **relations** — the sequences of world-state changes (:mod:`oacdsl.verify`, split rule),
   after transient states are dropped. For a simulated run with its contacts file
   (:mod:`oacdsl.verify_contacts`) the execution's changes are the simulation's own
   contacts; the AAS's view of its virtual markers is compared with them and every
   disagreement is reported as a *finding* (of the segmentation, not of the robot).
2. **end state** — :mod:`oacdsl.verify_endstate`, per object.
3. **motion** — :mod:`oacdsl.verify_motion`, per sub-action.

A recorded execution without contacts (another person's take, a real robot's motion capture)
is first brought to the demonstration's pace and frame rate (:func:`normalised`: played
faster or slower by the ratio of the two durations, within ×1/3…×3, and resampled), so that
the same AAS sees the same events in a slower, faster or differently sampled take.

``verified`` = 1 and 2 hold; ``faithful`` = 1, 2 and 3 hold. With ``any_hands`` the
execution's hands may be exchanged consistently (a left-handed take): both assignments are
tried and the better kept. ``oacc reproduce``, ``oacc run --demonstration`` and ``oacc
verify`` all call :func:`verify_execution`.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np

from oacdsl.library import Library
from oacdsl.model import Scene
from oacdsl.segmentation.params import AasParams
from oacdsl.segmentation.recording import Recording
from oacdsl.segmentation.result import Keyframe, Segmentation
from oacdsl.verify import Verification, verify
from oacdsl.verify_contacts import SimContacts
from oacdsl.verify_liquids import without_shared_container
from oacdsl.verify_relations import Check
from oacdsl.verify_spans import Unmerged, aligned_spans, frame_of
from oacdsl.verify_tolerances import DEFAULT_TOLERANCES, VerifyTolerances
from oacdsl.world import Relation

__all__ = ["Check", "LazyPoses", "VerifyOutcome", "normalised", "verify_execution"]

KINDS = ("relations", "end_state", "motion")


@dataclass(frozen=True)
class VerifyOutcome:
    checks: tuple[Check, ...]
    relations: Verification
    #: Where the AAS of the execution's markers and the simulation's contacts disagree.
    findings: tuple[str, ...] = ()
    #: Demonstrated features not judged, and why.
    notes: tuple[str, ...] = ()
    hand_map: Mapping[str, str] = field(default_factory=dict)
    relations_source: str = "aas"
    tolerances: VerifyTolerances = DEFAULT_TOLERANCES
    #: The execution's segmentation the relations check used, and its motion spans.
    execution_segmentation: Segmentation | None = None

    def passed(self, kind: str) -> bool:
        return all(c.passed for c in self.checks if c.kind == kind)

    @property
    def verified(self) -> bool:
        return self.passed("relations") and self.passed("end_state")

    @property
    def faithful(self) -> bool:
        return self.verified and self.passed("motion")

    def failed(self) -> list[Check]:
        return [c for c in self.checks if not c.passed]

    def summary(self) -> str:
        """One line: ``verified, faithful`` or what failed."""
        if self.faithful:
            return "verified and faithful: the execution changes the world as demonstrated, ends as" \
                   " demonstrated and moves as demonstrated"
        kinds = [k.replace("_", " ") for k in KINDS if not self.passed(k)]
        head = "verified, not faithful" if self.verified else "not verified"
        return f"{head}: {', '.join(kinds)} failed ({len(self.failed())} check(s))"

    def to_json(self) -> dict[str, Any]:
        return {
            "verified": self.verified,
            "faithful": self.faithful,
            "summary": self.summary(),
            "checks": [c.to_json() for c in self.checks],
            "relations_source": self.relations_source,
            "findings": list(self.findings),
            "notes": list(self.notes),
            "hand_map": dict(self.hand_map),
            "tolerances": self.tolerances.to_json(),
        }


class LazyPoses(Mapping[str, Any]):
    """The rigid fits of a recording's instances (≥ 3 markers), each fitted when first asked for:
    a robot's hands carry ~90 markers each and most checks need two or three instances."""

    def __init__(self, recording: Recording) -> None:
        from oacdsl.segmentation.poses import MIN_MARKERS

        self.recording = recording
        self.names = [n for n in recording.instances if len(recording.groups[n]) >= MIN_MARKERS]
        self._fitted: dict[str, Any] = {}

    def __getitem__(self, name: str) -> Any:
        if name not in self.names:
            raise KeyError(name)
        if name not in self._fitted:
            from oacdsl.segmentation.poses import fit_instance

            self._fitted[name] = fit_instance(self.recording, name)
        return self._fitted[name]

    def __iter__(self) -> Any:
        return iter(self.names)

    def __len__(self) -> int:
        return len(self.names)

    def __contains__(self, name: object) -> bool:
        return name in self.names


def _renamed(rec: Recording, names: Mapping[str, str]) -> Recording:
    if not names:
        return rec
    groups = {names.get(k, k): v for k, v in rec.groups.items()}
    return replace(rec, groups=groups)


def _renamed_contacts(c: SimContacts, names: Mapping[str, str]) -> SimContacts:
    if not names:
        return c
    from oacdsl.world import relation

    changes = tuple((f, frozenset(relation(names.get(a, a), names.get(b, b)) for a, b in rels))
                    for f, rels in c.changes)
    return replace(c, instances=tuple(names.get(i, i) for i in c.instances), changes=changes)


def _hand_swaps(agents: frozenset[str]) -> list[dict[str, str]]:
    hands = sorted(agents)
    if len(hands) != 2:
        return [{}]
    return [{}, {hands[0]: hands[1], hands[1]: hands[0]}]


def verify_execution(
    demonstration: Recording,
    execution: Recording,
    *,
    scene: Scene,
    library: Library,
    params: AasParams,
    contacts: SimContacts | None = None,
    demo_segmentation: Segmentation | None = None,
    execution_aas: Segmentation | None = None,
    any_hands: bool = False,
    tolerances: VerifyTolerances = DEFAULT_TOLERANCES,
) -> VerifyOutcome:
    """Judge ``execution`` against ``demonstration`` (module docstring). Both are grouped by
    the scene's instances; ``params`` segment the demonstration (and a recorded execution
    without contacts); ``execution_aas``: the execution's AAS segmentation when the caller has
    it already (a simulated run's, for the findings)."""
    from oacdsl.geometry import resolve_scene
    from oacdsl.matching.transient import agents_of, stable_segmentation
    from oacdsl.segmentation import segment

    agents = agents_of(library.instance_classes(scene))
    shapes = resolve_scene(library, scene)
    containers = {n for n, g in shapes.items() if g is not None and g.container}
    liquids = {n for n, g in shapes.items() if g is not None and g.role == "liquid"}
    demo_seg = demo_segmentation if demo_segmentation is not None else segment(demonstration, params)
    demo_seg = without_shared_container(demo_seg, liquids, containers, agents.__contains__)
    demo_seg = stable_segmentation(demo_seg, agents.__contains__)[0]
    demo_posed = LazyPoses(demonstration)
    unmerged = _lazy(lambda: segment(demonstration, replace(params, merge_s=0.0)).keyframes,
                     frame_of(demonstration))
    best: VerifyOutcome | None = None
    if contacts is None:  # a recorded take: to the demonstration's pace and frame rate
        span = float(demonstration.times_s[-1] - demonstration.times_s[0])
        tempo = float(execution.times_s[-1] - execution.times_s[0]) / span if span > 0 else 1.0
        execution = normalised(execution, float(np.clip(tempo, 1 / 3, 3.0)), demonstration.rate_hz)
    for swap in _hand_swaps(agents) if any_hands else [{}]:
        rec = _renamed(execution, swap)
        sim = _renamed_contacts(contacts, swap) if contacts is not None else None
        aas = execution_aas if not swap else None
        outcome = _judge(demonstration, demo_seg, demo_posed, rec, sim, aas, params, agents,
                         (containers, liquids), tolerances, any_hands, swap, segment, stable_segmentation,
                         unmerged)
        rank = (outcome.verified, outcome.faithful, -len(outcome.failed()))
        if best is None or rank > (best.verified, best.faithful, -len(best.failed())):
            best = outcome
    if best is None:  # pragma: no cover  (the loop runs at least once)
        raise ValueError("no hand assignment was tried")
    return best


def _lazy(make: Callable[[], Sequence[Keyframe]], frame: Callable[[float], int]) -> Unmerged:
    """``make()``'s keyframes as ``(frame, relations)``, computed when first asked for: a
    recording's keyframes without merging, where a keyframe merges a judged pair's change with
    others (:mod:`oacdsl.verify_spans`)."""
    found: list[list[tuple[int, frozenset[Relation]]]] = []

    def get() -> list[tuple[int, frozenset[Relation]]]:
        if not found:
            found.append([(frame(k.time_s), k.state.relations) for k in make()])
        return found[0]

    return get


def normalised(rec: Recording, tempo: float, rate_hz: float) -> Recording:
    """``rec`` played ``tempo`` times as fast and sampled at ``rate_hz`` (linear interpolation;
    a sample next to a gap is a gap): a take brought to the demonstration's pace and rate."""
    t = np.asarray(rec.times_s, dtype=np.float64) - float(rec.times_s[0])
    if tempo == 1.0 and rate_hz == rec.rate_hz:
        return rec
    n = int(np.floor(t[-1] / tempo * rate_hz + 1e-9)) + 1
    new_t = np.minimum(np.arange(n) / rate_hz * tempo, t[-1])
    if len(t) < 2:
        return rec
    idx = np.clip(np.searchsorted(t, new_t, side="right") - 1, 0, len(t) - 2)
    w = ((new_t - t[idx]) / (t[idx + 1] - t[idx]))[:, None, None]
    p = rec.positions_m
    positions = (1 - w) * p[idx] + w * p[idx + 1]
    return replace(rec, rate_hz=rate_hz, times_s=np.arange(n) / rate_hz, positions_m=positions)


def _judge(demo_rec: Recording, demo_seg: Segmentation, demo_posed: Any, rec: Recording,
           sim: SimContacts | None, aas_seg: Segmentation | None, params: AasParams, agents: frozenset[str],
           kinds: tuple[set[str], set[str]],
           tol: VerifyTolerances, any_hands: bool, swap: Mapping[str, str], segment: Any,
           stable: Any, unmerged: Unmerged) -> VerifyOutcome:
    from oacdsl.verify_endstate import compare_object, end_state
    from oacdsl.verify_motion import motion_checks
    from oacdsl.verify_relations import disagreements, relations_check

    instances = tuple(demo_seg.instances)
    missing = sorted(set(instances) - set(rec.instances))
    checks: list[Check] = []
    findings: list[str] = []
    if missing:
        checks.append(Check("relations.instances", "relations", False, ", ".join(instances),
                            ", ".join(rec.instances), "the same tracked instances",
                            f"the execution has no markers for {', '.join(missing)}"))
        rec_instances = [i for i in instances if i in rec.instances]
    else:
        rec_instances = list(instances)
    if sim is not None:
        run_seg = sim.segmentation(tuple(rec_instances), tol)
        unmerged_tol, contacts = replace(tol, contact_merge_s=0.0), sim
        run_unmerged = _lazy(lambda: contacts.segmentation(tuple(rec_instances), unmerged_tol).keyframes,
                             frame_of(rec))
        source = "simulation contacts"
        known = AasParams.__dataclass_fields__
        aas = AasParams(**{k: v for k, v in sim.aas.items() if k in known}) if sim.aas else params
        seen = stable(aas_seg if aas_seg is not None else segment(rec, aas), agents.__contains__)[0]
        findings += disagreements(seen, stable(run_seg, agents.__contains__)[0], rec_instances)
    else:
        source = "aas"
        run_seg = segment(rec, params)
        run_unmerged = _lazy(lambda: segment(rec, replace(params, merge_s=0.0)).keyframes, frame_of(rec))
    containers, liquids = kinds
    run_seg = without_shared_container(run_seg, liquids, containers, agents.__contains__)
    run_seg = stable(run_seg, agents.__contains__)[0]
    dk, rk = demo_seg.keyframes, run_seg.keyframes
    v = verify([k.state for k in dk], [k.state for k in rk],
               demonstration_frames=[k.frame for k in dk], robot_frames=[k.frame for k in rk],
               demonstration_times_s=[k.time_s for k in dk], robot_times_s=[k.time_s for k in rk],
               instances=rec_instances, tolerance=tol.relations_distance, merge=True)
    checks.append(relations_check(v, source))
    # end state, per object
    is_agent = agents.__contains__
    demo_end = end_state(demo_rec, dk[-1].state, is_agent, containers.__contains__, tol, liquids.__contains__)
    run_end = end_state(rec, rk[-1].state, is_agent, containers.__contains__, tol, liquids.__contains__)
    for name, d in sorted(demo_end.objects.items()):
        r = run_end.objects.get(name)
        if r is None:
            checks.append(Check(f"end_state.{name}", "end_state", False, d.describe(), "—", "present",
                                f"{name} has no markers at the execution's end"))
            continue
        for aspect, ok, dv, rv, tv, detail in compare_object(name, d, r, tol, {}):
            checks.append(Check(f"end_state.{name}.{aspect}", "end_state", ok, dv, rv, tv, detail))
    # motion, per sub-action
    demo_subs = list(demo_seg.sub_actions())
    spans = aligned_spans(v, dk, rk, rec)
    mchecks, notes = motion_checks(demo_rec, demo_subs, demo_posed, rec, spans, LazyPoses(rec), {}, tol,
                                   any_hands, frozenset(liquids), (unmerged, run_unmerged), agents)
    for m in mchecks:
        checks.append(Check(f"motion.{m.sub_action}.{m.feature}", "motion", m.passed, m.demonstration,
                            m.execution, m.tolerance, m.detail or f"sub-action {m.sub_action} ({m.label})"))
    if not mchecks:
        notes.append("no demonstrated sub-action has a reliable oscillation, turn or tilt to judge")
    return VerifyOutcome(tuple(checks), v, tuple(findings), tuple(notes), dict(swap), source, tol, run_seg)
