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

from delkit.logic.formula import TOP
from planners.classical import CAction, CState, goal_for, solve_bfs, solve_classical
from planners.epico import ROBOTS, EpicoError, Instance, Reading
from planners.task import ActionSpec, EventAction, MacroSpec, Task

__all__ = ["EpicoLimits", "Solution", "solve", "process_e_plan", "TaskRecord", "epistemic_task", "EXTERNAL",
           "perspective_check", "plan_from_perspective", "PerspectiveCheck", "local_state", "actor_of"]


@dataclass(frozen=True)
class EpicoLimits:
    """Limits: epistemic search wall seconds (the seed's 110 s), per classical call seconds and actions;
    the epistemic search (``bfs``: optimal length, duplicate detection; ``tree``: BFS without it, as the
    e-PICO paper's planner; ``gbfs``/``astar``) and the classical engine (``bfs`` or ``clingo``)."""

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
    macro: str = ""

    def to_json(self) -> dict[str, Any]:
        return {"task": self.task, "kind": self.kind, "macro": self.macro or None, "actions": list(self.actions),
                "seconds": round(self.seconds, 6)}


@dataclass(frozen=True)
class Solution:
    """The result of :func:`solve`: the three plans, the times (initial state, epistemic search, classical
    breakdown; seconds) and the number of classical calls."""

    instance: Instance
    macros: bool | tuple[str, ...]
    epistemic_plan: tuple[str, ...]
    flat_plan: tuple[str, ...]
    primitive_plan: dict[str, Any]
    times: Mapping[str, float]
    classical_calls: int
    classical_call_seconds: tuple[float, ...]
    tasks: tuple[TaskRecord, ...]
    search: Mapping[str, Any] = field(default_factory=dict)
    final_state: CState | None = None
    classical_call_cpu: tuple[float, ...] = ()

    def to_json(self) -> dict[str, Any]:
        return {"goal": self.instance.goal, "colors": self.instance.colors, "reading": self.instance.reading.to_json(),
                "macros": self.macros if isinstance(self.macros, bool) else list(self.macros),
                "epistemic_plan": list(self.epistemic_plan), "flat_plan": list(self.flat_plan),
                "primitive_plan": self.primitive_plan, "times": {k: round(v, 6) for k, v in self.times.items()},
                "classical_calls": self.classical_calls,
                "classical_call_seconds": [round(t, 6) for t in self.classical_call_seconds],
                "classical_call_cpu": [round(t, 6) for t in self.classical_call_cpu],
                "tasks": [t.to_json() for t in self.tasks], "search": dict(self.search)}

    def write(self, path) -> None:
        """Write the primitive plan (``delkit.arms.plan/1``) as JSON."""
        from pathlib import Path

        Path(path).write_text(json.dumps(self.primitive_plan, indent=2) + "\n")


def epistemic_task(instance: Instance, *, macros: bool | Iterable[str] = True) -> tuple[Task, Task, list[MacroSpec]]:
    """(primitive task, task offered to the planner, grounded macros) of an instance; ``macros`` True (every
    macro the domain declares), False, or the names of the declarations to offer. An ontic action with
    partially observant agents (the hand-over reading's ``take_from_shared``) becomes an
    :class:`~planners.task.EventAction` (:func:`partially_observed_ontic`)."""
    from dataclasses import replace

    from planners.lang.epddl import parse_epddl
    from planners.macros import ground_macros, parse_macros, with_macros

    task = parse_epddl(instance.domain_text, instance.problem_text, domain_source="specs/epico/domain.epddl",
                       problem_source=f"epico_{instance.goal}_{instance.colors}")
    if any(isinstance(a, ActionSpec) and a.kind == "ontic" and a.partial for a in task.actions):
        task = replace(task, actions=tuple(partially_observed_ontic(a, task.agents)
                                           if isinstance(a, ActionSpec) and a.kind == "ontic" and a.partial
                                           else a for a in task.actions), _cache={})
    if macros is False:
        return task, task, []
    decls = parse_macros(instance.domain_text, source="specs/epico/domain.epddl")
    if macros is not True:
        wanted = set(macros)  # type: ignore[arg-type]
        unknown = sorted(wanted - {d.name for d in decls})
        if unknown:
            raise EpicoError(f"macro(s) {', '.join(unknown)} not declared in this reading's domain "
                             f"(declared: {', '.join(d.name for d in decls)})")
        decls = [d for d in decls if d.name in wanted]
        if not decls:
            return task, task, []
    ms = ground_macros(task, decls, instance.problem_text)
    return task, with_macros(task, ms), ms


