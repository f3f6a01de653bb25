"""Benchmark: parse + validate a generated OAC library vs. the ``pddl`` package on the same content.

Generates a library of N OACs over 200 classes (plus Hand and Graspable, the classes
of the skills they execute with explicit arguments, ``execute place(h, o)``, checked
against the skill's signature; N = 1,000 and 10,000 by default)
and an equivalent PDDL domain: one type per class (single parent: PDDL types
have one), one action per OAC with the same parameters and the same number of
precondition and effect atoms (``a <-> b`` → ``(touching ?a ?b)``,
``a <-> nothing`` → ``(free ?a)``, ``not`` → ``(not …)``). Both sides get the
text in memory and are timed after their parser is built (Lark grammar
construction excluded on both sides); each figure is the median of
``--repeat`` runs in this process. Times are CPU seconds of this process
(``time.process_time``), which other jobs on a shared machine disturb far
less than wall-clock time; ``--wall`` measures wall-clock time instead.

    python benchmarks/compile.py            # 1k and 10k
    python benchmarks/compile.py --sizes 1000 --repeat 3
"""

from __future__ import annotations

import argparse
import random
import statistics
import sys
import time
from collections.abc import Callable
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from oacdsl.compiler import compile_sources  # noqa: E402
from oacdsl.compiler.grammar import lark_parser  # noqa: E402
from oacdsl.skills import SIGNATURES  # noqa: E402

N_CLASSES = 200
OACS_PER_FILE = 1000


class Spec:
    """The generated content, shared by both renderings."""

    def __init__(self, n_oacs: int, seed: int = 1) -> None:
        rng = random.Random(seed)
        self.classes = [f"C{i:03d}" for i in range(N_CLASSES)]
        # the skills' classes: h is a Hand, every generated class a Graspable (C000's parent)
        self.parent = {
            c: (self.classes[rng.randrange(i)] if i else "Graspable") for i, c in enumerate(self.classes)
        }
        self.parent = {"Hand": None, "Graspable": None, **self.parent}
        self.classes = ["Hand", "Graspable", *self.classes]
        generated = self.classes[2:]
        skills = sorted(n for n, s in SIGNATURES.items() if [a.cls for a in s.args] == ["Hand", "Graspable"])
        self.oacs = []
        for i in range(n_oacs):
            o, t = (rng.choice(generated) for _ in range(2))
            self.oacs.append((f"act{i}", (("h", "Hand"), ("o", o), ("t", t)), skills[i % len(skills)]))
        # every OAC: pre h <-> nothing, not o <-> t; effect h <-> o, o <-> t (2 + 2 atoms);
        # execute reach_and_grasp(h, o) or place(h, o), checked against the skill's signature


def oac_texts(spec: Spec) -> dict[str, str]:
    files = {
        "gen/classes.oac": "".join(
            f"class {c} : {spec.parent[c]}\n" if spec.parent[c] else f"class {c}\n" for c in spec.classes
        )
    }
    for start in range(0, len(spec.oacs), OACS_PER_FILE):
        chunk = []
        for name, params, skill in spec.oacs[start : start + OACS_PER_FILE]:
            plist = ", ".join(f"{p}: {c}" for p, c in params)
            chunk.append(
                f"oac {name}({plist}) {{\n"
                f"    pre     h <-> nothing, not o <-> t\n"
                f"    effect  h <-> o, o <-> t\n"
                f"    execute {skill}(h, o)\n}}\n"
            )
        files[f"gen/actions{start // OACS_PER_FILE:02d}.oac"] = "\n".join(chunk)
    return files


def pddl_text(spec: Spec) -> str:
    types = " ".join(f"{c} - {spec.parent[c] or 'Thing'}" for c in spec.classes)
    actions = []
    for name, params, _ in spec.oacs:
        plist = " ".join(f"?{p} - {c}" for p, c in params)
        actions.append(
            f"  (:action {name}\n    :parameters ({plist})\n"
            f"    :precondition (and (free ?h) (not (touching ?o ?t)))\n"
            f"    :effect (and (touching ?h ?o) (touching ?o ?t)))"
        )
    return (
        "(define (domain generated)\n"
        "  (:requirements :strips :typing :negative-preconditions)\n"
        f"  (:types Thing - object {types})\n"
        "  (:predicates (touching ?a - Thing ?b - Thing) (free ?a - Thing))\n" + "\n".join(actions) + ")\n"
    )


def median_time(fn: Callable[[], object], repeat: int, clock: Callable[[], float]) -> float:
    times = []
    for _ in range(repeat):
        start = clock()
        fn()
        times.append(clock() - start)
    return statistics.median(times)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--sizes", type=int, nargs="+", default=[1000, 10000], help="numbers of OACs")
    ap.add_argument("--repeat", type=int, default=5, help="runs per measurement (median)")
    ap.add_argument("--wall", action="store_true", help="wall-clock time instead of CPU time")
    args = ap.parse_args(argv)
    clock = time.perf_counter if args.wall else time.process_time

    from pddl.parser.domain import DomainParser

    lark_parser()  # build our parser once, like the pddl parser below
    pddl_parser = DomainParser()
    print(f"{'wall-clock' if args.wall else 'CPU'} seconds, median of {args.repeat}")
    print(f"{'OACs':>7} {'oacc s':>9} {'pddl s':>9} {'pddl/oacc':>9} {'oacc µs/OAC':>12} {'pddl µs/OAC':>12}")
    for n in args.sizes:
        spec = Spec(n)
        texts, pddl = oac_texts(spec), pddl_text(spec)
        result = compile_sources(texts)
        if not result.ok:
            raise SystemExit("generated library has errors: " + result.errors[0].header())
        domain = pddl_parser(pddl)
        if len(domain.actions) != n or sum(len(m.decls) for m in result.modules) != n + len(spec.classes):
            raise SystemExit("the two renderings differ in size")
        ours = median_time(lambda t=texts: compile_sources(t), args.repeat, clock)
        theirs = median_time(lambda p=pddl: pddl_parser(p), args.repeat, clock)
        per_oac = f"{ours / n * 1e6:>12.1f} {theirs / n * 1e6:>12.1f}"
        print(f"{n:>7} {ours:>9.3f} {theirs:>9.3f} {theirs / ours:>9.2f} {per_oac}", flush=True)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
