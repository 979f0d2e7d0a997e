"""The e-PICO hierarchy (seed 004, Listing 1 with its printing bugs fixed): epistemic plan → flatten macros →
pure epistemic tasks pass through → every ontic task is broken down by the classical planner, from the
classical state carried from task to task → one ``delkit.arms.plan/1`` primitive plan.

Listing 1 as printed calls ``process_simple_task(t, c_init)`` with an unbound ``t`` (the loop variable is
``simple_task``), has its ``else`` at the level of the ``for`` (so a non-macro task would be processed
after the loop instead of in place of it) and drops ``c_init`` in the non-macro call; and
``process_simple_task`` sends ``c_plan`` to the actuator also for epistemic tasks, where it is unbound.
:func:`process_e_plan` is the corrected version.

Anchoring (Sec. 4.3): after every ontic task the classical state must make the epistemic actual world's
``occup_by`` fluents true as the epistemic plan says (which robot's block of which colour lies on the shared
table); otherwise an :class:`~planners.epico.EpicoError` names the task. Along the plan every agent must keep
a consistent belief state (no agent may believe ⊥ — no vacuous success), also checked here.
"""

from __future__ import annotations

import json
import time
from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field
from typing import Any

from planners.classical import CAction, CState, goal_for, solve_bfs, solve_classical
from planners.epico import ROBOTS, EpicoError, Instance
from planners.task import ActionSpec, MacroSpec, Task

__all__ = ["EpicoLimits", "Solution", "solve", "process_e_plan", "TaskRecord", "epistemic_task"]


@dataclass(frozen=True)
class EpicoLimits:
    """Limits: epistemic search wall seconds (the seed's 110 s), per classical call seconds and actions;
    the epistemic search (``bfs``: optimal length) and the classical engine (``bfs`` or ``clingo``)."""

    timeout: float = 110.0
    classical_timeout: float = 10.0
    classical_max_steps: int = 30
    search: str = "bfs"
    classical: str = "bfs"


@dataclass(frozen=True)
class TaskRecord:
    """One simple task of the flattened plan and the primitive actions it became."""

    task: str
    kind: str
    actions: tuple[dict, ...]
    seconds: float = 0.0

    def to_json(self) -> dict[str, Any]:
        return {"task": self.task, "kind": self.kind, "actions": list(self.actions), "seconds": round(self.seconds, 6)}


@dataclass(frozen=True)
class Solution:
    """The result of :func:`solve`: the three plans, the times (initial state, epistemic search, classical
    breakdown; seconds) and the number of classical calls."""

    instance: Instance
    macros: bool
    epistemic_plan: tuple[str, ...]
    flat_plan: tuple[str, ...]
    primitive_plan: dict[str, Any]
    times: Mapping[str, float]
    classical_calls: int
    classical_call_seconds: tuple[float, ...]
    tasks: tuple[TaskRecord, ...]
    search: Mapping[str, Any] = field(default_factory=dict)
    final_state: CState | None = None

    def to_json(self) -> dict[str, Any]:
        return {"goal": self.instance.goal, "colors": self.instance.colors, "macros": self.macros,
                "epistemic_plan": list(self.epistemic_plan), "flat_plan": list(self.flat_plan),
                "primitive_plan": self.primitive_plan, "times": {k: round(v, 6) for k, v in self.times.items()},
                "classical_calls": self.classical_calls,
                "classical_call_seconds": [round(t, 6) for t in self.classical_call_seconds],
                "tasks": [t.to_json() for t in self.tasks], "search": dict(self.search)}

    def write(self, path) -> None:
        """Write the primitive plan (``delkit.arms.plan/1``) as JSON."""
        from pathlib import Path

        Path(path).write_text(json.dumps(self.primitive_plan, indent=2) + "\n")


