"""Fixtures of the viewer's tests: a headless Chromium (one per test module, :mod:`delkit.view.browser`) and
a viewer server in a thread."""

from __future__ import annotations

import pytest


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