def partially_observed_ontic(act: ActionSpec, agents: tuple[str, ...]) -> EventAction:
    """An ontic action whose ``partial`` agents cannot tell it from doing nothing: events ``e`` (its effects)
    and ``skip`` (no change), both with precondition ⊤ (executability is checked at the designated world,
    as for every mA* action), ``e`` designated; full observers tell them apart, partial observers do not,
    the others are oblivious. (mA* defines partial observability for sensing and announcements only; this
    is the reading delkit gives it for an ontic action.) Observers must be unconditional."""
    from delkit.models.events import action, ontic

    if any(c != TOP for _, c in (*act.full, *act.partial)):
        raise EpicoError(f"{act.name}: a partially observed ontic action needs unconditional observers")
    full = [a for a, _ in act.full]
    partial = [a for a, _ in act.partial if a not in full]
    post = ontic(list(act.effects), agents, full=agents, name=act.name).post[0]
    em = action(agents, [("e", TOP, post), ("skip", TOP, {})], full=full, partial=partial, designated=["e"],
                name=act.name)
    return EventAction(act.name, lambda bits: em, (), act.executable, act.where, kind="ontic",
                       designated_pre=(TOP,))


def _space(ptask: Task):
    """The planner's default state space (the compact backend; it applies a MacroSpec as the composed event
    model of its steps, Definition 4.1), with its initial state built."""
    from planners.epistemic import make_space

    space = make_space(ptask)
    space.initial()
    return space


def _search(space, limits: EpicoLimits):
    """The epistemic search: BFS (optimal length) or a best-first search."""
    from planners.epistemic import Limits, best_first, bfs

    lim = Limits(timeout=limits.timeout)
    if limits.search == "bfs":
        return bfs(space, lim)
    if limits.search == "tree":
        return tree_bfs(space, lim)
    return best_first(space, lim, kind=limits.search)  # type: ignore[arg-type]


def tree_bfs(space, limits):
    """Breadth-first search without duplicate detection, goal test at generation: the search of the e-PICO
    paper's planner (EFP's BFS, whose visited-state check is an option) — a tree of b^d nodes for branching b
    and plan length d, where a macro that shortens the plan by k steps divides the work by about b^k. Same
    optimal plans as :func:`planners.epistemic.bfs`; ``search`` is ``tree``."""
    from collections import deque

    from planners.epistemic import SearchResult

    t0 = time.perf_counter()
    s0, _ = space.initial()
    if space.is_goal(s0):
        return SearchResult("solved", (), 0, 1, 0.0, "tree", "the goal holds initially")
    frontier: deque = deque([(s0, ())])
    expanded = generated = 0
    while frontier:
        if limits.timeout is not None and time.perf_counter() - t0 > limits.timeout:
            return SearchResult("limit", None, expanded, generated, time.perf_counter() - t0, "tree",
                                f"no plan within limits: time limit {limits.timeout:g} s")
        state, path = frontier.popleft()
        expanded += 1
        for name, nxt, _ in space.successors(state):
            generated += 1
            if space.is_goal(nxt):
                return SearchResult("solved", (*path, name), expanded, generated, time.perf_counter() - t0, "tree")
            frontier.append((nxt, (*path, name)))
    return SearchResult("unsolvable", None, expanded, generated, time.perf_counter() - t0, "tree",
                        "the reachable tree is exhausted: no plan exists")


