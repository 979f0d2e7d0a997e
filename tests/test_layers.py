"""The layers of docs/design.md: imports only point down (delkit ← planners ← {sim, arms}; sim and arms do
not import each other). Every import statement of every module counts, lazy ones inside functions too."""

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
