"""Synthetic marker-based demonstrations with ground truth (``oacc synth``).

The one scene is the paper's dough task (Wächter et al. 2013, IV-B):
:func:`dough_demonstration` returns a :class:`Demonstration` — the noisy
recording (metres, 100 Hz, NaN gaps), the same scene without noise and gaps,
and the ground truth as a JSON-ready dict. Everything is a pure function of the
seed (``numpy.random.default_rng(seed)``). See docs/demonstration.md.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

from oacdsl.errors import SegmentationError
from oacdsl.segmentation.points import recording_from_points
from oacdsl.segmentation.recording import Recording
from oacdsl.segmentation.synth.dough import FLIGHT_S, STORIES, Script, dough_script
from oacdsl.segmentation.synth.realism import Gap, NoiseModel, add_noise, apply_gaps, random_gaps
from oacdsl.segmentation.synth.reference import PaperRule, world_states
from oacdsl.segmentation.synth.truth import pass_by_facts, time_script, truth_document

__all__ = [
    "DEFAULT_SEED",
    "FLIGHT_S",
    "SCENES",
    "STORIES",
    "Demonstration",
    "PaperRule",
    "default_rule",
    "dough_demonstration",
]

#: The seed of the bundled demonstration ``data/dough.c3d``.
DEFAULT_SEED = 2013

#: Scripted occlusions: (instance, marker, story moment, offset s, duration s, why).
_SCRIPTED_GAPS: tuple[tuple[str, str, str, float, float, str], ...] = (
    (
        "liquid_two",
        "LQ2",
        "grasp_red_cup",
        -0.9,
        0.08,
        "the liquid's only marker is hidden inside the green cup (the whole instance is missing)",
    ),
    ("left_hand", "LWTS", "grasp_red_cup", 1.0, 0.25, "wrist marker hidden while carrying the red cup"),
    ("red_cup", "RC2", "pour_liquid_one", 0.5, 0.12, "rim marker turned away while the cup is tilted"),
    ("right_hand", "RIFD", "grasp_green_cup", 1.0, 0.2, "finger marker hidden while carrying the green cup"),
    ("orange_bowl", "OB2", "mix", 1.0, 0.3, "front rim marker hidden by the mixer while mixing"),
    ("mixer", "MX2", "mix", 2.0, 0.15, "mixer marker hidden by the hand while mixing"),
)


def default_rule(rate_hz: float = 100.0) -> PaperRule:
    """The project's AAS defaults (:class:`~oacdsl.segmentation.params.AasParams`) at ``rate_hz``."""
    from oacdsl.segmentation.params import AasParams

    p = AasParams().resolved(rate_hz)
    return PaperRule(p.distance_m, p.speed_m_s, p.n, p.merge_s)


@dataclass(frozen=True)
class Demonstration:
    """A synthetic demonstration: the recording, the noise-free scene, and the ground truth."""

    recording: Recording
    clean: Recording
    truth: dict[str, Any]


def _scripted_gaps(script: Script, timing_raw: list[int], source: str, strict: bool = True) -> list[Gap]:
    """The scripted occlusions; one within 0.3 s of a change is refused (``strict``, the paper's
    order, laid out so that it never happens) or left out (the other stories)."""
    rate = script.rate_hz
    gaps = []
    for inst, label, mark, offset_s, dur_s, why in _SCRIPTED_GAPS:
        first = int(round((script.marks[mark] + offset_s) * rate))
        last = first + max(int(round(dur_s * rate)), 1) - 1
        near = [f for f in timing_raw[1:] if first - 0.3 * rate <= f <= last + 0.3 * rate]
        if near and not strict:
            continue
        if near:  # the script is laid out so that this never happens; refuse rather than guess
            raise SegmentationError(
                f"scripted gap on {inst}:{label} is within 0.3 s of the change at frame {near[0]}",
                location=source,
            )
        gaps.append(Gap(inst, label, first, last, why))
    return gaps


