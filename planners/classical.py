"""The classical level of e-PICO: one arm's block world, solved optimally (fewest arm actions) with clingo.

State (:class:`CState`): per robot three stacks of blocks (bottom → top), the shared table ("barrier"),
each block's colour and, for a block on the shared table, the robot it belongs to. Actions of one arm
(seed 004, Listing 5, the argument order of ``delkit.arms.plan/1``; stacks and levels 0-based):

* ``pick(block, on, level, stack)`` — the gripper is empty, ``block`` is the top of ``stack`` of the arm's
  own table, at ``level``, lying on ``on`` (a block, or ``table`` at level 0);
* ``place(block, onto, level, stack)`` — the arm holds ``block``; it goes on top of ``stack``;
* ``put_on_barrier(block)`` — the arm holds ``block``; it goes onto the shared table;
* ``take_from_barrier(block)`` — the gripper is empty and ``block`` is the top of the shared table.

The same domain is written in PDDL in ``specs/epico/classical.pddl`` (the reference); here it is encoded in
ASP (as the seed does for its A^V encoding) and solved by clingo's multi-shot incremental mode: the horizon
grows one step at a time and the first satisfiable horizon is the optimal plan length (one action per step).
An ontic task of the epistemic plan becomes a goal (:func:`goal_for`):

* ``put_on_shared(R, C)``: a block of colour C from R's stacks lies on the shared table, R's gripper empty;
* ``take_from_shared(R, O, C)``: O's C block from the shared table lies on one of R's stacks, gripper empty.
"""

from __future__ import annotations

import time
from collections.abc import Mapping
from dataclasses import dataclass, field
from types import MappingProxyType
from typing import Any

from delkit.errors import PlanningError

__all__ = ["CState", "CAction", "CGoal", "ClassicalResult", "solve_classical", "solve_bfs", "goal_for", "apply",
           "ASP", "to_pddl"]


@dataclass(frozen=True)
class CAction:
    """A primitive arm action (Listing 5)."""

    robot: str
    name: str
    args: tuple

    def __str__(self) -> str:
        return f"{self.robot}: {self.name}({', '.join(map(str, self.args))})"

    def to_json(self) -> dict[str, Any]:
        return {"robot": self.robot, "action": self.name, "args": list(self.args)}


@dataclass(frozen=True)
class CState:
    """Classical state: stacks per robot (bottom → top), the shared table (bottom → top), colours, owners
    (the robot a block on the shared table belongs to)."""

    stacks: tuple[tuple[str, tuple[tuple[str, ...], ...]], ...]
    barrier: tuple[str, ...]
    colors: Mapping[str, str] = field(compare=False, hash=False)
    owners: tuple[tuple[str, str], ...] = ()
    hand: tuple[tuple[str, str], ...] = ()  # (robot, block) while a block is held (within a task only)

    @staticmethod
    def make(stacks: Mapping[str, Any], barrier: tuple[str, ...], colors: Mapping[str, str],
             owners: Mapping[str, str] | None = None) -> CState:
        return CState(tuple((r, tuple(tuple(s) for s in stacks[r])) for r in sorted(stacks)), tuple(barrier),
                      MappingProxyType(dict(colors)), tuple(sorted((owners or {}).items())))

    def of(self, robot: str) -> tuple[tuple[str, ...], ...]:
        for r, st in self.stacks:
            if r == robot:
                return st
        raise PlanningError(f"unknown robot {robot!r} in the classical state")

    def owner(self, block: str) -> str | None:
        return dict(self.owners).get(block)

    def with_robot(self, robot: str, stacks: tuple[tuple[str, ...], ...], barrier: tuple[str, ...],
                   owners: Mapping[str, str], hand: Mapping[str, str]) -> CState:
        return CState(tuple((r, stacks if r == robot else st) for r, st in self.stacks), barrier, self.colors,
                      tuple(sorted(owners.items())), tuple(sorted(hand.items())))

    def to_json(self) -> dict[str, Any]:
        return {"stacks": {r: [list(s) for s in st] for r, st in self.stacks}, "barrier": list(self.barrier),
                "owners": dict(self.owners)}


@dataclass(frozen=True)
class CGoal:
    """The classical goal of one ontic task: ``kind`` is ``put`` (a ``color`` block of ``robot`` on the
    shared table) or ``take`` (``block`` from the shared table onto one of ``robot``'s stacks)."""

    robot: str
    kind: str
    color: str = ""
    block: str = ""

    def describe(self) -> str:
        if self.kind == "put":
            return f"a {self.color} block of {self.robot} on the shared table"
        return f"{self.block} from the shared table on a stack of {self.robot}"


