"""``delkit plan`` (epistemic planning on mA* / E-PDDL specs) and ``delkit check`` (plan + property checker).

Exit statuses: ``plan`` — 0 plan found, 1 no plan exists (state space exhausted), 3 no plan within the
limits; ``check`` — 0 valid, 1 invalid; both — 2 bad input. A failure is never printed as an empty plan.
Heavy imports stay inside the commands.

Start-up: typer (with the click and pydantic it imports) costs about 0.1 s, half of the 0.2 s budget of a
``delkit plan`` run on a small instance. :func:`fast_args` therefore parses the *plain* forms of a ``plan``
/ ``check`` command line by hand (known options, well-formed values) and the commands run without typer;
anything else (``--help``, an unknown option, a malformed value, a missing argument, ``--``) returns None
and goes through typer as before, so help texts, usage errors and exit statuses stay typer's own. The
command bodies (:func:`run_plan`, :func:`run_check`) are shared by both paths.
"""

from __future__ import annotations

import json
import re
import sys
from collections.abc import Callable
from pathlib import Path
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    import typer


def _echo(text: str) -> None:
    print(text, file=sys.stdout, flush=False)


def run_plan(spec: Path, problem: Path | None = None, search: str = "bfs", timeout: float = 60.0,
             max_nodes: int | None = None, max_memory: float = 8192.0, engine: str = "fast",
             allow_inconsistent: bool = False, as_json: bool = False) -> int:
    """The body of ``delkit plan``; returns the exit status."""
    from delkit.errors import PlanningError
    from planners.epistemic import Limits, plan
    from planners.lang import load_task

    if search not in ("bfs", "gbfs", "astar"):
        raise PlanningError(f"--search {search!r}: use bfs, gbfs or astar")
    task = load_task(spec, problem)
    res = plan(task, search=search, engine=engine,  # type: ignore[arg-type]
               limits=Limits(timeout=timeout, max_expanded=max_nodes, max_memory_mb=max_memory),
               allow_inconsistent=allow_inconsistent)
    out = res.to_json()
    out["task"] = task.name
    if as_json:
        _echo(json.dumps(out))
    else:
        if res.solved:
            _echo(f"plan of length {res.length} ({search}, {res.expanded} expanded, {res.generated} "
                  f"generated, {res.seconds:.3f} s):")
            for i, a in enumerate(res.plan or (), 1):
                _echo(f"  {i}. {a}")
            if not res.plan:
                _echo("  (empty: the goal holds in the initial state)")
        else:
            _echo(f"NO PLAN ({res.status}): {res.reason} — {res.expanded} expanded, {res.generated} "
                  f"generated, {res.seconds:.3f} s")
    return 0 if res.solved else (1 if res.status == "unsolvable" else 3)


def run_check(files: list[Path], prop: list[str] | None = None, props_file: Path | None = None,
              allow_inconsistent: bool = False, as_json: bool = False) -> int:
    """The body of ``delkit check``; returns the exit status."""
    from delkit.errors import ParseError, io_reason
    from planners.lang import load_task
    from planners.validate import check_plan, parse_property, read_plan

    if len(files) not in (2, 3):
        raise ParseError(f"expected SPEC PLAN_FILE or DOMAIN PROBLEM PLAN_FILE, got {len(files)} file(s)",
                         source="delkit check")
    task = load_task(files[0], files[1] if len(files) == 3 else None)
    steps = read_plan(files[-1])
    texts: list[tuple[str, str, int]] = [(t, "--property", 1) for t in prop or ()]   # (text, source, line)
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
        _echo(json.dumps(res.to_json()))
    elif res.valid:
        _echo(f"valid: {len(steps)} step(s), goal reached"
              + (f", {len(properties)} propert{'y' if len(properties) == 1 else 'ies'} hold"
                 if properties else ""))
    else:
        _echo(f"INVALID at step {res.step} ({res.action or 'initial state'}): {res.reason}")
    return 0 if res.valid else 1


