"""Fixtures of the viewer's tests: a headless Chromium (one per test module, :mod:`delkit.view.browser`), a
viewer server in a thread, and a fresh ``delkit epico run`` result (one physics run per session)."""

from __future__ import annotations

import os
import subprocess
import sys
from importlib.util import find_spec
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]


@pytest.fixture(scope="module")
def browser():
    from delkit.view.browser import chromium, why_unavailable

    why = why_unavailable()
    if why:
        pytest.skip(why)
    with chromium() as drv:
        yield drv


@pytest.fixture
def serve():
    """``serve(doc) -> url``: a viewer in a thread, stopped after the test."""
    pytest.importorskip("starlette", reason="delkit view needs starlette (pip install 'delkit[view]')")
    from delkit.view.server import start

    running = []

    def go(doc):
        r = start(doc)
        running.append(r)
        return r.url

    yield go
    for r in running:
        r.stop()


@pytest.fixture(scope="session")
def epico_result(tmp_path_factory) -> Path:
    """``result.json`` of a run made now by ``delkit epico run --goal alpha --colors 1 --out DIR`` (the current
    result schema, whatever it is): about 10 s of simulated arms, once per session."""
    for mod in ("mujoco", "mink"):
        if find_spec(mod) is None:
            pytest.skip(f"{mod} is not installed: an e-PICO run needs pip install 'delkit[arms]'")
    out = tmp_path_factory.mktemp("epico-run")
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([str(ROOT), os.environ.get("PYTHONPATH", "")])}
    r = subprocess.run([sys.executable, "-m", "delkit", "epico", "run", "--goal", "alpha", "--colors", "1",
                        "--out", str(out)], capture_output=True, text=True, env=env, timeout=600)
    assert r.returncode == 0, r.stderr[-2000:]
    return out / "result.json"
