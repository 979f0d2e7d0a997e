"""The gossip problem, on knowledge structures with knowledge transformers (SMCDEL's
``SMCDEL.Examples.GossipS5`` encoding).

n agents each know one secret; in a telephone call two agents tell each other every secret they know. An
agent who knows all secrets is an *expert*. Literature answer (Tijdeman 1971; Baker & Shostak, *Gossips and
telephones*, Discrete Math. 1972; Hajnal, Milner & Szemerédi 1972): the least number of calls after which
everyone is an expert is 1 for n = 2, 3 for n = 3 and 2n − 4 for n ≥ 4 (4 calls for 4 agents:
01, 23, 02, 13).

Encoding: V = {``h_i_j``: i has j's secret, i ≠ j}, θ = no one has another's secret, nobody observes
anything. Every call is the same transformer with event variables ``c_i_j`` (i < j, exactly one true):
``h_i_j`` becomes ``h_i_j ∨ (i and j in the call) ∨ (i in the call ∧ ⋁_k (k in the call ∧ h_k_j))``; agent
k observes the event variables of the calls it takes part in (the others learn that a call happened, not
which); the designated event is the actual call.

The second variant (SMCDEL's ``SMCDEL.Examples.GossipKw``; :func:`solve_gossip_kw`): the vocabulary is the
secrets themselves, ``s_i`` (agent i's secret is true; all are true in the actual state, nothing else is
known), and agent i initially knows only whether ``s_i``. An *expert* knows every secret: ⋀_j K_i s_j. A
call between a and b is an event model with one event per (call (i, j), set X of exchanged secrets):
precondition ``⋀_k (k ∈ X ↔ x_k)`` with ``x_k = s_k`` for k ∈ {i, j} and ``x_k = K_i s_k ∨ K_j s_k``
otherwise (a secret passes as true when a caller knows it); the callers see which event it is, every other
agent sees only that it is not in the call; the designated events are those of the actual call (the symbolic
backend uses the same product as a belief transformer with 2n event variables, SMCDEL's encoding:
:func:`kw_call_transformer`). So here
the callers learn the *facts* and, with them, what the other knew — knowing whether, on a belief structure
(:class:`delkit.backends.symbolic_belief.BeliefStructure`, SMCDEL's ``SMCDEL.Symbolic.K``) or on the explicit model
(2^n worlds, the product update). Literature answer: the same least numbers of calls (1, 3, 2n − 4).
"""

from __future__ import annotations

import itertools
import time
from dataclasses import dataclass
from typing import Any

from delkit.logic.formula import Formula, Not, Prop, conj, disj

__all__ = ["GossipResult", "gossip_structure", "call_transformer", "after_calls", "all_experts",
           "solve_gossip", "minimum_calls", "kw_initial", "kw_call", "kw_call_transformer", "kw_after", "kw_experts",
           "kw_minimum_calls", "GossipKwResult", "solve_gossip_kw"]


@dataclass(frozen=True)
class GossipResult:
    """``calls``: a shortest call sequence making everyone an expert; ``shorter_fail``: every sequence of
    one call fewer was checked and fails; ``seconds``: CPU time of the search."""

    n: int
    calls: tuple[tuple[int, int], ...]
    shorter_fail: bool
    sequences_checked: int
    seconds: float

    def as_dict(self) -> dict:
        return {"puzzle": "gossip", "engine": "symbolic", "n": self.n, "minimum_calls": len(self.calls),
                "calls": [list(c) for c in self.calls], "every_shorter_sequence_fails": self.shorter_fail,
                "sequences_checked": self.sequences_checked, "seconds": self.seconds}


def _has(i: int, j: int) -> str:
    return f"h_{i}_{j}"


def _calls(n: int) -> list[tuple[int, int]]:
    return [(i, j) for i in range(n) for j in range(i + 1, n)]


def gossip_structure(n: int) -> Any:
    """The initial structure: nobody has another's secret (common knowledge), nobody observes anything."""
    from delkit.backends.symbolic import KnowledgeStructure

    voc = [_has(i, j) for i in range(n) for j in range(n) if i != j]
    return KnowledgeStructure.create(voc, conj(Not(Prop(v)) for v in voc), {str(i): [] for i in range(n)})


def call_transformer(n: int, call: tuple[int, int], tag: str) -> Any:
    """The transformer of one call (``tag`` makes its event variables fresh: every call adds its own)."""
    from delkit.backends.symbolic import Transformer

    ev = {c: f"c{tag}_{c[0]}_{c[1]}" for c in _calls(n)}

    def in_call(k: int) -> Formula:
        return disj(Prop(v) for c, v in ev.items() if k in c)

    calls = list(ev.values())
    law = conj([disj(Prop(v) for v in calls)]
               + [Not(Prop(a) & Prop(b)) for a, b in itertools.combinations(calls, 2)])
    changes = {_has(i, j): disj([Prop(_has(i, j)), in_call(i) & in_call(j),
                                 in_call(i) & disj(in_call(k) & Prop(_has(k, j)) for k in range(n)
                                                   if k not in (i, j))])
               for i in range(n) for j in range(n) if i != j}
    observed = {str(k): tuple(v for c, v in ev.items() if k in c) for k in range(n)}
    return Transformer(tuple(calls), law, changes, observed, designated=Prop(ev[tuple(sorted(call))]))