def goal_for(task_name: str, state: CState, agents: tuple[str, ...] = ("robot1", "robot2")) -> CGoal:
    """The classical goal of a grounded ontic task ``put_on_shared_R_C`` / ``take_from_shared_R_O_C``."""
    kind = next((k for p, k in (("put_on_shared_", "put"), ("take_from_shared_", "take"))
                 if task_name.startswith(p)), None)
    rest = task_name.split("_")[3:]
    if kind is None:
        raise PlanningError(f"{task_name}: not an ontic task of the e-PICO domain (put_on_shared_R_C or "
                            f"take_from_shared_R_O_C)")
    robot = rest[0]
    if kind == "put":
        return CGoal(robot, "put", color=rest[1])
    owner, color = rest[1], rest[2]
    cands = [b for b in state.barrier if state.colors[b] == color and state.owner(b) == owner]
    if not cands:
        raise PlanningError(f"{task_name}: no {color} block of {owner} on the shared table "
                            f"(the shared table holds {list(state.barrier) or 'nothing'})")
    return CGoal(robot, "take", color=color, block=cands[-1])


# ----------------------------------------------------------------------------- ASP encoding

ASP = r"""
#program base.
at(B,S,L,0) :- init_at(B,S,L).
bar(B,L,0) :- init_bar(B,L).
#program state(t).
occ(S,L,t) :- at(_,S,L,t).
top(B,S,L,t) :- at(B,S,L,t), not occ(S,L+1,t).
height(S,0,t) :- stack(S), not occ(S,0,t).
height(S,L+1,t) :- occ(S,L,t), not occ(S,L+1,t).
full(t) :- held(_,t).
barocc(L,t) :- bar(_,L,t).
bartop(B,t) :- bar(B,L,t), not barocc(L+1,t).
barh(0,t) :- not barocc(0,t).
barh(L+1,t) :- barocc(L,t), not barocc(L+1,t).
:- barocc(1,t).  % the shared table holds one block
#program step(t).
1 { pick(B,S,L,t) : top(B,S,L,t-1), not full(t-1);
    place(B,S,L,t) : held(B,t-1), height(S,L,t-1);
    putbar(B,t) : held(B,t-1);
    takebar(B,t) : bartop(B,t-1), not full(t-1) } 1.
held(B,t) :- pick(B,_,_,t).
held(B,t) :- takebar(B,t).
held(B,t) :- held(B,t-1), not place(B,_,_,t), not putbar(B,t).
at(B,S,L,t) :- place(B,S,L,t).
at(B,S,L,t) :- at(B,S,L,t-1), not pick(B,S,L,t).
bar(B,L,t) :- putbar(B,t), barh(L,t-1).
bar(B,L,t) :- bar(B,L,t-1), not takebar(B,t).
#program check(t).
#external query(t).
ok(t) :- goal_put(C), bar(B,_,t), color(B,C), mine(B), not full(t).
ok(t) :- goal_take(B), at(B,_,_,t), not full(t).
:- query(t), not ok(t).
"""


@dataclass(frozen=True)
class ClassicalResult:
    """A classical plan, its final state, and the solver's cost: wall seconds and the horizons tried."""

    goal: CGoal
    actions: tuple[CAction, ...]
    state: CState
    seconds: float
    horizon: int

    def to_json(self) -> dict[str, Any]:
        return {"goal": self.goal.describe(), "actions": [a.to_json() for a in self.actions],
                "seconds": round(self.seconds, 6), "horizon": self.horizon}


def _facts(state: CState, goal: CGoal) -> str:
    own = state.of(goal.robot)
    out = [f"stack({s})." for s in range(len(own))]
    blocks = {b for st in own for b in st} | set(state.barrier)
    for s, st in enumerate(own):
        for lvl, b in enumerate(st):
            out.append(f"init_at({_q(b)},{s},{lvl}). mine({_q(b)}).")
    for lvl, b in enumerate(state.barrier):
        out.append(f"init_bar({_q(b)},{lvl}).")
    out += [f"color({_q(b)},{_q(state.colors[b])})." for b in sorted(blocks)]
    if goal.kind == "put":
        out.append(f"goal_put({_q(goal.color)}).")
    else:
        out.append(f"goal_take({_q(goal.block)}).")
    return "\n".join(out)


