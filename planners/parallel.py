"""Parallel breadth-first search of one task: ``delkit plan FILE --jobs N`` (N ≥ 2) on a single task.

Hash-distributed, layer-synchronous BFS on the compact backend, in N *parts*: the calling process is part 0
and N-1 actors (:func:`delkit.executors.actors`: spawned local processes, or actors of a Dask cluster with
``scheduler``) are the others; each reads the task once and keeps its own compact engine. A state belongs to
the part its canonical record hashes to (``hash((valuations, hash(frame))) % N`` — ints and tuples of ints
hash alike in every process); each part keeps the visited set of its own states, expands its own frontier
and deduplicates what it is sent, so expansion *and* duplicate detection run in parallel and the caller only
coordinates the layers and forwards the bytes between parts.

A successor owned by another part travels as (valuations, frame number, the parent's path, step) with the
frames (successor masks, designated worlds) that part has not been sent before — a frame is shared by many
states — and a part never sends a state twice (it expands in path order, so the first copy it sent had the
smaller path). Keys are the serial search's own ``(valuations, frame)``, so duplicate detection is exact.

Same plan as serial :func:`planners.epistemic.bfs`: serial BFS gives each state the first (parent's rank,
successor position) that generates it and stops at the first goal generated, i.e. the lexicographically
least sequence of successor positions among shortest paths (through non-pruned states). Every state here
carries that sequence (its *path*: position × number of actions + action index, so the plan is read off
it); a part keeps the least path of every new state, the next frontier is sorted by it, and the frontier is
expanded in rounds (contiguous slices in path order). When a round's merge finds goals, every part also
expands its remaining states whose path is at most the best goal's parent's, and the least goal path after
that is serial BFS's plan. Goal test at generation, the same dead-end pruning (h_epi's dead ends are seen
but not expanded) and the same believes-⊥ rule, as the parts run the serial search's state space.

What limits the speed-up (measured in ``bench/RESULTS-planner.md`` §10): the caches of the state space and
the compact engine are per process, so each part fills its own — the candidate actions per designated
valuation, the transition tables, and above all the product *shapes* per frame, whose look-ups the engine
turns off for an event model while fewer than a quarter of them hit: split between parts, the states of a
task hit at different rates and one part may lose its hits (Grapevine_5 pl6: +20 % product refinements in
all); each part's own start-up (reading the task, overlapped with the caller's); a barrier per phase (the
slowest part); the successors sent between parts (pickled once, unpickled once, a frame only the first time
a part sends it); the work past the goal in the last round; and the commutation memo of the serial space (a
sensing's successor predicted from two known transitions), which sees only its own part's transitions.
"""

from __future__ import annotations

import gc
import pickle
import time
from operator import itemgetter
from pathlib import Path
from typing import Any

__all__ = ["run_plan_parallel", "parallel_bfs"]

#: at most this many rounds per layer (the work past the goal is at most about one round of the last layer)
ROUNDS = 12
#: at least this many states per part in a round (fewer rounds on small layers: a round costs a barrier)
MIN_ROUND = 24
#: states with more worlds than this belong to the part their frame hashes to (all states of a frame in one
#: part: the compact engine caches a product's shape per frame); smaller ones by their frame and the
#: valuation(s) of their designated world(s) (the state space caches the candidate actions per the latter:
#: Selective-Communication's parts spend ~14 % less CPU than when owned by all valuations and the frame)
FRAME_WORLDS = 16


_MUL, _LOW64 = 0x9E3779B97F4A7C15, 0xFFFFFFFFFFFFFFFF


def _mix(h: int) -> int:
    """The high bits of a multiplicative hash of ``h``: Python's tuple hashes are not uniform modulo small
    numbers (their low bits follow the tuples' structure), which would give one part most of a kind of state."""
    return ((h * _MUL) & _LOW64) >> 32


def _small_owner(val: tuple, points: tuple, fh: int) -> int:
    here = hash(val[points[0]]) if len(points) == 1 else hash(frozenset([val[p] for p in points]))
    return ((((here ^ fh) * _MUL) & _LOW64) >> 32)