def register(app: typer.Typer) -> None:
    """Attach ``plan`` and ``check`` to the top-level app."""
    import typer

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
        raise typer.Exit(run_plan(spec, problem, search, timeout, max_nodes, max_memory, engine,
                                  allow_inconsistent, as_json))

    @app.command("check")
    def check_command(
        files: list[Path] = typer.Argument(..., help="SPEC [PROBLEM] PLAN_FILE"),
        prop: list[str] = typer.Option([], "--property", "-p",
                                       help='"always φ", "eventually φ" or "at end φ" (repeatable)'),
        props_file: Path | None = typer.Option(None, "--properties", help="file with one property a line"),
        allow_inconsistent: bool = typer.Option(False, "--allow-inconsistent",
                                                help="do not fail when an agent comes to believe ⊥"),
        as_json: bool = typer.Option(False, "--json", help="print one JSON object"),
    ) -> None:
        """Replay a plan on a spec and check its executability, goal and properties."""
        raise typer.Exit(run_check(files, prop, props_file, allow_inconsistent, as_json))


# ---------------------------------------------------------------------------------------------- fast path
_NUM = re.compile(r"(?:[0-9]+(?:\.[0-9]*)?|\.[0-9]+)\Z")
_INT = re.compile(r"[0-9]+\Z")

# option -> (keyword, kind); kind: flag, str, float, int, path, list
_PLAN_OPTS = {"--search": ("search", "str"), "--timeout": ("timeout", "float"), "--max-nodes": ("max_nodes", "int"),
              "--max-memory": ("max_memory", "float"), "--engine": ("engine", "str"),
              "--allow-inconsistent": ("allow_inconsistent", "flag"), "--json": ("as_json", "flag")}
_CHECK_OPTS = {"--property": ("prop", "list"), "-p": ("prop", "list"), "--properties": ("props_file", "path"),
               "--allow-inconsistent": ("allow_inconsistent", "flag"), "--json": ("as_json", "flag")}


def _value(kind: str, text: str) -> Any:
    """The option value, or raise ValueError for anything but its plain well-formed spelling."""
    if kind in ("float", "int"):
        if not (_INT if kind == "int" else _NUM).match(text):
            raise ValueError(text)
        return int(text) if kind == "int" else float(text)
    if not text or text.startswith("-"):
        raise ValueError(text)
    return Path(text) if kind == "path" else text


def fast_args(argv: list[str]) -> Callable[[], int] | None:
    """A call of :func:`run_plan` / :func:`run_check` for a plain ``plan`` / ``check`` command line, or None
    (the caller then lets typer parse it: help, usage errors and every unusual spelling stay typer's)."""
    if not argv or argv[0] not in ("plan", "check"):
        return None
    opts = _PLAN_OPTS if argv[0] == "plan" else _CHECK_OPTS
    kw: dict[str, Any] = {}
    pos: list[Path] = []
    i = 1
    try:
        while i < len(argv):
            arg = argv[i]
            i += 1
            if not arg.startswith("-"):
                if not arg:
                    return None
                pos.append(Path(arg))
                continue
            # --opt=value splits at '='; a short option is only taken alone (click reads -pX as -p X)
            name, eq, inline = arg.partition("=") if arg.startswith("--") else (arg, "", "")
            spec = opts.get(name)
            if spec is None:
                return None  # --help, --, -x, unknown options: typer's business
            key, kind = spec
            if kind == "flag":
                if eq:
                    return None
                kw[key] = True
                continue
            if eq:
                text = inline
            elif i < len(argv):
                text = argv[i]
                i += 1
            else:
                return None
            value = _value(kind, text)
            if kind == "list":
                kw.setdefault(key, []).append(value)
            elif key in kw:
                return None  # repeated single-valued option: let typer decide
            else:
                kw[key] = value
    except ValueError:
        return None
    if argv[0] == "plan":
        if not 1 <= len(pos) <= 2:
            return None
        return lambda: run_plan(pos[0], pos[1] if len(pos) == 2 else None, **kw)
    if not pos:
        return None
    return lambda: run_check(pos, **kw)
