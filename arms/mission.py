"""The closed loop on the planner's own DEL belief state: plan → shield → act in physics → observe → update the
belief state with the task's event model → check → (on a divergence) repair and replan from the belief state.

A *mission* is a world (the robots' tables), an e-PICO goal (α … δ, seed 004 Sec. 5) and an epistemic
*model* — the planner's side (``arms.cli.epico_run.EpicoModel``; ``arms`` does not import a planner): the
task, the state space the planner searched (compact or numpy backend), the initial belief state and
``plan(belief, world_json)``, which plans **from the belief state** (the epistemic search starts from it;
the classical level from the observed block positions and the colours the cameras saw).

The robots' beliefs *are* that DEL state (:class:`arms.beliefs.BeliefState`): it starts as the task's
initial state and changes only by the event model of an executed task — the sensing event the side
camera's observation selects, the announcement as received (or lost), the ontic task's model.

**No oracle in the loop.** Inside the loop nothing reads ground truth but poses (which the domain does not
make epistemic): colours come only from the side cameras (:mod:`arms.sensing`), and ownership from where a
block stands (``Mission.stands``: the robot in front of which it stands, or stood before it went onto the
shared table — updated from the measured poses, never from the generator's start map). The classical level
breaks each task down just before it runs, from the measured positions and the colours seen by then
(``unseen`` for the rest: no plan picks a block for a colour nobody has seen).

Per task:

* **shield** (before): the task's precondition as the domain states it (epistemic parts included, e.g.
  ``K_robot1 hold(robot1, red)`` for robot1's ``put_on_shared``) is evaluated on the belief state; false →
  the task is not executed, the step says which conjuncts failed for whom, and the loop repairs and
  replans from the belief state. Every primitive action's classical precondition is checked on the
  measured state before it runs (recovery actions too). ``shield=False`` (``--no-shield``) turns off every
  belief-side guard — shield, look and bisimulation checks (computed and reported as *unheeded*, not acted
  on), camera completeness, goal-in-belief — and exists only to show the run that goes wrong without them;
* physical check (after each primitive): every block within ``tolerance`` of its symbolic place;
* **check** (after the task): a *look* by the robot that acted (a sensing task's own look): what its
  cameras decide (:func:`observe_fluents`: its own ``hold`` fluents, every ``occup_by``) against the belief
  state's actual world and its own beliefs; and the belief state bisimilar to the plan's prediction (a lost
  message shows here: announcements are acknowledged). A difference is a named divergence (which fluent,
  who saw it). At the end of a plan both robots look.

Repair: put down a held block, re-seat blocks off their slot, read the poses; the look that found the
divergence enters the belief state as a **named belief revision** (:meth:`arms.beliefs.BeliefState.look`:
the public "may have changed" event on the contradicted fluents, then the look's sensing event); both
robots look at the shared table (a public observation); then the planner plans from the belief state (a
block on the shared table is taken back by a planned, shielded ``take_from_shared``). Evidence is never
discarded: a sensing task whose observation contradicts every actual world revises the state the same way.
A take of the other robot's block moves it to the taker's table: the mission applies "``hold(owner, c)``
may have changed" after it, so that ``hold`` keeps its meaning.

The **audit** (``Mission.audit``) is a separate judge: the simulation's painted colours and poses against
the belief state, after every task and at the end, written into the run's JSON (``audit``); no decision
reads it. Success: the goal holds in the belief state, both robots' final looks agree with it, every fired
fault was caught (by a look, the shield, an acknowledgement or the pose check), every block within
``tolerance``, no arm–arm contact.

Faults (``Fault``; K counts primitive actions over the whole run, the fault fires at the first suitable
action at or after K): ``drop@K`` (the hand opens just after lift-off), ``misplace@K`` (the block goes to
the next stack), ``swap-colours`` (two blocks of different colours exchanged before the run),
``drop-msg@K`` (an announcement is lost: the listeners' state does not change), ``repaint@K`` (right
after a sensing task, a block of the sensing robot is repainted), ``occlusion`` (a grey block stands in
front of the stack of the first block the plan puts on the shared table: the low side camera cannot see
it). A fault whose action never comes is reported as "never fired".
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable, Iterable, Mapping
from dataclasses import dataclass, field, replace
from types import MappingProxyType
from typing import Any

import numpy as np

from arms.beliefs import BeliefError, BeliefState, pretty
from arms.executor import Executor, MotionError
from arms.plan import Action, parse_plan
from arms.plan import apply_action as _apply
from arms.sensing import nearest_colour
from arms.world import COLORS, ArmsError, Location, PlanError, SymbolicState, World, initial_state, rgba_of
from delkit.errors import DelkitError

__all__ = ["Goal", "GOALS", "Fault", "parse_fault", "GoalUnreachable", "Mission", "MissionResult", "goal_of",
           "random_world", "world_from_layout", "StepRecord", "observe_fluents", "UNSEEN"]

#: the colour the classical level is given for a block no camera has seen (it matches no task's colour)
UNSEEN = "unseen"


class GoalUnreachable(ArmsError):
    """The planner found no plan for the goal from the belief state."""


@dataclass(frozen=True)
class Goal:
    """e-PICO's goals: a robot believes ``distinct`` different colours of blocks that started in front of
    the other robot (and, with ``free_barrier``, the shared table is empty at the end)."""

    name: str
    distinct: int
    free_barrier: bool


GOALS: Mapping[str, Goal] = MappingProxyType({
    "alpha": Goal("alpha", 1, False), "beta": Goal("beta", 1, True),
    "gamma": Goal("gamma", 2, False), "delta": Goal("delta", 2, True),
})
_GREEK = {"α": "alpha", "β": "beta", "γ": "gamma", "δ": "delta"}


def goal_of(name: str) -> Goal:
    key = _GREEK.get(name.strip(), name.strip().lower())
    if key not in GOALS:
        raise ArmsError(f"unknown goal {name!r}; use alpha, beta, gamma or delta (α β γ δ)")
    return GOALS[key]


_AT_FAULTS = ("drop", "misplace", "drop-msg", "repaint")
_FIRES_ON = {"drop": ("pick", "take_from_barrier"), "misplace": ("place", "put_on_barrier"),
             "drop-msg": ("announce",), "repaint": ("sense",)}


@dataclass(frozen=True)
class Fault:
    """``drop`` / ``misplace`` / ``drop-msg`` / ``repaint`` at primitive action ``at`` (or the first suitable
    one after), ``swap-colours`` or ``occlusion``."""

    kind: str
    at: int = 0

    def __str__(self) -> str:
        return f"{self.kind}@{self.at}" if self.kind in _AT_FAULTS else self.kind


def parse_fault(text: str) -> Fault:
    """``drop@K``, ``misplace@K``, ``drop-msg@K``, ``repaint@K``, ``swap-colours`` or ``occlusion``."""
    t = text.strip().lower()
    if t in ("swap-colours", "swap-colors"):
        return Fault("swap-colours")
    if t == "occlusion":
        return Fault("occlusion")
    kind, _, at = t.partition("@")
    if kind in _AT_FAULTS and at.isdigit():
        return Fault(kind, int(at))
    raise ArmsError(f"unknown fault {text!r}; use drop@K, misplace@K, drop-msg@K, repaint@K (K = index of a "
                    "primitive action), swap-colours or occlusion")


@dataclass
class StepRecord:
    """One primitive action (executed or stopped by the shield) and what was found."""

    index: int           # primitive action number over the whole run
    plan: int            # which plan (0 = the first, 1 = the first replan, ...)
    task: str
    robot: str
    text: str
    ok: bool
    message: str
    observed: dict
    sim_time: float
    max_block_error: float
    fault: str = ""
    precondition: str = ""          # the task's precondition (readable), evaluated on the belief state
    precondition_holds: bool | None = None
    executed: bool = True
    checks: dict = field(default_factory=dict)

    def to_json(self) -> dict:
        return {"index": self.index, "plan": self.plan, "task": self.task, "robot": self.robot, "text": self.text,
                "executed": self.executed, "precondition": self.precondition,
                "precondition_holds": self.precondition_holds, "ok": self.ok, "message": self.message,
                "observed": self.observed, "checks": self.checks, "t_sim_s": round(self.sim_time, 3),
                "max_block_error_m": None if math.isnan(self.max_block_error) else self.max_block_error,
                "fault": self.fault}


@dataclass
class MissionResult:
    """The mission's outcome (see module docstring for what ``success`` requires)."""

    success: bool
    goal: str
    reason: str
    goal_in_world: bool
    goal_in_beliefs: bool
    max_block_error: float
    arm_contacts: int
    replans: int
    steps: list[StepRecord]
    plans: list[list[dict]]
    planning_seconds: list[float]
    belief_log: list[dict]
    beliefs: dict
    lost: list[str]
    faults: list[str]
    sim_seconds: float
    wall_seconds: float
    cpu_seconds: float
    grasp: str
    files: dict = field(default_factory=dict)
    backend: str = "compact"
    shield: bool = True
    unfired: list[str] = field(default_factory=list)
    unheeded: list = field(default_factory=list)    # --no-shield: (step, divergence) found, not acted on
    audit: dict = field(default_factory=dict)       # the judge (ground truth vs beliefs); read by no decision
    caught_by: list = field(default_factory=list)   # per fired fault: what caught it (look, shield, ack, pose)
    guard_cpu_seconds: float = 0.0   # CPU in the shield and the checks (precondition, fluents, bisimulation)
    belief_cpu_seconds: float = 0.0  # CPU of the belief updates (event models applied, knowledge for the log)
    planning_cpu_seconds: list = field(default_factory=list)  # CPU of each (re)plan
    exec_cpu_seconds: float = 0.0    # CPU of executing the tasks (physics, control, sensing, shield, checks, updates)

    @property
    def realtime_factor(self) -> float:
        return self.sim_seconds / self.wall_seconds if self.wall_seconds > 0 else float("inf")

    @property
    def unsafe_steps(self) -> list[StepRecord]:
        """Steps executed although their precondition was false in the belief state."""
        return [s for s in self.steps if s.executed and s.precondition_holds is False]

    def tasks(self) -> list[dict]:
        """Per plan and task: the planned actions, what the arms did, what was observed, and whether the
        shield and the checks found the world and the belief state as the plan expects (``ok``)."""
        out: list[dict] = []
        for no, plan in enumerate(self.plans):
            for t in [*plan, {"task": "recovery", "actions": []}, {"task": "re-sense", "actions": []}]:
                done = [s for s in self.steps if s.plan == no and s.task == t["task"]]
                if not done and t["task"] in ("recovery", "re-sense"):
                    continue
                observed: dict = {}
                for s in done:
                    for k, v in s.observed.items():
                        if k != "columns":
                            observed.setdefault(k, {}).update(v) if isinstance(v, dict) else observed.update({k: v})
                ok = bool(done) and all(s.ok for s in done)
                out.append({"plan": no, "task": t["task"], "planned": [a for a in t.get("actions", [])],
                            "done": [s.text + (f" [fault: {s.fault}]" if s.fault else "")
                                     + ("" if s.executed else " [not executed: shield]") for s in done],
                            "observed": observed, "ok": ok,
                            "precondition": done[0].precondition if done else "",
                            "status": "match" if ok else "diverged" if done else "not executed (replanned)",
                            "message": next((s.message for s in done if not s.ok), "")})
        return out

    def to_json(self) -> dict:
        return {"success": self.success, "goal": self.goal, "reason": self.reason,
                "goal_in_world": self.goal_in_world, "goal_in_beliefs": self.goal_in_beliefs,
                "belief_backend": self.backend, "shield": self.shield,
                "max_block_error_m": self.max_block_error, "arm_contacts": self.arm_contacts,
                "replans": self.replans, "plans": self.plans,
                "planning": [{"seconds": t, "cpu_s": c}  # wall and CPU time of each (re)plan
                             for t, c in zip(self.planning_seconds, self.planning_cpu_seconds, strict=False)],
                "tasks": self.tasks(), "steps": [s.to_json() for s in self.steps],
                "unsafe_steps": [s.index for s in self.unsafe_steps],
                "unheeded": [{"step": i, "divergence": m} for i, m in self.unheeded],
                "audit": self.audit, "caught_by": self.caught_by,
                "belief_log": self.belief_log, "beliefs": self.beliefs, "lost_blocks": self.lost,
                "faults": self.faults, "faults_never_fired": self.unfired, "sim_seconds": self.sim_seconds,
                "wall_s": self.wall_seconds, "cpu_s": self.cpu_seconds, "guard_cpu_s": self.guard_cpu_seconds,
                "belief_cpu_s": self.belief_cpu_seconds, "exec_cpu_s": self.exec_cpu_seconds,
                "grasp": self.grasp, "files": self.files}