class _Part:
    """One part of the search (module docstring): its visited set, its frontier, the layer being built."""

    def __init__(self, me: int, n: int, spec: str, problem: str | None, library: list[str], strict: bool,
                 engine: str, allow_inconsistent: bool, built: tuple | None = None) -> None:
        from planners.heuristics import dead_end_test

        if built is None:
            from planners.lang import load_task
            from planners.lang.epddl_run import space_for

            task = load_task(Path(spec), Path(problem) if problem else None, [Path(p) for p in library],
                             strict=strict)
            space = space_for(task, engine, allow_inconsistent)
        else:
            task, space = built
        self.me, self.n, self.space = me, n, space
        self.dead = dead_end_test(space)  # as serial BFS: proven dead ends are seen but not expanded
        self.nact = len(task.actions)
        self.aindex = {a.name: i for i, a in enumerate(task.actions)}
        self.seen: set = set()
        self.cur: dict = {}  # key -> [least path, state (None: a goal or a pruned dead end)] of this layer
        self.goals: list = []  # keys of this layer's goal states
        self.fhash: dict[int, int] = {}  # local frame number -> hash of the frame
        self.sent: list[set] = [set() for _ in range(n)]  # keys sent to each part
        self.fsent: list[set] = [set() for _ in range(n)]  # frame numbers each part has been sent
        self.fmap: list[dict] = [{} for _ in range(n)]  # per sending part: its frame number -> ours
        self.expanded = self.generated = self.pruned = 0
        s0, k0 = space.initial()
        self.fast_key = k0 == (s0.val, s0.fid)  # the key is (valuations, frame number): built without a state
        self.seen.add(k0)
        self.frontier: list = [((), s0)] if self._owner(s0) == me else []
        self.pos = 0
        self.start_cpu = time.process_time()  # this process's CPU until the part is ready (its start-up)

    def _owner(self, s: Any) -> int:
        fh = self.fhash.get(s.fid)
        if fh is None:
            fh = self.fhash[s.fid] = _mix(hash((s.masks, s.points)))
        return (fh if len(s.val) > FRAME_WORLDS else _small_owner(s.val, s.points, fh)) % self.n

    def _new(self, key: Any, path: tuple, s: Any) -> None:
        if self.space.is_goal(s):
            self.cur[key] = [path, None]
            self.goals.append(key)
        elif self.dead is not None and self.dead(s):
            self.cur[key] = [path, None]
            self.pruned += 1
        else:
            self.cur[key] = [path, s]

    def size(self) -> int:
        return len(self.frontier) - self.pos

    def started(self) -> tuple[int, float]:
        """(frontier size, the process's CPU seconds until the part was ready)."""
        return self.size(), self.start_cpu

    def expand(self, count: int | None, upto: tuple | None, deadline: float) -> tuple[list, int, int, bool, float]:
        """Expand the next ``count`` states of the frontier (or, ``upto``: those whose path is ≤ it), in path
        order, until the wall-clock ``deadline`` (``time.time()``); the successors owned here are merged at once.
        Returns (per part the pickled successors it owns, or None), states expanded, states left, deadline hit,
        CPU seconds."""
        c0 = time.process_time()
        me, n, nact, aindex, big, mix, small = self.me, self.n, self.nact, self.aindex, FRAME_WORLDS, _mix, _small_owner
        seen, cur, fhash, sent, fsent = self.seen, self.cur, self.fhash, self.sent, self.fsent
        new, succ, front = self._new, self.space.successors, self.frontier
        out: list[list] = [[] for _ in range(n)]
        frames: list[list] = [[] for _ in range(n)]
        i, end = self.pos, len(front) if count is None else min(len(front), self.pos + count)
        late = False
        gen = 0
        while i < end:
            path, s = front[i]
            if upto is not None and path > upto:
                break
            if time.time() > deadline:
                late = True
                break
            front[i] = None  # the state is not needed any more
            i += 1
            j = 0
            for name, nxt, key in succ(s):
                elem = j * nact + aindex[name]
                j += 1
                fid = nxt.fid
                fh = fhash.get(fid)
                if fh is None:
                    fh = fhash[fid] = mix(hash((nxt.masks, nxt.points)))
                o = (fh if len(nxt.val) > big else small(nxt.val, nxt.points, fh)) % n  # as _owner
                if o == me:
                    if key in seen:
                        e = cur.get(key)
                        if e is not None:
                            p = path + (elem,)
                            if p < e[0]:
                                e[0] = p
                        continue
                    seen.add(key)
                    new(key, path + (elem,), nxt)
                    continue
                so = sent[o]
                if key in so:  # sent before, with a smaller path (this part expands in path order)
                    continue
                so.add(key)
                if fid not in fsent[o]:
                    fsent[o].add(fid)
                    frames[o].append((fid, nxt.masks, nxt.points))
                out[o].append((nxt.val, fid, path, elem))
            gen += j
        done = i - self.pos
        self.expanded += done
        self.generated += gen
        self.pos = i
        blobs = [None if o == me or not out[o] else pickle.dumps((frames[o], out[o]), pickle.HIGHEST_PROTOCOL)
                 for o in range(n)]
        return blobs, done, len(front) - i, late, time.process_time() - c0

    def merge(self, blobs: list[tuple[int, bytes]]) -> tuple[tuple | None, float]:
        """Merge the successors other parts sent (``(sender, bytes)``); the least path of this layer's goals
        and the CPU seconds."""
        c0 = time.process_time()
        from delkit.compact import CompactState, frame_id

        seen, cur, new, fast = self.seen, self.cur, self._new, self.fast_key
        for src, blob in blobs:
            frames, recs = pickle.loads(blob)
            fm = self.fmap[src]
            for rfid, masks, points in frames:
                fm[rfid] = (frame_id(masks, points), masks, points)
            for val, rfid, ppath, elem in recs:
                lf, masks, points = fm[rfid]
                s = None
                if fast:
                    key = (val, lf)
                else:
                    s = CompactState(val, masks, points, lf)
                    key = s.key
                if key in seen:
                    e = cur.get(key)
                    if e is not None:
                        p = ppath + (elem,)
                        if p < e[0]:
                            e[0] = p
                    continue
                seen.add(key)
                new(key, ppath + (elem,), s if s is not None else CompactState(val, masks, points, lf))
        return min((cur[k][0] for k in self.goals), default=None), time.process_time() - c0

    def next_layer(self) -> int:
        """The new states (not goals, not dead ends) become the frontier, in path order; its size."""
        self.frontier = sorted(((e[0], e[1]) for e in self.cur.values() if e[1] is not None), key=itemgetter(0))
        self.cur = {}
        self.pos = 0
        return len(self.frontier)

    def stats(self) -> tuple[int, int, int, int]:
        """(expanded, generated, dead ends: believes ⊥ + pruned, distinct states seen)."""
        return self.expanded, self.generated, self.space.dead_ends + self.pruned, len(self.seen)


