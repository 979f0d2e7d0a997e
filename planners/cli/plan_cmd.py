"""``delkit plan`` (epistemic planning on mA* / E-PDDL 2021 / EPDDL 2026 specs), ``delkit check`` (plan +
property checker) and ``delkit convert`` (write a task as EPDDL 2026 or mA*).

Exit statuses: ``plan`` — 0 plan found, 1 no plan exists (state space exhausted), 3 no plan within the
limits (the limit also covers reading, grounding and building the initial state); ``check`` — 0 valid,
1 invalid, 3 ``--timeout`` reached (default 60 s, as for ``plan``); all — 2 bad input. ``--timeout``
counts from the start of the process, 0 or inf means no limit (:func:`delkit.resources.parse_timeout`, the
same for every command). A failure is never printed as an empty plan. The language of a file is decided by
its content. Heavy imports stay inside the commands.

Start-up: typer (with the click and pydantic it imports) costs about 0.1 s, half of the 0.2 s budget of a
``delkit plan`` run on a small instance. :func:`fast_args` therefore parses the *plain* forms of a ``plan``
/ ``check`` command line by hand (known options, well-formed values) and the commands run without typer;
anything else (``--help``, an unknown option, a malformed value, a missing argument, ``--``) returns None
and goes through typer as before, so help texts, usage errors and exit statuses stay typer's own. The
command bodies (:func:`run_plan`, :func:`run_check`) are shared by both paths.
"""

from __future__ import annotations

import re
from collections.abc import Callable
from pathlib import Path

from delkit._lazy import lazy_module

TYPE_CHECKING = False  # typing.TYPE_CHECKING without importing typing (start-up: delkit._records)
if TYPE_CHECKING:
    import json
    from typing import Any

    import typer
else:
    json = lazy_module("json")  # only --json needs it (start-up)


from planners.commands import _echo, run_check, run_plan  # noqa: E402,F401  (the bodies; re-exported)

_TIMEOUT_HELP = ("wall-clock limit in seconds, counted from the start of the process (0 or inf: no limit); "
                 "reaching it is exit status 3")


_CHECK_HELP = (
    "Replay a plan on a spec and check its executability, goal and properties.\n\n"
    "A plan under which an agent comes to believe ⊥ (no accessible world at the actual world, so every belief "
    "goal would hold vacuously) fails on mA* and E-PDDL tasks unless --allow-inconsistent is given. EPDDL (2026) "
    "semantics keeps such states (as plank does): the plan is checked on, with one warning line per such state "
    "on stderr and their list in the JSON field inconsistent_beliefs.\n\n"
    "Exit status: 0 valid, 1 invalid, 2 bad input, 3 --timeout reached.")