def all_experts(n: int) -> Formula:
    return conj(Prop(_has(i, j)) for i in range(n) for j in range(n) if i != j)


def after_calls(n: int, calls: list[tuple[int, int]], start: Any = None) -> Any:
    ks = gossip_structure(n) if start is None else start
    for step, c in enumerate(calls):
        ks = ks.transform(call_transformer(n, c, f"{len(ks.vocabulary)}x{step}"))
    return ks


def minimum_calls(n: int, limit: int = 8) -> tuple[tuple[tuple[int, int], ...], bool, int]:
    """Iterative deepening over call sequences (prefixes shared by a depth-first search): the first length
    at which some sequence makes everyone an expert, a witness, and how many sequences were checked.

    Symmetry: agents can be renamed so that the first call is 01, and a call repeating the one just made
    changes nothing — so only those sequences are searched (every shorter sequence still fails, since each
    one is a renaming of a searched one or contains a useless repeat)."""
    goal = all_experts(n)
    first = (0, 1)
    checked = 0
    for length in range(limit + 1):
        if length == 0:
            checked += 1
            if gossip_structure(n).holds(goal):
                return (), True, checked
            continue
        stack: list[tuple[tuple[tuple[int, int], ...], Any]] = [((first,), after_calls(n, [first]))]
        while stack:
            seq, ks = stack.pop()
            if len(seq) == length:
                checked += 1
                if ks.holds(goal):
                    return seq, True, checked
                continue
            for c in reversed(_calls(n)):
                if c != seq[-1]:
                    stack.append((seq + (c,), after_calls(n, [c], ks)))
    raise ValueError(f"gossip: no sequence of at most {limit} calls makes all {n} agents experts")


def solve_gossip(n: int = 4) -> GossipResult:
    from delkit.backends.symbolic import prepare

    prepare()
    t0 = time.process_time()
    seq, ok, checked = minimum_calls(n)
    return GossipResult(n, seq, ok, checked, time.process_time() - t0)


# ----------------------------------------------------------------------------- GossipKw: knowing whether
def _secret(i: int) -> str:
    return f"s{i}"


def kw_initial(n: int, *, symbolic: bool = True) -> Any:
    """Every secret true, each agent knows only whether its own is: a belief structure (``symbolic``) or the
    explicit S5 model of 2^n worlds."""
    from delkit.logic.formula import TOP

    secrets = [_secret(i) for i in range(n)]
    if symbolic:
        from delkit.backends.symbolic_belief import BeliefStructure

        return BeliefStructure.create(secrets, TOP, {str(i): f"{s}' <-> {s}" for i, s in enumerate(secrets)},
                                      actual=conj(Prop(s) for s in secrets))
    import numpy as np

    from delkit.models.kripke import KripkeModel
    from delkit.models.relation import Relation

    w = np.arange(1 << n, dtype=np.int64)
    val = ((w[:, None] >> np.arange(n)[None, :]) & 1).astype(bool)
    rels = {str(i): Relation.from_labels(val[:, i].astype(np.int64)) for i in range(n)}
    return KripkeModel(tuple(secrets), tuple(str(i) for i in range(n)), val, rels, ((1 << n) - 1,))


def kw_call(n: int, call: tuple[int, int]) -> Any:
    """The event model of the call ``call`` (see the module docstring): 2^n events per possible call."""
    import numpy as np

    from delkit.logic.formula import K
    from delkit.models.events import EventModel
    from delkit.models.relation import Relation

    names, pre, members = [], [], []
    for c in _calls(n):
        passes = [Prop(_secret(k)) if k in c else K(str(c[0]), Prop(_secret(k))) | K(str(c[1]), Prop(_secret(k)))
                  for k in range(n)]
        for mask in range(1 << n):
            names.append(f"{c[0]}{c[1]}:{mask}")
            pre.append(conj(x if (mask >> k) & 1 else Not(x) for k, x in enumerate(passes)))
            members.append(c)
    m = len(names)
    rels = {str(a): Relation.from_labels(np.array([e if a in members[e] else m for e in range(m)]))
            for a in range(n)}
    des = tuple(e for e in range(m) if members[e] == tuple(sorted(call)))
    return EventModel(tuple(names), tuple(str(a) for a in range(n)), tuple(pre), tuple({} for _ in range(m)), rels,
                      des, name=f"call{call[0]}{call[1]}")


def kw_experts(n: int) -> Formula:
    """⋀_i ⋀_j K_i s_j: everyone knows every secret."""
    from delkit.logic.formula import K

    return conj(K(str(i), Prop(_secret(j))) for i in range(n) for j in range(n))