def parallel_bfs(spec: Path, problem: Path | None, jobs: int, *, timeout: float | None = 60.0,
                 max_nodes: int | None = None, engine: str = "auto", allow_inconsistent: bool = False,
                 library: list[Path] | None = None, strict: bool = False, scheduler: str | None = None,
                 stats: dict | None = None):
    """BFS of one task in ``jobs`` parts (this process and ``jobs - 1`` local processes, or actors of the Dask
    cluster at ``scheduler``); a :class:`planners.epistemic.SearchResult` (``search`` = ``"bfs"``) and the
    task, or (None, task) when the task runs on the numpy backend (the caller then searches serially).

    ``stats`` (a dict) receives ``start_cpu`` (each part's process CPU seconds until it was ready: its
    start-up; the helpers' runs alongside the caller's), ``parts_cpu`` (each part's CPU seconds in the
    search's phases), ``phases`` (expand and merge phases, each a barrier) and ``critical_cpu``: the sum over
    phases of the slowest part's CPU — the search's length on idle cores, whatever the machine's load (the
    caller's own coordination and the start-up are outside it)."""
    from delkit.executors import actors
    from delkit.resources import keep_alive
    from planners.epistemic import SearchResult
    from planners.lang import load_task
    from planners.lang.epddl_run import space_for
    from planners.spaces import CompactSpace

    t0 = time.perf_counter()
    limit = float("inf") if timeout is None else timeout
    wall_end = time.time() + limit
    jobs = max(1, int(jobs))
    args = (str(spec), str(problem) if problem else None, [str(p) for p in library or ()], strict, engine,
            allow_inconsistent)
    was = gc.isenabled()
    gc.disable()  # as serial BFS (planners.epistemic._gc_paused): many long-lived objects, no cycles per node
    try:
        with actors(_Part, [(i, jobs, *args) for i in range(1, jobs)], dask=scheduler) as helpers:
            warm = [h.call("started") for h in helpers]  # the helpers read the task while this process does
            task = load_task(spec, problem, list(library or ()), strict=strict,
                             deadline=None if timeout is None else time.monotonic() + timeout)
            space = space_for(task, engine, allow_inconsistent)
            if not isinstance(space, CompactSpace):
                return None, task  # the numpy backend's states are not records: the caller searches serially
            s0, _k0 = space.initial()
            if space.is_goal(s0):
                return SearchResult("solved", (), 0, 1, time.perf_counter() - t0, "bfs",
                                    "the goal holds initially", distinct_states=1), task
            me = _Part(0, jobs, *args, built=(task, space))
            keep_alive(me)  # console script: freeing the search's states must not delay the exit
            try:
                ready = [me.started()] + [w.result(max(0.0, wall_end - time.time())) for w in warm]
            except TimeoutError:  # a worker still starting (a loaded machine) when the time is up
                return SearchResult("limit", None, 0, 1, time.perf_counter() - t0, "bfs",
                                    f"no plan within limits: time limit {limit:g} s reached", 0, 1), task
            sizes = [r[0] for r in ready]
            if stats is not None:
                stats["start_cpu"] = [round(r[1], 3) for r in ready]
            return _coordinate(me, helpers, sizes, task, t0, limit, wall_end, max_nodes,
                               {} if stats is None else stats), task
    finally:
        if was:
            gc.enable()