def solve(instance: Instance, *, macros: bool | Iterable[str] = True, known: Mapping[str, Iterable[Any]] | None = None,
          limits: EpicoLimits = EpicoLimits(), perspective: str | None = None) -> Solution:
    """Spec → epistemic plan (with or without macros) → flattened plan → classical breakdown → plan/1.
    ``macros``: True (all the domain's macros), False, or the names of the macro declarations to offer.

    ``perspective``: None or ``"external"`` — the e-PICO paper's reading: an external planner that knows the
    actual world plans for both robots (each step is checked at the actual world); a robot's name — the plan
    must work in every world that robot considers possible, every step known applicable by the robot that
    executes it (implicit coordination, Engesser et al. 2017; :func:`plan_from_perspective`, on explicit
    Kripke models: 4^n worlds, practical up to about 3 colours).

    ``known`` (robot ↦ colours, or (owner, colour) pairs) says what each robot already knows, e.g. when
    replanning from what was observed. Raises :class:`EpicoError` if no plan is found within the limits or
    a task cannot be carried out (naming it)."""
    from planners.macros import flatten

    if known:
        instance = instance.with_known(known)
    if not isinstance(macros, bool):
        macros = tuple(macros)
    import delkit.logic.semantics  # noqa: F401 - imports (≈0.5 s cold) are not part of the initial-state time
    import planners.spaces  # noqa: F401

    t0, c0 = time.perf_counter(), time.process_time()
    task, ptask, ms = epistemic_task(instance, macros=macros)
    space = _space(ptask)  # the initial state: grounded task, its Kripke model and its compact form
    t_init, c_init = time.perf_counter() - t0, time.process_time() - c0
    view = perspective or EXTERNAL
    if view == EXTERNAL:
        res = _search(space, limits)
    else:
        res = plan_from_perspective(ptask, view, limits)
    if not res.solved:
        hint = ""
        if view != EXTERNAL:
            ext = _search(space, limits)
            if ext.solved:
                chk = perspective_check(ptask, ext.plan or (), view)
                hint = (f"; the external planner's plan {', '.join(ext.plan or ()) or '(empty)'} fails from "
                        f"{view}'s perspective at step {(chk.step or 0) + 1}: {chk.reason}")
        raise EpicoError(f"epistemic planner: no plan for {instance.goal} with {instance.colors} colour(s) "
                         f"({instance.reading.name} reading, {_macro_words(macros)}, "
                         f"{'external planner' if view == EXTERNAL else view + chr(39) + 's perspective'}): "
                         f"{res.reason}{hint}")
    eplan = tuple(res.plan or ())
    flat = tuple(flatten(eplan, ms))
    t1 = time.perf_counter()
    records, final, calls = process_e_plan(task, eplan, instance.classical_init, limits, macros=ms)
    if tuple(r.task for r in records) != flat:
        raise EpicoError(f"the hierarchy processed {[r.task for r in records]}, not the flattened plan {list(flat)}")
    t_class = sum(w for w, _ in calls)
    t_hier = time.perf_counter() - t1
    actions = [a for r in records for a in r.actions]
    primitive = {"format": "delkit.arms.plan/1", "world": instance.layout.to_world(), "actions": actions}
    _check_primitive(primitive)
    return Solution(instance, macros, eplan, flat, primitive,
                    {"initial": t_init, "initial_cpu": c_init, "epistemic": res.seconds, "classical": t_class,
                     "hierarchy": t_hier, "total": t_init + res.seconds + t_hier,
                     "classical_cpu": sum(c for _, c in calls)},
                    len(calls), tuple(w for w, _ in calls), tuple(records),
                    {"expanded": res.expanded, "generated": res.generated, "dead_ends": res.dead_ends,
                     "search": res.search, "length": len(eplan), "perspective": view,
                     "perspective_meaning": perspective_meaning(view)}, final, tuple(c for _, c in calls))


def perspective_meaning(view: str) -> str:
    """One line: what a plan of this reading guarantees."""
    if view == EXTERNAL:
        return ("external planner (the e-PICO paper's reading): a planner that knows the actual world plans for "
                "both robots; every step is applicable in the actual world")
    return (f"{view}'s perspective (implicit coordination, Engesser et al. 2017): the plan works in every world "
            f"{view} considers possible, every step known applicable by the robot that executes it")


def _macro_words(macros: bool | tuple[str, ...]) -> str:
    return ("with macros" if macros else "without macros") if isinstance(macros, bool) else \
        "with macro(s) " + ", ".join(macros) if macros else "without macros"


def _check_primitive(obj: dict) -> None:
    from planners.blocks import ArmsError
    from planners.primitive import parse_plan, symbolic_trace

    try:
        symbolic_trace(parse_plan(obj, source="e-PICO primitive plan"))
    except ArmsError as exc:
        raise EpicoError(f"the primitive plan is not executable: {exc}") from None