def epistemic_task(instance: Instance, *, macros: bool = True) -> tuple[Task, Task, list[MacroSpec]]:
    """(primitive task, task offered to the planner, grounded macros) of an instance."""
    from planners.lang.epddl import parse_epddl
    from planners.macros import ground_macros, parse_macros, with_macros

    task = parse_epddl(instance.domain_text, instance.problem_text, domain_source="specs/epico/domain.epddl",
                       problem_source=f"epico_{instance.goal}_{instance.colors}")
    if not macros:
        return task, task, []
    ms = ground_macros(task, parse_macros(instance.domain_text, source="specs/epico/domain.epddl"),
                       instance.problem_text)
    return task, with_macros(task, ms), ms


class _MacroSpace:
    """Interim: the planner's fast state space plus macros applied step by step (Φ(A_n, … Φ(A_1, s))), until
    the planner applies MacroSpecs itself. Intermediate states are not tested for consistency, as the
    composed update would not see them; the flattened plan is checked step by step afterwards."""

    def __init__(self, task: Task, macros: list[MacroSpec]) -> None:
        from planners.fastdel import FastSpace

        self.fs = FastSpace(task)
        self.macros = macros
        self.dead_ends = 0

    def initial(self):
        return self.fs.initial()

    def is_goal(self, s) -> bool:
        return self.fs.is_goal(s)

    def goal_count(self, s) -> int:
        return self.fs.goal_count(s)

    def successors(self, s):
        yield from self.fs.successors(s)
        self.dead_ends = self.fs.dead_ends
        for m in self.macros:
            cur = s
            for st in m.steps:
                cur = self.fs.step(cur, st.name)
                if cur is None:
                    break
            if cur is None:
                continue
            if any(not cur.succ[a][cur.point] for a in range(len(cur.succ))):
                self.dead_ends += 1
                continue
            yield m.name, cur, cur.key


def _search(task: Task, ptask: Task, macros: list[MacroSpec], limits: EpicoLimits):
    from planners.epistemic import Limits, best_first, bfs, make_space

    lim = Limits(timeout=limits.timeout)
    try:
        space = make_space(ptask)
    except Exception:  # noqa: BLE001 - the planner does not take MacroSpecs yet: step-by-step interim space
        if not macros:
            raise
        space = _MacroSpace(task, macros)
    if limits.search == "bfs":
        return bfs(space, lim)
    return best_first(space, lim, kind=limits.search)  # type: ignore[arg-type]


def solve(instance: Instance, *, macros: bool = True, known: Mapping[str, Iterable[Any]] | None = None,
          limits: EpicoLimits = EpicoLimits()) -> Solution:
    """Spec → epistemic plan (with or without macros) → flattened plan → classical breakdown → plan/1.

    ``known`` (robot ↦ colours, or (owner, colour) pairs) says what each robot already knows, e.g. when
    replanning from what was observed. Raises :class:`EpicoError` if no plan is found within the limits or
    a task cannot be carried out (naming it)."""
    from planners.macros import flatten

    if known:
        instance = instance.with_known(known)
    t0 = time.perf_counter()
    task, ptask, ms = epistemic_task(instance, macros=macros)
    t_init = time.perf_counter() - t0
    res = _search(task, ptask, ms, limits)
    if not res.solved:
        raise EpicoError(f"epistemic planner: no plan for {instance.goal} with {instance.colors} colour(s) "
                         f"({'with' if macros else 'without'} macros): {res.reason}")
    eplan = tuple(res.plan or ())
    flat = tuple(flatten(eplan, ms))
    t1 = time.perf_counter()
    records, final, calls = process_e_plan(task, flat, instance.classical_init, limits)
    t_class = sum(calls)
    t_hier = time.perf_counter() - t1
    actions = [a for r in records for a in r.actions]
    primitive = {"format": "delkit.arms.plan/1", "world": instance.layout.to_world(), "actions": actions}
    _check_primitive(primitive)
    return Solution(instance, macros, eplan, flat, primitive,
                    {"initial": t_init, "epistemic": res.seconds, "classical": t_class,
                     "hierarchy": t_hier, "total": t_init + res.seconds + t_hier},
                    len(calls), tuple(calls), tuple(records),
                    {"expanded": res.expanded, "generated": res.generated, "dead_ends": res.dead_ends,
                     "search": res.search, "length": len(eplan)}, final)