def _coordinate(me: _Part, helpers: list, sizes: list[int], task: Any, t0: float, limit: float, wall_end: float,
                max_nodes: int | None, stats: dict):
    from delkit.resources import TimeLimit
    from planners.epistemic import SearchResult

    n = 1 + len(helpers)
    expanded = 0

    def run_all(method: str, per_part: list[tuple]) -> list:
        pending = [h.call(method, *per_part[i + 1]) for i, h in enumerate(helpers)]
        first = getattr(me, method)(*per_part[0])
        # a part checks the deadline between states: its reply comes at most one expansion after it
        return [first] + [p.result(max(1.0, wall_end - time.time() + 1.0)) for p in pending]

    def phase(cpus: list[float]) -> None:
        # a phase lasts as long as its slowest part: the rest of the parts' CPU ran alongside it
        for i, c in enumerate(cpus):
            busy[i] += c
        stats["critical_cpu"] += max(cpus)
        stats["phases"] += 1

    def expand_merge(per_part: list[tuple]) -> tuple[tuple | None, list[int], bool]:
        nonlocal expanded
        res = run_all("expand", per_part)
        phase([r[4] for r in res])
        expanded += sum(r[1] for r in res)
        if any(r[3] for r in res):  # the time is up: no merge
            return None, [r[2] for r in res], True
        goals = run_all("merge", [([(src, res[src][0][d]) for src in range(n) if res[src][0][d] is not None],)
                                  for d in range(n)])
        phase([g[1] for g in goals])
        best = min((g[0] for g in goals if g[0] is not None), default=None)
        return best, [r[2] for r in res], any(r[3] for r in res)

    busy = [0.0] * n
    stats.update(critical_cpu=0.0, phases=0, parts_cpu=busy)  # (start_cpu: set by parallel_bfs)

    def done(status: str, plan: tuple | None, reason: str) -> SearchResult:
        st = run_all("stats", [()] * n)
        stats["parts_cpu"] = [round(b, 3) for b in busy]
        stats["critical_cpu"] = round(stats["critical_cpu"], 3)
        return SearchResult(status, plan, expanded, sum(s[1] for s in st), time.perf_counter() - t0, "bfs", reason,
                            sum(s[2] for s in st), sum(s[3] for s in st) - (n - 1))  # the initial state: once

    time_out = f"no plan within limits: time limit {limit:g} s reached"
    try:
        return _layers(me, sizes, task, t0, limit, wall_end, max_nodes, run_all, expand_merge, done, time_out,
                       lambda: expanded)
    except TimeLimit:  # the caller's alarm stopped an expansion of part 0: the workers may be mid-call
        _e, gen, dead, seen = me.stats()
        return SearchResult("limit", None, expanded, gen, time.perf_counter() - t0, "bfs", time_out, dead, seen)


