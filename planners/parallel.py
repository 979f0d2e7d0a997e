"""Parallel breadth-first search of one task: ``delkit plan FILE --jobs N`` (N ≥ 2) on a single task.

Hash-distributed, layer-synchronous BFS on the compact backend, in N *parts*: the calling process is part 0
and N-1 actors (:func:`delkit.executors.actors`: spawned local processes, or actors of a Dask cluster with
``scheduler``) are the others; each reads the task once and keeps its own compact engine. A state belongs to
the part its canonical record hashes to (by its frame if it has more than :data:`FRAME_WORLDS` worlds, else by
the set of its worlds' valuations — ints and tuples of ints hash alike in every process); each part keeps
the visited set of its own states, expands its own frontier and deduplicates what it is sent, so expansion
*and* duplicate detection run in parallel and the caller only coordinates the layers and forwards the bytes
between parts.

A successor owned by another part travels as (valuations, frame number, the parent's path, step) with the
frames (successor masks, designated worlds) that part has not been sent before — a frame is shared by many
states — and a part never sends a state twice (it expands in path order, so the first copy it sent had the
smaller path). Keys are the serial search's own ``(valuations, frame)``, so duplicate detection is exact.

Same plan as serial :func:`planners.epistemic.bfs`: serial BFS gives each state the first (parent's rank,
successor position) that generates it and stops at the first goal generated, i.e. the lexicographically
least sequence of successor positions among shortest paths (through non-pruned states). Every state here
carries that sequence (its *path*: position × number of actions + action index, so the plan is read off
it); a part keeps the least path of every new state and its frontier is sorted by it. The goal test is the
generating part's (at generation, as serially; a goal is not sent), and the first goal a part generates is
its least; it publishes the goal's parent's path at once (:class:`_Bound`, shared memory), and every part
stops its layer at its first state past the least published bound — having expanded all of its states up to
the least goal's parent, so the least goal path of all parts is serial BFS's plan. A layer is therefore one
phase (one barrier): a part merges what the others sent it during the previous layer, sorts its new
frontier and expands it. (Dask's actors do not share the bound: their layers are expanded in rounds,
and after a round that finds a goal, one more round expands every part's states up to the goal's parent.)
Goal test at generation, the same dead-end pruning (h_epi's dead ends are seen but not expanded) and the same
believes-⊥ rule, as the parts run the serial search's state space.

What limits the speed-up (measured in ``bench/RESULTS-planner.md`` §10, §15): the caches of the state space
and the compact engine are per process, so each part fills its own — the candidate actions per designated
valuation, the transition tables, the product *shapes* per frame (whose look-ups the engine turns off while
few of them hit) and the commutation memo of the serial space (a sensing's successor predicted from two
known transitions: a part sends the transitions it computes to the parts owning their successors,
:meth:`_Part._forward`, but a sibling's transition computed by another part in the same layer comes too late
— on the CC task the parts apply 7 % more products than serial BFS, 24 % without the forwarding); each part's
own start-up (reading the task, overlapped with the caller's); the
imbalance of the parts in each layer; and the successors sent between parts (pickled once, unpickled once, a
frame only the first time a part sends it).
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
#: part: the compact engine caches a product's shape per frame); smaller ones by the set of their worlds'
#: valuations (the engine's tables per event and valuation, and the space's candidate actions per designated
#: valuation, are filled once per process: Selective-Communication's parts compute 1.05 M table entries and
#: 11,686 candidate lists, as serial BFS does, against 1.32 M and 15,122 when owned by frame and designated
#: valuation — the parts' CPU −14 %)
FRAME_WORLDS = 16
#: send the transitions of commuting actions to the parts owning their successors (:meth:`_Part._forward`)
FORWARD = True


_MUL, _LOW64 = 0x9E3779B97F4A7C15, 0xFFFFFFFFFFFFFFFF


def _mix(h: int) -> int:
    """The high bits of a multiplicative hash of ``h``: Python's tuple hashes are not uniform modulo small
    numbers (their low bits follow the tuples' structure), which would give one part most of a kind of state."""
    return ((h * _MUL) & _LOW64) >> 32


def _first_visit(seen: set, cur: dict, key: Any, path: tuple, elem: Any) -> bool:
    """Whether ``key`` is new to this part (then it is recorded as seen). A key seen before that is still in the
    current layer keeps the least of its paths (``path + (elem,)`` if smaller): the parts' merged layers then
    hold serial BFS's parents."""
    if key in seen:
        e = cur.get(key)
        if e is not None:
            p = path + (elem,)
            if p < e[0]:
                e[0] = p
        return False
    seen.add(key)
    return True

class _Bound:
    """The least goal path's parent found so far in the last layer, shared by the parts of local processes
    (a lock-protected array of int64: a version, the path's length, the path): a part stops expanding its
    frontier at the first state past it. Only a hint for speed — a part that has not seen it yet expands more
    states than needed, never fewer — so the plan does not depend on when it is read."""

    SIZE = 512  #: paths (layers) longer than this are not shared: the parts then expand their whole last layer

    def __init__(self, array: Any) -> None:
        self.array, self.raw, self.version, self.path = array, array.get_obj(), 0, None

    @classmethod
    def new(cls) -> Any:
        import multiprocessing

        return multiprocessing.get_context("spawn").Array("q", 2 + cls.SIZE, lock=True)

    def read(self) -> tuple | None:
        """The bound (a path) or None; the array is read under its lock only when its version changed."""
        if self.raw[0] != self.version:
            with self.array.get_lock():
                self.version, length = self.raw[0], self.raw[1]
                self.path = tuple(self.raw[2:2 + length])
        return self.path

    def offer(self, path: tuple) -> None:
        """Publish ``path`` if it is less than the bound (or there is none)."""
        if len(path) > self.SIZE:
            return
        with self.array.get_lock():
            raw = self.raw
            if raw[0] and raw[1] == len(path) and tuple(raw[2:2 + raw[1]]) <= path:
                return
            raw[2:2 + len(path)] = path
            raw[1] = len(path)
            raw[0] += 1


class _Part:
    """One part of the search (module docstring): its visited set, its frontier, the layer being built."""

    def __init__(self, me: int, n: int, spec: str, problem: str | None, library: list[str], strict: bool,
                 engine: str, allow_inconsistent: bool, bound: Any = None, built: tuple | None = None) -> None:
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
        self.bound = None if bound is None else _Bound(bound)
        self.dead = dead_end_test(space)  # as serial BFS: proven dead ends are seen but not expanded
        self.nact = len(task.actions)
        self.aindex = {a.name: i for i, a in enumerate(task.actions)}
        self.seen: set = set()
        self.cur: dict = {}  # key -> [least path, state (None: a pruned dead end)] of the layer being built
        self.goal: tuple | None = None  # the least goal path this part generated (in the last layer)
        self.fhash: dict[int, int] = {}  # local frame number -> hash of the frame
        self.sent: list[set] = [set() for _ in range(n)]  # keys sent to each part
        self.fsent: list[set] = [set() for _ in range(n)]  # frame numbers each part has been sent
        self.fmap: list[dict] = [{} for _ in range(n)]  # per sending part: its frame number -> ours
        self.expanded = self.generated = self.pruned = 0
        s0, k0 = space.initial()
        self.fast_key = k0 == (s0.val, s0.fid)  # the key is (valuations, frame number): built without a state
        # the actions whose transitions the state space memoises (their keys must be (valuations, frame number))
        self.commute = (getattr(space, "_commute", None) or None) if self.fast_key and FORWARD else None
        self.seen.add(k0)
        self.frontier: list = [((), s0)] if self._owner(s0) == me else []
        self.pos = 0
        self.chunk = len(self.frontier)
        self.start_cpu = time.process_time()  # this process's CPU until the part is ready (its start-up)

    def _owner(self, s: Any) -> int:
        if len(s.val) <= FRAME_WORLDS:
            return _mix(hash(frozenset(s.val))) % self.n
        fh = self.fhash.get(s.fid)
        if fh is None:
            fh = self.fhash[s.fid] = _mix(hash((s.masks, s.points)))
        return fh % self.n

    def started(self) -> tuple[int, float]:
        """(frontier size, the process's CPU seconds until the part was ready)."""
        return len(self.frontier), self.start_cpu

    def step(self, inbox: list[tuple[int, bytes]], new_layer: bool, rounds: int, budget: int | None,
             upto: tuple | None, deadline: float) -> tuple[list, int, int, tuple | None, bool, int, float]:
        """One phase: merge the successors other parts sent (``(sender, bytes)``: states of the layer being
        built); if ``new_layer``, the layer built becomes the frontier (in path order; its states expanded in
        ``rounds`` slices); then expand the frontier's next slice (at most ``budget`` states; with ``upto``,
        exactly the states whose path is ≤ it), in path order, up to the shared bound and until the wall-clock
        ``deadline`` (``time.time()``). Successors owned here are merged at once; a goal among the successors
        (tested by the part that generates it) is not kept. Returns (per part the pickled successors it owns,
        or None), states expanded, states left, the least goal path generated so far, deadline hit, frontier
        size, CPU seconds."""
        c0 = time.process_time()
        if inbox:
            self._merge(inbox)
        if new_layer:
            self.frontier = sorted(((e[0], e[1]) for e in self.cur.values() if e[1] is not None),
                                   key=itemgetter(0))
            self.cur = {}
            self.pos = 0
            self.chunk = max(MIN_ROUND, -(-len(self.frontier) // max(1, rounds)))
        me, n, nact, aindex, big, mix = self.me, self.n, self.nact, self.aindex, FRAME_WORLDS, _mix
        seen, cur, fhash, sent, fsent = self.seen, self.cur, self.fhash, self.sent, self.fsent
        succ, front, is_goal, dead, bound = (self.space.successors, self.frontier, self.space.is_goal, self.dead,
                                             self.bound)
        out: list[list] = [[] for _ in range(n)]
        frames: list[list] = [[] for _ in range(n)]
        mem: list[list] = [[] for _ in range(n)]  # per part: transitions of commuting actions (see _forward)
        commute = self.commute
        i = self.pos
        end = len(front) if upto is not None else min(len(front), i + self.chunk)
        if budget is not None:
            end = min(end, i + max(0, budget))
        late = False
        gen = done = 0
        stops = [p for p in (upto, None if self.goal is None else self.goal[:-1]) if p is not None]
        stop = min(stops) if stops else None  # expand no state past this path (None: no goal known yet)
        while i < end:
            path, s = front[i]
            if bound is not None:
                b = bound.read()
                if b is not None and (stop is None or b < stop):
                    stop = b
            if stop is not None and path > stop:
                i = len(front)  # the states left need no expansion: the goal's layer ends here
                break
            if time.time() > deadline:
                late = True
                break
            front[i] = None  # the state is not needed any more
            i += 1
            done += 1
            j = 0
            moved: list = []  # (action, successor, its part) of the commuting actions, for _forward
            for name, nxt, key in succ(s):
                elem = j * nact + aindex[name]
                j += 1
                fid, nval = nxt.fid, nxt.val
                if len(nval) > big:  # as _owner
                    fh = fhash.get(fid)
                    if fh is None:
                        fh = fhash[fid] = mix(hash((nxt.masks, nxt.points)))
                    o = fh % n
                else:
                    o = (((hash(frozenset(nval)) * _MUL) & _LOW64) >> 32) % n
                if commute is not None and name in commute:
                    moved.append((name, nxt, o))
                if o == me:
                    if not _first_visit(seen, cur, key, path, elem):
                        continue
                else:
                    so = sent[o]
                    if key in so:  # sent before, with a smaller path (this part expands in path order)
                        continue
                    so.add(key)
                if is_goal(nxt):  # goal test at generation, as serial BFS (the least path: the first one here)
                    if self.goal is None:
                        self.goal = path + (elem,)
                        if bound is not None:
                            bound.offer(path)
                        if stop is None or path < stop:
                            stop = path
                    continue
                if o == me:
                    if dead is not None and dead(nxt):
                        cur[key] = [path + (elem,), None]
                        self.pruned += 1
                    else:
                        cur[key] = [path + (elem,), nxt]
                    continue
                if fid not in fsent[o]:
                    fsent[o].add(fid)
                    frames[o].append((fid, nxt.masks, nxt.points))
                out[o].append((nval, fid, path, elem))
            gen += j
            if moved:
                self._forward(s, moved, mem, frames)
        self.expanded += done
        self.generated += gen
        self.pos = i
        blobs = [None if o == me or not (out[o] or mem[o])
                 else pickle.dumps((frames[o], out[o], mem[o]), pickle.HIGHEST_PROTOCOL) for o in range(n)]
        return blobs, done, len(front) - i, self.goal, late, len(front), time.process_time() - c0

    def _forward(self, s: Any, moved: list, mem: list, frames: list) -> None:
        """Send the transitions of ``s`` by commuting actions to the parts that own their successors: the state
        space predicts a sensing's successor from them (``CompactSpace._predicted``: s·a from p·b = s, p·a and
        p·a·b), and a part records only the transitions it computes — so the owner of p·b would miss p's. The
        receiver records them as its own (keys translated to its frame numbers)."""
        me, fsent = self.me, self.fsent
        for o in {o for _n, _x, o in moved if o != me}:
            fs, fr = fsent[o], frames[o]
            if s.fid not in fs:
                fs.add(s.fid)
                fr.append((s.fid, s.masks, s.points))
            moves = []
            for name, x, _o in moved:
                if x.fid not in fs:
                    fs.add(x.fid)
                    fr.append((x.fid, x.masks, x.points))
                moves.append((name, x.val, x.fid))
            mem[o].append((s.val, s.fid, moves))

    def _merge(self, blobs: list[tuple[int, bytes]]) -> None:
        """Merge the successors other parts sent (``(sender, bytes)``; none is a goal: its sender tested it)."""
        from delkit.backends.compact import CompactState, frame_id

        seen, cur, fast, dead = self.seen, self.cur, self.fast_key, self.dead
        for src, blob in blobs:
            frames, recs, mems = pickle.loads(blob)
            fm = self.fmap[src]
            for rfid, masks, points in frames:
                fm[rfid] = (frame_id(masks, points), masks, points)
            remember = self.space._remember
            for pval, prf, moves in mems:
                kp = (pval, fm[prf][0])
                for name, val, rfid in moves:
                    remember(kp, name, (val, fm[rfid][0]))
            for val, rfid, ppath, elem in recs:
                lf, masks, points = fm[rfid]
                s = None
                if fast:
                    key = (val, lf)
                else:
                    s = CompactState(val, masks, points, lf)
                    key = s.key
                if not _first_visit(seen, cur, key, ppath, elem):
                    continue
                if s is None:
                    s = CompactState(val, masks, points, lf)
                if dead is not None and dead(s):
                    cur[key] = [ppath + (elem,), None]
                    self.pruned += 1
                else:
                    cur[key] = [ppath + (elem,), s]

    def stats(self) -> tuple[int, int, int, int]:
        """(expanded, generated, dead ends: believes ⊥ + pruned, distinct states seen)."""
        return self.expanded, self.generated, self.space.dead_ends + self.pruned, len(self.seen)


def parallel_bfs(spec: Path, problem: Path | None, jobs: int, *, timeout: float | None = 60.0,
                 max_nodes: int | None = None, engine: str = "auto", allow_inconsistent: bool = False,
                 library: list[Path] | None = None, strict: bool = False, scheduler: str | None = None,
                 stats: dict | None = None, rounds: int | None = None, share_goal: bool | None = None):
    """BFS of one task in ``jobs`` parts (this process and ``jobs - 1`` local processes, or actors of the Dask
    cluster at ``scheduler``); a :class:`planners.epistemic.SearchResult` (``search`` = ``"bfs"``) and the
    task, or (None, task) when the task runs on the numpy backend (the caller then searches serially).

    ``share_goal``: the parts share the least goal's parent as soon as one generates it (:class:`_Bound`; by
    default with local processes, not on Dask). ``rounds``: the phases a layer is expanded in (default: 1 when
    the parts share the goal, else :data:`ROUNDS`: a round's barrier is where they learn of a goal).

    ``stats`` (a dict) receives ``start_cpu`` (each part's process CPU seconds until it was ready: its
    start-up; the helpers' runs alongside the caller's), ``parts_cpu`` (each part's CPU seconds in the
    search's phases), ``phases`` (each a barrier), ``layers`` and ``critical_cpu``: the sum over phases of the
    slowest part's CPU — the search's length on idle cores, whatever the machine's load (the caller's own
    coordination and the start-up are outside it)."""
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
    bound = _Bound.new() if (not scheduler if share_goal is None else share_goal) else None
    if rounds is None:
        rounds = ROUNDS if bound is None else 1
    args = (str(spec), str(problem) if problem else None, [str(p) for p in library or ()], strict, engine,
            allow_inconsistent, bound)
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
            if stats is not None:
                stats["start_cpu"] = [round(r[1], 3) for r in ready]
            return _coordinate(me, helpers, task, t0, limit, wall_end, max_nodes, rounds,
                               {} if stats is None else stats), task
    finally:
        from planners.epistemic import resume_collector

        resume_collector(was)  # console script: the search's objects frozen out of the collector first


def _coordinate(me: _Part, helpers: list, task: Any, t0: float, limit: float, wall_end: float,
                max_nodes: int | None, rounds: int, stats: dict):
    from delkit.resources import TimeLimit
    from planners.epistemic import SearchResult

    n = 1 + len(helpers)
    expanded = 0
    busy = [0.0] * n
    stats.update(critical_cpu=0.0, phases=0, layers=1, parts_cpu=busy)  # (start_cpu: set by parallel_bfs)

    def run_all(method: str, per_part: list[tuple]) -> list:
        pending = [h.call(method, *per_part[i + 1]) for i, h in enumerate(helpers)]
        first = getattr(me, method)(*per_part[0])
        # a part checks the deadline between states: its reply comes at most one expansion after it
        return [first] + [p.result(max(1.0, wall_end - time.time() + 1.0)) for p in pending]

    def done(status: str, plan: tuple | None, reason: str) -> SearchResult:
        st = run_all("stats", [()] * n)
        stats["parts_cpu"] = [round(b, 3) for b in busy]
        stats["critical_cpu"] = round(stats["critical_cpu"], 3)
        return SearchResult(status, plan, expanded, sum(s[1] for s in st), time.perf_counter() - t0, "bfs", reason,
                            sum(s[2] for s in st), sum(s[3] for s in st) - (n - 1))  # the initial state: once

    time_out = f"no plan within limits: time limit {limit:g} s reached"
    names = [a.name for a in task.actions]
    inbox: list[list] = [[] for _ in range(n)]
    new_layer, upto = False, None
    try:
        while True:
            if time.perf_counter() - t0 > limit:
                return done("limit", None, time_out)
            if max_nodes is not None and expanded >= max_nodes:
                return done("limit", None, f"no plan within limits: expanded-node limit {max_nodes} reached")
            budget = None if max_nodes is None else -(-(max_nodes - expanded) // n)
            res = run_all("step", [(inbox[d], new_layer, rounds, budget, upto, wall_end) for d in range(n)])
            cpus = [r[6] for r in res]  # a phase lasts as long as its slowest part: the others ran alongside it
            for i, c in enumerate(cpus):
                busy[i] += c
            stats["critical_cpu"] += max(cpus)
            stats["phases"] += 1
            expanded += sum(r[1] for r in res)
            if any(r[4] for r in res):
                return done("limit", None, time_out)
            if new_layer and not any(r[5] for r in res):
                return done("unsolvable", None, "the reachable state space is exhausted: no plan exists")
            inbox = [[(src, res[src][0][d]) for src in range(n) if res[src][0][d] is not None] for d in range(n)]
            goal = min((r[3] for r in res if r[3] is not None), default=None)
            if goal is not None and (upto is not None or not any(r[2] for r in res)):
                nact = len(names)  # every state up to the least goal's parent is expanded: serial BFS's plan
                return done("solved", tuple(names[e % nact] for e in goal), "")
            if goal is not None:  # (rounds: the parts did not all see the goal) expand up to its parent
                upto, inbox, new_layer = goal[:-1], [[] for _ in range(n)], False
                continue
            new_layer = not any(r[2] for r in res)
            stats["layers"] += new_layer
    except TimeLimit:  # the caller's alarm stopped an expansion of part 0: the workers may be mid-call
        _e, gen, dead, seen = me.stats()
        return SearchResult("limit", None, expanded, gen, time.perf_counter() - t0, "bfs", time_out, dead, seen)


def run_plan_parallel(spec: Path, problem: Path | None = None, *, jobs: int = 2, search: str = "bfs",
                      as_json: bool = False, timeout: float = 60.0, max_nodes: int | None = None,
                      engine: str = "auto", allow_inconsistent: bool = False, library: list[Path] | None = None,
                      strict: bool = False, scheduler: str | None = None, **rest: Any) -> int:
    """``delkit plan FILE --jobs N`` for one task: :func:`parallel_bfs` (BFS only; other searches, the
    numpy backend and ``--consistent-beliefs`` run serially, as without ``--jobs``); returns the exit status."""

    from planners.commands import report_search, run_plan

    serial = dict(search=search, as_json=as_json, timeout=timeout, max_nodes=max_nodes, engine=engine,
                  allow_inconsistent=allow_inconsistent, library=library, strict=strict, **rest)
    if search != "bfs" or rest.get("consistent_beliefs"):  # --consistent-beliefs: the serial search
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
