"""Epistemic puzzles solved by *planning*: the epistemic planner finds the announcement sequence.

Muddy children as a planning task (the protocol of :mod:`delkit.puzzles.muddy`, but found by search rather
than run): the initial state is the muddy children's S5 model *before* the father speaks (N children, the
first M muddy, each sees every forehead but its own); the actions are public, truthful announcements

* ``father``: ⋁_i m_i ("at least one of you is muddy");
* ``nobody-knows``: ⋀_i ¬Kw_{c_i} m_i (a round in which every child says "I don't know");
* with ``individual=True`` also ``c{k}-does-not-know``: ¬Kw_{c_k} m_k (one child's answer; SMCDEL's
  ``MuddyPlanning`` offers these);

and the goal is that the muddy children know they are muddy, ⋀_{i<M} K_{c_i} m_i. An announcement is
applicable only where it is true (``planners.task``: truthful announcements).

Literature answer (Fagin, Halpern, Moses & Vardi, *Reasoning about Knowledge*, 1995, §1.1): the father's
announcement, then M − 1 rounds of "nobody knows"; after them the muddy children know. Breadth-first search
finds this plan and proves that nothing shorter exists (it expands every shorter sequence).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal

from delkit.errors import ModelError
from delkit.logic.formula import TOP, Formula, K, Kw, Not, Prop, conj
from planners.epistemic import Limits, SearchResult, plan
from planners.task import ActionSpec, Task

__all__ = ["muddy_planning_task", "solve_muddy_plan", "MuddyPlanResult", "literature_muddy_plan"]

MAX_CHILDREN = 10


def _announce(name: str, formula: Formula, agents: tuple[str, ...]) -> ActionSpec:
    return ActionSpec(name, kind="announcement", sensed=((formula, TOP),), full=tuple((a, TOP) for a in agents))


def muddy_planning_task(children: int, muddy: int, *, individual: bool = False) -> Task:
    """The planning task above (children c0 … c{N-1}, c0 … c{M-1} muddy)."""
    from delkit.puzzles.muddy import at_least_one, muddy_model, nobody_knows

    if not 1 <= muddy <= children <= MAX_CHILDREN:
        raise ModelError(f"muddy planning: need 1 <= muddy <= children <= {MAX_CHILDREN}, got children "
                         f"{children}, muddy {muddy} (use --muddy <= --children <= {MAX_CHILDREN})")
    model = muddy_model(children, muddy)
    agents = tuple(model.agents)
    acts = [_announce("father", at_least_one(children), agents),
            _announce("nobody-knows", nobody_knows(children), agents)]
    if individual:
        acts += [_announce(f"{a}-does-not-know", Not(Kw(a, Prop(p))), agents)
                 for a, p in zip(agents, model.props, strict=True)]
    goal = conj(K(agents[i], Prop(model.props[i])) for i in range(muddy))
    return Task(f"muddy-plan-{children}-{muddy}", tuple(model.props), agents, model, tuple(acts), goal,
                source="planners.puzzles.muddy_planning_task")


def literature_muddy_plan(muddy: int) -> tuple[str, ...]:
    """The father's announcement, then M − 1 "nobody knows" rounds."""
    return ("father",) + ("nobody-knows",) * (muddy - 1)


@dataclass(frozen=True)
class MuddyPlanResult:
    children: int
    muddy: int
    individual: bool
    result: SearchResult

    def as_dict(self) -> dict:
        r = self.result
        return {"puzzle": "muddy-plan", "children": self.children, "muddy": self.muddy,
                "individual_answers": self.individual, "status": r.status,
                "plan": None if r.plan is None else list(r.plan), "length": r.length,
                "nobody_knows_rounds": None if r.plan is None else r.plan.count("nobody-knows"),
                "literature_plan": list(literature_muddy_plan(self.muddy)),
                "matches_literature": r.plan == literature_muddy_plan(self.muddy),
                "search": r.search, "expanded": r.expanded, "generated": r.generated,
                "seconds": round(r.seconds, 4)}


def solve_muddy_plan(children: int = 3, muddy: int = 2, *, search: Literal["bfs", "astar", "gbfs"] = "bfs",
                     individual: bool = False, timeout: float | None = 60.0) -> MuddyPlanResult:
    """Plan for :func:`muddy_planning_task` with the chosen search."""
    task = muddy_planning_task(children, muddy, individual=individual)
    return MuddyPlanResult(children, muddy, individual, plan(task, search=search, limits=Limits(timeout=timeout)))