def process_e_plan(task: Task, e_plan: Iterable[str], c_init: CState, limits: EpicoLimits = EpicoLimits(), *,
                   macros: Iterable[MacroSpec] = ()) -> tuple[list[TaskRecord], CState, list[tuple[float, float]]]:
    """Listing 1, corrected: for every task of the epistemic plan, a macro is broken down into its simple
    tasks and each is processed in order, with the classical state carried along; a simple task is
    processed in place. Returns the task records, the final classical state and (wall, CPU) seconds of
    each classical call."""
    by_name = {m.name: m for m in macros}
    run = _Runner(task, c_init, limits)
    for name in e_plan:
        if name in by_name:  # is_macro_task(task)
            for simple in by_name[name].step_names:  # break_down_macro(macro=task)
                run.process_simple_task(simple, macro=name)
        else:
            run.process_simple_task(name)
    return run.records, run.c_state, run.calls


class _Runner:
    """``process_simple_task`` of Listing 1 with its state: the classical state (carried from task to task)
    and the epistemic state (replayed on the compact backend for the anchoring and consistency checks)."""

    def __init__(self, task: Task, c_init: CState, limits: EpicoLimits) -> None:
        from planners.spaces import CompactSpace

        self.task, self.limits, self.c_state = task, limits, c_init
        self.fs = CompactSpace(task)
        self.s, _ = self.fs.initial()
        self.records: list[TaskRecord] = []
        self.calls: list[tuple[float, float]] = []

    def process_simple_task(self, name: str, macro: str = "") -> None:
        task, i = self.task, len(self.records) + 1
        act = task.action(name)
        if not isinstance(act, (ActionSpec, EventAction)):
            raise EpicoError(f"task {i} ({name}) is not a simple task (a macro inside a macro?)")
        new = self.fs.step(self.s, name)
        if new is None:
            raise EpicoError(f"task {i} ({name}) is not applicable in the epistemic state it is reached in")
        bad = self.fs.inconsistent(new)
        if bad:
            raise EpicoError(f"task {i} ({name}) leaves {', '.join(bad)} believing ⊥ (no accessible world): "
                             "vacuous success is refused")
        self.s = new
        if act.kind != "ontic":  # is_epistemic_task: sensing or announcement, executed as is
            self.records.append(TaskRecord(name, act.kind, (_epistemic_primitive(name, self.c_state, task),),
                                           macro=macro))
            return
        goal = goal_for(name, self.c_state, task.agents)  # send_to_c_planner(ontic_task=t, initial_state=c_init)
        engine = solve_bfs if self.limits.classical == "bfs" else solve_classical
        c0 = time.process_time()
        try:
            r = engine(self.c_state, goal, max_steps=self.limits.classical_max_steps,
                       timeout=self.limits.classical_timeout)
        except Exception as exc:
            raise EpicoError(f"task {i} ({name}): {exc}") from None
        self.calls.append((r.seconds, time.process_time() - c0))
        self.c_state = r.state
        _anchor(task, self.fs, self.s, self.c_state, i, name)
        self.records.append(TaskRecord(name, "ontic", tuple(_prim(a) for a in r.actions), r.seconds, macro=macro))


def _prim(a: CAction) -> dict[str, Any]:
    return a.to_json()


def _anchor(task: Task, fs, s, c_state: CState, i: int, name: str) -> None:
    """The classical state must agree with the epistemic actual world on every ``occup_by`` fluent."""
    val = s.val[s.point]
    pidx = fs.engine.pidx
    for j, p in enumerate(task.props):
        if not p.startswith("occup_by_"):
            continue
        robot, color = p[len("occup_by_"):].split("_", 1)
        epi = bool((val >> pidx[p]) & 1)
        cla = any(c_state.colors[b] == color and c_state.owner(b) == robot for b in c_state.barrier)
        if epi != cla:
            raise EpicoError(f"task {i} ({name}): anchoring failed: {p} is {epi} in the epistemic state but the "
                             f"classical state has {list(c_state.barrier) or 'nothing'} on the shared table")
        del j


def _epistemic_primitive(name: str, c_state: CState, task: Task) -> dict[str, Any]:
    robot = next((r for r in task.agents if name.split("_").count(r)), ROBOTS[0])
    color = name.rsplit("_", 1)[-1]
    if name.startswith(("sense_table_", "sense_color_")):  # the arms look at all the robot's stacks
        return {"robot": robot, "action": "sense"}
    if name.startswith("announce_table_free_"):
        return {"robot": robot, "action": "announce", "to": [r for r in task.agents if r != robot]}
    if name.startswith("announce_block_on_barrier_"):
        block = next((b for b in c_state.barrier if c_state.colors[b] == color), None)
        if block is None:
            raise EpicoError(f"{name}: no {color} block on the shared table to announce")
        return {"robot": robot, "action": "announce", "args": [block], "to": [r for r in task.agents if r != robot]}
    raise EpicoError(f"{name}: no primitive action for this epistemic task")


