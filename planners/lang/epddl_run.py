"""Running tasks with :class:`planners.task.EventAction` (EPDDL 2026): the planner's state space for them
(:func:`space_for`). Their plan check is :func:`planners.validate.check_plan`, which switches to its EPDDL mode
for such tasks (no agent-believes-⊥ pruning — EPDDL states may be K or KD45 and plank never prunes them — and
the first failure explained at the designated world where it happens).
"""

from __future__ import annotations

from planners.task import Task, has_event_actions

__all__ = ["has_event_actions", "space_for"]


def space_for(task: Task, engine: str = "auto", allow_inconsistent: bool = False):
    """The planner's state space for ``task``. EPDDL (2026) tasks never prune states where an agent believes ⊥
    (K and KD45 states are legitimate there, and plank does not prune them). ``auto``: an EPDDL task whose
    initial state has more than 4096 worlds runs on the numpy backend, whose S5 relations are partitions —
    the compact backend's bit sets cost O(worlds²) per relation there (Tiger: 20,480 worlds, 42 s vs 1.5 s
    for the same 3 expansions) — anything else on the compact backend."""
    from planners.epistemic import make_space

    event = has_event_actions(task)
    if engine == "auto":
        engine = "del" if event and (task.plain_initial or task.initial).n_worlds > 4096 else "fast"
    return make_space(task, engine=engine, allow_inconsistent=allow_inconsistent or event)  # type: ignore[arg-type]
