"""Checking a plan of a task with :class:`planners.task.EventAction` (EPDDL 2026) step by step, explaining the
first failure at the designated world where it happens (a multi-pointed state fails where *one* designated
world fails).

The transition is the core's (:func:`planners.task.apply_action`: plank's ``updater`` — the event model is
chosen by the truth of the action's conditions in the state; the action applies iff every designated world
satisfies the precondition of some designated event; product update). No agent-believes-⊥ pruning: EPDDL
states may be K or KD45 and plank never prunes them.
"""

from __future__ import annotations

from delkit.formula import show
from planners.task import EventAction, Task, apply_action, uncovered_worlds

__all__ = ["check_event_plan", "has_event_actions", "space_for"]


def has_event_actions(task: Task) -> bool:
    return any(isinstance(a, EventAction) for a in task.actions)


def space_for(task: Task, engine: str = "auto", allow_inconsistent: bool = False):
    """The planner's state space for ``task``. EPDDL (2026) tasks never prune states where an agent believes ⊥
    (K and KD45 states are legitimate there, and plank does not prune them). ``auto``: an EPDDL task whose
    initial state has more than 4096 worlds runs on the numpy backend, whose S5 relations are partitions —
    the compact backend's bit sets cost O(worlds²) per relation there (Tiger: 20,480 worlds, 42 s vs 1.5 s
    for the same 3 expansions) — anything else on the compact backend."""
    from planners.epistemic import make_space

    event = has_event_actions(task)
    if engine == "auto":
        engine = "del" if event and task.initial.n_worlds > 4096 else "fast"
    return make_space(task, engine=engine, allow_inconsistent=allow_inconsistent or event)  # type: ignore[arg-type]


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
    for i, name in enumerate(plan, 1):
        act = task.action(name)
        new = apply_action(task, act, model)
        if new is None:
            bad = [w for w in model.designated if not model.holds(act.executable, [w])]
            if bad:
                why, ag, wd = explain(model, act.executable, bad[0])
                return CheckResult(False, n, i, name, "precondition",
                                   f"step {i} ({name}) is not executable: {show(act.executable)} fails — {why}",
                                   ag, wd)
            em = task.event_model(act, model)
            bad_w = uncovered_worlds(em, model)[0]
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
