"""No Python file of the runtime or the pipeline names a class, kind or instance of the
standard library as a string: what an object is comes from the language (its geometry,
its grasp), so a new object needs only a ``.oac`` file (issue 10)."""

import re
from pathlib import Path

from oacdsl.compiler import load_library

ROOT = Path(__file__).resolve().parents[1]
SCANNED = ("oacdsl/runtime", "oacdsl/pipeline")
#: Tables of names still written in Python, by file (none: the kitchen's places and
#: contents are the scene's 'at' and 'in' statements in library/kitchen.oac).
PENDING: dict[str, tuple[str, ...]] = {}
#: Words that are the robot's own (ARMAR-III's links hand_r, hand_l), not the library's.
ROBOT = {"oacdsl/runtime/urdf.py": {"hand"}}


def standard_names() -> set[str]:
    lib = load_library(sorted((ROOT / "library").glob("*.oac")))
    names = set(lib.scenes) | set(lib.oacs) - {"grasp", "place", "pour", "mix", "wipe"}
    for cls in lib.classes:
        names |= {cls, cls.lower()}  # the class and the "kind" the runtime used to call it
    for scene in lib.scenes.values():
        names |= {inst.name for inst in scene.instances}
    return names


def quoted(text: str, names: set[str]) -> list[tuple[int, str]]:
    """(line, name) of every name written as a whole string literal: "cup" or 'cup'."""
    pattern = re.compile(r"""(["'])(""" + "|".join(map(re.escape, sorted(names))) + r""")\1""")
    return [(text.count("\n", 0, m.start()) + 1, m.group(2)) for m in pattern.finditer(text)]


def pending_lines(path: str, text: str) -> set[int]:
    """Lines of the tables listed in PENDING (from ``NAME ... = {`` to the closing brace)."""
    lines = text.splitlines()
    out: set[int] = set()
    for table in PENDING.get(path, ()):
        start = next(i for i, line in enumerate(lines) if re.match(rf"{table}\b.*=", line))
        end = next(i for i in range(start, len(lines)) if "}" in lines[i])
        out |= set(range(start + 1, end + 2))
    return out


def test_the_names_are_the_standard_librarys():
    names = standard_names()
    assert {
        "Cup",
        "cup",
        "orange_bowl",
        "liquid_one",
        "mixer",
        "sponge",
        "tray",
        "Liquid",
        "kitchen",
    } <= names


def test_the_detector_finds_a_quoted_name():
    assert quoted("x = {\"cup\": 1}\nif kind == 'bowl':", {"cup", "bowl"}) == [(1, "cup"), (2, "bowl")]
    assert quoted("a cup, ``bowl``, f'{cup}'", {"cup", "bowl"}) == []


def test_no_standard_library_name_in_the_runtime_or_the_pipeline():
    names = standard_names()
    found = []
    for folder in SCANNED:
        for path in sorted((ROOT / folder).rglob("*.py")):
            rel = path.relative_to(ROOT).as_posix()
            text = path.read_text(encoding="utf-8")
            allowed = pending_lines(rel, text)
            found += [
                f"{rel}:{line}: {name!r}"
                for line, name in quoted(text, names)
                if line not in allowed and name not in ROBOT.get(rel, ())
            ]
    assert not found, "standard-library names in Python:\n" + "\n".join(found)
