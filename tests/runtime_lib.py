"""The library the runtime tests execute: the standard library (``library/``) plus the
test scenes and composed OACs of ``tests/data/runtime_tasks.oac`` (the paper's dough OAC,
one-skill tasks, small scenes), loaded with the parser."""

from functools import lru_cache
from pathlib import Path

from oacdsl.compiler import load_library
from oacdsl.model import Instance

ROOT = Path(__file__).resolve().parents[1]
TASKS = ROOT / "tests" / "data" / "runtime_tasks.oac"
#: The hand-written standard library: the top-level files of ``library/`` (``learned/`` holds
#: what ``oacc reproduce``/``oacc compose`` wrote, e.g. a composed ``dough`` like the one in TASKS).
STANDARD = tuple(sorted((ROOT / "library").glob("*.oac")))


@lru_cache(maxsize=1)
def task_library():
    return load_library([*STANDARD, TASKS])


def inst(name, *classes, environment=False):
    return Instance(name=name, classes=classes, environment=environment)
