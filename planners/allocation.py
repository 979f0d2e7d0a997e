"""Epistemic multi-robot task allocation (seed 000, §5.4): SSI bundling, makespan minimisation, gossip auction.

The problem is ST-MR-TA (single-task robots, multi-robot tasks, time-extended): task τ needs N_τ robots
present at the same time; a robot executes its bundle B_j in order and waits at a task until all of its
N_τ robots have arrived (the joint arrival time t_iτ of eq. 20).

* :func:`ssi_bundles` — Algorithm 1: tasks are auctioned one by one; robot j bids
  ``h(x_j, τ) = λ_τ − S_j^{B_j ⊕_end τ}`` (eq. 22), where S_j^B is the travel time of bundle B from the
  robot's believed state; the N_τ highest bidders append τ. A disconnected robot's bid is made on its
  behalf from the belief of the connected robot that heard from it most recently (``informer``).
* :func:`schedule` / :func:`makespan` — joint start times and the makespan of a set of bundles (∞ when the
  orders deadlock, e.g. robot a does τ1 then τ2 while robot b does τ2 then τ1).
* :func:`minimise_makespan` — Algorithm 2: every task of every bundle is tried at every position; a move is
  kept when it lowers the makespan. Tasks already gossiped to a disconnected robot (``locked``) are not moved,
  so the order other robots were told is kept.
* :func:`gossip_auction` — Algorithm 3: the robots that know the allocation (D, initially the connected
  group) bid on the robots that must be told (G); each informer takes its best target, the target joins D
  and can itself gossip in the next round (the cascade).
* :func:`milp_allocation` — an exact mixed-integer programme (scipy HiGHS) for small instances: assignment
  y_iτ with Σ_i y_iτ = N_τ, per-robot routing arcs with flow conservation, common start times S_τ with
  big-M precedence ``S_σ ≥ S_τ + δ_τ + c_τσ − M(1 − x_iτσ)``. Objective ``"utility"`` (default) is eq. 20,
  max Σ_i Σ_τ u_iτ(t_iτ) y_iτ with the utility of the bids, u_iτ(t) = λ_τ − t (eq. 22; t_iτ = S_τ, the joint
  start); ``"makespan"`` minimises the makespan (what Algorithm 2 targets). :func:`team_utility` scores
  any bundles by eq. 20; both are used to report the optimality gap of Algorithms 1–2.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field

import numpy as np
from scipy.optimize import Bounds, LinearConstraint, milp

from delkit.errors import PlanningError

__all__ = ["Task", "Robot", "Allocation", "Schedule", "euclidean_cost", "bundle_cost", "ssi_bundles",
           "schedule", "makespan", "team_utility", "minimise_makespan", "gossip_auction", "allocate",
           "milp_allocation"]

Cost = Callable[[tuple[float, float], tuple[float, float]], float]


@dataclass(frozen=True)
class Task:
    """A task τ = (x_τ, y_τ, r_τ = n_required, λ_τ = reward) with an optional service ``duration``."""

    id: int
    xy: tuple[float, float]
    n_required: int = 1
    reward: float = 100.0
    duration: float = 0.0


@dataclass(frozen=True)
class Robot:
    """A robot as seen by the bidder: its (believed) position and the time it becomes free."""

    id: int
    xy: tuple[float, float]
    ready: float = 0.0


@dataclass(frozen=True)
class Schedule:
    """Start time of each task, finishing time of each robot, and the makespan (∞ on deadlock)."""

    start: Mapping[int, float]
    finish: Mapping[int, float]
    makespan: float


@dataclass(frozen=True)
class Allocation:
    """Result of Algorithms 1–3: task bundles, gossip bundles (who tells whom, in order), bids and makespan."""

    bundles: Mapping[int, tuple[int, ...]]
    gossip: Mapping[int, tuple[int, ...]]
    makespan: float
    bids: Mapping[tuple[int, int], float] = field(default_factory=dict)
    bid_by: Mapping[int, int] = field(default_factory=dict)
    start: Mapping[int, float] = field(default_factory=dict)


def euclidean_cost(speed: float = 3.0) -> Cost:
    """Travel time at ``speed`` along the straight line."""

    def cost(a: tuple[float, float], b: tuple[float, float]) -> float:
        return float(np.hypot(a[0] - b[0], a[1] - b[1])) / speed

    return cost


def bundle_cost(robot: Robot, bundle: Sequence[int], tasks: Mapping[int, Task], cost: Cost) -> float:
    """S_j^B: travel plus service time of bundle B from the robot's state (S_j^∅ = 0)."""
    t, at = 0.0, robot.xy
    for tid in bundle:
        t += cost(at, tasks[tid].xy) + tasks[tid].duration
        at = tasks[tid].xy
    return t


