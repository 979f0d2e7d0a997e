"""The planning layer's commands: ``delkit plan``, ``check``, ``convert`` and ``delkit epico`` (generate, solve,
macros, table; ``epico run`` is added by the arms layer). Registered through the ``delkit.commands`` entry
point ``planners``; ``plan`` and ``check`` also have a typer-free fast path (``delkit.fast``)."""

from __future__ import annotations

from pathlib import Path

from planners.cli.plan_cmd import fast_args

TYPE_CHECKING = False  # typing.TYPE_CHECKING without importing typing (start-up: delkit._records)
if TYPE_CHECKING:
    from typing import Any

__all__ = ["register", "fast_args", "DEMO_SECTIONS", "VIEWERS", "PUZZLES"]


def register(app: Any) -> None:
    """Attach the planning layer's commands to the top-level app."""
    from planners.cli import epico_cmd, plan_cmd, puzzle_cmd

    plan_cmd.register(app)
    epico_cmd.register(app)
    puzzle_cmd.register(app)


#: rows of ``delkit puzzle --list`` for the puzzles this layer adds (delkit.cli.plugins.plugin_puzzles)
PUZZLES = [
    {"command": "muddy-plan", "answer": "the planner's shortest plan: father, then M-1 rounds of 'nobody knows'",
     "backends": ["explicit (planner)"], "source": "Fagin, Halpern, Moses, Vardi 1995, sec. 1.1; SMCDEL's "
     "MuddyPlanning", "docs": "docs/puzzles.md#muddy-children-planning"},
]


def _planner(out: Path) -> dict[str, Any]:
    from planners.demo import run_demo as planner_demo

    return planner_demo(out)


def _epico(out: Path) -> dict[str, Any]:
    from planners.hierarchy import run_demo as epico_demo

    return epico_demo(out)


DEMO_SECTIONS = [
    (30, "Epistemic planning + plan check", _planner),
    (70, "e-PICO: epistemic plan to primitive arm actions", _epico),
]


def _task_viewer(paths: Any, options: dict) -> Any:
    from planners.view import task_viewer

    return task_viewer(paths, options)


def _epico_viewer(paths: Any, options: dict) -> Any:
    from planners.view import epico_viewer

    return epico_viewer(paths, options)


#: documents for ``delkit view`` (delkit.view.document.viewers): tasks with plans, e-PICO results
VIEWERS = (_task_viewer, _epico_viewer)