def dough_demonstration(
    seed: int = DEFAULT_SEED,
    rate_hz: float = 100.0,
    rule: PaperRule | None = None,
    noise: NoiseModel | None = None,
    source: str = "synth:dough",
    flight_s: float = FLIGHT_S,
    story: str = "paper",
) -> Demonstration:
    """The paper's dough demonstration for ``seed`` at ``rate_hz`` (Hz).

    ``noise`` defaults to :class:`NoiseModel` (white jitter 0.05 mm); ``flight_s`` is the
    liquids' time in the air, seconds (see :func:`~oacdsl.segmentation.synth.dough.dough_script`);
    ``story`` one of :data:`STORIES`: the paper's order (the default; ``data/dough.c3d``), a
    hand-over of the red cup, or both hands at work at once
    (:mod:`oacdsl.segmentation.synth.stories`).

    ``rule`` (default: :func:`default_rule`, the project's AAS defaults: d = 150 mm,
    v = 100 mm/s, n = 0.1 s, merge 0.3 s) times the ground-truth keyframes on the
    noise-free scene. Raises
    :class:`~oacdsl.errors.SegmentationError` if the scene does not produce the
    scripted keyframes under ``rule``.
    """
    rule = rule or default_rule(rate_hz)
    noise = noise or NoiseModel()
    rng = np.random.default_rng(seed)
    if story not in STORIES:
        known = ", ".join(STORIES)
        raise SegmentationError(f"unknown story {story!r}; the stories are {known}", location=source)
    script = dough_script(rng, rate_hz, flight_s, story)
    pairs, touching = world_states(script.markers_m, rate_hz, rule)
    timing = time_script(script, touching, pairs, rule, seed)
    gaps = _scripted_gaps(script, timing.raw, source, strict=story == "paper")
    noisy = add_noise(script.markers_m, rate_hz, noise, rng, hands=("left_hand", "right_hand"))
    pass_by = pass_by_facts(script, "right_hand", "green_cup", rule)
    forbidden = timing.near_changes(0.5) + [(g.first - 10, g.last + 10) for g in gaps]
    forbidden.append((pass_by["frame"] - 50, pass_by["frame"] + 50))
    gaps += random_gaps(script.labels, script.times_s.shape[0], forbidden, rng)
    gaps.sort(key=lambda g: (g.first, g.instance, g.label))
    noisy = apply_gaps(noisy, script.labels, gaps)
    f_bounce = int(round(script.marks["bounce"] * rate_hz))
    bounce = [f for f in timing.raw if f_bounce - 10 <= f <= f_bounce + 0.5 * rate_hz]
    # the hand that set the red cup down (the bounce is its let-go)
    bounce_hand = min(
        (st for st in script.steps if st.oac == "place" and st.args[1] == "red_cup"),
        key=lambda st: abs(st.time_s - script.marks["bounce"]),
    ).args[0]
    realism = {
        "noise": noise.to_json(),
        "flight_s": flight_s,
        "gaps": [
            {
                "instance": g.instance,
                "marker": f"{g.instance}:{g.label}",
                "first_frame": g.first,
                "last_frame": g.last,
                "reason": g.reason,
                "during": [
                    list(p)
                    for p in timing.relations(g.first)
                    if g.instance in p and all(touching[g.first : g.last + 1, pairs.index(p)])
                ],
            }
            for g in gaps
        ],
        "pass_by": pass_by,
        "bounce": {
            "instance": "red_cup",
            "hand": bounce_hand,
            "raw_changes": bounce,
            "merged_into": bounce[-1] if bounce else None,
        },
    }
    truth = truth_document(script, timing, seed, script.labels, realism)
    order = sorted(script.markers_m)
    recording = recording_from_points({k: noisy[k] for k in order}, rate_hz, source, script.labels)
    clean = recording_from_points(
        {k: script.markers_m[k] for k in order}, rate_hz, source + ":clean", script.labels
    )
    return Demonstration(recording, clean, truth)


#: Scene name → generator, for ``oacc synth SCENE``.
SCENES: dict[str, Callable[..., Demonstration]] = {"dough": dough_demonstration}