# ----------------------------------------------------------------------------- Tables 1 and 2

#: Seed 004, Table 1 (seconds; None = TO): goal ↦ colours ↦ (macro no, macro yes)
SEED_TABLE1: dict[str, dict[int, tuple[float | None, float | None]]] = {
    "alpha": {1: (0.019, 0.004), 2: (1.200, 0.080), 3: (5.192, 1.382), 4: (104.0, 25.889)},
    "beta": {1: (0.083, 0.013), 2: (4.946, 0.242), 3: (21.780, 4.235), 4: (None, 85.144)},
    "gamma": {2: (18.663, 1.427), 3: (None, 24.805), 4: (None, None)},
    "delta": {2: (None, 4.827), 3: (None, 92.998), 4: (None, None)},
}
#: Seed 004, Table 2: goal ↦ colours ↦ (cumulative classical seconds, calls); None = TO
SEED_TABLE2: dict[str, dict[int, tuple[float, int] | None]] = {
    "alpha": {1: (0.074, 1), 2: (0.083, 1), 3: (0.092, 1), 4: (0.112, 1)},
    "beta": {1: (0.157, 2), 2: (0.172, 2), 3: (0.177, 2), 4: (0.202, 2)},
    "gamma": {2: (0.250, 3), 3: (0.267, 3), 4: None},
    "delta": {2: (0.332, 4), 3: (0.351, 4), 4: None},
}
#: Seed 004 §5: initial-state construction, seconds, per number of colours
SEED_INITIAL = {1: 0.003, 2: 0.031, 3: 0.126, 4: 2.117}
#: the peer implementation (PyPI echosys) as measured on a machine like ours: macro off / on
PEER_TABLE1: dict[str, dict[int, tuple[float | None, float | None]]] = {
    "alpha": {3: (4.4, 0.51), 4: (None, 19.8)},
    "beta": {3: (55.9, 4.9)},
    "delta": {2: (8.5, 10.4), 3: (None, None)},
}


#: the macro sides of a Table-1 cell: name ↦ ``solve``'s ``macros`` (False, True or declaration names)
TABLE_SIDES: tuple[tuple[str, bool | tuple[str, ...]], ...] = (("off", False), ("on", True))
#: the hand-over reading's sides: no macro, Listing 4's, the §5 prose macro, both
HANDOVER_SIDES: tuple[tuple[str, bool | tuple[str, ...]], ...] = (
    ("off", False), ("pspb", ("pspb_and_announce",)), ("take", ("take_and_announce",)), ("on", True))


def table_cell(goal: str, colors: int, *, repeat: int = 1, timeout: float = 110.0,
               reading: Reading | None = None, sides: Iterable[tuple[str, Any]] = TABLE_SIDES,
               symmetric: bool | None = None, search: str = "bfs") -> dict[str, Any]:
    """One cell of Tables 1–2 for a reading (default: the paper's), each macro side (default: off and on)
    run ``repeat`` times; wall and CPU seconds (mean) of initial state + epistemic search + hierarchy, the
    initial state alone, states expanded, classical seconds and calls. ``status`` per side is ``ok`` /
    ``TO`` (no plan within the limit) / ``ND`` (not defined: γ and δ with one colour)."""
    from planners.epico import defined, generate, reading_of

    rd = reading if reading is not None else reading_of(symmetric=symmetric)
    sides = tuple(sides)
    out: dict[str, Any] = {"goal": goal, "colors": colors, "reading": rd.name, "sides": [n for n, _ in sides],
                           "search": search}
    if not defined(goal, colors):
        out["status"] = "ND"
        return out
    inst = generate(goal, colors, reading=rd)
    for side, macros in sides:
        walls, cpus, inits, sol = [], [], [], None
        for _ in range(repeat):
            c0, w0 = time.process_time(), time.perf_counter()
            try:
                sol = solve(inst, macros=macros, limits=EpicoLimits(timeout=timeout, search=search))
            except EpicoError as exc:
                if "no plan" not in str(exc):
                    raise
                out[side] = {"status": "TO", "reason": str(exc)}
                break
            walls.append(time.perf_counter() - w0)
            cpus.append(time.process_time() - c0)
            inits.append(sol.times["initial_cpu"])
        else:
            assert sol is not None
            out[side] = {"status": "ok", "wall": sum(walls) / len(walls), "cpu": sum(cpus) / len(cpus),
                         "initial": sol.times["initial"], "initial_cpu": sum(inits) / len(inits),
                         "epistemic": sol.times["epistemic"],
                         "classical": sol.times["classical"], "classical_cpu": sol.times["classical_cpu"],
                         "calls": sol.classical_calls,
                         "max_call": max(sol.classical_call_seconds, default=0.0),
                         "max_call_cpu": max(sol.classical_call_cpu, default=0.0),
                         "plan": list(sol.epistemic_plan), "flat_plan": list(sol.flat_plan),
                         "flat_length": len(sol.flat_plan),
                         "primitive_length": len(sol.primitive_plan["actions"]), "expanded": sol.search["expanded"],
                         "generated": sol.search["generated"],
                         "branching": sol.search["generated"] / max(sol.search["expanded"], 1)}
    first, last = out.get(sides[0][0], {}), out.get(sides[-1][0], {})
    out["status"] = "ok" if all(out.get(n, {}).get("status") == "ok" for n, _ in sides) else "TO"
    if first.get("status") == last.get("status") == "ok":  # first / last side on CPU time (wall is noisy here)
        out["ratio"] = first["cpu"] / last["cpu"] if last["cpu"] > 0 else None
    return out