class _Divergence(Exception):
    """Raised inside the loop: what a sensor, the shield or the acknowledgement of a message reports is not
    what the plan expects. ``by``: what found it (look, shield, ack, pose); ``looker``/``seen``: the look
    that found it and what it saw (the repair revises the belief state with it)."""

    def __init__(self, msg: str, fluents: tuple[str, ...] = (), *, looker: str = "",
                 seen: Mapping[str, bool] | None = None, by: str = "") -> None:
        super().__init__(msg)
        self.fluents = fluents
        self.looker = looker
        self.seen = dict(seen) if seen is not None else None
        self.by = by


def _colour_names(world: World) -> dict[str, str]:
    return {b: nearest_colour(np.array(world.colors[b])) for b in world.blocks}


def _fluent(p: str) -> tuple[str, str, str]:
    """``hold_robot1_red`` → ("hold", "robot1", "red")."""
    kind = "occup_by" if p.startswith("occup_by_") else "hold"
    owner, colour = p[len(kind) + 1:].split("_", 1)
    return kind, owner, colour


def _conjuncts(f: Any) -> list:
    from delkit.logic.formula import And

    return [x for part in f.args for x in _conjuncts(part)] if isinstance(f, And) else [f]


def _k(agent: str, p: str, value: bool) -> Any:
    from delkit.logic.formula import K, Not, Prop

    return K(agent, Prop(p) if value else Not(Prop(p)))


