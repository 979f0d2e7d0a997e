"""`make docs`: the API reference is generated from the docstrings (pdoc) without a warning."""

from __future__ import annotations

import importlib.util
import sys
from pathlib import Path

import pytest

pytest.importorskip("pdoc")
ROOT = Path(__file__).resolve().parents[1]


def _api():
    spec = importlib.util.spec_from_file_location("delkit_docs_api", ROOT / "docs" / "api.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_the_core_reference_builds_without_warnings(tmp_path):
    problems = _api().build(tmp_path, ("delkit",))
    assert problems == []
    page = (tmp_path / "delkit" / "models" / "kripke.html").read_text(encoding="utf-8")
    assert "KripkeModel" in page and "product" in page  # a module of the core, documented from its docstrings
    assert (tmp_path / "delkit" / "cli" / "plugins.html").exists()


def test_a_warning_fails_the_build(tmp_path, monkeypatch):
    pkg = tmp_path / "src" / "noisy"
    pkg.mkdir(parents=True)
    (pkg / "__init__.py").write_text('"""A package."""\n')
    (pkg / "loud.py").write_text('"""Warns on import."""\nimport warnings\nwarnings.warn("something is off")\n')
    monkeypatch.syspath_prepend(str(tmp_path / "src"))
    problems = _api().build(tmp_path / "out", ("noisy",))
    assert problems == ["UserWarning: something is off"]
    sys.modules.pop("noisy.loud", None)
    sys.modules.pop("noisy", None)


@pytest.mark.slow
def test_the_whole_reference_builds_without_warnings(tmp_path):
    assert _api().main(["--out", str(tmp_path)]) == 0
    assert len(list(tmp_path.rglob("*.html"))) > 80