def ssi_bundles(robots: Sequence[Robot], tasks: Sequence[Task], cost: Cost,
                informer: Mapping[int, int] | None = None,
                initial: Mapping[int, Sequence[int]] | None = None, context: Sequence[Task] = ()) -> Allocation:
    """Algorithm 1 (modified SSI auction) of ``tasks``, appended to the ``initial`` bundles (whose tasks are in
    ``context``). Raises if a task needs more robots than there are bidders."""
    task_map = {t.id: t for t in [*context, *tasks]}
    bundles = {r.id: list((initial or {}).get(r.id, ())) for r in robots}
    for tid in (tid for b in bundles.values() for tid in b):
        if tid not in task_map:
            raise PlanningError(f"initial bundle names unknown task {tid}")
    bids: dict[tuple[int, int], float] = {}
    for tau in tasks:
        if tau.n_required > len(robots):
            raise PlanningError(f"task {tau.id} needs {tau.n_required} robots but only {len(robots)} can bid")
        for r in robots:
            bids[(r.id, tau.id)] = tau.reward - bundle_cost(r, [*bundles[r.id], tau.id], task_map, cost)  # eq. 22
        order = sorted(robots, key=lambda r: (-bids[(r.id, tau.id)], r.id))
        for r in order[:tau.n_required]:
            bundles[r.id].append(tau.id)
    by = {r.id: (informer or {}).get(r.id, r.id) for r in robots}
    sched = schedule(robots, bundles, task_map, cost)
    return Allocation({k: tuple(v) for k, v in bundles.items()}, {}, sched.makespan, bids, by)


def schedule(robots: Sequence[Robot], bundles: Mapping[int, Sequence[int]], tasks: Mapping[int, Task],
             cost: Cost) -> Schedule:
    """Joint start times: τ starts when its last assigned robot arrives; robots leave after δ_τ."""
    ptr = {r.id: 0 for r in robots}
    time = {r.id: r.ready for r in robots}
    pos = {r.id: r.xy for r in robots}
    members: dict[int, list[int]] = {}
    for rid, b in bundles.items():
        for tid in b:
            members.setdefault(tid, []).append(rid)
    start: dict[int, float] = {}
    remaining = set(members)
    while remaining:
        progressed = False
        for tid in sorted(remaining):
            who = members[tid]
            if all(ptr[r] < len(bundles[r]) and bundles[r][ptr[r]] == tid for r in who):
                t0 = max(time[r] + cost(pos[r], tasks[tid].xy) for r in who)
                start[tid] = t0
                for r in who:
                    time[r] = t0 + tasks[tid].duration
                    pos[r] = tasks[tid].xy
                    ptr[r] += 1
                remaining.discard(tid)
                progressed = True
        if not progressed:
            return Schedule(start, time, float("inf"))
    span = max([start[t] + tasks[t].duration for t in start], default=0.0)
    return Schedule(start, time, span)


def makespan(robots: Sequence[Robot], bundles: Mapping[int, Sequence[int]], tasks: Mapping[int, Task],
             cost: Cost) -> float:
    """Time at which the last task finishes (∞ if the bundle orders deadlock)."""
    return schedule(robots, bundles, tasks, cost).makespan


def team_utility(robots: Sequence[Robot], bundles: Mapping[int, Sequence[int]], tasks: Mapping[int, Task],
                 cost: Cost) -> float:
    """Eq. 20's objective Σ_i Σ_τ u_iτ(t_iτ) y_iτ with u_iτ(t) = λ_τ − t and t_iτ the joint start of τ
    (−∞ if the bundle orders deadlock)."""
    sched = schedule(robots, bundles, tasks, cost)
    if not np.isfinite(sched.makespan):
        return float("-inf")
    return float(sum(tasks[t].reward - sched.start[t] for b in bundles.values() for t in b))


