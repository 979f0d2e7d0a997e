"""``delkit plan`` (epistemic planning on mA* / E-PDDL specs) and ``delkit check`` (plan + property checker).

Exit statuses: ``plan`` — 0 plan found, 1 no plan exists (state space exhausted), 3 no plan within the
limits; ``check`` — 0 valid, 1 invalid; both — 2 bad input. A failure is never printed as an empty plan.
Heavy imports stay inside the commands.
"""

from __future__ import annotations

import json
from pathlib import Path

import typer


def register(app: typer.Typer) -> None:
    """Attach ``plan`` and ``check`` to the top-level app."""

    @app.command("plan")
    def plan_command(
        spec: Path = typer.Argument(..., help="mA* file, or E-PDDL domain file"),
        problem: Path | None = typer.Argument(None, help="E-PDDL problem file (with an E-PDDL domain)"),
        search: str = typer.Option("bfs", "--search", help="bfs (optimal), gbfs or astar"),
        timeout: float = typer.Option(60.0, "--timeout", help="wall-clock limit in seconds"),
        max_nodes: int | None = typer.Option(None, "--max-nodes", help="limit on expanded nodes"),
        max_memory: float = typer.Option(8192.0, "--max-memory", help="resident memory limit in MiB"),
        engine: str = typer.Option("fast", "--engine", help="fast (specialised states) or del (generic delkit)"),
        allow_inconsistent: bool = typer.Option(False, "--allow-inconsistent",
                                                help="expand states where an agent believes ⊥"),
        as_json: bool = typer.Option(False, "--json", help="print one JSON object"),
    ) -> None:
        """Find a plan (BFS: of minimal length) for an mA* or E-PDDL problem."""
        import time

        from delkit.errors import PlanningError
        from delkit.resources import ResourceError, deadline
        from planners.epistemic import Limits, SearchResult, plan
        from planners.lang import load_task

        if search not in ("bfs", "gbfs", "astar"):
            raise PlanningError(f"--search {search!r}: use bfs, gbfs or astar")
        Limits(timeout=timeout, max_expanded=max_nodes, max_memory_mb=max_memory)  # refuse bad limits before work
        t0 = time.monotonic()
        name = str(spec)
        try:
            # --timeout covers every phase: reading, grounding and the initial state too, not only the search
            with deadline(timeout, "reading, grounding and building the initial state"):
                task = load_task(spec, problem)
            name = task.name
            left = timeout - (time.monotonic() - t0)
            if left <= 0:
                raise ResourceError("the time limit ran out while building the initial state")
            # the search checks its own limit; the deadline (a little later) is the backstop for every other phase
            with deadline(left + 2.0, "building the search space or searching"):
                res = plan(task, search=search, engine=engine,  # type: ignore[arg-type]
                           limits=Limits(timeout=left, max_expanded=max_nodes, max_memory_mb=max_memory),
                           allow_inconsistent=allow_inconsistent)
        except ResourceError as exc:
            if "--timeout" not in str(exc) and "time limit" not in str(exc):
                raise
            res = SearchResult("limit", None, 0, 0, time.monotonic() - t0, search,
                               reason=f"--timeout {timeout:g} s reached: {exc}")
        out = res.to_json()
        out["task"] = name
        if as_json:
            typer.echo(json.dumps(out))
        else:
            if res.solved:
                typer.echo(f"plan of length {res.length} ({search}, {res.expanded} expanded, {res.generated} "
                           f"generated, {res.seconds:.3f} s):")
                for i, a in enumerate(res.plan or (), 1):
                    typer.echo(f"  {i}. {a}")
                if not res.plan:
                    typer.echo("  (empty: the goal holds in the initial state)")
            else:
                typer.echo(f"NO PLAN ({res.status}): {res.reason} — {res.expanded} expanded, {res.generated} "
                           f"generated, {res.seconds:.3f} s")
        raise typer.Exit(0 if res.solved else (1 if res.status == "unsolvable" else 3))

    @app.command("check")
    def check_command(
        files: list[Path] = typer.Argument(..., help="SPEC [PROBLEM] PLAN_FILE"),
        prop: list[str] = typer.Option([], "--property", "-p",
                                       help='"always φ", "eventually φ" or "at end φ" (repeatable)'),
        props_file: Path | None = typer.Option(None, "--properties", help="file with one property a line"),
        allow_inconsistent: bool = typer.Option(False, "--allow-inconsistent",
                                                help="do not fail when an agent comes to believe ⊥"),
        timeout: float = typer.Option(0.0, "--timeout", min=0.0, help="wall-clock limit in seconds (0: none)"),
        as_json: bool = typer.Option(False, "--json", help="print one JSON object"),
    ) -> None:
        """Replay a plan on a spec and check its executability, goal and properties."""
        from delkit.resources import deadline

        with deadline(timeout, "delkit check"):
            _check(files, prop, props_file, allow_inconsistent, as_json)


def _check(files: list[Path], prop: list[str], props_file: Path | None, allow_inconsistent: bool,
           as_json: bool) -> None:
    from delkit.errors import ParseError, io_reason
    from planners.lang import load_task
    from planners.validate import check_plan, parse_property, read_plan

    if len(files) not in (2, 3):
        raise ParseError(f"expected SPEC PLAN_FILE or DOMAIN PROBLEM PLAN_FILE, got {len(files)} file(s)",
                         source="delkit check")
    task = load_task(files[0], files[1] if len(files) == 3 else None)
    steps = read_plan(files[-1])
    texts: list[tuple[str, str, int]] = [(t, "--property", 1) for t in prop]   # (text, source, line)
    if props_file is not None:
        try:
            lines = props_file.read_text().splitlines()
        except (OSError, UnicodeDecodeError) as exc:
            raise ParseError(f"cannot read: {io_reason(exc)}", source=str(props_file)) from None
        texts += [(ln.strip(), str(props_file), i) for i, ln in enumerate(lines, 1)
                  if ln.strip() and not ln.lstrip().startswith("#")]
    properties = [parse_property(t, task, source=src, line=line) for t, src, line in texts]
    res = check_plan(task, steps, properties, allow_inconsistent=allow_inconsistent, plan_source=str(files[-1]))
    if as_json:
        typer.echo(json.dumps(res.to_json()))
    elif res.valid:
        typer.echo(f"valid: {len(steps)} step(s), goal reached"
                   + (f", {len(properties)} propert{'y' if len(properties) == 1 else 'ies'} hold"
                      if properties else ""))
    else:
        typer.echo(f"INVALID at step {res.step} ({res.action or 'initial state'}): {res.reason}")
    raise typer.Exit(0 if res.valid else 1)
