"""The explorer's HTTP fuzz (bench/fuzz_http.py) finds nothing: no 500, traceback, hang or leaked byte."""

from __future__ import annotations

import importlib.util
from pathlib import Path

import pytest

pytest.importorskip("starlette", reason="delkit view needs starlette (pip install 'delkit[view]')")
pytest.importorskip("uvicorn", reason="delkit view needs uvicorn (pip install 'delkit[view]')")

_spec = importlib.util.spec_from_file_location("fuzz_http", Path(__file__).resolve().parents[2] / "bench" /
                                               "fuzz_http.py")
fuzz_http = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(fuzz_http)


def test_a_sample_of_every_request_family_finds_nothing():
    rows = fuzz_http.run_all(scale=0.05, seed=1, only=["traversal", "encodings", "json-numbers", "cross-origin"])
    assert all(r["inputs"] > 0 for r in rows) and len(rows) == 4
    assert [f for r in rows for f in r["failures"]] == []


@pytest.mark.slow
def test_every_family_finds_nothing():
    rows = fuzz_http.run_all(scale=1.0, seed=0)
    assert {r["family"] for r in rows} == set(fuzz_http.families())
    assert sum(r["inputs"] for r in rows) >= 1000
    assert [f for r in rows for f in r["failures"]] == []
