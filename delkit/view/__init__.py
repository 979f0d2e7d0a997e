"""``delkit view``: an explorer for models, plans and missions in the browser, and a stepper for notebooks.

* :mod:`delkit.view.document` — what is shown (:class:`Document` of :class:`Frame` s of graph panels), the
  viewers that build documents from files (the core's, and the layers' through ``VIEWERS``), and the one JSON
  API's semantics (:func:`evaluate`, :func:`possible`: every truth value computed by delkit in Python);
* :mod:`delkit.view.server` — the local web server (Starlette + uvicorn, 127.0.0.1, a random token, capped
  bodies and models);
* :mod:`delkit.view.notebook` — :class:`Stepper`, a self-contained HTML widget of precomputed frames for
  Jupyter (no server).

The page draws with cytoscape.js, shipped in ``delkit/view/static`` with its licence (nothing fetched at
run time).
"""

from __future__ import annotations

from delkit.view.document import (
    Document,
    Frame,
    Panel,
    evaluate,
    graph_json,
    load_document,
    possible,
    register_viewer,
    viewers,
)
from delkit.view.notebook import Stepper

__all__ = ["Document", "Frame", "Panel", "evaluate", "graph_json", "load_document", "possible", "register_viewer",
           "viewers", "Stepper"]