def kw_call_transformer(state: Any, n: int, call: tuple[int, int]) -> Any:
    """The call as a belief transformer on ``state`` (SMCDEL's ``callTrf``; the same product as
    :func:`kw_call`'s event model, with 2n event variables instead of n(n−1)/2 · 2^n events): fresh
    ``in_k`` (k is in the call) and ``x_k`` (secret k passes as true); law: exactly one call (i, j) happens
    and ``x_k ↔`` (s_k if k ∈ {i, j}, else K_i s_k ∨ K_j s_k); agent a observes whether it is in the call
    and, if it is, every event variable."""
    from delkit.backends.symbolic import _fresh
    from delkit.logic.formula import Iff, Implies, K

    taken = set(state.bdd.vars)
    tag = _fresh("g", taken)
    inc = [f"_{tag}in{k}" for k in range(n)]
    xs = [f"_{tag}x{k}" for k in range(n)]

    def happens(c: tuple[int, int]) -> Formula:
        return conj(Prop(v) if k in c else Not(Prop(v)) for k, v in enumerate(inc))

    def passes(c: tuple[int, int], k: int) -> Formula:
        s = Prop(_secret(k))
        return s if k in c else K(str(c[0]), s) | K(str(c[1]), s)

    law = disj(happens(c) & conj(Iff(Prop(xs[k]), passes(c, k)) for k in range(n)) for c in _calls(n))
    every = conj(Iff(Prop(v + "'"), Prop(v)) for v in inc + xs)
    obs = {str(a): Iff(Prop(inc[a] + "'"), Prop(inc[a])) & Implies(Prop(inc[a]), every) for a in range(n)}
    return state.transform_symbolic(inc + xs, law, obs, happens(tuple(sorted(call))))


def _kw_step(state: Any, n: int, c: tuple[int, int]) -> Any:
    if hasattr(state, "transform_symbolic"):
        return kw_call_transformer(state, n, c)
    from delkit.models.update import product_update

    return product_update(state, kw_call(n, c))


def kw_after(n: int, calls: list[tuple[int, int]], *, symbolic: bool = True, start: Any = None) -> Any:
    state = kw_initial(n, symbolic=symbolic) if start is None else start
    for c in calls:
        state = _kw_step(state, n, c)
    return state


def kw_minimum_calls(n: int, *, symbolic: bool = True, limit: int = 8
                     ) -> tuple[tuple[tuple[int, int], ...], bool, int]:
    """:func:`minimum_calls` for the knowing-whether variant (the same symmetry: the first call is 01 and no
    call repeats the one just made — after a call both callers know the same secrets, so repeating it adds
    nothing, and knowing a fact is never lost)."""
    from delkit.logic.formula import K

    # the goal's conjuncts one by one, stopping at the first that fails (most sequences fail early)
    parts = [K(str(i), Prop(_secret(j))) for i in range(n) for j in range(n) if i != j]
    parts += [K(str(i), Prop(_secret(i))) for i in range(n)]  # true from the start; checked last
    start = kw_initial(n, symbolic=symbolic)

    def done(st: Any) -> bool:
        return all(st.holds(f) for f in parts)

    if done(start):
        return (), True, 1
    checked = 1
    for length in range(1, limit + 1):
        stack: list[tuple[tuple[tuple[int, int], ...], Any]] = [(((0, 1),), _kw_step(start, n, (0, 1)))]
        while stack:
            seq, st = stack.pop()
            if len(seq) == length:
                checked += 1
                if done(st):
                    return seq, True, checked
                continue
            for c in reversed(_calls(n)):
                if c != seq[-1]:
                    stack.append((seq + (c,), _kw_step(st, n, c)))
    raise ValueError(f"gossip (knowing whether): no sequence of at most {limit} calls makes all {n} agents experts")


@dataclass(frozen=True)
class GossipKwResult:
    """:class:`GossipResult` for the knowing-whether variant, plus ``engine`` and, after the witness calls,
    ``everyone_knows_all_experts`` (E_G of "everyone is an expert")."""

    n: int
    engine: str
    calls: tuple[tuple[int, int], ...]
    shorter_fail: bool
    sequences_checked: int
    everyone_knows_all_experts: bool
    seconds: float

    def as_dict(self) -> dict:
        return {"puzzle": "gossip", "variant": "kw", "engine": self.engine, "n": self.n,
                "minimum_calls": len(self.calls), "calls": [list(c) for c in self.calls],
                "every_shorter_sequence_fails": self.shorter_fail, "sequences_checked": self.sequences_checked,
                "everyone_knows_all_experts": self.everyone_knows_all_experts, "seconds": self.seconds}


def solve_gossip_kw(n: int = 4, *, symbolic: bool = True) -> GossipKwResult:
    """Least number of calls making everyone an expert, knowing-whether variant (CPU seconds)."""
    from delkit.logic.formula import E

    if symbolic:
        from delkit.backends.symbolic import prepare

        prepare()
    t0 = time.process_time()
    seq, ok, checked = kw_minimum_calls(n, symbolic=symbolic)
    end = kw_after(n, list(seq), symbolic=symbolic)
    everyone = end.holds(E(tuple(str(i) for i in range(n)), kw_experts(n)))
    return GossipKwResult(n, "symbolic" if symbolic else "explicit", seq, ok, checked, everyone,
                          time.process_time() - t0)
