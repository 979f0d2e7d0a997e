"""Search for epistemic plans: BFS (optimal length), GBFS and A* over bisimulation-contracted states.

A state is a pointed Kripke model; successors are the product updates M ⊗ E_A (seed 004 §2.1, the
transition function Φ) for every action A executable at the pointed world. States are contracted to
their bisimulation quotient and deduplicated by a canonical key (equal iff the pointed models are
bisimilar), so that bisimilar states are expanded once.

The state spaces live in :mod:`planners.spaces`: the planner picks a delkit backend — the compact bit-set
one (:mod:`delkit.compact`, default) or the numpy one (``--engine del``) — and never implements DEL itself.

No vacuous success: a state where some agent has no accessible world at the pointed world (it believes
⊥) is a dead end and is not expanded (``allow_inconsistent=True`` keeps it).

BFS tests the goal when a state is generated; since every action costs 1 the first plan found is of
minimal length. A* uses the admissible and consistent ``h_pdb`` (the belief-content cover bound ``h_epi`` with
executability chains, and a pattern database per first-order belief goal) and GBFS the goal count ``h_gc``
(:mod:`planners.heuristics`).
"""

from __future__ import annotations

import functools
import gc
import resource
import time
from collections import deque
from collections.abc import Callable, Hashable, Iterator

from delkit._records import DataclassFields, Record
from delkit.errors import PlanningError
from delkit.resources import counters
from planners.spaces import CompactSpace, DelSpace, make_space
from planners.task import Task, goal_conjuncts, has_event_actions

TYPE_CHECKING = False  # typing.TYPE_CHECKING without importing typing (start-up: delkit._records)
if TYPE_CHECKING:
    from typing import Any, Literal, Protocol
else:
    Protocol = object  # StateSpace is a typing.Protocol for the type checkers

__all__ = ["SearchResult", "Limits", "DelSpace", "CompactSpace", "make_space", "plan", "bfs", "best_first",
           "StateSpace", "goal_conjuncts"]

if TYPE_CHECKING:
    Status = Literal["solved", "unsolvable", "limit"]
else:
    Status = str


class Limits(Record):
    """Resource limits of a search: wall seconds, expanded nodes, resident memory (MiB). (This module's records
    are frozen dataclass-compatible records written by hand for start-up time: :mod:`delkit._records`.)"""

    __dataclass_fields__ = DataclassFields(("timeout", 60.0), ("max_expanded", None), ("max_memory_mb", 8192.0))
    timeout: float | None
    max_expanded: int | None
    max_memory_mb: float | None

    def __init__(self, timeout: float | None = 60.0, max_expanded: int | None = None,
                 max_memory_mb: float | None = 8192.0) -> None:
        self.__dict__.update(timeout=timeout, max_expanded=max_expanded, max_memory_mb=max_memory_mb)
        for name, value, rule in (("timeout", self.timeout, ">= 0 (seconds)"),
                                  ("max_expanded", self.max_expanded, ">= 0 (nodes)"),
                                  ("max_memory_mb", self.max_memory_mb, "> 0 (MiB)")):
            if value is None:
                continue
            if not (value > 0 if name == "max_memory_mb" else value >= 0):   # NaN fails too
                raise PlanningError(f"limit {name}={value!r} is impossible: it must be {rule}, or None for "
                                    f"no limit (CLI: --timeout, --max-nodes, --max-memory)")


class SearchResult(Record):
    """Outcome of a search. ``status`` is "solved" (``plan`` is a plan), "unsolvable" (the reachable
    state space was exhausted: no plan exists) or "limit" (a limit was hit: *no plan within limits*)."""

    __dataclass_fields__ = DataclassFields("status", "plan", "expanded", "generated", "seconds", "search",
                                           ("reason", ""), ("dead_ends", 0), ("distinct_states", 0))
    status: Status
    plan: tuple[str, ...] | None
    expanded: int
    generated: int
    seconds: float
    search: str
    reason: str
    dead_ends: int
    distinct_states: int

    def __init__(self, status: Status, plan: tuple[str, ...] | None, expanded: int, generated: int, seconds: float,
                 search: str, reason: str = "", dead_ends: int = 0, distinct_states: int = 0) -> None:
        self.__dict__.update(status=status, plan=plan, expanded=expanded, generated=generated, seconds=seconds,
                             search=search, reason=reason, dead_ends=dead_ends, distinct_states=distinct_states)

    @property
    def solved(self) -> bool:
        return self.status == "solved"

    @property
    def length(self) -> int | None:
        return None if self.plan is None else len(self.plan)

    def to_json(self) -> dict[str, Any]:
        return {"status": self.status, "plan": list(self.plan) if self.plan is not None else None,
                "length": self.length, "expanded": self.expanded, "generated": self.generated,
                "seconds": round(self.seconds, 4), "search": self.search, "reason": self.reason,
                "dead_ends": self.dead_ends, "distinct_states": self.distinct_states}


