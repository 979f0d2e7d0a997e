"""``delkit smcdel FILE``: answer the queries of an SMCDEL input file on the symbolic backend."""

from __future__ import annotations

import json

import typer


def register(app: typer.Typer) -> None:
    """Attach the ``smcdel`` command to the top-level app."""

    @app.command("smcdel")
    def smcdel(path: str = typer.Argument(..., help="an SMCDEL .smcdel.txt file (VARS, LAW, OBS or delkit's REL "
                                          "extension for belief structures, queries)"),
               max_states: int = typer.Option(100_000, "--max-states", min=1,
                                              help="the most states a WHERE? answer may list"),
               timeout: float = typer.Option(60.0, "--timeout", help="wall-clock limit in seconds from the start "
                                             "of the process (default 60; 0 or inf: none); reaching it is exit "
                                             "status 3"),
               as_json: bool = typer.Option(False, "--json", help="print one JSON object")) -> None:
        """Read SMCDEL's input language and answer its TRUE?/VALID?/WHERE? queries (as SMCDEL would)."""
        from delkit.io.smcdel import check_file
        from delkit.resources import deadline

        with deadline(timeout, f"smcdel {path}"):  # reading, building the structure and every query
            rows = check_file(path, max_states=max_states)
        if as_json:
            typer.echo(json.dumps({"file": path, "queries": rows}))
            return
        for r in rows:
            if r["query"] == "valid":
                typer.echo(f"Is {r['formula']} valid on the given structure?")
                typer.echo(str(r["answer"]))
            elif r["query"] == "true":
                typer.echo(f"Is {r['formula']} true at {json.dumps(r['state']).replace(' ', '')}?")
                typer.echo(str(r["answer"]))
            else:
                typer.echo(f"At which states is {r['formula']} true?")
                for st in r["answer"]:
                    typer.echo(json.dumps(st).replace(" ", ""))
            typer.echo("")