def minimise_makespan(robots: Sequence[Robot], bundles: Mapping[int, Sequence[int]], tasks: Sequence[Task],
                      cost: Cost, locked: Mapping[int, Sequence[int]] | None = None) -> dict[int, tuple[int, ...]]:
    """Algorithm 2: re-insert each unlocked task of each bundle at its best position if the makespan drops."""
    task_map = {t.id: t for t in tasks}
    best = {k: list(v) for k, v in bundles.items()}
    m_best = makespan(robots, best, task_map, cost)
    for r in robots:
        frozen = set((locked or {}).get(r.id, ()))
        for tid in list(best[r.id]):
            if tid in frozen:
                continue
            rest = [t for t in best[r.id] if t != tid]
            for n in range(len(rest) + 1):
                cand = dict(best)
                cand[r.id] = rest[:n] + [tid] + rest[n:]
                m = makespan(robots, cand, task_map, cost)
                if m < m_best - 1e-9:
                    best, m_best = cand, m
    return {k: tuple(v) for k, v in best.items()}


def gossip_auction(informed: Sequence[int], must_know: Sequence[int], positions: Mapping[int, tuple[float, float]],
                   cost: Cost, ready: Mapping[int, float] | None = None) -> dict[int, tuple[int, ...]]:
    """Algorithm 3: assign who travels to whom so that every robot in ``must_know`` learns the allocation.

    Bid ``b_vg = −(t_v + c(x_v, x̂_g))``: informer v, free at t_v and at x_v, reaches the believed position
    x̂_g of g. Each round every informer takes its best uninformed target; a target told at time t joins the
    informers from there (cascade). Returns the ordered gossip bundle of each informer.
    """
    D = list(dict.fromkeys(informed))
    if not D:
        raise PlanningError("gossip auction needs at least one informed robot")
    unknown = [g for g in [*D, *must_know] if g not in positions]
    if unknown:
        raise PlanningError(f"gossip auction: no (believed) position for robot(s) {sorted(set(unknown))}")
    t = {v: (ready or {}).get(v, 0.0) for v in positions}
    at = dict(positions)
    out: dict[int, list[int]] = {v: [] for v in positions}
    todo = [g for g in dict.fromkeys(must_know) if g not in D]
    while todo:
        for v in list(D):
            if not todo:
                break
            bids = {g: -(t[v] + cost(at[v], at[g])) for g in todo}
            g = max(todo, key=lambda k: (bids[k], -k))
            out[v].append(g)
            t[v] = t[g] = t[v] + cost(at[v], at[g])
            at[v] = at[g]
            D.append(g)
            todo.remove(g)
    return {k: tuple(v) for k, v in out.items() if v}


def allocate(robots: Sequence[Robot], tasks: Sequence[Task], cost: Cost, *, connected: Sequence[int],
             informer: Mapping[int, int] | None = None, locked: Mapping[int, Sequence[int]] | None = None,
             initial: Mapping[int, Sequence[int]] | None = None, context: Sequence[Task] = (),
             must_know: Sequence[int] | None = None) -> Allocation:
    """Algorithms 1 → 2 → 3 for new ``tasks`` on top of the ``initial`` bundles (tasks in ``context``).

    ``locked`` bundles keep their order (already gossiped); ``must_know`` defaults to the robots with a
    non-empty bundle (G_j); the gossip auction starts from the ``connected`` robots.
    """
    first = ssi_bundles(robots, tasks, cost, informer, initial, context)
    everything = [*context, *tasks]
    bundles = minimise_makespan(robots, first.bundles, everything, cost, locked)
    task_map = {t.id: t for t in everything}
    sched = schedule(robots, bundles, task_map, cost)
    need = list(must_know) if must_know is not None else [r for r, b in bundles.items() if b]
    pos = {r.id: r.xy for r in robots}
    ready = {r.id: r.ready for r in robots}
    gossip = gossip_auction([c for c in connected if c in pos], need, pos, cost, ready)
    return Allocation(bundles, gossip, sched.makespan, first.bids, first.bid_by, dict(sched.start))


