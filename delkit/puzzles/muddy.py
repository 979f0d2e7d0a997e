"""Muddy children, solved with public announcements on an explicit S5 model.

Vocabulary ``m0 … m{N-1}`` (child i is muddy). World ``w`` is the bitmask of the muddy children
(bit i set iff ``m_i``), so the initial model has 2^N worlds. Child i sees every forehead but its own:
its partition label is the world index with bit i cleared, ``w & ~(1 << i)``.

The protocol (Fagin, Halpern, Moses, Vardi, *Reasoning about Knowledge*, §1.1):

1. the father announces ``⋁_i m_i`` ("at least one of you is muddy"): ``M | ⋁_i m_i``;
2. in every round each child says whether it knows whether it is muddy; the round is the public
   announcement of the conjunction of the true answers ``±Kw_i m_i`` at the actual world. While nobody
   knows this is ``⋀_i ¬Kw_i m_i`` ("nobody knows").

Literature answer: with M ≥ 1 muddy children, "nobody knows" is announced M − 1 times, the muddy children
know in round M and the clean ones in round M + 1 (after hearing the muddy children's answers).
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

import delkit.logic.semantics  # noqa: F401 - loaded before timing (KripkeModel.check imports it lazily)
from delkit.errors import ModelError
from delkit.logic.formula import Formula, Kw, Not, Prop, conj, disj
from delkit.models.kripke import KripkeModel
from delkit.models.relation import Relation

__all__ = ["MAX_EXPLICIT_CHILDREN", "MuddyResult", "muddy_model", "solve_muddy", "at_least_one", "nobody_knows",
           "run_rounds"]


MAX_EXPLICIT_CHILDREN = 22  # 2^22 worlds × 22 partition labels ≈ 0.8 GB


@dataclass(frozen=True)
class MuddyResult:
    """Outcome of one run of the muddy children protocol.

    ``nobody_knows_rounds`` is the number of "nobody knows" announcements before some child knows;
    ``muddy_know_round`` / ``clean_know_round`` are the first rounds (1-based) in which all muddy / all
    clean children know whether they are muddy (``None`` if there is no clean child); ``worlds`` is the
    number of worlds after each announcement (father's first).
    """

    children: int
    muddy: int
    nobody_knows_rounds: int
    muddy_know_round: int
    clean_know_round: int | None
    worlds: tuple[int, ...]
    seconds: float

    def as_dict(self) -> dict:
        return {"puzzle": "muddy", "children": self.children, "muddy": self.muddy,
                "nobody_knows_rounds": self.nobody_knows_rounds, "muddy_know_round": self.muddy_know_round,
                "clean_know_round": self.clean_know_round, "worlds": list(self.worlds),
                "seconds": self.seconds}


def _props(n: int) -> tuple[str, ...]:
    return tuple(f"m{i}" for i in range(n))


def _agents(n: int) -> tuple[str, ...]:
    return tuple(f"c{i}" for i in range(n))


def muddy_model(children: int, muddy: int) -> KripkeModel:
    """The initial S5 model: 2^N worlds (bitmasks), child i's partition ``w & ~(1<<i)``.

    The actual world has children 0 … muddy−1 muddy. Built without Python loops over worlds.
    """
    if children < 1:
        raise ModelError(f"muddy children: need at least one child, got {children}")
    if not 0 <= muddy <= children:
        raise ModelError(f"muddy children: muddy must be in 0..{children}, got {muddy}")
    if children > MAX_EXPLICIT_CHILDREN:
        raise ModelError(f"muddy children: {children} children means 2^{children} explicit worlds (at most "
                         f"{MAX_EXPLICIT_CHILDREN} children explicitly); use the BDD engine: `delkit puzzle muddy "
                         "--symbolic` or delkit.backends.symbolic.muddy_symbolic")
    w = np.arange(1 << children, dtype=np.int64)
    bits = np.int64(1) << np.arange(children, dtype=np.int64)
    valuation = (w[:, None] & bits[None, :]) != 0
    rels = {a: Relation(n=w.size, labels=w & ~bits[i]) for i, a in enumerate(_agents(children))}
    actual = (1 << muddy) - 1
    return KripkeModel(_props(children), _agents(children), valuation, rels, (actual,))


def at_least_one(children: int) -> Formula:
    """The father's announcement ⋁_i m_i."""
    return disj(Prop(p) for p in _props(children))


def nobody_knows(children: int) -> Formula:
    """⋀_i ¬Kw_{c_i} m_i: no child knows whether it is muddy."""
    return conj(Not(Kw(a, Prop(p))) for a, p in zip(_agents(children), _props(children), strict=True))


def run_rounds(state: Any, children: int, muddy: int, *, max_rounds: int | None = None,
               size: Callable[[Any], int] = len) -> tuple[Any, int, int, int | None, list[int]]:
    """The protocol after the father's announcement, on any structure with ``holds`` and ``announce``
    (a :class:`KripkeModel` or a :class:`delkit.backends.symbolic.KnowledgeStructure`).

    Returns the final state, the number of "nobody knows" rounds, the rounds in which all muddy / all
    clean children know, and ``size(state)`` after each announcement.
    """
    agents, props = _agents(children), _props(children)
    knows = [Kw(a, Prop(p)) for a, p in zip(agents, props, strict=True)]
    unknown = [Not(k) for k in knows]
    # one formula object per distinct answer vector (the "nobody knows" rounds repeat one): built and
    # hashed once, a structure-independent key for the engines' caches
    said: dict[tuple[bool, ...], Formula] = {}
    silent = (False,) * children
    nobody = said[silent] = conj(unknown)
    limit = max_rounds if max_rounds is not None else children + 2
    sizes: list[int] = []
    nobody_rounds = 0
    muddy_round: int | None = None
    clean_round: int | None = None
    for rnd in range(1, limit + 1):
        # "nobody knows" first, as one formula: one truth set per round (the announcement's own, cached by
        # the engine) instead of one per child; the children's answers one by one only when someone knows
        if state.holds(nobody):
            key = silent
        else:
            key = tuple([state.holds(k) for k in knows])  # children 0 … muddy-1 are the muddy ones
        if muddy_round is None and all(key[:muddy]):
            muddy_round = rnd
        if clean_round is None and muddy < children and all(key[muddy:]):
            clean_round = rnd
        if all(key):
            break
        if not any(key):
            nobody_rounds += 1
        # public announcement of every child's truthful answer
        announcement = said.get(key)
        if announcement is None:
            announcement = said[key] = conj(k if yes else n for k, n, yes in zip(knows, unknown, key, strict=True))
        state = state.announce(announcement)
        sizes.append(size(state))
    if muddy_round is None:
        raise ModelError(f"muddy children: no answer after {limit} rounds (raise max_rounds)")
    return state, nobody_rounds, muddy_round, clean_round, sizes


def solve_muddy(children: int, muddy: int, *, max_rounds: int | None = None) -> MuddyResult:
    """Run the protocol with the explicit engine (``KripkeModel.announce``) and time it."""
    if muddy < 1:
        raise ModelError("muddy children: the father's announcement needs at least one muddy child (--muddy >= 1)")
    t0 = time.perf_counter()
    model = muddy_model(children, muddy).announce(at_least_one(children))
    _, nobody, muddy_round, clean_round, sizes = run_rounds(model, children, muddy, max_rounds=max_rounds)
    return MuddyResult(children, muddy, nobody, muddy_round, clean_round, (model.n_worlds, *sizes),
                       time.perf_counter() - t0)
