"""``delkit view FILE [FILE...]``: open a model, structure, task with a plan, or e-PICO result in the browser.

The files are read once, at start-up, by the first viewer that recognises them (:mod:`delkit.view.document`:
the core reads models and structures; the planning layer registers tasks with plans and e-PICO results).
"""

from __future__ import annotations

import sys
from pathlib import Path

import typer

__all__ = ["register"]


def register(app: typer.Typer) -> None:
    """Attach ``delkit view``."""

    @app.command("view")
    def view_cmd(
        files: list[Path] = typer.Argument(..., metavar="FILE [PLAN]",
                                           help="model (.json/.dot), structure (.smcdel.txt), task (mA*, E-PDDL "
                                                "DOMAIN PROBLEM, EPDDL) with an optional plan, or e-PICO "
                                                "result.json"),
        port: int = typer.Option(0, "--port", min=0, max=65535, help="port on 127.0.0.1 (0: a free one)"),
        no_browser: bool = typer.Option(False, "--no-browser", help="print the URL, do not open a browser"),
        max_worlds: int = typer.Option(512, "--max-worlds", min=1, max=5000,
                                       help="draw a structure's Kripke model up to this many states"),
        library: list[Path] = typer.Option([], "--library", "-l", help="EPDDL action-type library (repeatable)"),
    ) -> None:
        """Explore a model, a plan's states or a mission's beliefs in the browser (127.0.0.1, token URL)."""
        from delkit.cli.plugins import require_extra

        require_extra("view", "starlette", "uvicorn", what="delkit view")
        from delkit.view.document import load_document
        from delkit.view.server import serve

        doc = load_document(files, max_worlds=max_worlds, library=list(library))
        try:
            serve(doc, port=port, open_browser=not no_browser, echo=lambda s: print(s, file=sys.stderr, flush=True))
        except KeyboardInterrupt:
            print("delkit view: stopped", file=sys.stderr)