def _q(name: str) -> str:
    return '"' + name.replace('"', '') + '"'


def solve_classical(state: CState, goal: CGoal, *, max_steps: int = 30, timeout: float = 10.0) -> ClassicalResult:
    """An optimal (fewest actions) plan for ``goal`` from ``state`` with clingo; :class:`PlanningError` if
    there is none within ``max_steps`` actions or ``timeout`` seconds. Needs ``delkit[asp]`` (clingo)."""
    from delkit.errors import require_extra

    require_extra("asp", "clingo", what="the clingo classical planner")
    import clingo

    t0 = time.perf_counter()
    ctl = clingo.Control(["--warn=none"])
    ctl.add("base", [], _facts(state, goal))
    ctl.add("base", [], ASP)
    ctl.ground([("base", []), ("state", [clingo.Number(0)]), ("check", [clingo.Number(0)])])
    found: list[clingo.Symbol] = []
    for t in range(max_steps + 1):
        if t > 0:
            ctl.ground([("step", [clingo.Number(t)]), ("state", [clingo.Number(t)]),
                        ("check", [clingo.Number(t)])])
            ctl.release_external(clingo.Function("query", [clingo.Number(t - 1)]))
        ctl.assign_external(clingo.Function("query", [clingo.Number(t)]), True)
        with ctl.solve(yield_=True) as handle:
            model = next(iter(handle), None)
            if model is not None:
                found = list(model.symbols(atoms=True))
                break
        if time.perf_counter() - t0 > timeout:
            raise PlanningError(f"classical planner: no plan for {goal.describe()} within {timeout:g} s")
    else:
        raise PlanningError(f"classical planner: no plan for {goal.describe()} within {max_steps} actions "
                            f"(from {state.to_json()})")
    steps = sorted((s.arguments[-1].number, s) for s in found if s.name in ("pick", "place", "putbar", "takebar"))
    actions: list[CAction] = []
    cur = state
    for _, s in steps:
        a = s.arguments
        b = a[0].string
        if s.name in ("pick", "place"):
            st, lvl = a[1].number, a[2].number
            own = cur.of(goal.robot)
            if s.name == "pick":
                on = own[st][lvl - 1] if lvl > 0 else "table"
            else:
                on = own[st][-1] if own[st] else "table"
            act = CAction(goal.robot, s.name, (b, on, lvl, st))
        else:
            act = CAction(goal.robot, "put_on_barrier" if s.name == "putbar" else "take_from_barrier", (b,))
        cur = apply(cur, act)
        actions.append(act)
    if not reached(cur, goal):
        raise PlanningError(f"classical planner: the plan for {goal.describe()} does not reach it (bug)")
    return ClassicalResult(goal, tuple(actions), cur, time.perf_counter() - t0, len(actions))


def successors(state: CState, robot: str) -> list[tuple[CAction, CState]]:
    """Every applicable action of ``robot``'s arm and its successor state (for the BFS engine)."""
    own = state.of(robot)
    hand = dict(state.hand)
    out: list[CAction] = []
    if robot in hand:
        b = hand[robot]
        for st, stack in enumerate(own):
            out.append(CAction(robot, "place", (b, stack[-1] if stack else "table", len(stack), st)))
        if not state.barrier:
            out.append(CAction(robot, "put_on_barrier", (b,)))
    else:
        for st, stack in enumerate(own):
            if stack:
                out.append(CAction(robot, "pick", (stack[-1], stack[-2] if len(stack) > 1 else "table",
                                                   len(stack) - 1, st)))
        if state.barrier:
            out.append(CAction(robot, "take_from_barrier", (state.barrier[-1],)))
    return [(a, apply(state, a)) for a in out]


def solve_bfs(state: CState, goal: CGoal, *, max_steps: int = 30, timeout: float = 10.0) -> ClassicalResult:
    """Breadth-first search over the arm's states (optimal: fewest actions), same contract as
    :func:`solve_classical`."""
    from collections import deque

    t0 = time.perf_counter()
    if reached(state, goal):
        return ClassicalResult(goal, (), state, time.perf_counter() - t0, 0)
    parent: dict[CState, tuple[CState, CAction] | None] = {state: None}
    frontier = deque([(state, 0)])
    while frontier:
        s, d = frontier.popleft()
        if d >= max_steps or time.perf_counter() - t0 > timeout:
            break
        for act, nxt in successors(s, goal.robot):
            if nxt in parent:
                continue
            parent[nxt] = (s, act)
            if reached(nxt, goal):
                acts: list[CAction] = []
                cur: CState = nxt
                while parent[cur] is not None:
                    prev, a = parent[cur]  # type: ignore[misc]
                    acts.append(a)
                    cur = prev
                return ClassicalResult(goal, tuple(reversed(acts)), nxt, time.perf_counter() - t0, len(acts))
            frontier.append((nxt, d + 1))
    raise PlanningError(f"classical planner (bfs): no plan for {goal.describe()} within {max_steps} actions / "
                        f"{timeout:g} s (from {state.to_json()})")


