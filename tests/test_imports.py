"""The package's import graph: acyclic, and the command line is a leaf layer.

Every module of ``oacdsl`` is read with :mod:`ast`; every import it makes,
at the top or inside a function, is an edge. ``from a.b import c`` is an edge
to ``a.b.c`` when that is a module, else to ``a.b``; importing a module also
runs the ``__init__`` of each package above it, so those packages are edges
too (except the importer's own packages, which are already running).
"""

from __future__ import annotations

import ast
import importlib
from pathlib import Path

import networkx as nx

import oacdsl

PACKAGE = Path(oacdsl.__file__).resolve().parent


def _modules() -> dict[str, Path]:
    out = {}
    for path in sorted(PACKAGE.rglob("*.py")):
        parts = list(path.relative_to(PACKAGE.parent).with_suffix("").parts)
        if parts[-1] == "__init__":
            parts.pop()
        out[".".join(parts)] = path
    return out


def _imported(name: str, path: Path) -> set[str]:
    """Every name ``name`` imports (absolute), from any depth of its syntax tree."""
    package = name if path.name == "__init__.py" else name.rpartition(".")[0]
    found: set[str] = set()
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"), str(path))):
        if isinstance(node, ast.Import):
            found.update(alias.name for alias in node.names)
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = package.split(".")[: len(package.split(".")) - node.level + 1]
                source = ".".join([*base, node.module] if node.module else base)
            else:
                source = node.module or ""
            found.add(source)
            found.update(f"{source}.{alias.name}" for alias in node.names)
    return found


def import_graph() -> nx.DiGraph:
    modules = _modules()
    graph = nx.DiGraph()
    graph.add_nodes_from(modules)
    for name, path in modules.items():
        own = {".".join(name.split(".")[:i]) for i in range(1, name.count(".") + 2)}
        for target in _imported(name, path):
            if target not in modules:
                continue
            parts = target.split(".")
            for i in range(1, len(parts) + 1):
                ancestor = ".".join(parts[:i])
                if ancestor in modules and ancestor not in own:
                    graph.add_edge(name, ancestor)
    return graph


def test_the_graph_sees_imports_inside_functions():
    graph = import_graph()
    # e.g. cli/run_cmd.py imports the runtime inside a function: the walk must see such imports
    assert len(graph) > 100 and graph.number_of_edges() > len(graph)
    inner = [
        (name, target)
        for name, path in _modules().items()
        for fn in ast.walk(ast.parse(path.read_text(encoding="utf-8")))
        if isinstance(fn, ast.FunctionDef)
        for node in ast.walk(fn)
        if isinstance(node, ast.ImportFrom) and (target := node.module or "") in graph
        and not name.startswith(target + ".")  # its own packages are already running
    ]
    assert inner and all(graph.has_edge(name, target) for name, target in inner)


def test_the_import_graph_of_oacdsl_is_acyclic():
    graph = import_graph()
    cycles = [sorted(c) for c in nx.strongly_connected_components(graph) if len(c) > 1]
    cycles += [[n] for n in graph if graph.has_edge(n, n)]
    assert not cycles, f"import cycles: {cycles}"


def test_only_the_command_line_imports_the_command_line():
    graph = import_graph()
    outside = sorted(
        (name, target)
        for name, target in graph.edges
        if target.split(".")[:2] == ["oacdsl", "cli"] and name.split(".")[:2] != ["oacdsl", "cli"]
        and name != "oacdsl.__main__"
    )
    assert not outside, f"modules outside oacdsl/cli import it: {outside}"


def test_every_module_imports_on_its_own():
    """The graph is of real modules: each one imports (robot extras allowed to be absent)."""
    for name in _modules():
        if name == "oacdsl.__main__":  # runs the command line when imported
            continue
        try:
            importlib.import_module(name)
        except ModuleNotFoundError as error:
            if error.name not in {"mujoco", "placo", "imageio", "imageio_ffmpeg"}:
                raise
