"""Top-level commands owned by the core: ``delkit demo`` and ``delkit version``.

``delkit demo`` runs the main job of every part end to end, each section timed: the DEL puzzles with
their literature answers, epistemic planning + plan checking, action consistency, a communication-
restricted exploration mission, and the two Franka arms executing a plan. A section whose optional
runtime piece (e.g. an OpenGL context for pictures) is missing says so and the rest goes on; a section
that *fails* makes the demo exit with status 1.
"""

from __future__ import annotations

import json
import time
from pathlib import Path
from typing import Any

import typer


def run_demo(out: Path, only: list[str] | None = None) -> list[dict[str, Any]]:
    """Run the demo sections; returns one record per section (title, ok, seconds, result)."""
    from rich.console import Console

    from delkit.cli.plugins import demo_sections
    from delkit.errors import DelkitError, MissingExtraError

    sections = [(title, fn) for _, title, fn in demo_sections()]
    if any(not o.strip() for o in only or ()):  # '' is in every title: it would run everything
        raise DelkitError("--only needs a word of a section title, e.g. --only puzzles; it was empty")
    unmatched = [o for o in only or () if not any(o.lower() in title.lower() for title, _ in sections)]
    if unmatched:  # a typo would otherwise run nothing and report success
        raise DelkitError(f"--only {unmatched[0]!r} matches no demo section; sections: "
                          f"{'; '.join(title for title, _ in sections)}")
    try:
        out.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise DelkitError(f"{out}: cannot create the output directory ({exc.strerror}); give a writable "
                          f"--out directory") from None
    console = Console(stderr=True)
    records: list[dict[str, Any]] = []
    for title, fn in sections:
        if only and not any(o.lower() in title.lower() for o in only):
            continue
        console.rule(f"[bold]{title}")
        t0 = time.perf_counter()
        try:
            result = fn(out)
        except MissingExtraError as exc:  # a layer whose extra is not installed (a light install): skipped, said
            result = {"ok": None, "summary": f"skipped: {exc}"}
        ok = result.get("ok", True) if isinstance(result, dict) else True
        ok = None if ok is None else bool(ok)
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
            table.add_column("seconds", justify="right")
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
