"""Parallel breadth-first search of one task: ``delkit plan FILE --jobs N`` (N ≥ 2) on a single task.

Layer-synchronous BFS on the compact backend. The parent keeps the visited set and the frontier; each layer
is cut into chunks that N worker processes expand (each worker reads the task once and keeps its own compact
engine). A state travels as its canonical record (valuations, successor masks, designated worlds) — the
engine's frame numbers are per process, the record is the same in every process — and a worker returns,
per state of its chunk and in the successor order of the serial search, (action, record, goal?) with the
duplicates of its chunk removed. The parent merges the chunks in frontier order, drops the states seen
before and stops at the first goal in that order: the plan is the one serial :func:`planners.epistemic.bfs`
finds (same generation order, same duplicate detection, goal test at generation, the same dead-end pruning),
so lengths are optimal and equal. Chunks are merged in order as they arrive and the search stops at the chunk
with the first goal (``expanded`` counts the states of the merged chunks; chunks of the last layer already in
the workers' hands are wasted work).

What limits the speed-up: the parent's merge (hashing and deduplicating every successor record) is serial;
records are pickled both ways; layers end with a barrier (the slowest chunk); workers pay their own task
reading. It pays when an expansion is expensive (states with many worlds) and layers are wide.
"""

from __future__ import annotations

import time
from pathlib import Path
from typing import Any

__all__ = ["run_plan_parallel", "parallel_bfs"]

_SPACE: Any = None
_DEAD: Any = None


def _record(s: Any) -> tuple:
    return (s.val, s.masks, s.points)


def _init(spec: str, problem: str | None, library: list[str], strict: bool, engine: str,
          allow_inconsistent: bool) -> None:
    global _SPACE, _DEAD
    from planners.heuristics import dead_end_test
    from planners.lang import load_task
    from planners.lang.epddl_run import space_for

    task = load_task(Path(spec), Path(problem) if problem else None, [Path(p) for p in library], strict=strict)
    _SPACE = space_for(task, engine, allow_inconsistent)
    _DEAD = dead_end_test(_SPACE)  # as serial BFS: proven dead ends are seen but not expanded


def _expand(chunk: list[tuple]) -> tuple[list[list[tuple]], int]:
    """Expand the states of a chunk: per state its new successors (action, record, is goal); dead ends."""
    from delkit.compact import CompactState, frame_id

    space = _SPACE
    before = space.dead_ends
    out = []
    seen: set = set()
    for val, masks, points in chunk:
        s = CompactState(val, masks, points, frame_id(masks, points))
        succ = []
        for name, nxt, _key in space.successors(s):
            rec = _record(nxt)
            if rec in seen:
                continue
            seen.add(rec)
            goal = space.is_goal(nxt)
            succ.append((name, rec, goal, not goal and _DEAD is not None and _DEAD(nxt)))
        out.append(succ)
    return out, space.dead_ends - before


def parallel_bfs(spec: Path, problem: Path | None, jobs: int, *, timeout: float = 60.0,
                 max_nodes: int | None = None, engine: str = "auto", allow_inconsistent: bool = False,
                 library: list[Path] | None = None, strict: bool = False):
    """Layer-synchronous BFS in ``jobs`` worker processes; a :class:`planners.epistemic.SearchResult`
    (``search`` = ``"bfs"``), and the task."""
    import multiprocessing

    from planners.epistemic import SearchResult
    from planners.lang import load_task
    from planners.lang.epddl_run import space_for
    from planners.spaces import CompactSpace

    t0 = time.perf_counter()
    lib = [str(p) for p in library or ()]
    task = load_task(spec, problem, list(library or ()), strict=strict, deadline=time.monotonic() + timeout)
    space = space_for(task, engine, allow_inconsistent)
    if not isinstance(space, CompactSpace):
        return None, task  # the numpy backend's states are not records: the caller searches serially
    s0, _k0 = space.initial()
    if space.is_goal(s0):
        return SearchResult("solved", (), 0, 1, time.perf_counter() - t0, "bfs", "the goal holds initially",
                            distinct_states=1), task
    r0 = _record(s0)
    parent: dict[tuple, Any] = {r0: None}
    frontier = [r0]
    expanded = generated = dead = 0
    ctx = multiprocessing.get_context("spawn")
    pool = ctx.Pool(jobs, initializer=_init, initargs=(str(spec), str(problem) if problem else None, lib, strict,
                                                       engine, space.allow_inconsistent))

    def done(status: str, plan: tuple | None, reason: str) -> tuple[SearchResult, Any]:
        return SearchResult(status, plan, expanded, generated, time.perf_counter() - t0, "bfs", reason, dead,
                            len(parent)), task

    try:
        while frontier:
            left = timeout - (time.perf_counter() - t0)
            if left <= 0:
                return done("limit", None, f"no plan within limits: time limit {timeout:g} s reached")
            if max_nodes is not None and expanded >= max_nodes:
                return done("limit", None, f"no plan within limits: expanded-node limit {max_nodes} reached")
            size = max(1, min(256, -(-len(frontier) // (4 * jobs))))
            chunks = [frontier[i:i + size] for i in range(0, len(frontier), size)]
            results = pool.imap(_expand, chunks)  # in order: merged as they come, stopped at the first goal
            nxt = []
            goal = None
            for chunk in chunks:
                try:
                    succs, d = results.next(timeout=max(0.0, timeout - (time.perf_counter() - t0)))
                except multiprocessing.TimeoutError:
                    return done("limit", None, f"no plan within limits: time limit {timeout:g} s reached")
                dead += d
                expanded += len(chunk)
                for rec, succ in zip(chunk, succs, strict=True):
                    for name, new, is_goal, is_dead in succ:
                        generated += 1
                        if new in parent:
                            continue
                        parent[new] = (rec, name)
                        if is_goal and goal is None:
                            goal = new
                        if is_dead:
                            dead += 1
                        else:
                            nxt.append(new)
                    if goal is not None:
                        break
                if goal is not None:
                    break
            if goal is not None:
                plan = []
                key = goal
                while parent[key] is not None:
                    key, act = parent[key]
                    plan.append(act)
                return done("solved", tuple(reversed(plan)), "")
            frontier = nxt
        return done("unsolvable", None, "the reachable state space is exhausted: no plan exists")
    finally:
        pool.terminate()
        pool.join()


def run_plan_parallel(spec: Path, problem: Path | None = None, *, jobs: int = 2, search: str = "bfs",
                      as_json: bool = False, timeout: float = 60.0, max_nodes: int | None = None,
                      engine: str = "auto", allow_inconsistent: bool = False, library: list[Path] | None = None,
                      strict: bool = False, **rest: Any) -> int:
    """``delkit plan FILE --jobs N`` for one task: :func:`parallel_bfs` (BFS only; other searches and the
    numpy backend run serially, as without ``--jobs``); returns the exit status."""

    from planners.commands import report_search, run_plan

    serial = dict(search=search, as_json=as_json, timeout=timeout, max_nodes=max_nodes, engine=engine,
                  allow_inconsistent=allow_inconsistent, library=library, strict=strict, **rest)
    if search != "bfs":
        return run_plan(spec, problem, **serial)
    res, task = parallel_bfs(spec, problem, jobs, timeout=timeout, max_nodes=max_nodes, engine=engine,
                             allow_inconsistent=allow_inconsistent, library=library, strict=strict)
    if res is None:
        return run_plan(spec, problem, **serial)
    return report_search(res, {**res.to_json(), "task": task.name, "jobs": jobs}, f"parallel bfs, {jobs} workers",
                         as_json)