def register(app: typer.Typer) -> None:
    """Attach ``plan`` and ``check`` to the top-level app."""
    import typer

    @app.command("plan")
    def plan_command(
        files: list[Path] = typer.Argument(..., help="mA* file, or E-PDDL DOMAIN PROBLEM; several tasks: a batch "
                                                     "(mA* files, each domain followed by its problems)"),
        library: list[Path] = typer.Option([], "--library", "-l", help="EPDDL action-type library (repeatable)"),
        strict: bool = typer.Option(False, "--strict", help="refuse mA* duplicate declarations"),
        search: str = typer.Option("bfs", "--search", help="bfs (optimal), gbfs, astar (optimal), novelty (BFWS) "
                                                           "or auto (novelty, GBFS, then A* in one time budget)"),
        timeout: float = typer.Option(60.0, "--timeout", help=_TIMEOUT_HELP),
        max_nodes: int | None = typer.Option(None, "--max-nodes", help="limit on expanded nodes"),
        max_memory: float = typer.Option(8192.0, "--max-memory", help="resident memory limit in MiB"),
        engine: str = typer.Option("auto", "--engine",
                                   help="fast (compact bit sets), del (numpy, delkit's reference) or auto"),
        allow_inconsistent: bool = typer.Option(False, "--allow-inconsistent",
                                                help="expand states where an agent believes ⊥"),
        consistent_beliefs: bool = typer.Option(False, "--consistent-beliefs",
                                                help="prune states where an agent believes ⊥ (also on EPDDL, "
                                                     "whose default keeps them, as plank does)"),
        as_json: bool = typer.Option(False, "--json", help="print one JSON object (a batch: one per task)"),
        jobs: str | None = typer.Option(None, "--jobs", "-j", help="worker processes for a batch, 1..256 (default: "
                                                                  "one per core)"),
        scheduler: str | None = typer.Option(None, "--scheduler", help="run a batch on the Dask cluster at "
                                                                      "ADDRESS (e.g. tcp://host:8786)"),
        plan_out: Path | None = typer.Option(None, "--plan-out", help="also write the plan to FILE as JSON (read "
                                             "by delkit check and delkit view; one task only)"),
    ) -> None:
        """Find a plan (BFS: of minimal length) for an mA*, E-PDDL (2021) or EPDDL (2026) problem — or for every
        task of many files in one command (a batch: JSON lines, a summary, one process per core)."""
        from planners.batch import plan_files

        raise typer.Exit(plan_files(files, search=search, timeout=timeout, max_nodes=max_nodes,
                                    max_memory=max_memory, engine=engine, allow_inconsistent=allow_inconsistent,
                                    as_json=as_json, library=library, strict=strict, jobs=jobs, scheduler=scheduler,
                                    **({"plan_out": plan_out} if plan_out is not None else {}),
                                    **({"consistent_beliefs": True} if consistent_beliefs else {})))

    @app.command("check", help=_CHECK_HELP)
    def check_command(
        files: list[Path] = typer.Argument(..., help="SPEC [PROBLEM] PLAN_FILE (plan text, or the JSON of delkit "
                                                     "plan --plan-out / --json)"),
        library: list[Path] = typer.Option([], "--library", "-l", help="EPDDL action-type library (repeatable)"),
        strict: bool = typer.Option(False, "--strict", help="refuse mA* duplicate declarations"),
        prop: list[str] = typer.Option([], "--property", "-p",
                                       help='"always φ", "eventually φ" or "at end φ" (repeatable); φ in the '
                                            'formula syntax delkit reads everywhere (K_a p, C{a,b} p, ~ ! not, '
                                            '&, |, ->) or in mA* syntax (B(a, p), -p), the two mixed as in '
                                            '~B(a, p)'),
        props_file: Path | None = typer.Option(None, "--properties", help="file with one property a line"),
        allow_inconsistent: bool = typer.Option(False, "--allow-inconsistent",
                                                help="do not fail (mA*, E-PDDL) or warn (EPDDL) when an agent "
                                                     "comes to believe ⊥"),
        timeout: float = typer.Option(60.0, "--timeout", help=_TIMEOUT_HELP + " (default 60 s)"),
        as_json: bool = typer.Option(False, "--json", help="print one JSON object (a batch: one per group)"),
        jobs: str | None = typer.Option(None, "--jobs", "-j", help="worker processes for a batch of SPEC [PROBLEM] "
                                                                  "PLAN_FILE groups, 1..256"),
        scheduler: str | None = typer.Option(None, "--scheduler", help="run a batch on the Dask cluster at ADDRESS"),
        trace: bool = typer.Option(False, "--trace", help="print the state after every step"),
        trace_json: Path | None = typer.Option(None, "--trace-json", help="write the states along the plan as "
                                                                          "JSON to this file ('-': stdout)"),
    ) -> None:
        """Replay a plan on a spec and check its executability, goal and properties (many SPEC [PROBLEM]
        PLAN_FILE groups: a batch)."""
        from planners.batch import check_files

        raise typer.Exit(check_files(files, prop=prop, props_file=props_file, allow_inconsistent=allow_inconsistent,
                                     as_json=as_json, library=library, strict=strict, timeout=timeout, jobs=jobs,
                                     scheduler=scheduler, trace=trace, trace_json=trace_json))

    @app.command("convert")
    def convert_command(
        files: list[Path] = typer.Argument(..., help="mA* file, or E-PDDL DOMAIN PROBLEM"),
        to: str = typer.Option("epddl", "--to", help="epddl (EPDDL 2026: domain, problem, library) or mastar"),
        out: Path = typer.Option(Path("."), "--out", "-o", help="output directory"),
        name: str | None = typer.Option(None, "--name", help="base name of the written files (a plain name: no "
                                        "'/' or '..')"),
        force: bool = typer.Option(False, "--force", help="overwrite an input file that an output would replace"),
        as_json: bool = typer.Option(False, "--json", help="print the written paths as JSON"),
    ) -> None:
        """Write an mA* or E-PDDL (2021) task as EPDDL (2026), or as mA* where it fits."""
        from delkit.errors import ParseError
        from planners.lang import load_task
        from planners.lang.writer import to_epddl, to_mastar

        if to not in ("epddl", "mastar"):
            raise ParseError(f"--to {to!r}: use epddl or mastar", source="delkit convert")
        if len(files) not in (1, 2):
            raise ParseError(f"expected SPEC or DOMAIN PROBLEM, got {len(files)} file(s)", source="delkit convert")
        from delkit.resources import check_outputs

        if name is not None and (not name.strip() or "/" in name or "\\" in name or name in (".", "..")):
            raise ParseError(f"--name {name!r}: give a plain base name for the written files (not empty, no '/' "
                             f"or '..'), e.g. --name mytask", source="delkit convert")
        task = load_task(files[0], files[1] if len(files) == 2 else None)
        base = name or (files[-1].stem if len(files) == 2 else files[0].stem)
        if to == "epddl":
            dom, prob, lib = to_epddl(task, base)
            texts = {"domain": (out / f"{base}_domain.epddl", dom), "problem": (out / f"{base}_problem.epddl", prob),
                     "library": (out / "mastar.epddl", lib)}
        else:
            texts = {"mastar": (out / f"{base}.txt", to_mastar(task))}
        # every output checked before the first is written: none replaces an input, none leaves -o
        check_outputs([p for p, _ in texts.values()], files, force=force, folder=out)
        try:
            out.mkdir(parents=True, exist_ok=True)
        except OSError as exc:
            raise ParseError(f"cannot create the output directory: {exc.strerror}", source=str(out)) from None
        written: dict[str, str] = {}
        for kind, (path, text) in texts.items():
            path.write_text(text)
            written[kind] = str(path)
        if as_json:
            typer.echo(json.dumps(written))
        else:
            for kind, path in written.items():
                typer.echo(f"{kind}: {path}")


