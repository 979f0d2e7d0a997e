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
which); the designated event is the actual call. SMCDEL's second variant (``GossipKw``, secrets as
"knowing whether") is not encoded here.
"""

from __future__ import annotations

import itertools
import time
from dataclasses import dataclass
from typing import Any

from delkit.formula import Formula, Not, Prop, conj, disj

__all__ = ["GossipResult", "gossip_structure", "call_transformer", "after_calls", "all_experts",
           "solve_gossip", "minimum_calls"]


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
    from delkit.symbolic import KnowledgeStructure

    voc = [_has(i, j) for i in range(n) for j in range(n) if i != j]
    return KnowledgeStructure.create(voc, conj(Not(Prop(v)) for v in voc), {str(i): [] for i in range(n)})


def call_transformer(n: int, call: tuple[int, int], tag: str) -> Any:
    """The transformer of one call (``tag`` makes its event variables fresh: every call adds its own)."""
    from delkit.symbolic import Transformer

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
    from delkit.symbolic import prepare

    prepare()
    t0 = time.process_time()
    seq, ok, checked = minimum_calls(n)
    return GossipResult(n, seq, ok, checked, time.process_time() - t0)
