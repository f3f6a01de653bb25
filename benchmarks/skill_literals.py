"""Numeric literals in the runtime's skills: how much tuning each skill carries by itself.

    python benchmarks/skill_literals.py [--per-file] [DIR]

The rule (issue 19): every numeric literal in the Python source of ``DIR`` (default
``oacdsl/runtime/skills/``), found by parsing it (``ast``): an ``int``, ``float`` or
``complex`` constant, wherever it stands (a module constant, a default, an expression, an
f-string's arithmetic), except

- the neutral values ``0`` and ``1`` (``0.0``, ``1.0``; so ``-1`` too, whose literal is ``1``):
  ``max(0, …)``, unit vectors and ``1 - s`` are not tuning;
- indices: a literal inside a subscript's brackets (``t[:3, 3]``, ``t[2, 3]``, ``d["radius"]``):
  which element of a 4×4 transform is read is not tuning (it would otherwise be half the count);
- booleans (``True``/``False`` are constants, not numbers).

Docstrings and comments hold no numeric literals (text). Everything else counts: ``0.5``,
``2``, ``100`` (a conversion to centimetres in a message) and ``math.radians(15.0)`` alike,
so that a tuning value cannot hide by being written differently. Printed: the total, and
with ``--per-file`` the count per file. ``tests/test_skill_literals.py`` keeps the total
under a ceiling.
"""

from __future__ import annotations

import argparse
import ast
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
SKILLS = ROOT / "oacdsl" / "runtime" / "skills"

__all__ = ["count_file", "count_tree", "NEUTRAL"]

#: Values that are not counted (see the module docstring).
NEUTRAL = (0, 1)


def _is_counted(node: ast.AST) -> bool:
    if not isinstance(node, ast.Constant) or isinstance(node.value, bool):
        return False
    if not isinstance(node.value, (int, float, complex)):
        return False
    return node.value not in NEUTRAL


def count_file(path: Path) -> int:
    """Numeric literals of ``path`` by the module docstring's rule."""
    tree = ast.parse(path.read_text(encoding="utf-8"), filename=str(path))
    indices = {id(n) for sub in ast.walk(tree) if isinstance(sub, ast.Subscript) for n in ast.walk(sub.slice)}
    return sum(1 for node in ast.walk(tree) if _is_counted(node) and id(node) not in indices)


def count_tree(folder: Path = SKILLS) -> dict[str, int]:
    """File name (relative to ``folder``) → its count, every ``*.py`` below ``folder``."""
    return {str(p.relative_to(folder)): count_file(p) for p in sorted(folder.rglob("*.py"))}


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("folder", nargs="?", type=Path, default=SKILLS)
    parser.add_argument("--per-file", action="store_true", help="also print the count per file")
    args = parser.parse_args(argv)
    if not args.folder.is_dir():
        print(f"skill_literals: error: {args.folder}: not a folder", file=sys.stderr)
        return 2
    counts = count_tree(args.folder)
    if args.per_file:
        for name, n in sorted(counts.items(), key=lambda kv: -kv[1]):
            print(f"{n:5d}  {name}")
    print(f"{sum(counts.values())} numeric literals in {len(counts)} files of {args.folder}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