class StateSpace(Protocol):
    """What the search needs from a state representation."""

    def initial(self) -> tuple[Any, Hashable]: ...

    def successors(self, state: Any) -> Iterator[tuple[str, Any, Hashable]]: ...

    def is_goal(self, state: Any) -> bool: ...

    def goal_count(self, state: Any) -> int: ...

    dead_ends: int


class _Budget:
    def __init__(self, limits: Limits) -> None:
        self.limits = limits
        self.t0 = time.perf_counter()
        self.base_rss = _rss_mb()

    def exceeded(self, expanded: int) -> str:
        lim = self.limits
        if lim.max_expanded is not None and expanded >= lim.max_expanded:
            return f"expanded-node limit {lim.max_expanded} reached"
        if lim.timeout is not None and time.perf_counter() - self.t0 > lim.timeout:
            return f"time limit {lim.timeout:g} s reached"
        if lim.max_memory_mb is not None and expanded % 64 == 0 and _rss_mb() > lim.max_memory_mb:
            return f"memory limit {lim.max_memory_mb:g} MiB reached"
        return ""

    @property
    def seconds(self) -> float:
        return time.perf_counter() - self.t0


def _rss_mb() -> float:
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0


def _path(parent: dict, key: Hashable) -> tuple[str, ...]:
    out: list[str] = []
    while parent[key] is not None:
        key, act = parent[key]
        out.append(act)
    return tuple(reversed(out))


def _gc_paused(search: Callable[..., SearchResult]) -> Callable[..., SearchResult]:
    """Run a search with Python's cyclic garbage collector paused (restored afterwards). A search keeps
    hundreds of thousands of states, keys and frontier entries alive; the collector re-scans them as they
    age — a quarter of the CPU of a long BFS (Selective-Communication: 19.4 → 14.5 s). The searches and
    state spaces create no reference cycles per node (measured: what a collection finds after a 20,000-node
    BFS is a constant ~1,000 objects of set-up; ~1.6 objects a node on the numpy backend), so reference
    counting frees everything as before."""
    @functools.wraps(search)
    def run(*args: Any, **kwargs: Any) -> SearchResult:
        was = gc.isenabled()
        gc.disable()
        try:
            return search(*args, **kwargs)
        finally:
            resume_collector(was)
    return run


def resume_collector(was: bool) -> None:
    """Re-enable the collector after a search (if it was enabled before). In the console script
    (``resources.HARD_EXIT``: the process leaves by ``os._exit`` soon) the objects still alive — the state space
    and its caches, allocated while the collector was paused, so all in its youngest generation — are first
    frozen out of it: the next allocation would otherwise have the collector traverse every one of them
    (Grapevine-5 pl6: 0.3–0.55 s CPU). A library caller's objects are left to the collector as usual."""
    if not was:
        return
    from delkit import resources

    if resources.HARD_EXIT:
        gc.freeze()
    gc.enable()


@_gc_paused
def bfs(space: StateSpace, limits: Limits = Limits(), *, prune: bool = True) -> SearchResult:
    """Breadth-first search with duplicate detection; goal test at generation (optimal length).

    ``prune``: states that h_epi proves dead ends (a goal conjunct no action can make true again is false:
    :func:`planners.heuristics.dead_end_test`) are recorded as seen but not expanded — the same plan, fewer
    expansions; they are counted in ``dead_ends``."""
    budget = _Budget(limits)
    s0, k0 = space.initial()
    if space.is_goal(s0):
        return SearchResult("solved", (), 0, 1, budget.seconds, "bfs", "the goal holds initially",
                            distinct_states=1)
    dead = None
    if prune and getattr(space, "task", None) is not None:
        from planners.heuristics import dead_end_test

        dead = dead_end_test(space)
    parent: dict[Hashable, Any] = {k0: None}
    frontier: deque = deque([(s0, k0)])
    expanded = generated = pruned = 0
    live = counters()  # the counts so far, for a limit answer given from outside this loop (alarm, watchdog)
    while frontier:
        live["expanded"], live["generated"] = expanded, generated
        why = budget.exceeded(expanded)
        if why:
            return SearchResult("limit", None, expanded, generated, budget.seconds, "bfs", "no plan within "
                                "limits: " + why, space.dead_ends + pruned, len(parent))
        state, key = frontier.popleft()
        expanded += 1
        for name, nxt, nkey in space.successors(state):
            generated += 1
            if nkey in parent:
                continue
            parent[nkey] = (key, name)
            if space.is_goal(nxt):
                return SearchResult("solved", _path(parent, nkey), expanded, generated, budget.seconds, "bfs",
                                    "", space.dead_ends + pruned, len(parent))
            if dead is not None and dead(nxt):
                pruned += 1
                continue
            frontier.append((nxt, nkey))
    return SearchResult("unsolvable", None, expanded, generated, budget.seconds, "bfs",
                        "the reachable state space is exhausted: no plan exists", space.dead_ends + pruned,
                        len(parent))


