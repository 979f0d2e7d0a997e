"""Executing :class:`planners.task.EventAction` (EPDDL actions) on delkit Kripke models: one step, the plan
checker, and the generic (``--engine del``) state space.

Semantics (plank's ``updater``): the event model is built from the truth *in the state* (every designated
world) of the action's conditions; the action applies iff every designated world satisfies the precondition
of some designated event; the result is delkit's product update (designated = designated pairs).
No agent-believes-⊥ pruning: EPDDL states may be K or KD45 and plank never prunes them.
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass

import numpy as np

from delkit.bisim import canonical_form, contract
from delkit.formula import show
from delkit.kripke import KripkeModel
from delkit.update import preconditions, product_update
from planners.task import EventAction, Task

__all__ = ["event_model_in", "step", "check_event_plan", "EventDelSpace", "has_event_actions"]


def has_event_actions(task: Task) -> bool:
    return any(isinstance(a, EventAction) for a in task.actions)


def event_model_in(act: EventAction, model: KripkeModel, cache: dict | None = None):
    bits = tuple(model.holds(c) for c in act.conditions)
    if cache is None:
        return act.build(bits)
    key = (act.name, bits)
    em = cache.get(key)
    if em is None:
        em = cache[key] = act.build(bits)
    return em


def step(act: EventAction, model: KripkeModel, cache: dict | None = None) -> tuple[KripkeModel | None, int | None]:
    """(M ⊗ E, None) if ``act`` applies in ``model``, else (None, a designated world where no designated
    event's precondition holds, or None when ``executable`` fails)."""
    if not model.holds(act.executable):
        return None, None
    em = event_model_in(act, model, cache)
    pre = preconditions(model, em)
    des_w = list(model.designated)
    ok = pre[np.ix_(des_w, list(em.designated))].any(axis=1)
    if not ok.all():
        return None, des_w[int(np.flatnonzero(~ok)[0])]
    return product_update(model, em), None


@dataclass
class _Result:
    valid: bool
    steps: int
    step: int | None = None
    action: str | None = None
    kind: str | None = None
    reason: str = ""

    def to_json(self) -> dict:
        if self.valid:
            return {"valid": True, "steps": self.steps}
        return {"valid": False, "step": self.step, "action": self.action, "kind": self.kind, "reason": self.reason}


def check_event_plan(task: Task, plan: list[str], *, plan_source: str = "plan"):
    """Replay ``plan`` (EPDDL semantics, no contraction) and explain the first failing step."""
    from delkit.errors import PlanningError
    from planners.validate import CheckResult, explain

    for i, name in enumerate(plan, 1):
        try:
            task.action(name)
        except PlanningError as exc:
            raise PlanningError(f"{plan_source}: step {i}: {exc}") from None
    model = task.initial
    n = len(plan)
    cache: dict = {}
    for i, name in enumerate(plan, 1):
        act = task.action(name)
        if not isinstance(act, EventAction):
            raise PlanningError(f"{plan_source}: step {i}: {name} is not an event-model action")
        new, bad_w = step(act, model, cache)
        if new is None:
            if bad_w is None:
                why, ag, wd = explain(model, act.executable, model.designated[0])
                return CheckResult(False, n, i, name, "precondition",
                                   f"step {i} ({name}) is not executable: {show(act.executable)} fails — {why}",
                                   ag, wd)
            em = event_model_in(act, model, cache)
            whys = []
            for d in em.designated:
                why, _ag, _wd = explain(model, em.pre[d], bad_w)
                whys.append(f"event {em.events[d]}: {why}")
            wname = model.world_name(bad_w)
            return CheckResult(False, n, i, name, "not-applicable",
                               f"step {i} ({name}) is not applicable: at designated world {wname} no designated "
                               f"event's precondition holds ({'; '.join(whys)})", None, wname)
        model = new
    if not model.holds(task.goal):
        bad = [w for w in model.designated if not model.holds(task.goal, [w])]
        why, ag, wd = explain(model, task.goal, bad[0])
        return CheckResult(False, n, n, plan[-1] if plan else None, "goal",
                           f"the goal {show(task.goal)} does not hold after the plan"
                           f"{'' if n else ' (empty plan: in the initial state)'}: {why}", ag, wd)
    return CheckResult(True, n)


class EventDelSpace:
    """The generic delkit state space for tasks with EventActions (reference semantics, slow): product
    update, bisimulation contraction and canonical forms from ``delkit``; states are never pruned for
    inconsistent beliefs (EPDDL semantics)."""

    def __init__(self, task: Task) -> None:
        from planners.epistemic import goal_conjuncts

        self.task = task
        self.dead_ends = 0
        self._conj = goal_conjuncts(task.goal)
        self._cache: dict = {}

    def initial(self):
        m = contract(self.task.initial)
        return m, canonical_form(m, generated=False)

    def successors(self, model: KripkeModel) -> Iterator:
        for act in self.task.actions:
            new, _ = step(act, model, self._cache)
            if new is None:
                continue
            c = contract(new)
            yield act.name, c, canonical_form(c, generated=False)

    def is_goal(self, model: KripkeModel) -> bool:
        return model.holds(self.task.goal)

    def holds(self, model: KripkeModel, f) -> bool:
        return model.holds(f)

    def goal_count(self, model: KripkeModel) -> int:
        return sum(0 if model.holds(g) else 1 for g in self._conj)
