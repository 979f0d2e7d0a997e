"""The closed loop: plan → execute in physics → observe → monitor → (on divergence) re-sense, rebuild, replan.

A *mission* is a world (the robots' tables), an e-PICO goal (α … δ, seed 004 Sec. 5) and a planner given
as a callable ``replan(world_json, known) -> plan/1 dict``: ``world_json`` is the ``world`` object of the
plan format (``arms/README.md``) describing what the robots have *observed* (stacks bottom → top, block
colours as far as observed, the prior colour otherwise), ``known`` maps each robot to the colours it
believes ({robot: {block: colour}}). The planner may raise :class:`GoalUnreachable`. The arms layer
does not import any planner: ``delkit epico run`` passes the e-PICO pipeline in, the tests pass
:func:`simple_replanner` (a small hand-written planner for these goals, see there).

After every primitive action the monitor compares

* the simulated world with the symbolic state the plan expects (every block within ``tolerance``; a held
  block in the hand — a block that slipped or dropped fails here),
* what a ``sense`` saw (top block and level of each column, and its colour) with what the plan expects,
* every robot's beliefs (the DEL state of :mod:`arms.beliefs`, updated only by sensing and announcements)
  with the colours the plan assumes.

On a divergence it puts down a held block, re-senses every column of both tables and the shared table,
rebuilds the classical state from the measured block poses (a block that fell off the tables is *lost*)
and the colours from what was seen, asks the planner again and continues. It stops when the goal holds,
after ``max_replans`` replans, or when the planner says the goal is unreachable; it reports success
only if the goal holds both in the world (beliefs true of the simulated blocks, shared table free when
asked) and in the robots' beliefs, every block is within ``tolerance`` of its symbolic place and the
arms never touched.

Faults (``Fault``), injected deterministically: ``drop@K`` — at the first pick at or after primitive
action K (counted over the whole run), the hand lowers the block back to 1.5 cm above where it was and
opens; ``misplace@K`` — the first place / put_on_barrier at or after K puts the block on the robot's
next stack instead; ``swap-colours`` — two blocks of different colours have their colours exchanged in
the simulated world before the run (the planner still assumes the generator's colours).
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field, replace
from types import MappingProxyType

import numpy as np

from arms.beliefs import Beliefs
from arms.executor import Executor, MotionError
from arms.plan import Action, parse_plan
from arms.plan import apply_action as _apply
from arms.sensing import Sighting, nearest_colour
from arms.world import ArmsError, Location, PlanError, SymbolicState, World, initial_state, rgba_of

__all__ = ["Goal", "GOALS", "Fault", "parse_fault", "GoalUnreachable", "Mission", "MissionResult",
           "simple_replanner", "goal_of", "random_world", "world_from_layout"]

Replan = Callable[[dict, dict], dict]


class GoalUnreachable(ArmsError):
    """The planner found no plan for the goal from the observed state."""


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


@dataclass(frozen=True)
class Fault:
    """``drop`` / ``misplace`` at primitive action ``at`` (or the first suitable one after), or ``swap-colours``."""

    kind: str
    at: int = 0

    def __str__(self) -> str:
        return self.kind if self.kind == "swap-colours" else f"{self.kind}@{self.at}"


def parse_fault(text: str) -> Fault:
    """``drop@K``, ``misplace@K`` or ``swap-colours``."""
    t = text.strip().lower()
    if t in ("swap-colours", "swap-colors"):
        return Fault("swap-colours")
    kind, _, at = t.partition("@")
    if kind in ("drop", "misplace") and at.isdigit():
        return Fault(kind, int(at))
    raise ArmsError(f"unknown fault {text!r}; use drop@K, misplace@K (K = index of a primitive action) "
                    "or swap-colours")


@dataclass
class StepRecord:
    """One executed primitive action and what the monitor found."""

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

    def to_json(self) -> dict:
        return {"index": self.index, "plan": self.plan, "task": self.task, "robot": self.robot, "text": self.text,
                "ok": self.ok, "message": self.message, "observed": self.observed,
                "t_sim_s": round(self.sim_time, 3),
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

    @property
    def realtime_factor(self) -> float:
        return self.sim_seconds / self.wall_seconds if self.wall_seconds > 0 else float("inf")

    def tasks(self) -> list[dict]:
        """Per plan and task (the ``task`` field of the plan's actions, else one action each): the planned
        actions, what the arms did, what was observed, and whether the monitor found the world and the
        beliefs as the plan expects after it (``ok``)."""
        out: list[dict] = []
        for no, plan in enumerate(self.plans):
            order: list[str] = []
            planned: dict[str, list[str]] = {}
            for a in plan:
                if a["task"] not in planned:
                    order.append(a["task"])
                planned.setdefault(a["task"], []).append(a["text"])
            for key in [*order, "recovery", "re-sense"]:
                done = [s for s in self.steps if s.plan == no and s.task == key]
                if not done and key not in planned:
                    continue
                observed: dict = {}
                for s in done:
                    for k, v in s.observed.items():
                        if k != "columns":
                            observed.setdefault(k, {}).update(v) if isinstance(v, dict) else observed.update({k: v})
                ok = bool(done) and all(s.ok for s in done)
                out.append({"plan": no, "task": key, "planned": planned.get(key, []),
                            "done": [s.text + (f" [fault: {s.fault}]" if s.fault else "") for s in done],
                            "observed": observed, "ok": ok,
                            "status": "match" if ok else "diverged" if done else "not executed (replanned)",
                            "message": next((s.message for s in done if not s.ok), "")})
        return out

    def to_json(self) -> dict:
        return {"success": self.success, "goal": self.goal, "reason": self.reason,
                "goal_in_world": self.goal_in_world, "goal_in_beliefs": self.goal_in_beliefs,
                "max_block_error_m": self.max_block_error, "arm_contacts": self.arm_contacts,
                "replans": self.replans, "plans": self.plans,
                "planning": [{"seconds": t} for t in self.planning_seconds],  # wall time of each (re)plan
                "tasks": self.tasks(), "steps": [s.to_json() for s in self.steps],
                "belief_log": self.belief_log, "beliefs": self.beliefs, "lost_blocks": self.lost,
                "faults": self.faults, "sim_seconds": self.sim_seconds, "wall_s": self.wall_seconds,
                "cpu_s": self.cpu_seconds,  # real-time factor: sim_seconds / wall_s or / cpu_s
                "grasp": self.grasp, "files": self.files}


def _plan_summary(actions: list[Action]) -> list[dict]:
    return [{"task": str(a.args.get("task", f"{i}")), "text": str(a)} for i, a in enumerate(actions)]


class _Divergence(Exception):
    """Raised inside the loop: the world or the beliefs are not what the plan expects."""


def _colour_names(world: World) -> dict[str, str]:
    return {b: nearest_colour(np.array(world.colors[b])) for b in world.blocks}


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


class Mission:
    """One closed-loop mission (see module docstring)."""

    def __init__(self, world: World, goal: Goal | str, replan: Replan, *, plan: dict | None = None,
                 faults: tuple[Fault, ...] = (), grasp: str = "friction", tolerance: float = 0.01,
                 max_replans: int = 4, record_fps: float = 0.0,
                 progress: Callable[[str], None] | None = None) -> None:
        self.world = world                      # what the planner is told (the generator's colours)
        self.goal = goal_of(goal) if isinstance(goal, str) else goal
        self.replan = replan
        self.first_plan = plan
        self.faults = tuple(faults)
        self.grasp = grasp
        self.tolerance = tolerance
        self.max_replans = max_replans
        self.record_fps = record_fps
        self.progress = progress
        self.origin = {b: r for r in world.robots for st in world.stacks[r] for b in st}
        self.fault_log: list[str] = []

    # -- helpers ---------------------------------------------------------------------------------------
    def _say(self, msg: str) -> None:
        if self.progress is not None:
            self.progress(msg)

    def _plan(self, world_json: dict, known: dict) -> tuple[list[Action], float]:
        t0 = time.perf_counter()
        obj = self.replan(world_json, known)
        dt = time.perf_counter() - t0
        p = parse_plan(obj, source="replanned plan")
        got = {r: [list(s) for s in p.world.stacks[r]] for r in p.world.robots}
        if got != world_json["stacks"] or list(p.world.barrier) != world_json["barrier"]:
            raise ArmsError("the planner returned a plan for another world than the observed one")
        return list(p.actions), dt

    def _world_json(self, state: SymbolicState, colours: Mapping[str, str], lost: set[str]) -> dict:
        w = self.world
        stacks = {r: [[b for _, b in state.on_top("stack", r, s) if b not in lost]
                      for s in range(len(w.stacks[r]))] for r in w.robots}
        barrier = [b for _, b in state.on_top("barrier") if b not in lost]
        blocks = [b for r in w.robots for st in stacks[r] for b in st] + barrier
        lay = w.layout
        return {"robots": list(w.robots), "stacks": stacks, "barrier": barrier,
                "colors": {b: colours[b] for b in blocks},
                "layout": {"base_y": lay.base_y, "stack_x": lay.stack_x, "stack_pitch": lay.stack_pitch,
                           "table_z": lay.table_z, "block_size": lay.block_size}}

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

    def _goal_status(self, ex: Executor, beliefs: Beliefs, truth: Mapping[str, str], lost: set[str],
                     ) -> tuple[bool, bool, str]:
        g, w = self.goal, self.world
        in_beliefs = in_world = False
        detail = []
        for r in w.robots:
            other = [x for x in w.robots if x != r][0]
            mine = {b: beliefs.believed(r, b) for b in w.blocks if self.origin.get(b) == other}
            bel = {c for c in mine.values() if c is not None}
            true = {c for b, c in mine.items() if c is not None and truth[b] == c}
            in_beliefs |= len(bel) >= g.distinct
            in_world |= len(true) >= g.distinct
            detail.append(f"{r} believes {len(bel)} colour(s) of {other}'s blocks ({len(true)} true)")
        if g.free_barrier:
            lay = w.layout
            bx = lay.barrier_xy()
            on_shared = [b for b in w.blocks if b not in lost
                         and np.linalg.norm(ex.block_position(b)[:2] - bx) < 0.09
                         and ex.block_position(b)[2] > lay.table_z - 0.01]
            if on_shared:
                in_world = False
                detail.append(f"shared table holds {', '.join(on_shared)}")
        return in_world, in_beliefs, "; ".join(detail)

    # -- the loop --------------------------------------------------------------------------------------
    def run(self) -> MissionResult:
        t_wall, t_cpu = time.perf_counter(), time.process_time()
        prior = _colour_names(self.world)
        faults = list(self.faults)
        plans: list[list[dict]] = []
        planning: list[float] = []
        if self.first_plan is not None:
            p0 = parse_plan(self.first_plan, source="plan")
            if p0.world != self.world:
                raise ArmsError("the plan's world is not the mission's world")
            actions = list(p0.actions)
        else:
            actions, dt = self._plan(self.world.to_json() | {"colors": dict(prior)}, {})
            planning.append(dt)
        plans.append(_plan_summary(actions))
        true_world = self.world
        for f in [f for f in faults if f.kind == "swap-colours"]:
            first = next((a.args.get("block") for a in actions if a.name in ("pick", "announce")
                          and a.args.get("block")), None)
            true_world, msg = _swap_colours(self.world, first)
            self.fault_log.append(msg)
            faults.remove(f)
        truth = _colour_names(true_world)
        ex = Executor(true_world, grasp=self.grasp, tolerance=self.tolerance, record_fps=self.record_fps)
        beliefs = Beliefs(self.world.robots, self.world.blocks, tuple(sorted(set(prior.values()))))
        state = initial_state(self.world)
        lost: set[str] = set()
        anchors: dict[str, tuple[Location, np.ndarray]] = {}
        steps: list[StepRecord] = []
        replans, k, plan_no, reason = 0, 0, 0, ""
        while True:
            divergence = ""
            for pos, act in enumerate(actions):
                try:
                    state = self._step(ex, act, pos, state, k, plan_no, prior, beliefs, lost, anchors, faults, steps)
                except _Divergence as exc:
                    divergence = str(exc)
                k += 1
                if divergence:
                    break
            if not divergence:
                gw, gb, detail = self._goal_status(ex, beliefs, truth, lost)
                if gw and gb:
                    reason = f"goal {self.goal.name} holds in the world and in the beliefs ({detail})"
                    break
                divergence = f"the plan ended but goal {self.goal.name} does not hold ({detail})"
            if replans >= self.max_replans:
                reason = f"gave up after {replans} replans; last divergence: {divergence}"
                break
            replans += 1
            self._say(f"divergence: {divergence}; re-sensing and replanning ({replans})")
            try:
                state, anchors = self._recover(ex, state, beliefs, prior, lost, steps, k, plan_no)
            except (MotionError, PlanError) as exc:
                reason = f"recovery failed: {exc}"
                break
            plan_no += 1
            try:
                actions, dt = self._plan(self._world_json(state, prior, lost), beliefs.known())
            except GoalUnreachable as exc:
                reason = f"goal {self.goal.name} unreachable from the observed state: {exc}"
                break
            planning.append(dt)
            plans.append(_plan_summary(actions))
        for f in faults:
            self.fault_log.append(f"{f}: not fired (no {'pick' if f.kind == 'drop' else 'place'} at or after "
                                  f"action {f.at})")
        gw, gb, detail = self._goal_status(ex, beliefs, truth, lost)
        errs = self._errors(ex, state, lost, {})
        worst = max(errs.values(), default=0.0)
        ok_place = worst <= self.tolerance
        success = gw and gb and ok_place and ex.arm_contacts == 0
        if success is False and reason.startswith("goal") and "holds" in reason:
            reason += (f"; but a block is {worst * 100:.2f} cm from its symbolic place" if not ok_place
                       else f"; but the arms touched ({ex.arm_contacts} contacts)")
        self.executor = ex
        return MissionResult(
            success=success, goal=self.goal.name, reason=reason, goal_in_world=gw, goal_in_beliefs=gb,
            max_block_error=worst, arm_contacts=ex.arm_contacts, replans=replans, steps=steps, plans=plans,
            planning_seconds=planning, belief_log=[e.to_json() for e in beliefs.log], beliefs=beliefs.known(),
            lost=sorted(lost), faults=self.fault_log, sim_seconds=float(ex.data.time),
            wall_seconds=time.perf_counter() - t_wall, cpu_seconds=time.process_time() - t_cpu, grasp=self.grasp)

    # -- one primitive action --------------------------------------------------------------------------
    def _fault_for(self, act: Action, k: int, faults: list[Fault]) -> Fault | None:
        for f in faults:
            if k >= f.at and ((f.kind == "drop" and act.name in ("pick", "take_from_barrier"))
                              or (f.kind == "misplace" and act.name in ("place", "put_on_barrier"))):
                faults.remove(f)
                return f
        return None

    def _step(self, ex: Executor, act: Action, pos: int, state: SymbolicState, k: int, plan_no: int,
              prior: dict[str, str], beliefs: Beliefs, lost: set[str], anchors: dict, faults: list[Fault],
              steps: list[StepRecord]) -> SymbolicState:
        task = str(act.args.get("task", pos))
        rec = StepRecord(k, plan_no, task, act.robot, str(act), True, "ok", {}, 0.0, float("nan"))
        steps.append(rec)
        self._say(f"{k}: {act}")

        def diverge(msg: str) -> None:
            rec.ok, rec.message, rec.sim_time = False, msg, float(ex.data.time)
            raise _Divergence(f"action {k} ({act}): {msg}")

        try:
            nxt = _apply(self.world, state, act)
        except PlanError as exc:
            diverge(f"not applicable in the state the robots are in: {exc}")
        fault = self._fault_for(act, k, faults)
        run_act = act
        if fault is not None and fault.kind == "misplace":
            own = len(self.world.stacks[act.robot])
            stack = (int(act.args.get("stack", -1)) + 1) % own if act.name == "place" else min(
                range(own), key=lambda s: state.height("stack", act.robot, s))
            run_act = Action(act.robot, "place", MappingProxyType({"block": act.args["block"], "stack": stack}))
            rec.fault = f"misplace: onto {act.robot}'s stack {stack}"
        try:
            ex.execute(run_act, state)
            if fault is not None and fault.kind == "drop":
                src = self.world.position(state.places[act.args["block"]])
                ex.drop(act.robot, src[2] + 0.015)
                rec.fault = "drop: the hand opened just after lift-off"
        except MotionError as exc:
            diverge(f"motion failed: {exc}")
        if fault is not None:
            self.fault_log.append(f"{fault} at action {k} ({act}): {rec.fault}")
        t = float(ex.data.time)
        rec.sim_time = t
        if act.name == "sense":
            rec.observed = {"seen": {s.block: s.colour for s in ex.sightings if s.block},
                            "columns": [s.to_json() for s in ex.sightings]}
            for s in ex.sightings:
                if s.block is not None:
                    beliefs.sense(act.robot, s.block, s.colour, t)
        elif act.name == "announce":
            b = act.args.get("block")
            to = act.args.get("to", [r for r in self.world.robots if r != act.robot])
            to = tuple([to] if isinstance(to, str) else to)
            said = beliefs.believed(act.robot, b) if b else None
            if said is None and b in state.places and state.places[b].kind == "barrier":
                # e-PICO: a robot that has put a block on the shared table can tell its colour: it looks at
                # it first (line of sight; the block must be the top one there)
                ex.execute(Action(act.robot, "sense", MappingProxyType({"block": b})), state)
                for s in ex.sightings:
                    if s.block is not None:
                        beliefs.sense(act.robot, s.block, s.colour, float(ex.data.time))
                rec.observed["seen"] = {s.block: s.colour for s in ex.sightings if s.block}
                self._check_sightings(ex.sightings, nxt, prior, diverge)
                said = beliefs.believed(act.robot, b)
            if said is None:
                diverge(f"{act.robot} is to announce the colour of {b!r} but does not know it")
            planned = act.args.get("color", act.args.get("colour"))
            t = rec.sim_time = float(ex.data.time)
            beliefs.announce(act.robot, to, b, said, t)
            rec.observed.update({"announced": {b: said}, "to": list(to)})
            if planned is not None and planned != said:
                diverge(f"{act.robot} announced {b} is {said}; the plan expected {planned}")
        # -- the monitor --
        errs = self._errors(ex, nxt, lost, anchors)
        worst = max(errs, key=errs.get) if errs else None
        rec.max_block_error = errs[worst] if worst else 0.0
        if worst is not None and errs[worst] > self.tolerance:
            loc = nxt.places[worst]
            what = "is no longer in the hand" if loc.kind == "held" else f"is not at {loc.describe()}"
            diverge(f"block {worst!r} {what} ({errs[worst] * 100:.2f} cm off; tolerance "
                    f"{self.tolerance * 100:.1f} cm)")
        if act.name == "sense":
            self._check_sightings(ex.sightings, nxt, prior, diverge)
        for r, bel in beliefs.known().items():
            for b, c in bel.items():
                if prior.get(b) != c:
                    diverge(f"{r} believes {b} is {c}, the plan assumes {prior.get(b)}")
        rec.message = f"ok ({act})"
        return nxt

    def _check_sightings(self, sightings: list[Sighting], state: SymbolicState, prior: dict[str, str],
                         diverge: Callable[[str], None]) -> None:
        for s in sightings:
            r, _, stack = s.column.partition(" stack ")
            expect = state.on_top("barrier") if s.column == "shared table" else state.on_top("stack", r, int(stack))
            if not expect and s.block is None:
                continue
            if not expect or s.block is None or expect[-1] != (s.level, s.block):
                want = f"{expect[-1][1]} at level {expect[-1][0]}" if expect else "nothing"
                got = f"{s.block} at level {s.level}" if s.block else "nothing"
                diverge(f"{s.column}: saw {got}, the plan expects {want}")
            if prior.get(s.block) != s.colour:
                diverge(f"{s.column}: {s.block} looks {s.colour}, the plan believes it is {prior.get(s.block)}")

    # -- recovery --------------------------------------------------------------------------------------
    def _recover(self, ex: Executor, state: SymbolicState, beliefs: Beliefs, prior: dict[str, str],
                 lost: set[str], steps: list[StepRecord], k: int, plan_no: int,
                 ) -> tuple[SymbolicState, dict]:
        """Put down held blocks, re-sense every column, rebuild the state and the colour assumptions."""
        state, _ = self._observe_state(ex, lost)
        for r in self.world.robots:
            b = state.held_by(r)
            if b is not None:  # put it on the robot's lowest stack
                own = len(self.world.stacks[r])
                s = min(range(own), key=lambda i: state.height("stack", r, i))
                act = Action(r, "place", MappingProxyType({"block": b, "stack": s}))
                ex.execute(act, state)
                steps.append(StepRecord(k, plan_no, "recovery", r, str(act), True, "recovery: put down the held "
                                        "block", {}, float(ex.data.time), float("nan")))
                state, _ = self._observe_state(ex, lost)
        travel = ex._travel_z(state)
        for i, r in enumerate(self.world.robots):
            sightings = ex.sense_columns(r, ex.columns(r, barrier=(i == 0)), travel)
            t = float(ex.data.time)
            for s in sightings:
                if s.block is not None:
                    beliefs.sense(r, s.block, s.colour, t)
            steps.append(StepRecord(k, plan_no, "re-sense", r, f"{r}: sense(all)", True, "re-sense",
                                    {"seen": {s.block: s.colour for s in sightings if s.block}},
                                    t, float("nan")))
        for bel in beliefs.known().values():  # what was observed (now or earlier) replaces the prior
            prior.update(bel)
        state, anch = self._observe_state(ex, lost)
        for b in sorted(anch):  # re-seat a block resting off its slot, if it is on top of its stack
            loc = state.places[b]
            if loc.kind != "stack" or state.on_top("stack", loc.robot, loc.stack)[-1][1] != b:
                continue
            off = float(np.linalg.norm(anch[b] - self.world.position(loc)))
            for name, args in (("pick", {"block": b}), ("place", {"block": b, "stack": loc.stack})):
                act = Action(loc.robot, name, MappingProxyType(args))
                ex.execute(act, state)
                state = _apply(self.world, state, act)
            steps.append(StepRecord(k, plan_no, "recovery", loc.robot, f"{loc.robot}: re-seat({b})", True,
                                    f"recovery: {b} rested {off * 100:.1f} cm off its slot; picked and put back",
                                    {}, float(ex.data.time), float("nan")))
        if anch:
            state, anch = self._observe_state(ex, lost)
        return state, {b: (state.places[b], p) for b, p in anch.items()}


# -- a small planner for e-PICO's goals, for tests and as the fallback without planners/ ----------------
def simple_replanner(goal: Goal | str, origin: Mapping[str, str]) -> Replan:
    """A hand-written planner for the α–δ goals (not e-PICO's search; used to test the loop).

    For learner L ∈ (robot1, robot2) and teacher T the other robot: while L believes fewer than
    ``distinct`` colours of T's original blocks, T uncovers the shallowest block of a colour L does not
    know yet (moving the blocks above it onto T's lowest other stack), senses that stack, picks the block,
    puts it on the shared table and announces its colour to L; if the shared table is occupied first, L
    takes that block to its lowest stack. With ``free_barrier`` L clears the shared table at the end.
    Raises :class:`GoalUnreachable` if T's table does not hold enough colours.
    """
    g = goal_of(goal) if isinstance(goal, str) else goal

    def replan(world_json: dict, known: dict) -> dict:
        world = World.from_json(world_json)
        colours = {b: nearest_colour(np.array(world.colors[b])) for b in world.blocks}
        errors = []
        for learner in world.robots:
            teacher = [r for r in world.robots if r != learner][0]
            try:
                acts = _plan_for(world, colours, g, learner, teacher, origin, known.get(learner, {}))
            except GoalUnreachable as exc:
                errors.append(str(exc))
                continue
            return {"format": "delkit.arms.plan/1", "world": world_json, "actions": acts}
        raise GoalUnreachable("; ".join(errors))

    return replan


def _plan_for(world: World, colours: dict, g: Goal, learner: str, teacher: str, origin: Mapping[str, str],
              known: Mapping[str, str]) -> list[dict]:
    state = initial_state(world)
    acts: list[dict] = []

    def do(a: dict) -> None:
        nonlocal state
        act = parse_plan({"world": world.to_json(), "actions": [a]}).actions[0]
        state = _apply(world, state, act)
        acts.append(a)

    def lowest(robot: str, avoid: int = -1) -> int:
        own = [s for s in range(len(world.stacks[robot])) if s != avoid]
        return min(own, key=lambda s: state.height("stack", robot, s))

    def clear_barrier() -> None:
        for _lvl, b in reversed(state.on_top("barrier")):
            s = lowest(learner)
            do({"robot": learner, "action": "take_from_barrier", "args": [b]})
            do({"robot": learner, "action": "place", "args": [b, _top(state, learner, s), state.height(
                "stack", learner, s), s]})

    have = {c for b, c in known.items() if origin.get(b) == teacher}
    need = g.distinct - len(have)
    while need > 0:
        cands = []
        for b, loc in state.places.items():
            if origin.get(b) == teacher and loc.kind == "stack" and loc.robot == teacher and colours[b] not in have:
                depth = state.height("stack", teacher, loc.stack) - 1 - loc.level
                cands.append((depth, loc.stack, b))
        if not cands:
            raise GoalUnreachable(f"{teacher}'s table has no block of a colour {learner} does not know yet")
        _, s, b = min(cands)
        if state.on_top("barrier"):
            clear_barrier()
        for _lvl, over in reversed([x for x in state.on_top("stack", teacher, s) if x[0] > state.places[b].level]):
            t = lowest(teacher, avoid=s)
            do({"robot": teacher, "action": "pick", "args": [over, state.below(over), state.places[over].level, s]})
            do({"robot": teacher, "action": "place", "args": [over, _top(state, teacher, t),
                                                                state.height("stack", teacher, t), t]})
        do({"robot": teacher, "action": "sense", "stack": s})
        do({"robot": teacher, "action": "pick", "args": [b, state.below(b), state.places[b].level, s]})
        do({"robot": teacher, "action": "put_on_barrier", "args": [b]})
        do({"robot": teacher, "action": "announce", "args": [b], "to": [learner], "color": colours[b]})
        have.add(colours[b])
        need -= 1
    if g.free_barrier and state.on_top("barrier"):
        clear_barrier()
    return acts


def _top(state: SymbolicState, robot: str, stack: int) -> str:
    top = state.on_top("stack", robot, stack)
    return top[-1][1] if top else "table"


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