# ---------------------------------------------------------------------------------------------- fast path
_NUM = r"(?:[0-9]+(?:\.[0-9]*)?|\.[0-9]+)\Z"  # compiled on first use (re's cache): start-up
_INT = r"[0-9]+\Z"

# option -> (keyword, kind); kind: flag, str, float, int, path, list
_BATCH_OPTS = {"--jobs": ("jobs", "int"), "-j": ("jobs", "int"), "--scheduler": ("scheduler", "str")}  # batch.py
_PLAN_OPTS = {"--search": ("search", "str"), "--timeout": ("timeout", "float"), "--max-nodes": ("max_nodes", "int"),
              "--max-memory": ("max_memory", "float"), "--engine": ("engine", "str"),
              "--allow-inconsistent": ("allow_inconsistent", "flag"), "--json": ("as_json", "flag"),
              "--library": ("library", "plist"), "-l": ("library", "plist"), "--strict": ("strict", "flag"),
              "--plan-out": ("plan_out", "path"), "--consistent-beliefs": ("consistent_beliefs", "flag"),
              **_BATCH_OPTS}
_CHECK_OPTS = {"--property": ("prop", "list"), "-p": ("prop", "list"), "--properties": ("props_file", "path"),
               "--timeout": ("timeout", "float"),
               "--allow-inconsistent": ("allow_inconsistent", "flag"), "--json": ("as_json", "flag"),
               "--library": ("library", "plist"), "-l": ("library", "plist"), "--strict": ("strict", "flag"),
               "--trace": ("trace", "flag"), "--trace-json": ("trace_json", "path"),
              **_BATCH_OPTS}


def _value(kind: str, text: str) -> Any:
    """The option value, or raise ValueError for anything but its plain well-formed spelling."""
    if kind in ("float", "int"):
        if not re.match(_INT if kind == "int" else _NUM, text):
            raise ValueError(text)
        return int(text) if kind == "int" else float(text)
    if not text or text.startswith("-"):
        raise ValueError(text)
    return Path(text) if kind in ("path", "plist") else text


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
            if kind in ("list", "plist"):
                kw.setdefault(key, []).append(value)
            elif key in kw:
                return None  # repeated single-valued option: let typer decide
            else:
                kw[key] = value
    except ValueError:
        return None
    if not pos:
        return None
    from planners.batch import check_files, plan_files  # one task, a batch, or one task on many cores

    return (lambda: plan_files(pos, **kw)) if argv[0] == "plan" else (lambda: check_files(pos, **kw))
