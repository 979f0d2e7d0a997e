"""Running tasks with :class:`planners.task.EventAction` (EPDDL 2026): the planner's state space for them
(:func:`space_for`). Their plan check is :func:`planners.validate.check_plan`, which switches to its EPDDL mode
for such tasks (no agent-believes-⊥ pruning — EPDDL states may be K or KD45 and plank never prunes them — and
the first failure explained at the designated world where it happens).
"""

from __future__ import annotations

from planners.task import Task, has_event_actions

__all__ = ["has_event_actions", "space_for"]


def space_for(task: Task, engine: str = "auto", allow_inconsistent: bool = False, *, consistent_beliefs: bool = False):
    """The planner's state space for ``task``. Whether states where an agent believes ⊥ are kept is decided by
    :func:`planners.beliefs.belief_semantics` (EPDDL 2026 tasks keep them by default, as plank does;
    ``consistent_beliefs`` prunes them). ``auto``: an EPDDL task whose
    initial state has more than 4096 worlds runs on the numpy backend, whose S5 relations are partitions —
    the compact backend's bit sets cost O(worlds²) per relation there (Tiger: 20,480 worlds, 42 s vs 1.5 s
    for the same 3 expansions) — anything else on the compact backend."""
    from planners.epistemic import make_space

    event = has_event_actions(task)
    if engine == "auto":
        engine = "del" if event and (task.plain_initial or task.initial).n_worlds > 4096 else "fast"
    from planners.beliefs import keeps_inconsistent

    keep = keeps_inconsistent(task, consistent_beliefs=consistent_beliefs, allow_inconsistent=allow_inconsistent)
    return make_space(task, engine=engine, allow_inconsistent=keep)  # type: ignore[arg-type]
