"""Matching throughput: the indexed matcher against clingo on the same bindings.

For every point of the grid N sub-actions × L OACs, a random scene (10–50
instances of classes three levels deep, 5–20 % of the pairs touching), a
random sequence of N+1 world states (each differs from the one before by one
to three relations, like keyframes) and L random OACs (1–4 relations sharing
variables, positive, negated and ``x <-> nothing``) are matched twice in the
same process: by ``Matcher.raw_matches`` over every sub-action, and by clingo
with all sub-actions encoded once and ground once
(`benchmarks/asp_matcher.py`). The answers must be identical. Printed: both end
to end times (median of --repeat runs), clingo's conversion, grounding and
solving, and the ratio clingo / ours (> 1: ours is faster).

    python benchmarks/matching.py            # N ∈ {10², 10³, 10⁴}, L ∈ {10, 100, 1000}
    python benchmarks/matching.py --quick    # N ∈ {10², 10³}, L ∈ {10, 100}
"""

from __future__ import annotations

import argparse
import random
import statistics
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from asp_matcher import AspTimes, asp_matches  # noqa: E402

from oacdsl.library import Library  # noqa: E402
from oacdsl.matching import Matcher  # noqa: E402
from oacdsl.model import Atom, Instance, Module, Oac, ObjectClass, Param, Scene  # noqa: E402
from oacdsl.world import NOTHING, WorldState, relation  # noqa: E402


def hierarchy(rng: random.Random) -> list[ObjectClass]:
    """3 roots × 3 children × 3 grandchildren; a third of the grandchildren have a second parent."""
    classes = [ObjectClass(name=f"R{i}") for i in range(3)]
    mids = [ObjectClass(name=f"R{i}M{j}", parents=(f"R{i}",)) for i in range(3) for j in range(3)]
    leaves = []
    for m in mids:
        for k in range(3):
            parents = [m.name]
            if rng.random() < 1 / 3:
                parents.append(rng.choice([x.name for x in mids if x.name != m.name]))
            leaves.append(ObjectClass(name=f"{m.name}L{k}", parents=tuple(parents)))
    return classes + mids + leaves


def scene(rng: random.Random, classes: list[ObjectClass], n: int) -> Scene:
    leaves = [c.name for c in classes if "L" in c.name]
    return Scene(name="bench", instances=tuple(Instance(name=f"obj{i:02d}", classes=(rng.choice(leaves),))
                                               for i in range(n)))


def random_oac(rng: random.Random, classes: list[ObjectClass], k: int) -> Oac:
    """1–4 relations over variables that share: each relation after the first reuses a variable."""
    n_rel = rng.randint(1, 4)
    variables = ["v0"]
    atoms: list[tuple[str, Atom]] = []
    for r in range(n_rel):
        a = rng.choice(variables)
        kind = rng.choices(["pos", "neg", "none"], weights=[70, 15, 15])[0]
        if kind == "none":
            atom = Atom(left=a, right=NOTHING)
        else:
            if rng.random() < 0.7 or len(variables) < 2:
                b = f"v{len(variables)}"
                variables.append(b)
            else:
                b = rng.choice([v for v in variables if v != a])
            atom = Atom(left=a, right=b, negated=kind == "neg")
        where = "effect" if r == 0 else rng.choice(["pre", "effect"])
        atoms.append((where, atom))
    by_level = [[c.name for c in classes if c.name.count("M") == 0],
                [c.name for c in classes if "M" in c.name and "L" not in c.name],
                [c.name for c in classes if "L" in c.name]]
    params = tuple(Param(name=v, cls=rng.choice(by_level[rng.choices([0, 1, 2], weights=[1, 3, 2])[0]]))
                   for v in variables)
    return Oac(name=f"oac{k:04d}", params=params, pre=tuple(a for w, a in atoms if w == "pre"),
               effect=tuple(a for w, a in atoms if w == "effect"), skill="mix")


def sequence(rng: random.Random, names: list[str], density: float, n_sub: int) -> list[WorldState]:
    pairs = [relation(a, b) for i, a in enumerate(names) for b in names[i + 1:]]
    target = max(1, round(density * len(pairs)))
    current = set(rng.sample(pairs, target))
    states = [WorldState(frozenset(names), frozenset(current))]
    for _ in range(n_sub):
        for _ in range(rng.randint(1, 3)):
            if len(current) > target or (len(current) == target and rng.random() < 0.5):
                current.remove(rng.choice(sorted(current)))
            else:
                current.add(rng.choice([p for p in pairs if p not in current]))
        states.append(WorldState(frozenset(names), frozenset(current)))
    return states