def macro_report(colors: int = 2, handwritten: str | None = None) -> dict[str, Any]:
    """Every grounded macro of the domain proved equal to its sequence by z3 (in the first state of the
    optimal γ plan where it applies), and the hand-written macro (default: the seed's Listing 4) checked
    against the composition, with its counterexample."""
    from pathlib import Path

    from planners.epico import generate
    from planners.macros import check_handwritten, ground_handwritten, ground_macros, parse_macros, prove_macro
    from planners.macros import sequence_states as seq

    inst = generate("gamma" if colors >= 2 else "alpha", colors)
    task, _, ms = epistemic_task(inst)
    sol = solve(inst, macros=False)
    states = [task.initial]
    for name in sol.flat_plan:
        nxt = seq(task, [task.action(name)], states[-1])
        assert nxt is not None
        states.append(nxt[1][-1])
    proofs = []
    for m in ms:
        where = next((i for i, s in enumerate(states) if seq(task, m.steps, s) is not None), None)
        if where is None:  # never applicable along the plan: prove it where its owner has sensed
            continue
        p = prove_macro(task, m, states[where])
        proofs.append({**p.to_json(), "state": f"after {list(sol.flat_plan[:where]) or 'nothing'}"})
    from planners.demo import specs_dir

    specs = specs_dir() / "epico"
    path = Path(handwritten) if handwritten else specs / "listing4.txt"
    try:
        from delkit.paths import read_input

        text = read_input(path, "hand-written macro")
    except (OSError, UnicodeDecodeError) as exc:
        from delkit.errors import io_reason

        raise EpicoError(f"{path}: cannot read the hand-written macro ({io_reason(exc)})") from None
    htask, hand = ground_handwritten(inst.domain_text, inst.problem_text, text, source=str(path))
    hw = check_handwritten(htask, hand, ground_macros(htask, parse_macros(inst.domain_text), inst.problem_text))
    return {"proofs": proofs, "all_equal": all(p["equal"] for p in proofs) and bool(proofs),
            "handwritten": str(path), "handwritten_check": hw.to_json()}


def run_demo(out) -> dict[str, Any]:
    """The e-PICO section of ``delkit demo``: δ with 2 colours, macros on, to a primitive plan that
    ``arms.plan`` accepts; the macro proved equal to its sequence; Listing 4's counterexample."""
    from pathlib import Path

    from planners.epico import generate
    from planners.validate import check_plan

    inst = generate("delta", 2)
    sol = solve(inst, macros=True)
    task, _, ms = epistemic_task(inst)
    valid = check_plan(task, list(sol.flat_plan)).valid
    rep = macro_report(2)
    hw = rep["handwritten_check"]
    out = Path(out) / "epico"
    out.mkdir(parents=True, exist_ok=True)
    sol.write(out / "plan.json")
    ok = valid and rep["all_equal"] and not hw["consistent"]
    n_obl = sum(p["obligations"] for p in rep["proofs"])
    summary = (f"δ, 2 colours: {len(sol.epistemic_plan)} epistemic tasks ({len(sol.flat_plan)} flattened) → "
               f"{len(sol.primitive_plan['actions'])} primitive actions, {sol.classical_calls} classical calls, "
               f"{sol.times['total']:.2f} s; delkit check {'accepts' if valid else 'REJECTS'} it; "
               f"{len(rep['proofs'])} macro(s) {'proved equal' if rep['all_equal'] else 'NOT proved'} to their "
               f"sequence by z3 ({n_obl} obligations); Listing 4 "
               + (f"inconsistent: {hw['counterexample'].get('difference', '')}" if not hw["consistent"]
                  else "consistent?!") + f"; plan: {out / 'plan.json'}")
    return {"ok": ok, "summary": summary, "solution": sol.to_json(), "macros": rep}