def _layers(me: _Part, sizes: list[int], task: Any, t0: float, limit: float, wall_end: float,
            max_nodes: int | None, run_all: Any, expand_merge: Any, done: Any, time_out: str, count: Any):
    """The layers and rounds of :func:`_coordinate` (``count()``: the states expanded so far)."""
    n = len(sizes)
    names = [a.name for a in task.actions]
    while sum(sizes):
        rounds = max(1, min(ROUNDS, sum(sizes) // (MIN_ROUND * n)))
        chunk = [-(-sz // rounds) for sz in sizes]
        while True:
            if time.perf_counter() - t0 > limit:
                return done("limit", None, time_out)
            expanded = count()
            if max_nodes is not None and expanded >= max_nodes:
                return done("limit", None, f"no plan within limits: expanded-node limit {max_nodes} reached")
            step = chunk if max_nodes is None else [min(c, -(-(max_nodes - expanded) // n)) for c in chunk]
            goal, left, late = expand_merge([(c, None, wall_end) for c in step])
            if late:
                return done("limit", None, time_out)
            if goal is not None:
                # serial BFS's first goal: also expand every state that comes before the best goal's parent
                more, _left, late = expand_merge([(None, goal[:-1], wall_end)] * n)
                if late:
                    return done("limit", None, time_out)
                goal = more if more is not None else goal  # the least goal path: ≤ the one found first
                nact = len(names)
                return done("solved", tuple(names[e % nact] for e in goal), "")
            if not any(left):
                break
        sizes = run_all("next_layer", [()] * n)
    return done("unsolvable", None, "the reachable state space is exhausted: no plan exists")


def run_plan_parallel(spec: Path, problem: Path | None = None, *, jobs: int = 2, search: str = "bfs",
                      as_json: bool = False, timeout: float = 60.0, max_nodes: int | None = None,
                      engine: str = "auto", allow_inconsistent: bool = False, library: list[Path] | None = None,
                      strict: bool = False, scheduler: str | None = None, **rest: Any) -> int:
    """``delkit plan FILE --jobs N`` for one task: :func:`parallel_bfs` (BFS only; other searches and the
    numpy backend run serially, as without ``--jobs``); returns the exit status."""

    from planners.commands import report_search, run_plan

    serial = dict(search=search, as_json=as_json, timeout=timeout, max_nodes=max_nodes, engine=engine,
                  allow_inconsistent=allow_inconsistent, library=library, strict=strict, **rest)
    if search != "bfs":
        return run_plan(spec, problem, **serial)
    from delkit.resources import command_start, parse_timeout

    limit = parse_timeout(timeout)  # counted from the start of the process, as serial plan's (and its watchdog's)
    left = None if limit is None else max(0.0, command_start() + limit - time.monotonic())
    stats: dict = {}
    # the workers and part 0 check the deadline between states (not inside an expansion, as serial plan's alarm
    # does: an alarm would also fire inside the worker pipes' clean-up); the console's watchdog is the backstop
    res, task = parallel_bfs(spec, problem, jobs, timeout=left, max_nodes=max_nodes, engine=engine,
                             allow_inconsistent=allow_inconsistent, library=library, strict=strict,
                             scheduler=scheduler, stats=stats)
    if res is None:
        return run_plan(spec, problem, **serial)
    if res.status == "limit" and "time limit" in res.reason:
        import dataclasses

        res = dataclasses.replace(res, reason=f"no plan within limits: --timeout {timeout:g} s reached (counted "
                                              "from the start of the process) while searching")
    where = f"{jobs} parts on dask {scheduler}" if scheduler else f"{jobs} processes"
    return report_search(res, {**res.to_json(), "task": task.name, "jobs": jobs, "parallel": stats},
                         f"parallel bfs, {where}", as_json)