def ours(matcher_args: tuple, pairs: list[tuple[WorldState, WorldState]]) -> tuple[set, float]:
    oacs, classes, ancestors = matcher_args
    t0 = time.perf_counter()
    m = Matcher(oacs, classes, ancestors=ancestors)
    found = set()
    for s, (before, after) in enumerate(pairs):
        for co, b in m.raw_matches(before, after):
            found.add((co.index, s, b[: co.n_params]))
    return found, time.perf_counter() - t0


def point(n_sub: int, n_oacs: int, seed: int, repeat: int) -> dict:
    rng = random.Random(seed)
    classes = hierarchy(rng)
    n_inst = rng.randint(10, 50)
    density = rng.uniform(0.05, 0.20)
    sc = scene(rng, classes, n_inst)
    oacs = [random_oac(rng, classes, k) for k in range(n_oacs)]
    lib = Library([Module(path="<bench>", decls=(*classes, sc))])
    inst_classes = lib.instance_classes(sc)
    states = sequence(rng, [i.name for i in sc.instances], density, n_sub)
    pairs = list(zip(states, states[1:], strict=False))
    py_times, asp_runs = [], []
    answer = None
    for _ in range(repeat):
        found, dt = ours((oacs, inst_classes, lib.ancestors), pairs)
        py_times.append(dt)
        times = AspTimes()
        reference = asp_matches(oacs, inst_classes, pairs, "strict", times)
        asp_runs.append(times)
        if found != reference:
            only = sorted(found ^ reference)[:3]
            raise SystemExit(f"MISMATCH at N={n_sub} L={n_oacs}: {len(found)} vs {len(reference)}"
                             f" bindings; e.g. {only}")
        answer = found
    med = statistics.median
    return {
        "N": n_sub, "L": n_oacs, "instances": n_inst, "density": density, "matches": len(answer or ()),
        "ours": med(py_times), "convert": med(t.convert_s for t in asp_runs),
        "ground": med(t.ground_s for t in asp_runs), "solve": med(t.solve_s for t in asp_runs),
        "clingo": med(t.total_s for t in asp_runs),
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--quick", action="store_true", help="N ∈ {10², 10³}, L ∈ {10, 100}")
    parser.add_argument("--repeat", type=int, default=None, help="runs per point, median reported"
                        " (default: 3, 1 for N·L ≥ 10⁶)")
    parser.add_argument("--seed", type=int, default=2013)
    args = parser.parse_args()
    ns = [100, 1000] if args.quick else [100, 1000, 10000]
    ls = [10, 100] if args.quick else [10, 100, 1000]
    print("strict matching; times in seconds (median); ratio = clingo end to end / ours (> 1: ours faster)")
    header = (f"{'N':>6} {'L':>5} {'inst':>4} {'dens':>5} {'matches':>8} {'ours':>8} {'convert':>8}"
              f" {'ground':>8} {'solve':>8} {'clingo':>8} {'ratio':>7}")
    print(header)
    print("-" * len(header))
    behind = []
    for n in ns:
        for k, n_oacs in enumerate(ls):
            repeat = args.repeat or (1 if n * n_oacs >= 10**6 else 3)
            r = point(n, n_oacs, args.seed + 7 * k + n, repeat)
            ratio = r["clingo"] / r["ours"]
            if n >= 1000 and ratio <= 1:
                behind.append((n, n_oacs))
            print(f"{r['N']:>6} {r['L']:>5} {r['instances']:>4} {r['density']:>5.2f} {r['matches']:>8}"
                  f" {r['ours']:>8.3f} {r['convert']:>8.3f} {r['ground']:>8.3f} {r['solve']:>8.3f}"
                  f" {r['clingo']:>8.3f} {ratio:>7.1f}", flush=True)
    print("answers identical at every point; target (ahead of clingo at N ≥ 1000):",
          "met" if not behind else f"missed at {behind}")


if __name__ == "__main__":
    main()
