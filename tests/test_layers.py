"""The layers of docs/design.md: imports only point down (delkit ← planners ← {sim, arms}; sim and arms do
not import each other), and no module imports itself through others (no import circle). Every import
statement of every module counts: lazy ones inside functions and the ones under ``if TYPE_CHECKING:`` too."""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
PACKAGES = ("delkit", "planners", "sim", "arms")
#: package ↦ the packages it must not import
FORBIDDEN = {"delkit": {"planners", "sim", "arms"}, "planners": {"sim", "arms"}, "sim": {"arms"}, "arms": {"sim"}}


def imported_packages(path: Path) -> list[tuple[int, str]]:
    """(line, top-level package) of every import in the file, wherever it stands."""
    out = []
    for node in ast.walk(ast.parse(path.read_text(), filename=str(path))):
        if isinstance(node, ast.Import):
            out += [(node.lineno, alias.name.split(".")[0]) for alias in node.names]
        elif isinstance(node, ast.ImportFrom) and node.level == 0 and node.module:
            out.append((node.lineno, node.module.split(".")[0]))
        elif isinstance(node, ast.Call) and getattr(node.func, "attr", getattr(node.func, "id", "")) in (
                "import_module", "__import__") and node.args and isinstance(node.args[0], ast.Constant) \
                and isinstance(node.args[0].value, str):
            out.append((node.lineno, node.args[0].value.split(".")[0]))
    return out


def upward_imports(package: str) -> list[str]:
    bad = []
    for path in sorted((ROOT / package).rglob("*.py")):
        for line, top in imported_packages(path):
            if top in FORBIDDEN[package]:
                bad.append(f"{path.relative_to(ROOT)}:{line} imports {top}")
    return bad


@pytest.mark.parametrize("package", PACKAGES)
def test_imports_point_down(package):
    assert upward_imports(package) == []


def test_the_checker_sees_a_lazy_upward_import(tmp_path, monkeypatch):
    (tmp_path / "delkit").mkdir()
    (tmp_path / "delkit" / "x.py").write_text("def f():\n    from planners.task import Task\n    return Task\n")
    monkeypatch.setattr(f"{__name__}.ROOT", tmp_path)
    assert upward_imports("delkit") == ["delkit/x.py:2 imports planners"]


# ------------------------------------------------------------------------------------------ import circles
#: circles being broken elsewhere; each entry is exactly the set of modules of one circle
KNOWN_CIRCLES: list[set[str]] = [
    # planners/epico.py <-> planners/hierarchy.py: allowed until the e-PICO modules are split so that one
    # imports the other only (a circle with any other module in it still fails)
    {"planners.epico", "planners.hierarchy"},
]


def module_files(root: Path) -> dict[str, Path]:
    """Dotted module name ↦ file, for every module of the four packages (a package is its __init__)."""
    out = {}
    for package in PACKAGES:
        for path in sorted((root / package).rglob("*.py")):
            parts = list(path.relative_to(root).with_suffix("").parts)
            if parts[-1] == "__init__":
                parts.pop()
            out[".".join(parts)] = path
    return out


def import_graph(root: Path) -> dict[str, dict[str, int]]:
    """module ↦ {imported module of the four packages ↦ line of the first such import}.

    ``from a.b import c`` is an import of ``a.b.c`` when that is a module, else of ``a.b``; relative imports
    are resolved; an import of ``a.b.c`` where only ``a.b`` is a module counts as ``a.b``. Importing a module
    also runs its packages' ``__init__``, but that is not an edge here: a package re-exporting its
    submodules would otherwise make every submodule that imports a sibling part of a circle."""
    files = module_files(root)

    def known(name: str) -> str | None:
        while name and name not in files:
            name = name.rpartition(".")[0]
        return name or None

    graph: dict[str, dict[str, int]] = {}
    for mod, path in files.items():
        edges = graph.setdefault(mod, {})
        package = mod.split(".") if path.name == "__init__.py" else mod.split(".")[:-1]
        for node in ast.walk(ast.parse(path.read_text(), filename=str(path))):
            targets: list[str] = []
            if isinstance(node, ast.Import):
                targets = [alias.name for alias in node.names]
            elif isinstance(node, ast.ImportFrom):
                base = node.module or ""
                if node.level:
                    up = package[:len(package) - (node.level - 1)]
                    base = ".".join(up + ([node.module] if node.module else []))
                targets = [f"{base}.{a.name}" if f"{base}.{a.name}" in files else base for a in node.names]
            elif isinstance(node, ast.Call) and getattr(node.func, "attr", getattr(node.func, "id", "")) in (
                    "import_module", "__import__") and node.args and isinstance(node.args[0], ast.Constant) \
                    and isinstance(node.args[0].value, str):
                targets = [node.args[0].value]
            for target in targets:
                hit = known(target)
                if hit is not None and hit != mod:
                    edges.setdefault(hit, node.lineno)
    return graph