def _swap_colours(world: World, first: str | None) -> tuple[World, str]:
    """The world with the colours of ``first`` (or the first block) and the first block of another colour
    exchanged; a message saying what was swapped."""
    names = _colour_names(world)
    order = list(world.blocks)
    a = first if first in names else (order[0] if order else None)
    if a is None:
        return world, "swap-colours: no blocks"
    b = next((x for x in order if names[x] != names[a]), None)
    if b is None:
        return world, "swap-colours: every block has the same colour; nothing swapped"
    cols = dict(world.colors)
    cols[a], cols[b] = cols[b], cols[a]
    return replace(world, colors=MappingProxyType(cols)), f"swap-colours: {a} is {names[b]}, {b} is {names[a]}"


def observe_fluents(views: Iterable[Any], robot: str, props: Iterable[str], stands: Mapping[str, str],
                    shared: str = "shared table") -> dict[str, bool]:
    """What ``robot``'s look (its side camera's column views, every one complete) decides about the fluents
    ``props``, from the colours the camera saw and where each block stands (``stands``: block ↦ the robot in
    front of which it stands, or stood last before it went onto the shared table — from poses, not from any
    start map): ``hold(robot, c)`` — a block of colour c seen on robot's stacks or robot's block seen on the
    shared table; ``occup_by(o, c)`` — o's block of colour c seen on the shared table. Fluents about the
    other robot's stacks are not decided (its stacks are not in view): a robot never knows what it could
    not have sensed."""
    views = list(views)
    on_shared = {b: c for v in views if v.column == shared for b, c in v.blocks.items()}
    on_mine = {b: c for v in views if v.column != shared for b, c in v.blocks.items()}
    out: dict[str, bool] = {}
    for p in props:
        kind, owner, c = _fluent(p)
        if kind == "occup_by":
            out[p] = any(stands.get(b) == owner and col == c for b, col in on_shared.items())
        elif owner == robot:
            out[p] = (any(col == c for col in on_mine.values())
                      or any(stands.get(b) == robot and col == c for b, col in on_shared.items()))
    return out


def _swapped_blocks(world: World, swapped: World) -> list[str]:
    """The blocks the swap-colours fault repainted."""
    return [b for b in world.blocks if swapped.colors[b] != world.colors[b]]