@_gc_paused
def best_first(space: StateSpace, limits: Limits = Limits(), *, kind: Literal["gbfs", "astar"] = "gbfs",
               h: Callable[[Any], float] | None = None) -> SearchResult:
    """GBFS (f = h) or A* (f = g + h) with duplicate detection.

    Default heuristics: GBFS uses the goal count h_gc (unsatisfied top-level goal conjuncts; informative,
    not admissible); A* uses h_pdb (the largest of h_epi — the observer cover with the belief-content argument —,
    the executability chains of the pointed world's fluents, and per first-order belief goal the exact distance
    in an abstraction of the believer's and the tellers' views; :func:`planners.heuristics.h_pdb`), admissible
    and consistent, so A* (goal test at expansion, no reopening) returns plans of optimal length.
    """
    budget = _Budget(limits)
    if h is None:
        from planners.heuristics import h_gc, h_pdb

        h = h_gc(space) if kind == "gbfs" else h_pdb(space)
    from heapq import heappop, heappush  # here: BFS, the default, needs no heap (start-up)

    s0, k0 = space.initial()
    best_g: dict[Hashable, int] = {k0: 0}
    parent: dict[Hashable, Any] = {k0: None}
    counter = 0
    h0 = h(s0)
    if h0 == float("inf"):
        return SearchResult("unsolvable", None, 0, 1, budget.seconds, kind, "the heuristic proves the goal "
                            "unreachable: a false goal conjunct that no action can change", 0, 1)
    # ties: A* prefers the deeper node (fewer expansions, still optimal with a consistent h); GBFS the
    # shallower one (shorter plans)
    tie = -1 if kind == "astar" else 1
    heap: list = [(h0, 0, counter, s0, k0)]
    expanded = generated = 0
    closed: set[Hashable] = set()
    live = counters()  # the counts so far (see bfs)
    while heap:
        live["expanded"], live["generated"] = expanded, generated
        why = budget.exceeded(expanded)
        if why:
            return SearchResult("limit", None, expanded, generated, budget.seconds, kind,
                                "no plan within limits: " + why, space.dead_ends, len(parent))
        _, tg, _, state, key = heappop(heap)
        g = tg * tie
        if key in closed:
            continue
        if space.is_goal(state):
            return SearchResult("solved", _path(parent, key), expanded, generated, budget.seconds, kind, "",
                                space.dead_ends, len(parent))
        closed.add(key)
        expanded += 1
        for name, nxt, nkey in space.successors(state):
            generated += 1
            ng = g + 1
            if nkey in closed or best_g.get(nkey, 1 << 60) <= ng:
                continue
            best_g[nkey] = ng
            parent[nkey] = (key, name)
            counter += 1
            hv = h(nxt)
            if hv == float("inf"):
                continue
            f = hv if kind == "gbfs" else ng + hv
            heappush(heap, (f, tie * ng, counter, nxt, nkey))
    return SearchResult("unsolvable", None, expanded, generated, budget.seconds, kind,
                        "the reachable state space is exhausted: no plan exists", space.dead_ends, len(parent))


def plan(task: Task, *, search: Literal["bfs", "gbfs", "astar"] = "bfs", limits: Limits = Limits(),
         engine: Literal["fast", "compact", "del"] = "fast", allow_inconsistent: bool | None = None) -> SearchResult:
    """Plan for ``task`` with the chosen search; never raises on a failed search (see ``status``).

    ``allow_inconsistent`` None (the default): as ``delkit plan`` and the plan checker decide — a task with
    event-model actions (EPDDL 2026) keeps states where an agent believes ⊥ (EPDDL's and plank's semantics),
    any other prunes them."""
    if allow_inconsistent is None:
        allow_inconsistent = has_event_actions(task)
    space = make_space(task, engine=engine, allow_inconsistent=allow_inconsistent)
    if search == "bfs":
        return bfs(space, limits)
    if search in ("gbfs", "astar"):
        return best_first(space, limits, kind=search)
    raise PlanningError(f"unknown search {search!r}; use bfs, gbfs or astar")