def circles(graph: dict[str, dict[str, int]]) -> list[list[str]]:
    """The import circles: strongly connected components of more than one module (Tarjan), each sorted."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on_stack: set[str] = set()
    out: list[list[str]] = []

    def visit(v: str) -> None:  # recursion depth = length of an import chain: a few dozen at most
        index[v] = low[v] = len(index)
        stack.append(v)
        on_stack.add(v)
        for w in graph.get(v, {}):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on_stack:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on_stack.discard(w)
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1:
                out.append(sorted(comp))

    for v in sorted(graph):
        if v not in index:
            visit(v)
    return sorted(out)


def describe(graph: dict[str, dict[str, int]], circle: list[str]) -> str:
    inside = set(circle)
    return "; ".join(f"{m} -> {t} (line {line})" for m in circle for t, line in sorted(graph[m].items())
                     if t in inside)


def test_no_import_circle():
    graph = import_graph(ROOT)
    found = [c for c in circles(graph) if set(c) not in KNOWN_CIRCLES]
    assert found == [], "\n".join(describe(graph, c) for c in found)


def test_the_circle_finder_sees_lazy_relative_and_type_checking_imports(tmp_path, monkeypatch):
    pkg = tmp_path / "delkit"
    (pkg / "sub").mkdir(parents=True)
    (pkg / "__init__.py").write_text("")
    (pkg / "a.py").write_text("def f():\n    from delkit.b import g\n    return g\n")
    (pkg / "b.py").write_text("from typing import TYPE_CHECKING\nif TYPE_CHECKING:\n    from delkit.sub import c\n")
    (pkg / "sub" / "__init__.py").write_text("")
    (pkg / "sub" / "c.py").write_text("from .. import a\n")
    (pkg / "d.py").write_text("import delkit.a\n")  # imports into the circle but is not part of it
    monkeypatch.setattr(f"{__name__}.PACKAGES", ("delkit",))
    graph = import_graph(tmp_path)
    assert circles(graph) == [["delkit.a", "delkit.b", "delkit.sub.c"]]
    (pkg / "a.py").write_text("")
    assert circles(import_graph(tmp_path)) == []


# ------------------------------------------------------------------------------ parts inside delkit
#: delkit's parts, lowest first: a module may import its own part and lower ones. A part is the sub-package
#: (``delkit/models/``) or, for a module directly inside delkit/, the module itself.
DELKIT_RANKS: dict[str, float] = {
    "errors": 0, "_lazy": 0, "_records": 0, "paths": 0.5, "resources": 1, "progress": 1, "executors": 1,
    "logic": 2, "drawing": 3, "models": 4, "backends": 5, "io": 6, "verify": 7, "testing": 7,
    "puzzles": 8, "demo": 9, "view": 10, "cli": 11, "__main__": 12,
}
#: the upward imports allowed, each (importer, imported module) with its reason
KNOWN_UPWARD: dict[tuple[str, str], str] = {
    # the symbolic muddy children run the explicit puzzle's protocol (delkit.puzzles.muddy) on BDDs
    ("delkit.backends.symbolic", "delkit.puzzles.muddy"): "one protocol for both engines",
    # the viewer lists the viewers the installed plugins register (delkit.cli.plugins loads them)
    ("delkit.view.document", "delkit.cli.plugins"): "the plugin registry lives with the command",
}


def delkit_part(module: str) -> str | None:
    parts = module.split(".")
    return None if parts[0] != "delkit" or len(parts) == 1 else parts[1]


def upward_inside_delkit(root: Path) -> list[str]:
    graph = import_graph(root)
    bad = []
    for mod, edges in sorted(graph.items()):
        part = delkit_part(mod)
        if part is None:
            continue
        if part not in DELKIT_RANKS:
            bad.append(f"{mod}: not in a part of delkit (add it to DELKIT_RANKS and to docs/design.md)")
            continue
        for target, line in sorted(edges.items()):
            other = delkit_part(target)
            if other is None or other == part or (mod, target) in KNOWN_UPWARD:
                continue
            if DELKIT_RANKS.get(other, 99) >= DELKIT_RANKS[part]:
                bad.append(f"{mod} (line {line}) imports {target}: {part} may not import {other}")
    return bad


def test_parts_inside_delkit_import_only_lower_parts():
    assert upward_inside_delkit(ROOT) == []


def test_the_part_check_sees_an_upward_import_and_an_unplaced_module(tmp_path, monkeypatch):
    for sub in ("logic", "models"):
        (tmp_path / "delkit" / sub).mkdir(parents=True)
        (tmp_path / "delkit" / sub / "__init__.py").write_text("")
    (tmp_path / "delkit" / "__init__.py").write_text("")
    (tmp_path / "delkit" / "models" / "m.py").write_text("from delkit.logic import f\n")
    (tmp_path / "delkit" / "logic" / "f.py").write_text("def g():\n    from delkit.models.m import x\n")
    monkeypatch.setattr(f"{__name__}.PACKAGES", ("delkit",))
    assert upward_inside_delkit(tmp_path) == [
        "delkit.logic.f (line 2) imports delkit.models.m: logic may not import models"]
    (tmp_path / "delkit" / "stray.py").write_text("")
    assert "delkit.stray: not in a part of delkit (add it to DELKIT_RANKS and to docs/design.md)" in \
        upward_inside_delkit(tmp_path)
