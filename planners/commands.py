"""The bodies of ``delkit plan`` and ``delkit check`` for one task (:func:`run_plan`, :func:`run_check`),
shared by the typer command, the typer-free fast path (:mod:`planners.cli.plan_cmd`) and the batch and
parallel runners (:mod:`planners.batch`, :mod:`planners.parallel`), which is why they live below all three.

Exit statuses: ``plan`` — 0 plan found, 1 no plan exists (state space exhausted), 3 no plan within the
limits (the limit also covers reading, grounding and building the initial state); ``check`` — 0 valid,
1 invalid; all — 2 bad input, 3 a reached limit. A failure is never printed as an empty plan.
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

from delkit._lazy import lazy_module

TYPE_CHECKING = False  # typing.TYPE_CHECKING without importing typing (start-up: delkit._records)
if TYPE_CHECKING:
    import json
else:
    json = lazy_module("json")  # only --json needs it (start-up)


def _echo(text: str) -> None:
    print(text, file=sys.stdout, flush=False)


def run_plan(spec: Path, problem: Path | None = None, search: str = "bfs", timeout: float = 60.0,
             max_nodes: int | None = None, max_memory: float = 8192.0, engine: str = "auto",
             allow_inconsistent: bool = False, as_json: bool = False, library: list[Path] | None = None,
             strict: bool = False, plan_out: Path | None = None, consistent_beliefs: bool = False) -> int:
    """The body of ``delkit plan``; returns the exit status (``plan_out``: also write the plan there as a JSON
    plan file, :mod:`planners.plan_file`)."""
    from delkit.errors import PlanningError
    from planners.epistemic import SEARCHES, Limits, SearchResult, annotate, portfolio, run_search
    from planners.lang import load_task
    from planners.lang.initial import LoadTimeout

    if search not in SEARCHES:
        raise PlanningError(f"--search {search!r}: use " + ", ".join(SEARCHES))
    if consistent_beliefs and allow_inconsistent:
        raise PlanningError("--consistent-beliefs (prune states where an agent believes ⊥) and "
                            "--allow-inconsistent (keep them) contradict each other: give at most one")
    from delkit.resources import TimeLimit, command_start, counters, deadline, keep_alive, parse_timeout

    inputs = [Path(p) for p in (spec, problem, *(library or ())) if p is not None]
    if plan_out is not None:
        from planners.plan_file import check_plan_out

        check_plan_out(Path(plan_out), inputs)  # before any work: the plan must not replace an input
    limit = parse_timeout(timeout)  # 0 / inf: no limit; counted from the start of the process
    counters().update(expanded=0, generated=0)  # a limit answer before the search says so: nothing expanded
    Limits(timeout=limit, max_expanded=max_nodes, max_memory_mb=max_memory)  # impossible limits: exit 2
    start = command_start()
    reached = f"--timeout {timeout:g} s reached (counted from the start of the process)"

    def limit_result(phase: str, expanded: int = 0, generated: int = 0) -> SearchResult:
        return SearchResult("limit", None, expanded, generated, time.monotonic() - start, search,
                            reason=f"no plan within limits: {reached} while {phase}")

    # one deadline for every phase: the readers and the search check it themselves, the alarm (and, in the
    # console script, a watchdog) stop any phase that does not
    task = space = None
    try:
        with deadline(limit, "delkit plan"):
            task = load_task(spec, problem, list(library or ()), deadline=None if limit is None else start + limit,
                             strict=strict)
            from planners.lang.epddl_run import space_for

            left = None if limit is None else max(0.0, start + limit - time.monotonic())
            limits = Limits(timeout=left, max_expanded=max_nodes, max_memory_mb=max_memory)
            from planners.beliefs import belief_semantics

            semantics = belief_semantics(task, consistent_beliefs=consistent_beliefs,
                                         allow_inconsistent=allow_inconsistent)
            space = space_for(task, engine, allow_inconsistent, consistent_beliefs=consistent_beliefs)
            if search == "auto":
                unused = [space]  # the first phase searches the space built above; later phases get fresh ones

                def make():  # noqa: ANN202 - a StateSpace
                    return unused.pop() if unused else space_for(task, engine, allow_inconsistent,
                                                                 consistent_beliefs=consistent_beliefs)

                res = portfolio(make, limits)
            else:
                res = run_search(space, search, limits)
            res = annotate(res, space, semantics)
    except (LoadTimeout, TimeLimit) as exc:
        keep_alive(space, task, exc)  # console script: freeing the search space must not delay the exit
        live = counters()  # how far the search got when the alarm stopped it (0 before it started)
        res = limit_result("reading, grounding and building the initial state" if task is None else
                           "contracting the initial state" if space is None else "searching",
                           int(live.get("expanded", 0)) if space is not None else 0,
                           int(live.get("generated", 0)) if space is not None else 0)
    if res.status == "limit" and res.reason.endswith(" s reached") and "time limit" in res.reason:
        res = limit_result("searching", res.expanded, res.generated)
    if task is None:
        if as_json:
            _echo(json.dumps({**res.to_json(), "task": str(problem or spec)}))
        else:
            _echo(f"NO PLAN (timeout): {res.reason} — {res.seconds:.3f} s")
        return 3
    out = res.to_json()
    out["task"] = task.name
    if plan_out is not None:
        _plan_out(Path(plan_out), res, out, task.name, inputs)
    return report_search(res, out, search, as_json)


def _plan_out(path: Path, res, out: dict, name: str, inputs: list[Path]) -> None:
    """``--plan-out``: the plan file of a solved search; none written (said on stderr) without a plan."""
    import sys

    from planners.plan_file import plan_document, write_plan_file

    if res.solved:
        write_plan_file(path, plan_document(name, inputs, out), inputs)
        out["plan_file"] = str(path)
    else:
        print(f"delkit plan: --plan-out {path}: not written: no plan ({res.status})", file=sys.stderr, flush=True)


def report_search(res, out: dict, how: str, as_json: bool) -> int:
    """Print a search result (``out`` as JSON, or the plan / the reason as text; ``how`` names the search)
    and return ``delkit plan``'s exit status: 0 a plan, 1 none exists, 3 a limit."""
    if as_json:
        _echo(json.dumps(out))
    elif res.solved:
        _echo(f"plan of length {res.length} ({how}, {res.expanded} expanded, {res.generated} "
              f"generated, {res.seconds:.3f} s):")
        for i, a in enumerate(res.plan or (), 1):
            _echo(f"  {i}. {a}")
        if not res.plan:
            _echo("  (empty: the goal holds in the initial state)")
        if res.phases and res.optimal is not None:
            _echo("  length proven minimal" if res.optimal else "  length not proven minimal")
        for ph in res.phases:
            _echo(f"  phase {ph['search']}: {ph['status']}" + (f", length {ph['length']}" if ph['length'] is not None
                                                               else "") + f", {ph['seconds']:.3f} s")
        for v in res.vacuous:
            _echo(f"  vacuous: the goal conjunct {v['conjunct']} holds only because {', '.join(v['agents'])} "
                  f"believe(s) ⊥ (no accessible world at a designated world); --consistent-beliefs prunes such "
                  f"states")
    else:
        _echo(f"NO PLAN ({res.status}): {res.reason} — {res.expanded} expanded, {res.generated} "
              f"generated, {res.seconds:.3f} s")
    return 0 if res.solved else (1 if res.status == "unsolvable" else 3)


