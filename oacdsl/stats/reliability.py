"""Measured reliability of OACs: success rates with Wilson score intervals."""

from __future__ import annotations

import math
import statistics
from collections.abc import Iterable, Mapping
from dataclasses import asdict, dataclass
from typing import Any

__all__ = ["Reliability", "summarise", "wilson_interval"]

#: Two-sided 95 % quantile of the standard normal distribution.
Z_95 = 1.959963984540054


def wilson_interval(successes: int, trials: int, z: float = Z_95) -> tuple[float, float]:
    """The Wilson score interval of a success rate (default 95 %); (0, 1) for no trials.

    Unlike the normal ("Wald") interval it stays within [0, 1] and is sensible for
    the small counts and 0 % / 100 % rates that robot experiments produce.
    """
    if trials < 0 or not 0 <= successes <= trials:
        raise ValueError(f"need 0 <= successes <= trials, got {successes}/{trials}")
    if trials == 0:
        return 0.0, 1.0
    p = successes / trials
    z2 = z * z
    denom = 1.0 + z2 / trials
    centre = (p + z2 / (2 * trials)) / denom
    half = z * math.sqrt(p * (1 - p) / trials + z2 / (4 * trials * trials)) / denom
    low = 0.0 if successes == 0 else max(0.0, centre - half)
    high = 1.0 if successes == trials else min(1.0, centre + half)
    return low, high


@dataclass(frozen=True)
class Reliability:
    """What the store knows about one OAC (durations in seconds, rates in [0, 1])."""

    oac: str
    runs: int
    successes: int
    rate: float
    ci_low: float
    ci_high: float
    median_duration_s: float | None
    last_run_utc: str | None
    last_failure_utc: str | None
    last_failure: str | None

    def to_json(self) -> dict[str, Any]:
        return asdict(self)


def summarise(rows: Iterable[Mapping[str, Any]]) -> list[Reliability]:
    """One :class:`Reliability` per OAC, sorted by name, from store rows oldest first.

    Each row needs ``oac``, ``success``, ``duration_s``, ``error`` and ``time_utc``
    (the shape :meth:`oacdsl.stats.store.RunStore.rows` returns). A failure without
    an error message is reported as ``"failed (no reason recorded)"``.
    """
    by_oac: dict[str, list[Mapping[str, Any]]] = {}
    for row in rows:
        by_oac.setdefault(str(row["oac"]), []).append(row)
    out = []
    for oac in sorted(by_oac):
        group = by_oac[oac]
        ok = sum(1 for r in group if r["success"])
        lo, hi = wilson_interval(ok, len(group))
        durations = [float(r["duration_s"]) for r in group if r.get("duration_s") is not None]
        failures = [r for r in group if not r["success"]]
        last_fail = failures[-1] if failures else None
        out.append(
            Reliability(
                oac=oac,
                runs=len(group),
                successes=ok,
                rate=ok / len(group),
                ci_low=lo,
                ci_high=hi,
                median_duration_s=statistics.median(durations) if durations else None,
                last_run_utc=group[-1].get("time_utc"),
                last_failure_utc=last_fail.get("time_utc") if last_fail else None,
                last_failure=(last_fail.get("error") or "failed (no reason recorded)") if last_fail else None,
            )
        )
    return out
