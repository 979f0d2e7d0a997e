"""Search for epistemic plans: BFS (optimal length), GBFS and A* over bisimulation-contracted states.

A state is a pointed Kripke model; successors are the product updates M ⊗ E_A (seed 004 §2.1, the
transition function Φ) for every action A executable at the pointed world. States are contracted to
their bisimulation quotient and deduplicated by a canonical key (equal iff the pointed models are
bisimilar), so that bisimilar states are expanded once.

The state spaces live in :mod:`planners.spaces`: the planner picks a delkit backend — the compact bit-set
one (:mod:`delkit.backends.compact`, default) or the numpy one (``--engine del``) — and never implements DEL itself.

States where some agent has no accessible world at a designated world (it believes ⊥): one function,
:func:`planners.beliefs.belief_semantics`, decides whether they are kept (``reference``: plank's semantics, the
default on EPDDL 2026 tasks) or pruned (``consistent``: the default on mA* and E-PDDL, ``--consistent-beliefs``);
a plan whose goal holds only vacuously lists the conjuncts in ``SearchResult.vacuous``.

BFS tests the goal when a state is generated; since every action costs 1 the first plan found is of
minimal length. Satisficing: GBFS, and novelty search (:func:`novelty_search`, BFWS-style: novelty of the
designated valuations and of beliefs, then the goal count); ``--search auto`` (:func:`portfolio`) runs novelty,
GBFS and A* in one time budget, anytime. A* uses the admissible and consistent ``h_pdb`` (the belief-content cover bound ``h_epi`` with
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
from planners.task import Task, goal_conjuncts

TYPE_CHECKING = False  # typing.TYPE_CHECKING without importing typing (start-up: delkit._records)
if TYPE_CHECKING:
    from typing import Any, Literal, Protocol
else:
    Protocol = object  # StateSpace is a typing.Protocol for the type checkers

__all__ = ["SearchResult", "Limits", "DelSpace", "CompactSpace", "make_space", "plan", "bfs", "best_first",
           "novelty_search", "portfolio", "run_search", "SEARCHES", "PORTFOLIO", "annotate", "final_state",
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
                                           ("reason", ""), ("dead_ends", 0), ("distinct_states", 0),
                                           ("vacuous", ()), ("semantics", ""), ("phases", ()), ("optimal", None))
    status: Status
    plan: tuple[str, ...] | None
    expanded: int
    generated: int
    seconds: float
    search: str
    reason: str
    dead_ends: int
    distinct_states: int
    #: goal conjuncts of the final state that hold only because an agent they mention believes ⊥
    #: (:func:`planners.beliefs.vacuous_goals`); filled by :func:`plan` and ``delkit plan``
    vacuous: tuple[dict, ...]
    #: the semantics of inconsistent beliefs searched in (:func:`planners.beliefs.belief_semantics`)
    semantics: str
    #: a portfolio's phases (:func:`portfolio`): one dict per phase run, with the plans it improved
    phases: tuple[dict, ...]
    #: whether the plan's length is proven minimal (BFS, A* with an admissible h); None: not said
    optimal: bool | None

    def __init__(self, status: Status, plan: tuple[str, ...] | None, expanded: int, generated: int, seconds: float,
                 search: str, reason: str = "", dead_ends: int = 0, distinct_states: int = 0,
                 vacuous: tuple[dict, ...] = (), semantics: str = "", phases: tuple[dict, ...] = (),
                 optimal: bool | None = None) -> None:
        self.__dict__.update(status=status, plan=plan, expanded=expanded, generated=generated, seconds=seconds,
                             search=search, reason=reason, dead_ends=dead_ends, distinct_states=distinct_states,
                             vacuous=tuple(vacuous), semantics=semantics, phases=tuple(phases), optimal=optimal)

    def replace(self, **changes: Any) -> SearchResult:
        """A copy with some fields changed."""
        return SearchResult(**{**{f: getattr(self, f) for f in self.__dataclass_fields__}, **changes})

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
                "dead_ends": self.dead_ends, "distinct_states": self.distinct_states,
                **({"semantics": self.semantics} if self.semantics else {}),
                **({"vacuous": list(self.vacuous)} if self.status == "solved" else {}),
                **({"optimal": self.optimal} if self.optimal is not None else {}),
                **({"phases": list(self.phases)} if self.phases else {})}


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


def _expand_new(space: StateSpace, state: Any, key: Hashable, parent: dict[Hashable, Any],
                fresh: Callable[[Any, Hashable], None]) -> tuple[int, Hashable | None]:
    """Generate ``state``'s successors in order, record in ``parent`` each one first reached here, and hand it
    to ``fresh(state, key)`` — stopping at the first goal among them (the goal test at generation of BFS and
    novelty search). Returns (successors generated, the goal's key or None)."""
    n = 0
    for name, nxt, nkey in space.successors(state):
        n += 1
        if nkey in parent:
            continue
        parent[nkey] = (key, name)
        if space.is_goal(nxt):
            return n, nkey
        fresh(nxt, nkey)
    return n, None


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

    def keep(nxt: Any, nkey: Hashable) -> None:
        nonlocal pruned
        if dead is not None and dead(nxt):
            pruned += 1
        else:
            frontier.append((nxt, nkey))

    while frontier:
        live["expanded"], live["generated"] = expanded, generated
        why = budget.exceeded(expanded)
        if why:
            return SearchResult("limit", None, expanded, generated, budget.seconds, "bfs", "no plan within "
                                "limits: " + why, space.dead_ends + pruned, len(parent))
        state, key = frontier.popleft()
        expanded += 1
        n, goal = _expand_new(space, state, key, parent, keep)
        generated += n
        if goal is not None:
            return SearchResult("solved", _path(parent, goal), expanded, generated, budget.seconds, "bfs",
                                "", space.dead_ends + pruned, len(parent))
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


def novelty_atoms(space: StateSpace, *, epistemic: bool = True) -> Callable[[Any], tuple[Hashable, ...]]:
    """The atoms of a state for novelty: each proposition's value at each designated world's valuation, as the
    set of valuations of the designated worlds (``("v", p, value)`` for a proposition true or false at every
    designated world, ``("v?", p)`` when they differ), and the truth value of every modal subformula of the goal
    at the designated worlds (``("f", i, value)``) — with ``epistemic`` (the default) also of ``K_a p`` and ``K_a ¬p``
for every agent a and proposition p of the goal (a measured addition: without it a task whose actions only
inform, such as the spy family, has no new atom after the first step). Classical BFWS's atoms are the state's facts; an epistemic
    state's facts are its designated valuations, and its epistemic content that the goal can see is the truth
    of the goal's modal subformulas."""
    from delkit.logic.formula import Prop, is_propositional, subformulas

    task = getattr(space, "task", None)
    forms: list[Any] = []
    if task is not None:
        seen: set = set()
        for f in subformulas(task.goal):
            if not isinstance(f, Prop) and not is_propositional(f) and f not in seen:
                seen.add(f)
                forms.append(f)
    eng = getattr(space, "engine", None)
    props = list(eng.props if eng is not None else task.props if task is not None else ())
    if epistemic and task is not None:  # each agent's belief about each proposition the goal mentions
        from delkit.logic.formula import K, Not, props_of

        for p in sorted(props_of(task.goal)):
            for a in task.agents:
                forms += [K(a, Prop(p)), K(a, Not(Prop(p)))]

    def valuations(s: Any) -> list[frozenset[str]]:
        if eng is not None:  # compact state: valuations as bit masks in the engine's proposition order
            return [frozenset(p for j, p in enumerate(props) if s.val[w] >> j & 1) for w in s.points]
        return [frozenset(s.true_props(int(w))) for w in s.designated]

    def atoms(s: Any) -> tuple[Hashable, ...]:
        vals = valuations(s)
        out: list[Hashable] = []
        for p in props:
            here = {p in v for v in vals}
            out.append(("v", p, here.pop()) if len(here) == 1 else ("v?", p))
        for i, f in enumerate(forms):
            out.append(("f", i, space.holds(s, f)))  # type: ignore[attr-defined]
        return tuple(out)
    return atoms


#: novelty of pairs only for states with at most this many atoms (a pair table per #g grows as atoms²; above
#: it the search is BFWS with w ≤ 1 — a measured change, see bench/RESULTS-frontier.md)
PAIR_ATOMS = 64


@_gc_paused
def novelty_search(space: StateSpace, limits: Limits = Limits(), *, width: int = 2,
                   atoms: Callable[[Any], tuple[Hashable, ...]] | None = None, deeper: bool = False) -> SearchResult:
    """Best-first width search, BFWS(f5)-style (Lipovetzky & Geffner 2017): the open list is ordered by
    ⟨w, #g⟩ — w the novelty of a state among the states generated before with the same goal count #g (1 if
    it makes some atom true for the first time in that group, 2 if some pair of atoms, else ``width`` + 1),
    #g the unsatisfied goal conjuncts — ties broken by fewer steps (``deeper``: more steps), then first
    generated. No state is pruned
    (novelty > ``width`` only ranks it last), so the search is complete; plans are not optimal.

    Atoms (:func:`novelty_atoms`): the designated worlds' valuations and the truth of the goal's modal
    subformulas. The measured change to the paper's BFWS(f5): #r (the relaxed-plan atoms counter) is left out —
    there is no relaxed plan of a DEL task to count; #g alone partitions the novelty tables."""
    from heapq import heappop, heappush
    from itertools import combinations

    budget = _Budget(limits)
    atoms = atoms or novelty_atoms(space)
    s0, k0 = space.initial()
    if space.is_goal(s0):
        return SearchResult("solved", (), 0, 1, budget.seconds, "novelty", "the goal holds initially",
                            distinct_states=1)
    tables: dict[int, tuple[set, set]] = {}

    def novelty(s: Any, gc_: int) -> int:
        one, two = tables.setdefault(gc_, (set(), set()))
        at = atoms(s)
        w = width + 1
        new1 = [a for a in at if a not in one]
        if new1:
            w = 1
            one.update(new1)
        if width >= 2 and len(at) <= PAIR_ATOMS:
            new2 = [pr for pr in combinations(at, 2) if pr not in two]
            if new2:
                w = min(w, 2)
                two.update(new2)
        return w

    g0 = space.goal_count(s0)
    parent: dict[Hashable, Any] = {k0: None}
    counter = 0
    sign = -1 if deeper else 1
    heap: list = [(novelty(s0, g0), g0, 0, counter, s0, k0)]
    expanded = generated = g = 0

    def push(nxt: Any, nkey: Hashable) -> None:
        nonlocal counter
        gc_ = space.goal_count(nxt)
        counter += 1
        heappush(heap, (novelty(nxt, gc_), gc_, sign * (g + 1), counter, nxt, nkey))

    while heap:
        why = budget.exceeded(expanded)
        if why:
            return SearchResult("limit", None, expanded, generated, budget.seconds, "novelty",
                                "no plan within limits: " + why, space.dead_ends, len(parent))
        _, _, sg, _, state, key = heappop(heap)
        g = sg * sign
        expanded += 1
        n, goal = _expand_new(space, state, key, parent, push)
        generated += n
        if goal is not None:
            return SearchResult("solved", _path(parent, goal), expanded, generated, budget.seconds, "novelty",
                                "", space.dead_ends, len(parent))
    return SearchResult("unsolvable", None, expanded, generated, budget.seconds, "novelty",
                        "the reachable state space is exhausted: no plan exists", space.dead_ends, len(parent))


#: the phases of ``--search auto``, in order, and each one's share of the time left when it starts
PORTFOLIO = (("novelty", 0.3), ("gbfs", 0.4), ("astar", 1.0))


#: the share of the time left that the portfolio's last phase leaves unused once a plan exists
RESERVE = 0.15


def _quiet_alarm() -> None:
    """Stop the interval timer of :func:`delkit.resources.deadline` (main thread only): its deadline has
    passed and the caller reports the plan it has; the console's watchdog still ends the process if that hangs."""
    import signal
    import threading

    if threading.current_thread() is threading.main_thread():
        signal.setitimer(signal.ITIMER_REAL, 0)


def portfolio(make: Callable[[], StateSpace], limits: Limits = Limits(),
              phases: tuple[tuple[str, float], ...] = PORTFOLIO) -> SearchResult:
    """``--search auto``: satisficing phases, then an optimal one, in one time budget (anytime).

    Each phase gets a fresh state space (``make()``) and ``share`` of the time left when it starts (the last
    phase: all of it); the expanded-node and memory limits hold in every phase. A satisficing phase (novelty,
    GBFS) runs only until a plan is found; later satisficing phases are skipped once a plan exists. The optimal
    phase (A* with the admissible h_pdb, or BFS) then either proves a plan optimal, finds a shorter one, or
    runs out of time — the best plan so far is returned with ``optimal`` False. ``phases`` lists every phase
    run: its search, status, seconds, and the plan length it found; ``search`` names the phase whose plan is
    returned."""
    from delkit.resources import TimeLimit

    budget = _Budget(limits)
    best: SearchResult | None = None
    runs: list[dict] = []
    expanded = generated = 0
    last = None
    for i, (kind, share) in enumerate(phases):
        optimal_phase = kind in ("astar", "bfs")
        if best is not None and not optimal_phase:
            continue
        left = None if limits.timeout is None else max(0.0, limits.timeout - budget.seconds)
        if left is not None and left <= 0:
            break
        # the last phase, once a plan exists, leaves RESERVE of the time for reporting it (its set-up, such
        # as A*'s pattern databases, runs before its node loop checks the budget)
        mine = (left if left is None else left * share if i < len(phases) - 1
                else left * (1 - RESERVE) if best is not None else left)
        sub = Limits(timeout=mine, max_expanded=limits.max_expanded, max_memory_mb=limits.max_memory_mb)
        try:
            space = make()
            res = run_search(space, kind, sub)
        except TimeLimit:  # the process's deadline (``delkit plan``'s alarm) inside a phase: keep the best plan
            if best is None:
                raise
            _quiet_alarm()  # the alarm re-fires every 0.25 s after expiry: let the best plan be reported
            runs.append({"search": kind, "status": "limit", "seconds": round(budget.seconds, 4), "length": None,
                         "expanded": 0, "improved": False})
            break
        expanded += res.expanded
        generated += res.generated
        last = res
        runs.append({"search": kind, "status": res.status, "seconds": round(res.seconds, 4),
                     "length": res.length, "expanded": res.expanded,
                     "improved": bool(res.solved and (best is None or res.length < best.length))})  # type: ignore[operator]
        if res.solved and (best is None or res.length < best.length):  # type: ignore[operator]
            best = res
        if optimal_phase and res.status in ("solved", "unsolvable"):
            break
    if best is None:
        assert last is not None
        return last.replace(expanded=expanded, generated=generated, seconds=budget.seconds, phases=tuple(runs),
                            search="auto:" + last.search, optimal=None)
    proven = any(r["search"] in ("astar", "bfs") and r["status"] == "solved" for r in runs)
    return best.replace(expanded=expanded, generated=generated, seconds=budget.seconds, phases=tuple(runs),
                        search="auto:" + best.search, optimal=proven)


SEARCHES = ("bfs", "gbfs", "astar", "novelty", "auto")


def run_search(space: StateSpace, search: str, limits: Limits = Limits()) -> SearchResult:
    """One search on ``space`` by name (``auto`` needs a space factory: :func:`portfolio`)."""
    if search == "bfs":
        return _mark(bfs(space, limits), True)
    if search in ("gbfs", "astar"):
        return _mark(best_first(space, limits, kind=search), search == "astar")  # type: ignore[arg-type]
    if search == "novelty":
        return _mark(novelty_search(space, limits), False)
    raise PlanningError(f"unknown search {search!r}; use " + ", ".join(SEARCHES))


def _mark(res: SearchResult, optimal: bool) -> SearchResult:
    if res.solved:
        res.__dict__["optimal"] = optimal
    return res


def final_state(space: StateSpace, steps: tuple[str, ...]) -> Any:
    """The state a plan reaches from the initial state (each step applied with ``space.step``)."""
    s, _ = space.initial()
    for name in steps:
        s = space.step(s, name)  # type: ignore[attr-defined]
        if s is None:
            raise PlanningError(f"the plan's step {name!r} is not applicable on replay")
    return s


def annotate(res: SearchResult, space: StateSpace, semantics: str) -> SearchResult:
    """``res`` with its semantics and, for a plan, the goal conjuncts its final state satisfies only
    vacuously (:func:`planners.beliefs.vacuous_goals`)."""
    res.__dict__["semantics"] = semantics
    if res.solved and res.plan is not None and semantics == "reference":
        from planners.beliefs import vacuous_goals

        res.__dict__["vacuous"] = tuple(vacuous_goals(space, final_state(space, res.plan)))
    return res


def plan(task: Task, *, search: Literal["bfs", "gbfs", "astar", "novelty", "auto"] = "bfs",
         limits: Limits = Limits(), engine: Literal["fast", "compact", "del"] = "fast",
         allow_inconsistent: bool | None = None, consistent_beliefs: bool = False) -> SearchResult:
    """Plan for ``task`` with the chosen search; never raises on a failed search (see ``status``).

    The semantics of states where an agent believes ⊥ is decided by
    :func:`planners.beliefs.belief_semantics` (the same function ``delkit plan`` and the plan checker ask):
    by default EPDDL (2026) tasks keep them (plank's, the competition's reference), mA* and E-PDDL tasks prune
    them; ``allow_inconsistent=True`` keeps, ``consistent_beliefs=True`` prunes. A plan whose goal holds only
    vacuously lists the conjuncts in ``vacuous``."""
    from planners.beliefs import belief_semantics

    if search not in SEARCHES:
        raise PlanningError(f"unknown search {search!r}; use " + ", ".join(SEARCHES))
    semantics = belief_semantics(task, consistent_beliefs=consistent_beliefs,
                                 allow_inconsistent=bool(allow_inconsistent))
    keep = semantics == "reference"

    def make() -> StateSpace:
        return make_space(task, engine=engine, allow_inconsistent=keep)

    if search == "auto":
        res = portfolio(make, limits)
        return annotate(res, make(), semantics)
    space = make()
    return annotate(run_search(space, search, limits), space, semantics)
