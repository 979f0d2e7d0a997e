"""docs/design.md is true of the code: every module path it names exists, and every module directly inside
the four packages (``pkg/name.py`` and sub-packages ``pkg/sub/``) is in its module map."""

from __future__ import annotations

import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
DESIGN = ROOT / "docs" / "design.md"
PACKAGES = ("delkit", "planners", "sim", "arms")
_PATH = re.compile(r"`((?:delkit|planners|sim|arms)/[A-Za-z0-9_/]*(?:\.py|/))`")


def named_paths(text: str) -> set[str]:
    """Every ``pkg/…py`` or ``pkg/sub/`` written in backticks; a table cell's ``(`a.py`, `b.py`)`` after a
    sub-package such as ``planners/lang/`` names files inside it."""
    return set(_PATH.findall(text))


def top_level_modules(root: Path) -> set[str]:
    out = set()
    for package in PACKAGES:
        for path in (root / package).iterdir():
            if path.suffix == ".py" and path.name != "__init__.py":
                out.add(f"{package}/{path.name}")
            elif path.is_dir() and (path / "__init__.py").exists():
                out.add(f"{package}/{path.name}/")
    return out


def missing_and_stale(root: Path, text: str) -> tuple[list[str], list[str]]:
    named = named_paths(text)
    stale = sorted(p for p in named if not (root / p).exists())
    missing = sorted(top_level_modules(root) - named)
    return missing, stale


def test_design_lists_every_module_and_only_modules_that_exist():
    missing, stale = missing_and_stale(ROOT, DESIGN.read_text(encoding="utf-8"))
    assert stale == [], f"docs/design.md names modules that do not exist: {stale}"
    assert missing == [], f"modules missing from the module map of docs/design.md: {missing}"


def test_the_check_sees_a_new_module_and_a_removed_one(tmp_path):
    for package in PACKAGES:
        (tmp_path / package).mkdir()
        (tmp_path / package / "__init__.py").write_text("")
    (tmp_path / "delkit" / "thing.py").write_text("")
    (tmp_path / "planners" / "lang").mkdir()
    (tmp_path / "planners" / "lang" / "__init__.py").write_text("")
    text = "| `delkit/thing.py` | models |\n| `planners/lang/` | readers |\n"
    assert missing_and_stale(tmp_path, text) == ([], [])
    (tmp_path / "sim" / "new.py").write_text("")
    assert missing_and_stale(tmp_path, text) == (["sim/new.py"], [])
    (tmp_path / "delkit" / "thing.py").unlink()
    assert missing_and_stale(tmp_path, text) == (["sim/new.py"], ["delkit/thing.py"])


# ------------------------------------------------------------------- modules of delkit's sub-packages
#: delkit's sub-packages whose every module the module map lists one by one
DETAILED = ("delkit/logic", "delkit/drawing", "delkit/models", "delkit/backends", "delkit/io")


def detailed_modules(root: Path) -> set[str]:
    return {p.relative_to(root).as_posix() for d in DETAILED if (root / d).is_dir()
            for p in (root / d).glob("*.py") if p.name != "__init__.py"}


def test_design_lists_every_module_of_the_sub_packages():
    missing = sorted(detailed_modules(ROOT) - named_paths(DESIGN.read_text(encoding="utf-8")))
    assert missing == [], f"modules missing from the module map of docs/design.md: {missing}"


def test_the_sub_package_check_sees_a_new_module(tmp_path):
    (tmp_path / "delkit" / "models").mkdir(parents=True)
    (tmp_path / "delkit" / "models" / "relation.py").write_text("")
    text = "| `delkit/models/relation.py` | relations |"
    assert detailed_modules(tmp_path) == {"delkit/models/relation.py"}
    assert not detailed_modules(tmp_path) - named_paths(text)
    (tmp_path / "delkit" / "models" / "new.py").write_text("")
    assert detailed_modules(tmp_path) - named_paths(text) == {"delkit/models/new.py"}
