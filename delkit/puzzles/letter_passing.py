"""Letter passing (SMCDEL's ``SMCDEL.Examples.LetterPassing``; the implicit-coordination examples of Engesser,
Bolander, Mattmüller & Nebel, *Cooperative Epistemic Multi-Agent Planning for Implicit Coordination*, M4M
2017).

Agents 1 … n stand in a line; a letter lies with agent 1, addressed to one of 2 … n (common knowledge: it
is with 1 and not for 1). Agent 1 can read the address, the others cannot. A pass i → j (neighbours) is
public — everybody sees the letter move — and the receiver reads the address privately. The joint goal: the
letter reaches its addressee (``⋀_i for_i → at_i``).

Literature answer: with the letter for n, the plan 1 → 2 → … → n reaches the goal in n − 1 passes, no
shorter sequence does; agent 1 knows from the start that it works (K_1 for_n), every other agent learns the
address — and with it that the rest of the plan works — exactly when the letter reaches it: before, agent
k does not know whether the letter is for it (so it could not have planned the passes itself), after, it
knows, and the others know that it knows (the pass is public, what it read is not). After the last pass it
is common knowledge that the goal is reached. (For n = 3 these are SMCDEL's ``letter`` task and its plan
1 → 2, 2 → 3.)

Encodings: explicit (S5 model, one world per possible addressee; each pass an event model with one event
per addressee, told apart by the receiver only) and symbolic (knowledge structure V = {at_i, for_i}, agent
1 observes at_1 and every for_i, agent k observes at_k; a pass is a transformer whose event variables
``t_b`` spell the address in binary and are observed by the receiver, changing at_i := ⊥, at_j := ⊤).
"""

from __future__ import annotations

import time
from dataclasses import dataclass
from typing import Any

from delkit.errors import ModelError
from delkit.logic.formula import BOT, TOP, C, Formula, Implies, K, Kw, Not, Prop, conj, disj

__all__ = ["MAX_AGENTS", "LetterResult", "letter_start", "pass_event", "pass_transformer", "goal",
           "solve_letter_passing"]

MAX_AGENTS = 40  # explicit: n − 1 worlds, n − 1 events per pass; 40 agents take about 1 s
MAX_SYMBOLIC = 16  # measured: 16 agents 0.36 s, 19 agents 2.5 s CPU (the K_a goal checks grow ~2x per agent)


def _at(i: int) -> Prop:
    return Prop(f"at{i}")


def _for(i: int) -> Prop:
    return Prop(f"for{i}")


def goal(n: int) -> Formula:
    """The letter is with its addressee: ⋀_i (for_i → at_i)."""
    return conj(Implies(_for(i), _at(i)) for i in range(1, n + 1))


def _exactly_one(props: list[Prop]) -> Formula:
    return conj([disj(props)] + [Not(p & q) for k, p in enumerate(props) for q in props[k + 1:]])


def _agents(n: int) -> tuple[str, ...]:
    return tuple(str(i) for i in range(1, n + 1))


def letter_start(n: int, to: int, engine: str = "explicit") -> Any:
    """The letter with agent 1, addressed to ``to`` (2 … n)."""
    _check(n, to)
    ats, fors = [_at(i) for i in range(1, n + 1)], [_for(i) for i in range(1, n + 1)]
    if engine == "symbolic":
        from delkit.backends.symbolic import KnowledgeStructure

        law = conj([_exactly_one(ats), _exactly_one(fors), _at(1), Not(_for(1))])
        observed = {"1": [_at(1).name] + [p.name for p in fors]} | {str(k): [_at(k).name] for k in range(2, n + 1)}
        return KnowledgeStructure.create([p.name for p in ats + fors], law, observed, actual=_for(to))
    if engine != "explicit":
        raise ModelError(f"letter passing: unknown engine {engine!r}; use explicit or symbolic")
    from delkit.models.kripke import KripkeModel

    # world w: the letter is for agent w + 2; agent 1 tells the worlds apart, the others do not
    worlds = [{"at1", f"for{k}"} for k in range(2, n + 1)]
    rels = {"1": [[w] for w in range(n - 1)]} | {str(k): [list(range(n - 1))] for k in range(2, n + 1)}
    return KripkeModel.build(worlds, rels, designated=[to - 2], props=[p.name for p in ats + fors],
                             agents=_agents(n))


def pass_event(n: int, i: int, j: int) -> Any:
    """Pass i → j as an event model: event k (k = 2 … n): the letter is for k; the receiver tells the events
    apart, everybody else confuses them all; every event is designated (the actual address survives)."""
    from delkit.models.events import EventModel
    from delkit.models.relation import Relation

    events = {f"for{k}": {"pre": conj([_at(i), _for(k)]), "post": {f"at{i}": BOT, f"at{j}": TOP}}
              for k in range(2, n + 1)}
    rels: dict[str, Any] = {a: [list(events)] for a in _agents(n)}
    rels[str(j)] = Relation.identity(len(events))
    return EventModel.build(events, rels, designated=list(events), agents=_agents(n), name=f"pass{i}to{j}")