def milp_allocation(robots: Sequence[Robot], tasks: Sequence[Task], cost: Cost,
                    time_limit: float = 30.0, objective: str = "utility") -> tuple[float, dict[int, tuple[int, ...]]]:
    """Exact optimum of the ST-MR-TA instance (small instances), solved with HiGHS.

    ``objective="utility"``: eq. 20 (maximum team utility, returned as that utility); ``"makespan"``: the
    minimum makespan. Returns ``(value, bundles)``; bundles are recovered from the arc variables.
    """
    if objective not in ("utility", "makespan"):
        raise PlanningError(f"unknown MILP objective {objective!r}; use 'utility' (eq. 20) or 'makespan'")
    R, T = len(robots), len(tasks)
    if any(t.n_required > R for t in tasks):
        raise PlanningError("a task needs more robots than exist; the MILP is infeasible")
    names: list[tuple] = []

    def var(*key) -> int:
        names.append(key)
        return len(names) - 1

    y = {(i, a): var("y", i, a) for i in range(R) for a in range(T)}
    xs = {(i, a): var("xs", i, a) for i in range(R) for a in range(T)}
    xe = {(i, a): var("xe", i, a) for i in range(R) for a in range(T)}
    x = {(i, a, b): var("x", i, a, b) for i in range(R) for a in range(T) for b in range(T) if a != b}
    S = {a: var("S", a) for a in range(T)}
    Cm = var("C")
    n = len(names)
    c_tt = np.array([[cost(tasks[a].xy, tasks[b].xy) for b in range(T)] for a in range(T)])
    c_st = np.array([[robots[i].ready + cost(robots[i].xy, tasks[a].xy) for a in range(T)] for i in range(R)])
    dur = np.array([t.duration for t in tasks])
    big = float(c_st.max(initial=0) + c_tt.sum() + dur.sum() + 1.0) * (T + 1)
    rows, lo, hi = [], [], []

    def add(coefs: dict[int, float], lb: float, ub: float) -> None:
        row = np.zeros(n)
        for k, v in coefs.items():
            row[k] += v
        rows.append(row)
        lo.append(lb)
        hi.append(ub)

    for a in range(T):
        add({y[i, a]: 1 for i in range(R)}, tasks[a].n_required, tasks[a].n_required)
        add({Cm: 1, S[a]: -1}, dur[a], np.inf)
    for i in range(R):
        add({xs[i, a]: 1 for a in range(T)}, 0, 1)
        for a in range(T):
            inflow = {xs[i, a]: 1, y[i, a]: -1} | {x[i, b, a]: 1 for b in range(T) if b != a}
            add(inflow, 0, 0)
            outflow = {xe[i, a]: 1, y[i, a]: -1} | {x[i, a, b]: 1 for b in range(T) if b != a}
            add(outflow, 0, 0)
            add({S[a]: 1, xs[i, a]: -c_st[i, a]}, 0, np.inf)
            for b in range(T):
                if a != b:
                    gap = dur[a] + c_tt[a, b] + 1e-3
                    add({S[b]: 1, S[a]: -1, x[i, a, b]: -big}, gap - big, np.inf)
    obj = np.zeros(n)
    if objective == "makespan":
        obj[Cm] = 1.0
        for a in range(T):
            obj[S[a]] = 1e-4
    else:  # max Σ_τ N_τ (λ_τ − S_τ)  ⇔  min Σ_τ N_τ S_τ (Σ_i y_iτ = N_τ); C only tie-broken
        for a in range(T):
            obj[S[a]] = float(tasks[a].n_required)
        obj[Cm] = 1e-6
    integrality = np.array([0 if k[0] in ("S", "C") else 1 for k in names])
    ub = np.array([np.inf if k[0] in ("S", "C") else 1 for k in names])
    res = milp(obj, constraints=LinearConstraint(np.array(rows), lo, hi), integrality=integrality,
               bounds=Bounds(np.zeros(n), ub), options={"time_limit": time_limit})
    if res.x is None:
        raise PlanningError(f"MILP found no solution: {res.message}")
    sol = res.x
    bundles: dict[int, tuple[int, ...]] = {}
    for i in range(R):
        seq, cur = [], next((a for a in range(T) if sol[xs[i, a]] > 0.5), None)
        while cur is not None and len(seq) <= T:
            seq.append(cur)
            cur = next((b for b in range(T) if b != cur and sol[x[i, cur, b]] > 0.5), None)
        bundles[robots[i].id] = tuple(tasks[a].id for a in seq)
    if objective == "makespan":
        return float(sol[Cm]), bundles
    return float(sum(tasks[a].n_required * (tasks[a].reward - sol[S[a]]) for a in range(T))), bundles