def _check_primitive(obj: dict) -> None:
    from arms.plan import parse_plan, symbolic_trace
    from arms.world import ArmsError

    try:
        symbolic_trace(parse_plan(obj, source="e-PICO primitive plan"))
    except ArmsError as exc:
        raise EpicoError(f"the primitive plan is not executable: {exc}") from None


def process_e_plan(task: Task, flat_plan: Iterable[str], c_init: CState, limits: EpicoLimits = EpicoLimits()
                   ) -> tuple[list[TaskRecord], CState, list[float]]:
    """Listing 1, corrected: every simple task in order; pure epistemic tasks become ``sense`` /
    ``announce``; ontic tasks are broken down by the classical planner from the current classical state.
    Replays the epistemic plan alongside (fast engine) for the anchoring and consistency checks. Returns
    the task records, the final classical state and the seconds of each classical call."""
    from planners.fastdel import FastSpace

    fs = FastSpace(task)
    s, _ = fs.initial()
    c_state = c_init
    records: list[TaskRecord] = []
    calls: list[float] = []
    for i, name in enumerate(flat_plan, 1):
        act = task.action(name)
        if not isinstance(act, ActionSpec):
            raise EpicoError(f"task {i} ({name}) is not a simple task: flatten macros first")
        new = fs.step(s, name)
        if new is None:
            raise EpicoError(f"task {i} ({name}) is not applicable in the epistemic state it is reached in")
        bad = [ag for a, ag in enumerate(task.agents) if not new.succ[a][new.point]]
        if bad:
            raise EpicoError(f"task {i} ({name}) leaves {', '.join(bad)} believing ⊥ (no accessible world): "
                             "vacuous success is refused")
        s = new
        if act.kind == "ontic":
            goal = goal_for(name, c_state, task.agents)
            engine = solve_bfs if limits.classical == "bfs" else solve_classical
            try:
                r = engine(c_state, goal, max_steps=limits.classical_max_steps, timeout=limits.classical_timeout)
            except Exception as exc:
                raise EpicoError(f"task {i} ({name}): {exc}") from None
            calls.append(r.seconds)
            c_state = r.state
            _anchor(task, fs, s, c_state, i, name)
            records.append(TaskRecord(name, "ontic", tuple(_prim(a) for a in r.actions), r.seconds))
        else:
            records.append(TaskRecord(name, act.kind, (_epistemic_primitive(name, act, c_state, task),)))
    return records, c_state, calls


def _prim(a: CAction) -> dict[str, Any]:
    return a.to_json()


def _anchor(task: Task, fs, s, c_state: CState, i: int, name: str) -> None:
    """The classical state must agree with the epistemic actual world on every ``occup_by`` fluent."""
    val = s.val[s.point]
    for j, p in enumerate(task.props):
        if not p.startswith("occup_by_"):
            continue
        robot, color = p[len("occup_by_"):].split("_", 1)
        epi = bool((val >> fs.pidx[p]) & 1)
        cla = any(c_state.colors[b] == color and c_state.owner(b) == robot for b in c_state.barrier)
        if epi != cla:
            raise EpicoError(f"task {i} ({name}): anchoring failed: {p} is {epi} in the epistemic state but the "
                             f"classical state has {list(c_state.barrier) or 'nothing'} on the shared table")
        del j


def _epistemic_primitive(name: str, act: ActionSpec, c_state: CState, task: Task) -> dict[str, Any]:
    robot = next((r for r in task.agents if name.split("_").count(r)), ROBOTS[0])
    color = name.rsplit("_", 1)[-1]
    if name.startswith("sense_table_"):
        return {"robot": robot, "action": "sense", "task": name}
    if name.startswith("announce_block_on_barrier_"):
        block = next((b for b in c_state.barrier if c_state.colors[b] == color), None)
        if block is None:
            raise EpicoError(f"{name}: no {color} block on the shared table to announce")
        return {"robot": robot, "action": "announce", "args": [block], "color": color,
                "to": [r for r in task.agents if r != robot], "task": name}
    return {"robot": robot, "action": "announce", "task": name, "to": [r for r in task.agents if r != robot]}
