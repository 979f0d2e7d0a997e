"""``delkit puzzle muddy-plan``: muddy children as an epistemic planning task (:mod:`planners.puzzles`).

Added to the core's ``puzzle`` group (:func:`delkit.cli.plugins.group`); its row of ``delkit puzzle --list``
is :data:`planners.cli.PUZZLES`."""

from __future__ import annotations

from typing import Any

import typer


def register(app: Any) -> None:
    from delkit.cli.plugins import group

    sub = group(app, "puzzle", "Epistemic puzzles solved with DEL (literature answers).")

    @sub.command("muddy-plan")
    def muddy_plan(children: int = typer.Option(3, "--children", "-n", help="number of children N (1..10)"),
                   muddy: int = typer.Option(2, "--muddy", "-m", help="number of muddy children M (1..N)"),
                   search: str = typer.Option("bfs", "--search", help="bfs, astar or gbfs"),
                   individual: bool = typer.Option(False, "--individual", help="also offer each child's own "
                                                   "'I don't know' (SMCDEL's MuddyPlanning actions)"),
                   timeout: float = typer.Option(60.0, "--timeout", min=0.0, help="search limit in seconds"),
                   as_json: bool = typer.Option(False, "--json", help="print one JSON object")) -> None:
        """Muddy children planning: the planner finds 'father', then M-1 rounds of 'nobody knows'."""
        from delkit.cli.puzzle_cmd import _emit
        from delkit.errors import ModelError
        from planners.puzzles import solve_muddy_plan

        if search not in ("bfs", "astar", "gbfs"):
            raise ModelError(f"puzzle muddy-plan: --search must be bfs, astar or gbfs, got {search!r}")
        res = solve_muddy_plan(children, muddy, search=search, individual=individual,  # type: ignore[arg-type]
                               timeout=timeout or None)
        data = res.as_dict() | {"timed": "wall seconds of the search (planners.epistemic.plan)"}
        _emit(data, as_json, f"muddy children planning N={children}, M={muddy}")
        if not res.result.solved:
            raise typer.Exit(1)