# ----------------------------------------------------------------------------- plans from a robot's perspective

#: the two readings of a plan: ``external`` (the e-PICO paper's: a planner that knows the actual world checks
#: every step there) or a robot's name (implicit coordination, Engesser et al. 2017)
EXTERNAL = "external"


def actor_of(task: Task, act: ActionSpec | EventAction | MacroSpec) -> str:
    """The agent who executes ``act``: the first agent named among its arguments (the e-PICO actions' ``?ag``,
    e.g. ``take_from_shared_robot2_robot1_red`` is robot2's). A macro's steps have their own actors."""
    tokens = act.name.split("_")
    for t in tokens:
        if t in task.agents:
            return t
    raise EpicoError(f"action {act.name!r} names no agent of the task ({', '.join(task.agents)}): its actor is "
                     "unknown, so it cannot be planned from an agent's perspective")


def local_state(model, agent: str):
    """The agent's associated local state (Engesser et al. 2017, Def. 3): the same model with every world the
    agent considers possible from a designated world designated."""
    ws = sorted({int(v) for w in model.designated for v in model.successors(agent, int(w))})
    return model.with_designated(ws)


@dataclass(frozen=True)
class PerspectiveCheck:
    """Outcome of :func:`perspective_check`: ``valid`` iff every step is known applicable by its actor in every
    world the planning agent's perspective reaches and the goal holds in all of them at the end; else the
    first failing step (0-based; ``len(plan)`` = the goal), its actor and a world where it fails."""

    agent: str
    valid: bool
    step: int | None = None
    action: str = ""
    actor: str = ""
    reason: str = ""
    worlds: tuple[int, ...] = ()

    def to_json(self) -> dict[str, Any]:
        return {"perspective": self.agent, "valid": self.valid, "step": self.step, "action": self.action or None,
                "actor": self.actor or None, "reason": self.reason, "designated_worlds": list(self.worlds)}


def _world_text(model, w: int, props: Iterable[str], about=None) -> str:
    """A world as the propositions true there; with ``about`` (a formula) only its propositions, each with its
    truth value."""
    true = model.true_props(w)
    if about is not None:
        from delkit.logic.formula import props_of

        mine = sorted(props_of(about) & set(props))
        if mine:
            return "where " + ", ".join(f"{p} is {'true' if p in true else 'false'}" for p in mine)
    shown = sorted(true & set(props))
    return "where " + (", ".join(shown) + " (only) are true" if shown else "no fluent is true")


def perspective_step(task: Task, model, act):
    """One step of a plan from a perspective: ``act`` (an action, or a macro's steps in turn) by its actor i in
    the local state of i of ``model`` (multi-pointed). Returns (the successor, whose designated worlds are the
    updates of every world i considered possible, contracted) or (None, why not)."""
    from delkit.models.bisimulation import contract
    from delkit.models.update import product_update
    from planners.task import uncovered_worlds

    steps = act.steps if isinstance(act, MacroSpec) else (act,)
    for st in steps:
        i = actor_of(task, st)
        loc = local_state(model, i)
        bad = [int(w) for w in loc.designated if not loc.holds(st.executable, [int(w)])]
        if bad:
            return None, (f"{st.name}: {i} does not know it is applicable: its precondition fails in a world "
                          f"{i} considers possible, {_world_text(loc, bad[0], task.props, st.executable)}")
        em = task.event_model(st, loc)
        unc = uncovered_worlds(em, loc)
        if unc:
            return None, (f"{st.name}: no event of it can happen in a world {i} considers possible, "
                          f"{_world_text(loc, unc[0], task.props)}")
        new = product_update(loc, em)
        if not new.designated:
            return None, f"{st.name}: nothing {i} considers possible survives it"
        lost = new.inconsistent_agents()
        if lost:
            return None, f"{st.name}: leaves {lost[0][0]} believing ⊥ (no accessible world)"
        model = contract(new)
    return model, ""