class Mission:
    """One closed-loop mission on the planner's DEL belief state (see module docstring)."""

    def __init__(self, world: World, goal: Goal | str, model: Any, *, faults: tuple[Fault, ...] = (),
                 grasp: str = "friction", tolerance: float = 0.01, max_replans: int = 4, record_fps: float = 0.0,
                 progress: Callable[[str], None] | None = None, shield: bool = True,
                 see_through: bool = False) -> None:
        self.world = world                      # geometry (stacks, slots); its colours are the scene's paint only
        self.goal = goal_of(goal) if isinstance(goal, str) else goal
        self.model = model
        self.faults = tuple(faults)
        self.grasp = grasp
        self.tolerance = tolerance
        self.max_replans = max_replans
        self.record_fps = record_fps
        self.progress = progress
        self.shield = shield
        self.see_through = see_through          # sensor mutation (tests only)
        self.stands: dict[str, str] = {}        # block ↦ robot in front of which it stands (from poses)
        self.seen_colours: dict[str, str] = {}  # block ↦ colour a camera last saw
        self.fault_log: list[str] = []
        self.caught_by: list[dict] = []         # per fired fault: what caught it (look / shield / ack / pose)
        self.guard_cpu = 0.0    # CPU of the shield and the checks
        self.planning_cpu: list[float] = []
        self.exec_cpu = 0.0     # CPU of executing the plans' tasks (physics, control, sensing, shield, checks, updates)
        self.belief_cpu = 0.0   # CPU of the belief updates (event models applied, knowledge listed for the log)
        self.audit_log: list[dict] = []         # the judge's findings per task (never read by the loop)
        self._swapped: set[str] = set()         # swap-colours: the blocks whose paint was exchanged
        self.pending: list[str] = []            # faults fired but not caught yet

    # -- helpers ---------------------------------------------------------------------------------------
    def _say(self, msg: str) -> None:
        if self.progress is not None:
            self.progress(msg)

    def _stand(self, state: SymbolicState) -> None:
        """Where every block stands, from the (pose-verified) classical state: a block on a robot's stack is
        in front of that robot; a block on the shared table or in a hand keeps the robot it came from."""
        for b, loc in state.places.items():
            if loc.kind == "stack":
                self.stands[b] = loc.robot

    def _world_json(self, state: SymbolicState, lost: set[str]) -> dict:
        """The observed world for the planner: stacks from the measured poses, colours as the cameras last saw
        them (``unseen`` for a block no camera has seen: the classical level never picks it for a colour),
        the owner of a block on the shared table from where it stood."""
        w = self.world
        stacks = {r: [[b for _, b in state.on_top("stack", r, s) if b not in lost]
                      for s in range(len(w.stacks[r]))] for r in w.robots}
        barrier = [b for _, b in state.on_top("barrier") if b not in lost]
        blocks = [b for r in w.robots for st in stacks[r] for b in st] + barrier
        lay = w.layout
        return {"robots": list(w.robots), "stacks": stacks, "barrier": barrier,
                "colors": {b: self.seen_colours.get(b, UNSEEN) for b in blocks},
                "owners": {b: self.stands[b] for b in barrier if b in self.stands},
                "layout": {"base_y": lay.base_y, "stack_x": lay.stack_x, "stack_pitch": lay.stack_pitch,
                           "table_z": lay.table_z, "block_size": lay.block_size}}

    def _apply_task(self, b: BeliefState, name: str, robot: str, *, time: float = 0.0,
                    observed: Mapping[str, bool] | None = None, heard: bool = True, force: bool = False) -> Any:
        """The task's event model on ``b``; a take of the other robot's block then moves it to the taker's
        table: ``hold(owner, c)`` (and the taker's ``hold(taker, c)``) may have changed — the public "may have
        changed" event, so that ``hold`` keeps meaning "a block of colour c lies in front of o"."""
        ev = b.apply(name, robot=robot, time=time, observed=observed, heard=heard, force=force)
        if name.startswith("take_from_shared_"):
            taker, owner, colour = name[len("take_from_shared_"):].split("_")
            if taker != owner:
                moved = [p for p in (f"hold_{owner}_{colour}", f"hold_{taker}_{colour}") if p in b.task.props]
                if moved:
                    b.forget(moved, time=time, why=f"{taker} took {owner}'s {colour} block onto its own table: "
                             + ", ".join(map(pretty, moved)) + " may have changed")
        return ev

    def _plan(self, belief: BeliefState, world_json: dict) -> tuple[list, float, list, list[dict]]:
        """(tasks, planning seconds, predicted belief state after each task, JSON summary). The tasks'
        primitive actions are made just before each task runs (:meth:`_breakdown`), from the poses and the
        colours seen by then."""
        tasks, meta = self.model.plan(belief, world_json)
        self.planning_cpu.append(meta.get("cpu_s", float("nan")))
        pred, cur = [], belief.copy()
        for t in tasks:
            cur = cur.copy()
            act = self.model.task.action(t.name)
            obs = None
            if act.kind == "sensing":  # the planner's choice: the event true at the actual world
                val = cur.valuation()
                obs = {f.name: bool(val.get(f.name)) for f, _c in act.sensed}
            self._apply_task(cur, t.name, t.robot, observed=obs, force=True)
            pred.append(cur)
        summary = [{"task": t.name, "kind": t.kind, "robot": t.robot} for t in tasks]
        return tasks, meta["wall_s"], pred, summary

    def _breakdown(self, t: Any, state: SymbolicState, lost: set[str]) -> list[Action]:
        """The task's primitive actions from the current poses and seen colours (the classical level)."""
        wj = self._world_json(state, lost)
        acts = self.model.breakdown(t.name, wj) if hasattr(self.model, "breakdown") else list(t.actions)
        pw = dict(wj, colors={b: (c if c in COLORS else "grey") for b, c in wj["colors"].items()})
        pw.pop("owners", None)
        return list(parse_plan({"world": pw, "actions": acts}, source=f"task {t.name}").actions) if acts else []

    # -- ground truth: the judge and the fault injector only (never read by a decision of the loop) ---------
    def _true_colour(self, ex: Executor, b: str) -> str:
        return nearest_colour(ex.model.geom_rgba[ex.model.geom(f"block/{b}").id])

    def _audit_world(self, ex: Executor, lost: set[str]) -> dict[str, bool]:
        """The fluents as the simulation has them: the blocks' painted colours and where they stand."""
        lay = self.world.layout
        bx = lay.barrier_xy()
        held = set(ex.held.values())
        colour = {b: self._true_colour(ex, b) for b in self.world.blocks if b not in lost}
        on_shared = {b for b in colour if b not in held
                     and np.linalg.norm(ex.block_position(b)[:2] - bx) < 0.5 * lay.block_size + 0.01
                     and ex.block_position(b)[2] > lay.table_z}
        out = {}
        for p in self.model.task.props:
            kind, owner, c = _fluent(p)
            pool = on_shared if kind == "occup_by" else colour.keys()
            out[p] = any(self.stands.get(b) == owner and colour[b] == c for b in pool)
        return out

    def audit(self, ex: Executor, belief: BeliefState, lost: set[str], where: str) -> dict:
        """The judge: the simulation's fluents against the belief state (its actual world, and every
        ``K_a p`` believed while p is false). Written into the run's JSON; nothing in the loop reads it."""
        world = self._audit_world(ex, lost)
        val = belief.valuation()
        bad = [p for p in world if val.get(p) is not None and world[p] != val[p]]
        false_beliefs = [pretty(f"K{{{a}}} {'' if v else '¬'}{p}") for a in belief.task.agents for p, v in
                         ((p, not world[p]) for p in world) if belief.holds(_k(a, p, v))]
        return {"where": where, "agrees": not bad and not false_beliefs,
                "actual_world_differs": [f"{pretty(p)}: {str(world[p]).lower()} in the simulation, "
                                         f"{str(val[p]).lower()} in the belief state's actual world" for p in bad],
                "false_beliefs": false_beliefs, "world": world}

    # -- sensing ---------------------------------------------------------------------------------------
    def _look(self, ex: Executor, robot: str, rec: StepRecord) -> list:
        """The robot's side camera: low view, and (belief guards on) the high view for the columns the low
        one could not see completely."""
        views = ex.sense_side(robot, "low", see_through=self.see_through)
        rec.observed.setdefault("columns", []).extend(v.to_json() for v in views)
        hidden = [v for v in views if not v.complete]
        if hidden and "occlusion" in self._occlusion_pending:
            self._occlusion_pending.remove("occlusion")
            self.fault_log.append(f"occlusion fired at action {rec.index} ({rec.text}): the low side camera's view of "
                                  + ", ".join(v.column for v in hidden) + " is blocked")
            rec.fault = "occlusion: " + ", ".join(v.column for v in hidden) + " partly hidden"
            if not self.shield:
                self.pending.append("occlusion")
        if hidden and self.shield:
            names = ", ".join(f"{v.column} ({v.occluded} of {v.rays} rays occluded)" for v in hidden)
            rec.checks["occlusion"] = f"caught: the low side camera cannot see all of {names}; looking from above"
            high = {v.column: v for v in ex.sense_side(robot, "high", see_through=self.see_through)}
            views = [high[v.column] if not v.complete else v for v in views]
            rec.observed["columns"] += [high[v.column].to_json() for v in hidden]
            still = [v.column for v in views if not v.complete]
            if still:
                raise _Divergence(f"{robot} cannot see every block of {', '.join(still)} from either viewpoint",
                                  by="look")
            rec.checks["occlusion"] += "; repaired: the high viewpoint sees every block"
            if rec.fault.startswith("occlusion"):
                self.fault_log.append(f"occlusion: caught at action {rec.index} by a look (the low view was "
                                      "incomplete: no event of the sensing model selected); repaired from the high "
                                      "viewpoint")
                self.caught_by.append({"fault": "occlusion", "by": "look", "step": rec.index})
        seen = {b: c for v in views for b, c in v.blocks.items()}
        changed = {b: (self.seen_colours[b], c) for b, c in seen.items()
                   if b in self.seen_colours and self.seen_colours[b] != c}
        if changed:  # a block looks other than at the last look: the classical level uses the new colour
            rec.checks["colour change"] = "; ".join(f"{b} was seen {a}, now {c}" for b, (a, c) in changed.items())
            for p in [p for p in self.pending if p.startswith("repaint")]:
                self.pending.remove(p)
                self.fault_log.append(f"{p}: caught at action {rec.index} by a look: {rec.checks['colour change']}")
                self.caught_by.append({"fault": p, "by": "look", "step": rec.index})
        if "swap-colours" in self.pending and set(seen) & self._swapped:
            # the generator's colours were never the robots' beliefs: the first look at a swapped block
            # reports its real colour, and nothing was planned from the other one
            self.pending.remove("swap-colours")
            self.fault_log.append(f"swap-colours: caught at action {rec.index} by a look: "
                                  + ", ".join(f"{b} seen {seen[b]}" for b in sorted(set(seen) & self._swapped)))
            self.caught_by.append({"fault": "swap-colours", "by": "look", "step": rec.index})
        rec.observed.setdefault("seen", {}).update(seen)
        self.seen_colours.update(seen)
        return views

    def observation(self, views: list, robot: str, props: Iterable[str]) -> dict[str, bool]:
        """The mission's observation code: what the robot's look decides about ``props``."""
        return observe_fluents(views, robot, props, self.stands)

    def _check_look(self, ex: Executor, belief: BeliefState, robot: str, rec: StepRecord, where: str,
                    views: list | None = None) -> None:
        """The check after a task is a look: the robot's own cameras against the belief state's actual world
        (and the robot's own beliefs). A contradiction is a named divergence carrying the observation (the
        repair revises the belief state with it); with ``--no-shield`` it is reported and not acted on."""
        views = self._look(ex, robot, rec) if views is None else views
        obs = self.observation(views, robot, self.model.task.props)
        val = belief.valuation()
        bad = [p for p, v in obs.items()
               if (val.get(p) is not None and val[p] != v) or belief.holds(_k(robot, p, not v))]
        if not bad:
            rec.checks["look"] = f"{robot}'s look agrees with the belief state on " + (
                ", ".join(pretty(p) for p in sorted(obs)) or "nothing it can see")
            return
        words = [f"{pretty(p)} seen {str(obs[p]).lower()} by {robot}, "
                 f"{'unknown' if val.get(p) is None else str(val[p]).lower()} in the belief state's actual world"
                 for p in bad]
        msg = f"{where}: " + "; ".join(words)
        if not self.shield:
            rec.checks["unheeded"] = f"NOT acted on (--no-shield): {msg}"
            self.unheeded.append((rec.index, msg))
            return
        raise _Divergence(msg, tuple(bad), looker=robot, seen=obs, by="look")

    # -- the loop --------------------------------------------------------------------------------------
    def run(self) -> MissionResult:
        t_wall, t_cpu = time.perf_counter(), time.process_time()
        faults = list(self.faults)
        belief = self.model.initial_belief()
        true_world, occluders = self.world, []
        self._occlusion_pending: list[str] = []
        ex0 = initial_state(self.world)
        self._stand(ex0)
        for b in ex0.places:  # a block on the shared table at the start: its owner as the task states it
            if b not in self.stands:
                own = [_fluent(p)[1] for p, v in belief.valuation().items() if v and p.startswith("occup_by_")]
                if len(own) == 1:
                    self.stands[b] = own[0]
        plans: list[list[dict]] = []
        planning: list[float] = []
        tasks, dt, pred, summary = self._plan(belief, self._world_json(ex0, set()))
        planning.append(dt)
        plans.append(summary)
        first_put = next((t.name for t in tasks if t.name.startswith("put_on_shared_")), None)
        for f in [f for f in faults if f.kind == "swap-colours"]:
            true_world, msg = _swap_colours(self.world, self._fault_block(first_put))
            self._swapped = set(_swapped_blocks(self.world, true_world))
            self.fault_log.append(msg)
            faults.remove(f)
        for f in [f for f in faults if f.kind == "occlusion"]:
            target = self._fault_block(first_put)
            loc = ex0.places.get(target) if target else None
            if loc is None or loc.kind != "stack":
                self.fault_log.append("occlusion: never fired (the plan puts no block of a stack on the shared "
                                      "table)")
            else:
                i = self.world.robot_index(loc.robot)
                xy = self.world.layout.stack_xy(i, loc.stack, len(self.world.stacks[loc.robot]))
                occluders.append((float(xy[0] + 0.10), float(xy[1]), 0.09))
                self.fault_log.append(f"occlusion: a 9 cm grey block in front of {loc.robot}'s stack {loc.stack} hides "
                                      f"{target} and the blocks below level 2 from the low side camera")
                self._occlusion_pending.append("occlusion")
            faults.remove(f)
        ex = Executor(true_world, grasp=self.grasp, tolerance=self.tolerance, record_fps=self.record_fps,
                      occluders=tuple(occluders))
        self.executor = ex
        state = ex0
        lost: set[str] = set()
        anchors: dict[str, tuple[Location, np.ndarray]] = {}
        steps: list[StepRecord] = []
        replans, k, plan_no, reason = 0, 0, 0, ""
        self.pending: list[str] = [str(f) for f in self.faults if f.kind == "swap-colours"
                                   and not any("nothing swapped" in x or "no blocks" in x for x in self.fault_log)]
        self.unheeded: list[tuple[int, str]] = []   # --no-shield: divergences found but not acted on
        while True:
            divergence: _Divergence | None = None
            e0 = time.process_time()
            try:
                for ti, t in enumerate(tasks):
                    e0 = time.process_time()
                    state, k = self._task(ex, t, pred[ti], belief, state, k, plan_no, lost, anchors, faults, steps,
                                          tasks[ti + 1:])
                    self.exec_cpu += time.process_time() - e0
                    self.audit_log.append(self.audit(ex, belief, lost, f"after {t.name} (plan {plan_no})"))
                e0 = time.process_time()
                if self.shield:  # the end of the plan: both robots look
                    for r in self.world.robots:
                        rec = StepRecord(k, plan_no, "final look", r, f"{r}: look()", True, "final look", {},
                                         float(ex.data.time), float("nan"), precondition="(none: a look)",
                                         precondition_holds=True)
                        steps.append(rec)
                        g0 = time.process_time()
                        try:
                            self._check_look(ex, belief, r, rec, "at the end of the plan")
                        except _Divergence as exc:
                            rec.ok, rec.message = False, str(exc)
                            raise
                        finally:
                            self.guard_cpu += time.process_time() - g0
                self.exec_cpu += time.process_time() - e0
            except _Divergence as exc:
                self.exec_cpu += time.process_time() - e0
                divergence = exc
            if divergence is None:
                gb = belief.holds(self.model.task.goal)
                if gb or not self.shield:
                    reason = (f"goal {self.goal.name} holds in the belief state and both robots' final looks agree "
                              "with its actual world" if self.shield else f"the plan ended (--no-shield: nothing "
                              f"checked against the belief state; goal {self.goal.name} "
                              f"{'holds' if gb else 'does NOT hold'} in it)")
                    break
                divergence = _Divergence(f"the plan ended but goal {self.goal.name} does not hold in the belief "
                                         f"state ({'; '.join(belief.knowledge()) or 'nobody knows anything'})")
            self._caught(str(divergence), getattr(self, "k_now", k), divergence.by)
            if replans >= self.max_replans:
                reason = f"gave up after {replans} replans; last divergence: {divergence}"
                break
            replans += 1
            self._say(f"divergence: {divergence}; repairing and replanning from the belief state ({replans})")
            try:
                state, anchors = self._recover(ex, state, lost, steps, k, plan_no)
                plan_no += 1
                if divergence.seen is not None:  # the look that found it: a named revision, then its sensing
                    b0 = time.process_time()
                    belief.look(divergence.looker, divergence.seen, time=float(ex.data.time),
                                what=f"{divergence.looker}'s look that found the divergence")
                    self.belief_cpu += time.process_time() - b0
                self._look_at_shared(ex, belief, steps, k, plan_no)
                tasks, dt, pred, summary = self._plan(belief, self._world_json(state, lost))
            except (MotionError, PlanError) as exc:
                reason = f"recovery failed: {exc}"
                break
            except (GoalUnreachable, _Divergence, BeliefError) as exc:
                reason = f"goal {self.goal.name} unreachable from the belief state: {exc}"
                break
            planning.append(dt)
            plans.append(summary)
        unfired = []
        for f in faults:
            what = " or ".join(_FIRES_ON.get(f.kind, ("?",)))
            msg = f"{f}: never fired (no {what} at or after primitive action {f.at}; the run had {k})"
            self.fault_log.append(msg)
            unfired.append(str(f))
        for p in self._occlusion_pending:
            self.fault_log.append(f"{p}: never fired (no look at the hidden stack)")
            unfired.append(p)
        for p in self.pending:
            self.fault_log.append(f"{p}: NOT caught")
        final_audit = self.audit(ex, belief, lost, "end of the run")
        gb = belief.holds(self.model.task.goal)
        gw = gb and not final_audit["actual_world_differs"]
        errs = self._errors(ex, state, lost, {})
        worst = max(errs.values(), default=0.0)
        ok_place = worst <= self.tolerance
        success = gb and self.shield and reason.startswith("goal") and ok_place and ex.arm_contacts == 0 \
            and not self.pending
        if not self.shield and not final_audit["agrees"]:
            reason += "; the audit: the world does NOT agree with the belief state"
        if not success and reason.startswith("goal") and "holds" in reason:
            reason += (f"; but a block is {worst * 100:.2f} cm from its symbolic place" if not ok_place
                       else f"; but the arms touched ({ex.arm_contacts} contacts)" if ex.arm_contacts else
                       f"; but a fault was not caught: {self.pending}" if self.pending else "")
        if unfired:
            reason += f"; fault(s) never fired: {', '.join(unfired)}"
        self.belief = belief
        know = {a: [x for x in belief.knowledge([a])] for a in belief.task.agents}
        return MissionResult(
            success=success, goal=self.goal.name, reason=reason, goal_in_world=gw, goal_in_beliefs=gb,
            max_block_error=worst, arm_contacts=ex.arm_contacts, replans=replans, steps=steps, plans=plans,
            planning_seconds=planning, belief_log=[e.to_json() for e in belief.log], beliefs=know,
            lost=sorted(lost), faults=self.fault_log, sim_seconds=float(ex.data.time),
            wall_seconds=time.perf_counter() - t_wall, cpu_seconds=time.process_time() - t_cpu, grasp=self.grasp,
            backend=belief.backend, shield=self.shield, unfired=unfired, guard_cpu_seconds=self.guard_cpu,
            belief_cpu_seconds=self.belief_cpu, exec_cpu_seconds=self.exec_cpu,
            planning_cpu_seconds=list(self.planning_cpu), unheeded=list(self.unheeded),
            audit={"final": final_audit, "per_task": self.audit_log}, caught_by=list(self.caught_by))

    def _look_at_shared(self, ex: Executor, belief: BeliefState, steps: list[StepRecord], k: int,
                        plan_no: int) -> None:
        """Part of every repair: both robots' side cameras look at the shared table, which both see (a public
        observation of the ``occup_by`` fluents when the two looks agree; each robot's own look otherwise)."""
        occ = [p for p in self.model.task.props if p.startswith("occup_by_")]
        seen = {}
        for r in self.world.robots:
            rec = StepRecord(k, plan_no, "recovery", r, f"{r}: look(shared table)", True,
                             "recovery: look at the shared table", {}, float(ex.data.time), float("nan"),
                             precondition="(none: a look)", precondition_holds=True)
            steps.append(rec)
            views = [v for v in self._look(ex, r, rec) if v.column == "shared table"]
            seen[r] = self.observation(views, r, occ)
        b0 = time.process_time()
        first, *others = self.world.robots
        if all(seen[r] == seen[first] for r in others):
            belief.look(first, seen[first], time=float(ex.data.time), public=True,
                        what="both robots look at the shared table: " + (", ".join(
                            pretty(p) for p, v in sorted(seen[first].items()) if v) or "it is empty"))
        else:
            for r in self.world.robots:
                belief.look(r, seen[r], time=float(ex.data.time), what=f"{r} looks at the shared table")
        self.belief_cpu += time.process_time() - b0

    def _fault_block(self, task_name: str | None) -> str | None:
        """The fault injector's target (it may read the generator's layout; the robots never do): a block of
        the robot of ``put_on_shared_R_C`` painted C, else None."""
        if not task_name:
            return None
        robot, colour = task_name[len("put_on_shared_"):].split("_", 1)
        return next((b for b in self.world.blocks if self.stands.get(b) == robot
                     and _colour_names(self.world)[b] == colour), None)

    def _caught(self, msg: str, k: int, by: str = "") -> None:
        for p in list(self.pending):
            self.fault_log.append(f"{p}: caught at primitive action {k}{f' by {by}' if by else ''}: {msg}")
            self.caught_by.append({"fault": p, "by": by or "goal check", "step": k})
            self.pending.remove(p)

    # -- one task --------------------------------------------------------------------------------------
    def _fault_for(self, act: Action, k: int, faults: list[Fault]) -> Fault | None:
        for f in faults:
            if f.kind in _FIRES_ON and k >= f.at and act.name in _FIRES_ON[f.kind]:
                faults.remove(f)
                return f
        return None

    def _task(self, ex: Executor, t: Any, predicted: BeliefState, belief: BeliefState, state: SymbolicState,
              k: int, plan_no: int, lost: set[str], anchors: dict, faults: list[Fault], steps: list[StepRecord],
              rest: list) -> tuple[SymbolicState, int]:
        act = self.model.task.action(t.name)
        pre_text = pretty(act.executable)
        repaint = drop_msg = None
        g0 = time.process_time()
        holds = self._shield(belief, act)
        self.guard_cpu += time.process_time() - g0
        if not holds:
            failed = [pretty(c) for c in _conjuncts(act.executable) if not belief.holds(c)]
            msg = f"precondition of {t.name} false in the belief state for {t.robot}: {', '.join(failed)}"
            if self.shield:
                rec = StepRecord(k, plan_no, t.name, t.robot, f"{t.robot}: {t.name}", False,
                                 f"shield: not executed; {msg}", {}, float(ex.data.time), float("nan"),
                                 precondition=pre_text, precondition_holds=False, executed=False)
                steps.append(rec)
                raise _Divergence(f"action {k} ({t.name}): shield: {msg}", by="shield")
        else:
            msg = ""
        try:
            parsed = self._breakdown(t, state, lost)
        except (DelkitError, ArmsError) as exc:
            rec = StepRecord(k, plan_no, t.name, t.robot, f"{t.robot}: {t.name}", False, "", {},
                             float(ex.data.time), float("nan"), precondition=pre_text, precondition_holds=holds,
                             executed=False)
            rec.message = f"no primitive actions for {t.name} from the poses and the colours seen: {exc}"
            steps.append(rec)
            raise _Divergence(f"action {k} ({t.name}): {rec.message}", by="classical precondition") from None
        t.parsed = parsed
        views = None
        for pos, prim in enumerate(parsed):
            rec = StepRecord(k, plan_no, t.name, prim.robot, str(prim), True, "ok", {}, float(ex.data.time),
                             float("nan"), precondition=pre_text, precondition_holds=holds)
            steps.append(rec)
            self._say(f"{k}: {prim} [{t.name}]")
            self.k_now = k
            k += 1
            if not holds:
                rec.message = f"executed WITHOUT shield although the {msg}"

            def diverge(msg: str, fluents: tuple[str, ...] = (), rec: StepRecord = rec, prim: Action = prim,
                        by: str = "pose") -> None:
                rec.ok, rec.message, rec.sim_time = False, msg, float(ex.data.time)
                raise _Divergence(f"action {rec.index} ({prim}) [{t.name}]: {msg}", fluents, by=by)

            try:
                nxt = _apply(self.world, state, prim)
            except PlanError as exc:
                diverge(f"not applicable in the state the robots are in: {exc}", by="shield")
            fault = self._fault_for(prim, rec.index, faults)
            run_act = prim
            if fault is not None and fault.kind == "misplace":
                own = len(self.world.stacks[prim.robot])
                stack = (int(prim.args.get("stack", -1)) + 1) % own if prim.name == "place" else min(
                    range(own), key=lambda s: state.height("stack", prim.robot, s))
                run_act = Action(prim.robot, "place", MappingProxyType({"block": prim.args["block"], "stack": stack}))
                rec.fault = f"misplace: onto {prim.robot}'s stack {stack}"
            elif fault is not None and fault.kind == "drop-msg":
                drop_msg = rec.fault = f"drop-msg: the announcement of {t.name} is lost"
            elif fault is not None and fault.kind == "repaint":
                repaint = fault
            try:
                if prim.name == "sense":
                    views = self._look(ex, prim.robot, rec)
                    seen_views = views
                    obs = self.observation(seen_views, prim.robot, [f.name for f, _c in act.sensed])
                elif prim.name == "announce":
                    rec.observed["announced"] = {str(prim.args.get("block")): t.name}
                else:
                    ex.execute(run_act, state)
                if fault is not None and fault.kind == "drop":
                    src = self.world.position(state.places[prim.args["block"]])
                    ex.drop(prim.robot, src[2] + 0.015)
                    rec.fault = "drop: the hand opened just after lift-off"
            except MotionError as exc:
                diverge(f"motion failed: {exc}")
            if fault is not None and fault.kind != "repaint":
                self.fault_log.append(f"{fault} fired at action {rec.index} ({prim}): {rec.fault}")
                self.pending.append(str(fault))
            rec.sim_time = float(ex.data.time)
            errs = self._errors(ex, nxt, lost, anchors)
            worst = max(errs, key=errs.get) if errs else None
            rec.max_block_error = errs[worst] if worst else 0.0
            if worst is not None and errs[worst] > self.tolerance:
                loc = nxt.places[worst]
                what = "is no longer in the hand" if loc.kind == "held" else f"is not at {loc.describe()}"
                diverge(f"block {worst!r} {what} ({errs[worst] * 100:.2f} cm off; tolerance "
                        f"{self.tolerance * 100:.1f} cm)")
            state = nxt
            self._stand(state)
            if pos + 1 < len(parsed):
                rec.message = rec.message if not holds else f"ok ({prim})"
                continue
            # -- the task is done: its event model on the belief state, then the checks --
            b0 = time.process_time()
            n_log = len(belief.log)
            try:
                ev = self._apply_task(belief, t.name, t.robot, time=rec.sim_time,
                                      observed=obs if act.kind == "sensing" else None,
                                      heard=drop_msg is None, force=not self.shield)
                rec.observed["event"] = ev.chosen
                rec.observed["learnt"] = list(ev.learnt)
            except BeliefError as exc:
                self.belief_cpu += time.process_time() - b0
                diverge(f"the belief state cannot follow: {exc}", by="look")
            self.belief_cpu += time.process_time() - b0
            revised = [e for e in belief.log[n_log:] if e.kind == "revision"]
            if repaint is not None:
                self._repaint(ex, prim.robot, rest, rec, repaint)
            g0 = time.process_time()
            try:
                if revised and self.shield:
                    raise _Divergence(f"after {t.name}: {revised[-1].chosen} ({'; '.join(revised[-1].revised)})",
                                      by="look")
                # the check is a look by the robot that acted (a sensing task's own look: repaints after it
                # are for the next look to find)
                self._check_look(ex, belief, t.robot, rec, f"after {t.name}",
                                 views=views if act.kind == "sensing" else None)
                if not self.shield and belief.key() != predicted.key():
                    msg2 = (f"after {t.name} the belief state is not bisimilar to the plan's prediction: "
                            + "; ".join(belief.differences(predicted)))
                    rec.checks["unheeded"] = (rec.checks.get("unheeded", "")
                                              + f" NOT acted on (--no-shield): {msg2}").strip()
                    self.unheeded.append((rec.index, msg2))
                if self.shield:
                    if belief.key() != predicted.key():
                        diffs = belief.differences(predicted)
                        raise _Divergence(f"after {t.name} the belief state is not bisimilar to the plan's "
                                          f"prediction: {'; '.join(diffs) or 'same formulas, other structure'}",
                                          by="ack" if drop_msg else "look")
                    rec.checks["bisimilar"] = "the belief state is bisimilar to the plan's prediction"
            except _Divergence as exc:
                self.guard_cpu += time.process_time() - g0
                rec.ok, rec.message, rec.sim_time = False, str(exc), float(ex.data.time)
                raise _Divergence(f"action {rec.index} ({prim}) [{t.name}]: {exc}", exc.fluents, looker=exc.looker,
                                  seen=exc.seen, by=exc.by) from None
            self.guard_cpu += time.process_time() - g0
            if holds:
                rec.message = f"ok ({prim})"
        if not parsed:  # a task without primitive actions: only its event model
            self._apply_task(belief, t.name, t.robot, force=not self.shield)
        return state, k

    @staticmethod
    def _shield(belief: BeliefState, act: Any) -> bool:
        """The shield: the task's precondition (epistemic parts included) in the belief state."""
        return belief.holds(act.executable)

    def _repaint(self, ex: Executor, robot: str, rest: list, rec: StepRecord, fault: Fault) -> None:
        """The repaint fault: a block standing in front of ``robot`` gets another colour (a block of the colour
        the robot puts on the shared table next, if any; else its first block)."""
        mine = [b for b in self.world.blocks if self.stands.get(b) == robot]
        nxt = next((t.name for t in rest if t.name.startswith(f"put_on_shared_{robot}_")
                    or t.name.startswith(f"pspb_and_announce_{robot}_")), None)
        colour = nxt.rsplit("_", 1)[1] if nxt else None
        target = next((b for b in mine if self.seen_colours.get(b) == colour), mine[0] if mine else None)
        if target is None:
            return
        old = self._true_colour(ex, target)
        pal = list(self.model.colours) + [c for c in ("red", "black", "green", "blue", "yellow", "white")
                                          if c not in self.model.colours]
        new = next(c for c in pal if c != old)
        ex.model.geom_rgba[ex.model.geom(f"block/{target}").id] = rgba_of(new)
        rec.fault = f"repaint: {target} repainted from {old} to {new} after {robot} sensed it"
        self.fault_log.append(f"{fault} fired at action {rec.index} ({rec.text}): {rec.fault}")
        self.pending.append(str(fault))

    # -- physical state ----------------------------------------------------------------------------------
    def _observe_state(self, ex: Executor, lost: set[str]) -> tuple[SymbolicState, dict[str, np.ndarray]]:
        """Classical state from the measured block poses: column by nearest slot, level by height order.
        Blocks off every slot or below the table tops are added to ``lost``. Returns the state and the
        measured positions of blocks that rest more than ``tolerance`` from their slot (anchors)."""
        w, lay = self.world, self.world.layout
        slots: list[tuple[Location, np.ndarray]] = []
        for i, r in enumerate(w.robots):
            n = len(w.stacks[r])
            slots += [(Location("stack", r, s, 0), lay.stack_xy(i, s, n)) for s in range(n)]
        slots.append((Location("barrier"), lay.barrier_xy()))
        members: dict[Location, list[tuple[float, str]]] = {}
        places: dict[str, Location] = {}
        for b in w.blocks:
            p = ex.block_position(b)
            holder = next((r for r, hb in ex.held.items() if hb == b), None)
            if holder is not None and np.linalg.norm(p - ex.tcp_actual(holder)[:3, 3]) < 0.03:
                places[b] = Location("held", holder)
                continue
            if b in lost or p[2] < lay.table_z:
                lost.add(b)
                continue
            loc, xy = min(slots, key=lambda s: float(np.linalg.norm(s[1] - p[:2])))
            if np.linalg.norm(xy - p[:2]) > 0.5 * lay.block_size:
                lost.add(b)
                continue
            members.setdefault(loc, []).append((float(p[2]), b))
        anchors: dict[str, np.ndarray] = {}
        for loc, lst in members.items():
            for lvl, (_z, b) in enumerate(sorted(lst)):
                places[b] = replace(loc, level=lvl)
                if np.linalg.norm(ex.block_position(b) - w.position(places[b])) > self.tolerance:
                    anchors[b] = ex.block_position(b)
        for b in lost:
            places[b] = Location("barrier", "lost", -9, 0)  # kept out of every check and every plan
        return SymbolicState(MappingProxyType(places)), anchors

    def _errors(self, ex: Executor, state: SymbolicState, lost: set[str], anchors: dict[str, tuple]) -> dict:
        out = {}
        for b, loc in state.places.items():
            if b in lost:
                continue
            actual = ex.block_position(b)
            if loc.kind == "held":
                gap = float(np.linalg.norm(actual - ex.tcp_actual(loc.robot)[:3, 3]))
                out[b] = max(0.0, gap - 0.5 * self.tolerance)
            elif b in anchors and anchors[b][0] == loc:
                out[b] = float(np.linalg.norm(actual - anchors[b][1]))
            else:
                out[b] = float(np.linalg.norm(actual - self.world.position(loc)))
        return out

    def _recover(self, ex: Executor, state: SymbolicState, lost: set[str], steps: list[StepRecord], k: int,
                 plan_no: int) -> tuple[SymbolicState, dict]:
        """Put down held blocks, re-seat blocks resting off their slot, read the block positions (the
        classical state; beliefs are not touched here)."""
        state, _ = self._observe_state(ex, lost)
        for r in self.world.robots:
            b = state.held_by(r)
            if b is not None:  # put it on the robot's lowest stack
                own = len(self.world.stacks[r])
                s = min(range(own), key=lambda i: state.height("stack", r, i))
                act = Action(r, "place", MappingProxyType({"block": b, "stack": s}))
                _apply(self.world, state, act)  # its precondition on the measured state (PlanError if false)
                ex.execute(act, state)
                steps.append(StepRecord(k, plan_no, "recovery", r, str(act), True, "recovery: put down the held "
                                        "block", {}, float(ex.data.time), float("nan"),
                                        precondition=f"{r} holds {b} (measured); stack {s} is {r}'s lowest",
                                        precondition_holds=True))
                state, _ = self._observe_state(ex, lost)
        state, anch = self._observe_state(ex, lost)
        for b in sorted(anch):  # re-seat a block resting off its slot, if it is on top of its stack
            loc = state.places[b]
            if loc.kind != "stack" or state.on_top("stack", loc.robot, loc.stack)[-1][1] != b:
                continue
            off = float(np.linalg.norm(anch[b] - self.world.position(loc)))
            for name, args in (("pick", {"block": b}), ("place", {"block": b, "stack": loc.stack})):
                act = Action(loc.robot, name, MappingProxyType(args))
                nxt = _apply(self.world, state, act)  # its precondition on the measured state first
                ex.execute(act, state)
                state = nxt
            steps.append(StepRecord(k, plan_no, "recovery", loc.robot, f"{loc.robot}: re-seat({b})", True,
                                    f"recovery: {b} rested {off * 100:.1f} cm off its slot; picked and put back",
                                    {}, float(ex.data.time), float("nan"),
                                    precondition=f"{b} is the top of {loc.robot}'s stack {loc.stack} (measured)",
                                    precondition_holds=True))
        if anch:
            state, anch = self._observe_state(ex, lost)
        return state, {b: (state.places[b], p) for b, p in anch.items()}


