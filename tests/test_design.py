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
    (tmp_path / "delkit" / "kripke.py").write_text("")
    (tmp_path / "planners" / "lang").mkdir()
    (tmp_path / "planners" / "lang" / "__init__.py").write_text("")
    text = "| `delkit/kripke.py` | models |\n| `planners/lang/` | readers |\n"
    assert missing_and_stale(tmp_path, text) == ([], [])
    (tmp_path / "sim" / "new.py").write_text("")
    assert missing_and_stale(tmp_path, text) == (["sim/new.py"], [])
    (tmp_path / "delkit" / "kripke.py").unlink()
    assert missing_and_stale(tmp_path, text) == (["sim/new.py"], ["delkit/kripke.py"])
