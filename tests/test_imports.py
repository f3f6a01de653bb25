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


def _all_of(name: str) -> list[str] | None:
    """The module's ``__all__``, None when it declares none (or needs a robot extra not installed)."""
    try:
        module = importlib.import_module(name)
    except ModuleNotFoundError as error:
        if error.name not in {"mujoco", "placo", "imageio", "imageio_ffmpeg"}:
            raise
        return None
    listed = getattr(module, "__all__", None)
    return None if listed is None else list(listed)


def _from_imports() -> set[tuple[str, str, str]]:
    """(importer, module, name) of every ``from oacdsl.… import name`` of a module's own name
    (not a submodule), at any depth of the importer's syntax tree."""
    modules = _modules()
    found = set()
    for importer, path in modules.items():
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.ImportFrom) and not node.level and node.module in modules:
                found |= {(importer, node.module, a.name) for a in node.names
                          if f"{node.module}.{a.name}" not in modules}
    return found


def test_every_name_in_all_exists_and_is_listed_once():
    for name in _modules():
        listed = None if name == "oacdsl.__main__" else _all_of(name)
        if listed is None:
            continue
        assert len(listed) == len(set(listed)), f"{name}: __all__ lists a name twice"
        missing = [n for n in listed if not hasattr(importlib.import_module(name), n)]
        assert not missing, f"{name}: __all__ names what it lacks: {missing}"


#: Private names imported from another module, in parts other work is changing: to be made public
#: there (each entry must still be one, so that a fixed one leaves this list).
PRIVATE_KNOWN: set[tuple[str, str, str]] = set()


def test_no_module_imports_a_private_name_of_another():
    """A name starting with ``_`` belongs to its module: another module (in its package or not)
    that needs it gets it under a public name, listed in ``__all__``."""
    private = {(i, m, n) for i, m, n in _from_imports() if n.startswith("_") and not n.startswith("__")}
    assert not private - PRIVATE_KNOWN, f"private names imported: {sorted(private - PRIVATE_KNOWN)}"
    assert not PRIVATE_KNOWN - private, f"no longer imported, leave PRIVATE_KNOWN: {PRIVATE_KNOWN - private}"


#: Public names imported from a module whose ``__all__`` leaves them out, in parts other work is
#: changing (as :data:`PRIVATE_KNOWN`).
ALL_KNOWN = {
    ("oacdsl.runtime.skills.base", "REACH_TOLERANCE_M"),
    ("oacdsl.segmentation.grouping", "recognised_note"),
    ("oacdsl.segmentation.readers.limits", "Label"),
    ("oacdsl.segmentation.scales", "instance_size_m"),
    *(("oacdsl.segmentation.synth.dough", n) for n in ("R_CUP_LEFT_HAND", "R_CUP_RIGHT_HAND", "YAW_PI",
                                                        "mix_until_end", "pour_with")),
}


def test_what_other_modules_import_is_in_the_all_of_its_module():
    """``__all__`` is true: a module that declares one lists every name other modules take from it."""
    alls = {m: _all_of(m) for m in _modules() if m != "oacdsl.__main__"}
    left_out = {(m, n) for i, m, n in _from_imports()
                if not n.startswith("_") and alls.get(m) is not None and n not in alls[m]}
    assert not left_out - ALL_KNOWN, f"imported but not in __all__: {sorted(left_out - ALL_KNOWN)}"
    assert not ALL_KNOWN - left_out, f"now in __all__, leave ALL_KNOWN: {ALL_KNOWN - left_out}"