def world_from_layout(stacks: Mapping[str, list[list[str]]], colours: Mapping[str, str]) -> World:
    """A world from stacks (robot ↦ stacks bottom → top) and block colours (names)."""
    for b, c in colours.items():
        rgba_of(c, where=f"colour of {b}")
    return World.from_json({"stacks": {r: [list(s) for s in st] for r, st in stacks.items()},
                            "colors": dict(colours)})


COLOUR_ORDER = ("red", "green", "blue", "yellow", "orange", "purple")


def random_world(n_colours: int, seed: int, *, blocks_per_robot: tuple[int, int] = (3, 5)) -> World:
    """A seeded random e-PICO layout: each robot has 3 stacks and 3–5 blocks (at most 3 per stack),
    coloured from the first ``n_colours`` of red, green, blue, yellow (every colour used at least once
    on each table when there are enough blocks). Block names are ``r<robot>b<k>``."""
    rng = np.random.default_rng(seed)
    stacks: dict[str, list[list[str]]] = {}
    colours: dict[str, str] = {}
    pal = COLOUR_ORDER[:n_colours]
    for i, r in enumerate(("robot1", "robot2")):
        n = int(rng.integers(blocks_per_robot[0], blocks_per_robot[1] + 1))
        cols = list(pal) + [pal[int(rng.integers(len(pal)))] for _ in range(max(0, n - len(pal)))]
        cols = [cols[j] for j in rng.permutation(len(cols))][:n]
        st: list[list[str]] = [[], [], []]
        for kb in range(n):
            s = int(rng.choice([j for j in range(3) if len(st[j]) < 3]))
            name = f"r{i + 1}b{kb}"
            st[s].append(name)
            colours[name] = cols[kb]
        stacks[r] = st
    return world_from_layout(stacks, colours)


