"""Top-level commands owned by the core: ``delkit demo`` and ``delkit version``.

``delkit demo`` runs the main job of every part end to end, each section timed: the DEL puzzles with
their literature answers, epistemic planning + plan checking, action consistency, a communication-
restricted exploration mission, and the two Franka arms executing a plan. A section whose optional
runtime piece (e.g. an OpenGL context for pictures) is missing says so and the rest goes on; a section
that *fails* makes the demo exit with status 1.
"""

from __future__ import annotations

import importlib
import json
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

import typer

SECTIONS: list[tuple[str, str, str]] = [
    # (title, module, function)  — each function takes the output directory and returns a dict
    ("DEL puzzles (literature answers)", "delkit.puzzles", "demo_section"),
    ("Epistemic planning + plan check", "planners.demo", "run_demo"),
    ("Action consistency (VERIFYAC/ENFORCEAC)", "planners.consistency_demo", "run_demo"),
    ("Exploration with epistemic task allocation", "sim.demo", "run_demo"),
    ("Two Franka Pandas execute a plan", "arms.demo", "run_demo"),
]


def _load(module: str, func: str) -> Callable[[Path], dict[str, Any]] | None:
    try:
        mod = importlib.import_module(module)
    except ModuleNotFoundError as exc:
        if exc.name and module.startswith(exc.name):
            return None
        raise
    return getattr(mod, func, None)


def run_demo(out: Path, only: list[str] | None = None) -> list[dict[str, Any]]:
    """Run the demo sections; returns one record per section (title, ok, seconds, result)."""
    from rich.console import Console

    console = Console(stderr=True)
    out.mkdir(parents=True, exist_ok=True)
    records: list[dict[str, Any]] = []
    for title, module, func in SECTIONS:
        if only and not any(o.lower() in title.lower() or o.lower() in module for o in only):
            continue
        fn = _load(module, func)
        if fn is None:
            records.append({"section": title, "ok": None, "seconds": 0.0, "result": "not installed"})
            continue
        console.rule(f"[bold]{title}")
        t0 = time.perf_counter()
        result = fn(out)
        ok = bool(result.get("ok", True)) if isinstance(result, dict) else True
        records.append({"section": title, "ok": ok, "seconds": round(time.perf_counter() - t0, 2),
                        "result": result})
    return records


def register(app: typer.Typer) -> None:
    """Attach this module's commands to the top-level app."""

    @app.command()
    def version() -> None:
        """Print the delkit version."""
        from delkit import __version__

        typer.echo(__version__)

    @app.command()
    def demo(
        out: Path = typer.Option(Path("out/demo"), "--out", help="Directory for pictures and JSON results."),
        only: list[str] = typer.Option(None, "--only", help="Run only sections whose title contains this."),
        as_json: bool = typer.Option(False, "--json", help="Print the results as one JSON object."),
    ) -> None:
        """Run the main job of every part of delkit end to end and print what each part showed."""
        from rich.console import Console
        from rich.table import Table

        records = run_demo(out, only)
        (out / "demo.json").write_text(json.dumps(records, indent=2, default=str))
        failed = [r for r in records if r["ok"] is False]
        if as_json:
            typer.echo(json.dumps({"ok": not failed, "sections": records}, default=str))
        else:
            table = Table(title="delkit demo", show_lines=True)
            table.add_column("section")
            table.add_column("ok")
            table.add_column("s", justify="right")
            table.add_column("what it showed")
            for r in records:
                mark = {True: "[green]yes", False: "[red]NO", None: "[yellow]skipped"}[r["ok"]]
                res = r["result"]
                text = res.get("summary", "") if isinstance(res, dict) else str(res)
                table.add_row(r["section"], mark, f"{r['seconds']:.1f}", text)
            Console().print(table)
            typer.echo(f"results: {out / 'demo.json'}")
        if failed:
            raise typer.Exit(1)
