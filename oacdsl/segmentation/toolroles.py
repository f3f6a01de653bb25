"""What a tool contact means for the objects around it: five refinements of the tool rule.

Step 5 of the adaptive detector (:mod:`oacdsl.segmentation.tooluse`) finds *tool contacts*:
an object held by a hand stays within ``d`` of another for a while. On its own that rule
reads a few things into the KIT development clips that the dataset's labels and the
objects' heights say did not happen (Mix, Wipe, Scoop, Cut; see ``docs/segmentation-adaptive.md``).
These rules, applied in this order to the tool contacts, keep only what the demonstration did:

1. **A tool lying within reach when grasped touches its target once it moves.** A contact
   that starts while the tool is already within ``d`` of the target (it began because the
   hand took hold, not because the tool arrived) starts only where the tool–target distance
   leaves its value at the grasp by more than ``REST_M``; it is dropped if what is left is
   shorter than the dwell (Mix: the salad fork lying 84 mm beside the bowl is lifted away).
2. **What is let go of where it works stays there.** A contact between a held object and
   one nobody holds during it, that ends because the hand let go, continues while the two
   stay within ``d`` and nobody takes hold again (Wipe: the plate put into the draining
   rack; Mix: the servers left in the bowl; Scoop: the ladle put back into the bowl).
3. **Two tools in one target touch each other through it.** Two objects held by different
   hands that are both in tool contact with the same third object, neither resting on it,
   do not touch each other by the tool rule (Mix: fork and spoon both in the bowl; the
   co-motion rule relates neighbours only, in the same way).
4. **A tool works on the object, not on what that object rests on; a receptacle held near
   something does not touch it.** An object held still on another (while held, its distance
   to it varies by at most ``REST_M`` between the quartiles of their contact: Cut's cucumber
   held on the board, 0.7 mm; a spoon stirring in a bowl varies by 12 mm, 9.5 mm in a 10 Hz take
   at double speed, which twice ``REST_M`` called at rest) *rests on* it. When a held object
   receives the tool of the other hand while in tool contact with a
   third object: if it rests on that object, the tool does not touch that support (Cut: the
   knife cuts the cucumber held on the board, not the board); if it does not, the held
   object is the tool's receptacle, only held near the third (Scoop: the cup held by the
   bowl while the ladle scoops into it), and the two do not touch.
5. **A hand touches what its tool touches through the tool.** While a hand holds an object
   in tool contact with another that the hand does not hold, the hand does not touch that
   other, and not until it has left its reach ``d`` (Mix: the hand putting the fork into
   the bowl; Cut: the hand holding the cucumber on the board).

Rules 3 and 4 remove a contact from the added ones and veto it (so the paper's rule at a
pair's own distance does not bring it back); rule 5 only vetoes. All lengths are metres and
all spans frame intervals ``[a, b)``.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping

import numpy as np

from oacdsl.segmentation.episodes import true_runs

__all__ = ["REST_M", "refine"]

#: How much a distance may vary and still be "at rest", metres (marker jitter and a hand's tremor).
REST_M = 0.005

Spans = list[tuple[int, int]]


def refine(added: dict[int, Spans], removed: dict[int, Spans], n_frames: int,
           holds: Mapping[tuple[int, int], np.ndarray], objects: list[int], agents: set[int],
           pair: Callable[[int, int], int | None], dist: Callable[[int, int], np.ndarray],
           reach_m: float, dwell: int, rest_m: float = REST_M) -> tuple[dict[int, Spans], dict[int, Spans]]:
    """The tool contacts ``added`` and vetoes ``removed`` after rules 1–5 (module doc).

    ``holds``: (agent, object) → (F,) bool; ``pair(i, j)``: instance pair index or None;
    ``dist(i, j)``: (F,) closest marker distance, metres (inf beyond reach, NaN in a gap);
    ``dwell``: frames a tool contact lasts at least; ``rest_m``: metres a distance at rest
    varies (:data:`REST_M` for the reference demonstration).
    """
    held_by_any = {x: np.any([holds[(h, x)] for h in agents], axis=0) for x in objects}
    ends = {q: (i, j) for i in objects for j in objects if i < j and (q := pair(i, j)) is not None}
    out: dict[int, Spans] = {}
    worked: dict[int, Spans] = {}  # before rule 2: the frames the contact was worked in
    for q, spans in added.items():
        i, j = ends[q]
        d = dist(i, j)
        kept = []
        for a, b in spans:
            a = _trim_rest(d, a, b, reach_m, rest_m)  # rule 1
            if b - a < dwell:
                continue
            let_go = b < n_frames and not (held_by_any[i][b] or held_by_any[j][b])
            worked.setdefault(q, []).append((a, min(b, n_frames)))
            if let_go and (held_by_any[i][a:b].any() != held_by_any[j][a:b].any()):  # rule 2
                b = _first_not(d, reach_m, b, n_frames, held_by_any[i], held_by_any[j])
            kept.append((a, b))
        if kept:
            out[q] = kept
    vetoes = {q: list(s) for q, s in removed.items()}
    masks = {q: _mask(s, n_frames) for q, s in out.items()}
    holder = {x: [h for h in agents if holds[(h, x)].any()] for x in objects}
    drop: set[int] = set()
    rests = {(x, t): [(a, b) for a, b in worked[q] if _rests(dist(x, t)[a:b][held_by_any[x][a:b]], rest_m)]
             for q, (i, j) in ends.items() if q in worked for x, t in ((i, j), (j, i))}
    for q, (x, y) in ends.items():  # rule 3: two tools of different hands in one target
        if q not in masks or not holder[x] or not holder[y] or set(holder[x]) & set(holder[y]):
            continue
        for a in objects:
            qa, qb = pair(x, a), pair(y, a)
            if a in (x, y) or qa not in masks or qb not in masks or rests[(x, a)] or rests[(y, a)]:
                continue
            if (masks[q] & masks[qa] & masks[qb]).any():
                drop.add(q)
    for q, (x, s) in ((q, e) for q, (i, j) in ends.items() if q in worked for e in ((i, j), (j, i))):
        for a, b in worked[q]:  # rule 4: x receives the tool t of another hand while held at s
            for t in objects:
                qt, qx = pair(t, s), pair(t, x)
                if t in (x, s) or qx not in masks or qx in drop or not holder[x] or not holder[t] \
                        or set(holder[t]) & set(holder[x]) or not masks[qx][a:b].any():
                    continue
                if rests[(x, s)]:
                    if qt in masks:
                        drop.add(qt)  # x rests on s: t works on x, not on its support
                elif not holder[s]:
                    drop.add(q)  # x is held near s, not on it: a receptacle, not a tool
    for q in drop:
        vetoes.setdefault(q, []).extend(out.pop(q))
        masks.pop(q)
    for h in agents:  # rule 5: the hand touches through its tool
        for x in objects:
            for a in objects:
                qa, qh = pair(x, a), pair(h, a)
                if a == x or qa not in masks or qh is None or holds[(h, a)].any():
                    continue
                through = holds[(h, x)] & masks[qa]
                near = _near(dist(h, a), reach_m)
                for s, e in true_runs(through):
                    vetoes.setdefault(qh, []).append((s, _first_not(near, None, e, n_frames)))
    return out, {q: true_runs(_mask(s, n_frames)) for q, s in vetoes.items()}


def _trim_rest(d: np.ndarray, a: int, b: int, reach_m: float, rest_m: float) -> int:
    """The first frame of ``[a, b)`` where a contact that began within reach starts to move."""
    if a == 0 or not _near(d[a - 1], reach_m) or not np.isfinite(d[a]):
        return a
    start = d[a]
    while a < b and not abs(d[a] - start) > rest_m:
        a += 1
    return a


def _rests(d: np.ndarray, rest_m: float) -> bool:
    finite = d[np.isfinite(d)]
    if finite.size == 0:
        return False
    lo, hi = np.percentile(finite, [25, 75])
    return bool(hi - lo <= rest_m)


def _near(d: np.ndarray | np.floating, reach_m: float) -> np.ndarray:
    with np.errstate(invalid="ignore"):
        return np.asarray(d < reach_m)


def _first_not(d: np.ndarray, reach_m: float | None, b: int, n: int, *held: np.ndarray) -> int:
    """The first frame from ``b`` on (``n`` if none) where ``d`` is not within ``reach_m`` (``d``
    itself, a bool array, when ``reach_m`` is None) or one of ``held`` is True: a per-frame walk's
    end, looked for in windows that double."""
    width = 32
    while b < n:
        e = min(n, b + width)
        go = _near(d[b:e], reach_m) if reach_m is not None else d[b:e].copy()
        for mask in held:
            go &= ~mask[b:e]
        stop = np.flatnonzero(~go)
        if stop.size:
            return b + int(stop[0])
        b, width = e, width * 2
    return b


def _mask(spans: Spans, n: int) -> np.ndarray:
    m = np.zeros(n, dtype=bool)
    for a, b in spans:
        m[a:b] = True
    return m


