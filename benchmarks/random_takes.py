"""Seeded random combined takes of a recording: mirrored or not, faster or slower, another frame
rate with jitter, another size, turned about the vertical, one marker missing for 0.3 s.

A take is drawn from ``(seed, index)`` (:func:`draw`) and written as one line of parameters
(:meth:`RandomTake.spec`), which :func:`parse` reads back, so a take that fails can be made
again from its printed line alone (``benchmarks/kit_sweep_robot.py --variation 'LINE'``).

The ranges (:data:`RANGES`): mirror yes/no (even odds), speed ×0.6–×1.8 (the demonstration
done that many times as fast: the time ×1/speed, same frame rate), frame rate 10–120 Hz with
0.2 mm Gaussian jitter, scale ×0.85–×1.15 (about the mean xy on the floor), rotation 0–360°
about the vertical, and a 0.3 s gap in one marker of the object that travels farthest
(:func:`oacdsl.segmentation.takes.gap_marker`), starting at a drawn fraction (0.1–0.8) of the
take's duration. Each parameter is drawn uniformly within its range.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass, fields

import numpy as np

from oacdsl.segmentation.recording import Recording
from oacdsl.segmentation.takes import (
    IDENTITY,
    gap_marker,
    mirrored,
    resampled,
    rotated,
    scaled,
    stretched,
    with_gap,
)

__all__ = ["GAP_S", "JITTER_M", "RANGES", "RandomTake", "draw", "parse"]

#: The gap's length (s) and the jitter's standard deviation (m) of every random take.
GAP_S = 0.3
JITTER_M = 0.0002

#: name → (low, high) of each drawn parameter (uniform).
RANGES: dict[str, tuple[float, float]] = {
    "speed": (0.6, 1.8),
    "rate_hz": (10.0, 120.0),
    "scale": (0.85, 1.15),
    "rotation_deg": (0.0, 360.0),
    "gap_at": (0.1, 0.8),
}


@dataclass(frozen=True)
class RandomTake:
    """One combined take: applied in this order: mirror, speed, scale, rotation, frame rate with
    jitter (drawn from ``jitter_seed``), gap (at ``gap_at`` of the take's duration)."""

    mirror: bool
    speed: float
    rate_hz: float
    scale: float
    rotation_deg: float
    gap_at: float
    jitter_seed: int

    def spec(self) -> str:
        """The parameters as one line ``mirror=1 speed=1.234 …`` (:func:`parse` reads it)."""
        return " ".join(
            f"{k}={int(v) if isinstance(v, bool) else v}" for k, v in asdict(self).items()
        )

    def apply(self, rec: Recording) -> tuple[Recording, dict[str, str]]:
        """(the take of ``rec``, original hand → the take's hand)."""
        take, hands = mirrored(rec) if self.mirror else (rec, dict(IDENTITY))
        take = stretched(take, 1.0 / self.speed)
        take = scaled(take, self.scale)
        take = rotated(take, np.radians(self.rotation_deg))
        take = resampled(take, self.rate_hz, jitter_m=JITTER_M, seed=self.jitter_seed)
        marker, _ = gap_marker(take, GAP_S)
        start = float(take.times_s[0] + self.gap_at * (take.times_s[-1] - take.times_s[0]))
        return with_gap(take, marker, start, GAP_S), hands


def draw(seed: int, index: int, key: int = 0) -> RandomTake:
    """The ``index``-th random take of ``seed`` under ``key`` (e.g. a clip's own number): the
    same for the same three, whatever was drawn before it."""
    rng = np.random.default_rng([int(seed), int(key), int(index)])
    mirror = bool(rng.integers(2))
    values = {k: round(float(rng.uniform(lo, hi)), 3) for k, (lo, hi) in RANGES.items()}
    return RandomTake(mirror=mirror, jitter_seed=int(rng.integers(1_000_000)), **values)


def parse(text: str) -> RandomTake:
    """The take of a :meth:`RandomTake.spec` line; ``ValueError`` naming what is wrong."""
    given: dict[str, str] = {}
    for word in text.split():
        key, sep, value = word.partition("=")
        if not sep:
            raise ValueError(f"{word!r}: not NAME=VALUE")
        given[key] = value
    names = [f.name for f in fields(RandomTake)]
    missing = [n for n in names if n not in given]
    extra = [k for k in given if k not in names]
    if missing or extra:
        raise ValueError(f"random take: missing {missing or 'nothing'}, unknown {extra or 'nothing'}")
    try:
        out = RandomTake(
            mirror=given["mirror"] in ("1", "True", "true"),
            speed=float(given["speed"]),
            rate_hz=float(given["rate_hz"]),
            scale=float(given["scale"]),
            rotation_deg=float(given["rotation_deg"]),
            gap_at=float(given["gap_at"]),
            jitter_seed=int(given["jitter_seed"]),
        )
    except ValueError as err:
        raise ValueError(f"random take: {err}") from None
    if given["mirror"] not in ("0", "1", "True", "False", "true", "false"):
        raise ValueError(f"random take: mirror={given['mirror']} is not 0 or 1")
    if min(out.speed, out.rate_hz, out.scale) <= 0 or not 0 <= out.gap_at < 1:
        raise ValueError("random take: speed, rate_hz, scale must be > 0 and gap_at in [0, 1)")
    return out