def duplicate_layout(n_colours: int, seed: int) -> Any:
    """A seeded e-PICO layout (:class:`planners.epico.Layout`) in which each robot has several blocks of one
    colour: per robot 3–5 blocks on 3 stacks (at most 3 per stack), a random non-empty set of the first
    ``n_colours`` e-PICO colours, one of them on two or three blocks. Block names say nothing about colours
    (``a0``, ``a1``, … for robot1, ``b0``, … for robot2)."""
    from planners.epico import PALETTE, ROBOTS, Layout

    rng = np.random.default_rng(seed)
    pal = list(PALETTE[:n_colours])
    stacks: dict[str, tuple[tuple[str, ...], ...]] = {}
    colours: dict[str, str] = {}
    for i, r in enumerate(ROBOTS):
        chosen = [c for c in pal if rng.random() < 0.6] or [pal[int(rng.integers(len(pal)))]]
        twice = chosen[int(rng.integers(len(chosen)))]
        cols = chosen + [twice] * int(rng.integers(1, 3))
        while len(cols) < 3:
            cols.append(chosen[int(rng.integers(len(chosen)))])
        cols = cols[:5]
        cols = [cols[j] for j in rng.permutation(len(cols))]
        st: list[list[str]] = [[], [], []]
        for kb, c in enumerate(cols):
            s = int(rng.choice([j for j in range(3) if len(st[j]) < 3]))
            name = f"{'ab'[i]}{kb}"
            st[s].append(name)
            colours[name] = c
        stacks[r] = tuple(tuple(x) for x in st)
    return Layout(MappingProxyType(stacks), MappingProxyType(colours))
