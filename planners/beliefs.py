"""The planner's semantics of inconsistent beliefs: one function decides whether states where an agent believes ⊥
are kept, and one reports the goal conjuncts that hold only vacuously.

An agent *believes ⊥* at a designated world when it has no accessible world there; every belief formula
``B_a φ`` then holds at that world, vacuously. Two semantics, by name:

* ``"reference"`` — such states are ordinary states: kept, expanded, and may satisfy the goal. This is what
  the competition's reference planner does for EPDDL (2026): plank's breadth-first search applies every
  applicable action and tests the goal with the standard Kripke clause (a box over an empty set of worlds is
  true), with no consistency test (its ``bfs-planner`` search and ``model_checker``, read with the search tool).
* ``"consistent"`` — such states are dead ends: never expanded and never a goal (``--consistent-beliefs``).

The default is decided per task by :func:`belief_semantics`: ``reference`` for EPDDL (2026) tasks (they have
event-model actions), ``consistent`` for mA* and E-PDDL tasks (their planners, like EFP's mA* semantics, keep
beliefs consistent — the planner's default before this module existed). ``--allow-inconsistent`` forces
``reference``, ``--consistent-beliefs`` forces ``consistent``; both at once is an error. The planner
(:func:`planners.epistemic.plan`, ``delkit plan``: :func:`planners.lang.epddl_run.space_for`) and the plan checker
(:func:`planners.validate.check_plan`) all ask this function.

Under ``reference`` a plan may reach the goal only vacuously: :func:`vacuous_goals` lists, for the final state,
each goal conjunct that holds while an agent whose beliefs it mentions believes ⊥ at a designated world.
"""

from __future__ import annotations

TYPE_CHECKING = False
if TYPE_CHECKING:
    from typing import Any

    from planners.task import Task

__all__ = ["SEMANTICS", "belief_semantics", "keeps_inconsistent", "vacuous_goals"]

#: the two semantics of states where an agent believes ⊥
SEMANTICS = ("reference", "consistent")


def belief_semantics(task: Task, *, consistent_beliefs: bool = False, allow_inconsistent: bool = False) -> str:
    """``"reference"`` (keep states where an agent believes ⊥, as plank does) or ``"consistent"`` (prune them).

    ``consistent_beliefs`` / ``allow_inconsistent`` True force one; both False leave the task's default
    (reference for EPDDL 2026 tasks, consistent for mA* and E-PDDL tasks)."""
    from delkit.errors import PlanningError
    from planners.task import has_event_actions

    if consistent_beliefs and allow_inconsistent:
        raise PlanningError("--consistent-beliefs (prune states where an agent believes ⊥) and "
                            "--allow-inconsistent (keep them) contradict each other: give at most one")
    if consistent_beliefs:
        return "consistent"
    if allow_inconsistent:
        return "reference"
    return "reference" if has_event_actions(task) else "consistent"


def keeps_inconsistent(task: Task, *, consistent_beliefs: bool = False, allow_inconsistent: bool = False) -> bool:
    """Whether the search keeps states where an agent believes ⊥ (:func:`belief_semantics` is ``reference``)."""
    return belief_semantics(task, consistent_beliefs=consistent_beliefs,
                            allow_inconsistent=allow_inconsistent) == "reference"


def _believers(f: Any) -> set[str]:
    """The agents whose beliefs ``f`` mentions (K, Kw; for E, C, D, every member of the group)."""
    from delkit.logic.formula import agents_of

    return set(agents_of(f))


def _inconsistent_agents(space: Any, state: Any) -> set[str]:
    if hasattr(space, "inconsistent"):
        return set(space.inconsistent(state))
    return {a for a, _ in state.inconsistent_agents()}


def vacuous_goals(space: Any, state: Any) -> list[dict[str, Any]]:
    """For a goal state: each goal conjunct that holds while an agent it mentions believes ⊥ at a designated
    world (``{"conjunct": text, "agents": [...]}``) — the goal is reached only vacuously for those agents.
    Empty when no agent believes ⊥ (always so under the ``consistent`` semantics)."""
    from delkit.logic.formula import show
    from planners.task import goal_conjuncts

    bad = _inconsistent_agents(space, state)
    if not bad:
        return []
    out = []
    for g in goal_conjuncts(space.task.goal):
        agents = sorted(_believers(g) & bad)
        if agents and space.holds(state, g):
            out.append({"conjunct": show(g), "agents": agents})
    return out