def reached(state: CState, goal: CGoal) -> bool:
    """Does ``state`` satisfy the goal (with the gripper empty)?"""
    own = state.of(goal.robot)
    if state.hand:
        return False
    if goal.kind == "put":
        return any(state.colors[b] == goal.color and state.owner(b) == goal.robot for b in state.barrier)
    return goal.block not in state.barrier and any(goal.block in st for st in own)


def apply(state: CState, act: CAction) -> CState:
    """The state after one action; :class:`PlanningError` if its precondition does not hold."""
    own = [list(s) for s in state.of(act.robot)]
    barrier = list(state.barrier)
    owners = dict(state.owners)
    hand = dict(state.hand)
    b = act.args[0]
    if act.name == "pick":
        _, _, lvl, st = act.args
        if not own[st] or own[st][-1] != b or len(own[st]) - 1 != lvl or act.robot in hand:
            raise PlanningError(f"{act}: {b!r} is not the top of stack {st} at level {lvl}")
        own[st].pop()
        hand[act.robot] = b
    elif act.name == "take_from_barrier":
        if not barrier or barrier[-1] != b or act.robot in hand:
            raise PlanningError(f"{act}: {b!r} is not the top of the shared table")
        barrier.pop()
        owners.pop(b, None)
        hand[act.robot] = b
    elif act.name == "place":
        _, _, lvl, st = act.args
        if hand.get(act.robot) != b or len(own[st]) != lvl:
            raise PlanningError(f"{act}: {act.robot} does not hold {b!r} or level {lvl} is not free")
        own[st].append(b)
        hand.pop(act.robot)
    elif act.name == "put_on_barrier":
        if hand.get(act.robot) != b:
            raise PlanningError(f"{act}: {act.robot} does not hold {b!r}")
        barrier.append(b)
        owners[b] = act.robot if b not in owners else owners[b]
        hand.pop(act.robot)
    return state.with_robot(act.robot, tuple(tuple(s) for s in own), tuple(barrier), owners, hand)


def to_pddl(state: CState, goal: CGoal) -> str:
    """The PDDL problem (for ``specs/epico/classical.pddl``) of ``goal`` from ``state``; a ``put`` goal asks
    for one chosen block of the colour (the first of the robot's blocks of that colour: with one block per
    colour, the only one)."""
    own = state.of(goal.robot)
    blocks = [b for st in own for b in st] + list(state.barrier)
    nlev = len(blocks) + 1

    def nm(x: str) -> str:
        return "b_" + x.replace("-", "_")

    init = ["(handempty)"] + [f"(succ l{i} l{i + 1})" for i in range(nlev)]
    for s, st in enumerate(own):
        init.append(f"(above base{s} l0)")
        below = f"base{s}"
        for lvl, b in enumerate(st):
            init += [f"(on {nm(b)} {below})", f"(at {nm(b)} s{s} l{lvl})", f"(above {nm(b)} l{lvl + 1})",
                     f"(in-stacks {nm(b)})"]
            below = nm(b)
        init.append(f"(top s{s} {below})")
    init += [f"(on-barrier {nm(b)})" for b in state.barrier] or ["(barrier-free)"]
    if goal.kind == "put":
        target = next(b for st in own for b in st if state.colors[b] == goal.color)
        g = f"(and (on-barrier {nm(target)}) (handempty))"
    else:
        g = f"(and (handempty) (barrier-free) (in-stacks {nm(goal.block)}))"
    return (f"(define (problem epico-arm-{goal.kind})\n  (:domain epico-arm)\n"
            f"  (:objects {' '.join(nm(b) for b in blocks)} - block {' '.join(f'base{s}' for s in range(len(own)))} "
            f"- base {' '.join(f's{s}' for s in range(len(own)))} - stack "
            f"{' '.join(f'l{i}' for i in range(nlev + 1))} - level)\n"
            f"  (:init {' '.join(init)})\n  (:goal {g}))\n")