def perspective_initial(task: Task, agent: str):
    """The planning agent's perspective on the initial state: its local state (every world it considers
    possible from the actual world designated), contracted."""
    from delkit.models.bisimulation import contract

    if agent not in task.agents:
        raise EpicoError(f"perspective {agent!r}: not an agent of the task; use one of {', '.join(task.agents)} "
                         f"or {EXTERNAL!r} (the e-PICO paper's external planner)")
    return contract(local_state(task.initial, agent))


def perspective_check(task: Task, plan: Iterable[str], agent: str) -> PerspectiveCheck:
    """Is ``plan`` (action or macro names of ``task``) a plan from ``agent``'s perspective (implicit
    coordination, Engesser et al. 2017)? From ``agent``'s local state of the initial state, every step must be
    applicable in every world its actor considers possible from the worlds reached so far (the actor's local
    state: it knows the step is applicable), and the goal must hold in every world reached at the end. A plan
    valid from a perspective is valid for the external planner too (the actual world is among those worlds);
    not conversely."""
    plan = list(plan)
    s = perspective_initial(task, agent)
    for k, name in enumerate(plan):
        act = task.action(name)
        nxt, why = perspective_step(task, s, act)
        if nxt is None:
            return PerspectiveCheck(agent, False, k, name, actor_of(task, act), why,
                                    tuple(int(w) for w in s.designated))
        s = nxt
    bad = [int(w) for w in s.designated if not s.holds(task.goal, [int(w)])]
    if bad:
        return PerspectiveCheck(agent, False, len(plan), "", "", "the goal fails in a world reached, "
                                + _world_text(s, bad[0], task.props), tuple(int(w) for w in s.designated))
    return PerspectiveCheck(agent, True, worlds=tuple(int(w) for w in s.designated))


def plan_from_perspective(task: Task, agent: str, limits: EpicoLimits = EpicoLimits(), *,
                          max_depth: int = 12):
    """Breadth-first search for a shortest plan from ``agent``'s perspective (see :func:`perspective_check`):
    states are the multi-pointed models of :func:`perspective_step`, identified up to bisimulation. Returns a
    :class:`planners.epistemic.SearchResult` (``search`` = ``perspective:AGENT``); ``unsolvable`` when every
    perspective state within ``max_depth`` steps was expanded without reaching the goal."""
    from collections import deque

    from delkit.models.bisimulation import canonical_form
    from planners.epistemic import SearchResult

    t0 = time.perf_counter()
    s0 = perspective_initial(task, agent)
    name = f"perspective:{agent}"
    if s0.holds(task.goal):
        return SearchResult("solved", (), 0, 0, time.perf_counter() - t0, name)
    seen = {canonical_form(s0)}
    queue = deque([(s0, ())])
    expanded = generated = 0
    cut = False
    while queue:
        s, path = queue.popleft()
        if len(path) >= max_depth:
            cut = True
            continue
        if limits.timeout is not None and time.perf_counter() - t0 > limits.timeout:
            return SearchResult("limit", None, expanded, generated, time.perf_counter() - t0, name,
                                f"time limit {limits.timeout:g} s", distinct_states=len(seen))
        expanded += 1
        for act in task.actions:
            nxt, _ = perspective_step(task, s, act)
            if nxt is None:
                continue
            generated += 1
            key = canonical_form(nxt)
            if key in seen:
                continue
            seen.add(key)
            if nxt.holds(task.goal):
                return SearchResult("solved", (*path, act.name), expanded, generated, time.perf_counter() - t0,
                                    name, distinct_states=len(seen))
            queue.append((nxt, (*path, act.name)))
    if cut:
        return SearchResult("limit", None, expanded, generated, time.perf_counter() - t0, name,
                            f"no plan from {agent}'s perspective within {max_depth} steps ({len(seen)} distinct "
                            f"states; longer plans were not searched)", distinct_states=len(seen))
    return SearchResult("unsolvable", None, expanded, generated, time.perf_counter() - t0, name,
                        f"no plan from {agent}'s perspective: all {len(seen)} states reachable from its "
                        f"perspective were expanded without reaching the goal in every world",
                        distinct_states=len(seen))