def pass_transformer(n: int, i: int, j: int, tag: str) -> Any:
    """Pass i → j as a knowledge transformer: event variables ``t<tag>_b`` spell the addressee in binary
    (for_k → the bits of k), observed by j. (One event variable per agent, t_k ↔ for_k, would be SMCDEL's
    choice; with the t's declared after all for's its BDD has 2^n nodes, the binary code n · log n.)"""
    from delkit.backends.symbolic import Transformer

    bits = [Prop(f"t{tag}_{b}") for b in range(max(1, n.bit_length()))]
    code = [conj(bits[b] if (k >> b) & 1 else Not(bits[b]) for b in range(len(bits))) for k in range(n + 1)]
    law = conj([_at(i)] + [Implies(_for(k), code[k]) for k in range(1, n + 1)])
    observed = {a: ((tuple(e.name for e in bits)) if a == str(j) else ()) for a in _agents(n)}
    return Transformer(tuple(e.name for e in bits), law, {f"at{i}": BOT, f"at{j}": TOP}, observed)


def _check(n: int, to: int, engine: str = "explicit") -> None:
    cap = MAX_SYMBOLIC if engine == "symbolic" else MAX_AGENTS
    if not 2 <= n <= cap:
        more = f" (leave out --symbolic for up to {MAX_AGENTS})" if engine == "symbolic" else ""
        raise ModelError(f"letter passing: --agents must be 2..{cap}{more}, got {n}")
    if not 2 <= to <= n:
        raise ModelError(f"letter passing: --to must be an agent 2..{n} (agent 1 holds the letter and it is not "
                         f"for 1), got {to}")


def knows_addressee(n: int, agent: int) -> Formula:
    """⋁_k K_agent for_k: the agent knows whom the letter is for."""
    return disj(K(str(agent), _for(k)) for k in range(1, n + 1))


@dataclass(frozen=True)
class LetterResult:
    """``steps[0]`` is the start, ``steps[s]`` the state after pass s: the holder, who knows the address,
    who knows that the goal holds, whether it holds, whether it is common knowledge, and whether each
    not-yet-reached agent k knows *whether* the letter is for it (it does not)."""

    n: int
    to: int
    plan: tuple[tuple[int, int], ...]
    steps: tuple[dict, ...]
    engine: str
    seconds: float

    def as_dict(self) -> dict:
        return {"puzzle": "letter-passing", "engine": self.engine, "agents": self.n, "to": self.to,
                "plan": [f"{i}->{j}" for i, j in self.plan], "passes": len(self.plan),
                "goal_after_plan": self.steps[-1]["goal"], "steps": list(self.steps), "seconds": self.seconds}


def solve_letter_passing(n: int = 3, to: int | None = None, *, engine: str = "explicit") -> LetterResult:
    """Run the plan 1 → 2 → … → to and record who knows what after each pass."""
    to = n if to is None else to
    _check(n, to, engine)
    if engine == "symbolic":
        from delkit.backends.symbolic import prepare

        prepare()
    t0 = time.process_time()
    state = letter_start(n, to, engine)
    plan = tuple((i, i + 1) for i in range(1, to))
    g = goal(n)
    knows = [knows_addressee(n, a) for a in range(1, n + 1)]
    knows_goal = [K(str(a), g) for a in range(1, n + 1)]
    self_unsure = [Not(Kw(str(a), _for(a))) for a in range(1, n + 1)]
    ck_goal = C(_agents(n), g)

    def record(holder: int) -> dict:
        return {"holder": holder,
                "know_addressee": [a for a in range(1, n + 1) if state.holds(knows[a - 1])],
                "know_goal": [a for a in range(1, n + 1) if state.holds(knows_goal[a - 1])],
                "goal": bool(state.holds(g)), "common_knowledge_of_goal": bool(state.holds(ck_goal)),
                "unsure_whether_for_them": [a for a in range(1, n + 1) if state.holds(self_unsure[a - 1])],
                "holder_known_to_all": bool(state.holds(C(_agents(n), _at(holder))))}

    steps = [record(1)]
    base = tuple(state.vocabulary) if engine == "symbolic" else ()
    for s, (i, j) in enumerate(plan):
        if engine == "symbolic":
            # SMCDEL's optimize after every update: the old at-copies are constants
            state = state.transform(pass_transformer(n, i, j, str(s))).minimise(keep=base)
        else:
            from delkit.models.update import product_update

            state = product_update(state, pass_event(n, i, j))
        steps.append(record(j))
    return LetterResult(n, to, plan, tuple(steps), engine, time.process_time() - t0)