def run_check(files: list[Path], prop: list[str] | None = None, props_file: Path | None = None,
              allow_inconsistent: bool = False, as_json: bool = False, library: list[Path] | None = None,
              strict: bool = False, timeout: float = 60.0, trace: bool = False, trace_json: Path | None = None) -> int:
    """The body of ``delkit check``; returns the exit status (``timeout``: 60 s by default, 0:
    no limit). ``trace`` /
    ``trace_json`` also print / write the states along the plan (:mod:`planners.trace`)."""
    from delkit.resources import deadline, parse_timeout

    with deadline(parse_timeout(timeout), "delkit check"):  # 0 / inf: no limit; from the start of the process
        return _run_check(files, prop, props_file, allow_inconsistent, as_json, library, strict, trace, trace_json)


def _run_check(files: list[Path], prop: list[str] | None, props_file: Path | None, allow_inconsistent: bool,
               as_json: bool, library: list[Path] | None, strict: bool, trace: bool = False,
               trace_json: Path | None = None) -> int:
    from delkit.errors import ParseError, io_reason
    from planners.lang import load_task
    from planners.validate import check_plan, parse_property, read_plan

    if len(files) not in (2, 3):
        raise ParseError(f"expected SPEC PLAN_FILE or DOMAIN PROBLEM PLAN_FILE, got {len(files)} file(s)",
                         source="delkit check")
    if trace_json is not None:  # before anything is read or written: the trace never replaces an input
        from delkit.paths import refuse_overwrite_input

        refuse_overwrite_input([trace_json], [*files, props_file, *(library or ())], option="--trace-json")
    task = load_task(files[0], files[1] if len(files) == 3 else None, list(library or ()), strict=strict)
    steps = read_plan(files[-1])
    texts: list[tuple[str, str, int]] = [(t, "--property", 1) for t in prop or ()]   # (text, source, line)
    if props_file is not None:
        try:
            from delkit.paths import read_input

            lines = read_input(props_file, "properties file").splitlines()
        except (OSError, UnicodeDecodeError) as exc:
            raise ParseError(f"cannot read: {io_reason(exc)}", source=str(props_file)) from None
        texts += [(ln.strip(), str(props_file), i) for i, ln in enumerate(lines, 1)
                  if ln.strip() and not ln.lstrip().startswith("#")]
    properties = [parse_property(t, task, source=src, line=line) for t, src, line in texts]
    # one checker; EPDDL (2026) tasks are replayed with EPDDL's semantics (see check_plan's ``epddl``)
    res = check_plan(task, steps, properties, allow_inconsistent=allow_inconsistent, plan_source=str(files[-1]))
    for line in res.warnings():  # EPDDL kept a state where an agent believes ⊥ (also in the JSON)
        print(f"delkit: warning: {line}", file=sys.stderr)
    if trace or trace_json is not None:  # the states along the plan
        from planners.trace import emit_trace

        emit_trace(task, steps, text=trace, json_path=trace_json, allow_inconsistent=allow_inconsistent,
                   plan_source=str(files[-1]), echo=_echo)
    if as_json:
        _echo(json.dumps(res.to_json()))
    elif res.valid:
        _echo(f"valid: {len(steps)} step(s), goal reached"
              + (f", {len(properties)} propert{'y' if len(properties) == 1 else 'ies'} hold"
                 if properties else ""))
    else:
        _echo(f"INVALID at step {res.step} ({res.action or 'initial state'}): {res.reason}")
    return 0 if res.valid else 1
