"""Distinguishing formulas: bisimilar, with the bisimulation, or a modal formula that tells two models apart.

:func:`diff` compares two (multi-pointed) models, :func:`distinguishing_formula` two pointed ones. Both run
partition refinement on the disjoint union and keep every round's partition:

* round 0 splits worlds by valuation;
* round k+1 splits a block by the agents' successor blocks of round k.

Two worlds that end in different blocks are told apart by a formula built from the round in which they
were split (the construction behind the Hennessy–Milner theorem; Cleaveland, *On automatically explaining
bisimulation inequivalence*, CAV 1990):

* split in round 0: a literal whose value differs;
* split in round k+1 by agent a: x has a successor x' whose round-k block no successor of y has (then
  ``◇_a χ`` with χ true at x' and false at every successor of y), or the other way round (then ``K_a ¬χ``
  with χ true at that successor of y and false at every successor of x). χ is a conjunction of
  round-≤k formulas chosen greedily (each conjunct rules out as many of the remaining successors as
  possible), and among the candidate agents/successors the smallest formula is kept.

So the formula has the least modal depth that can separate the two worlds, and a small size. ``◇_a χ``
is written ``~K_a ~χ`` (delkit's formulas have no diamond). Multi-pointed models are compared by their
designated sets (as :func:`delkit.bisim.bisimilar`): they are bisimilar iff every designated world of each
has a bisimilar designated world in the other; otherwise the formula holds at every designated world of
one model and fails at a designated world of the other.

Symbolic structures (:class:`~delkit.symbolic.KnowledgeStructure`,
:class:`~delkit.symbolic_belief.BeliefStructure`) given to :func:`diff` are compared through their explicit
Kripke models (:func:`as_kripke`, refused above ``max_worlds`` states); the same refinement on BDDs, without
listing states, is :func:`delkit.bisimulation_symbolic.symbolic_diff`.
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from delkit.errors import ModelError
from delkit.formula import BOT, TOP, Formula, K, Not, children, conj, disj, modal_depth, show
from delkit.kripke import KripkeModel

__all__ = ["Diff", "diff", "distinguishing_formula", "refinement_history", "formula_size", "as_kripke",
           "MAX_WORLDS"]

MAX_WORLDS = 4096  # explicit translation of symbolic structures is refused above this many states


def formula_size(f: Formula) -> int:
    """Number of nodes of the formula tree (atoms, connectives and modalities)."""
    return 1 + sum(formula_size(c) for c in children(f))


def refinement_history(model: KripkeModel) -> list[np.ndarray]:
    """The partition of every refinement round (block number per world), until it is stable.

    Round 0 is the partition by valuation; the last entry is the coarsest bisimulation.
    """
    from delkit.bisim import refine

    history: list[np.ndarray] = []
    refine(model, sorted(model.agents), exact=True, history=history)
    return history


@dataclass
class _Explainer:
    """Distinguishing formulas between worlds of one model, memoised per pair."""

    model: KripkeModel
    history: list[np.ndarray]
    _memo: dict = field(default_factory=dict)
    _succ: dict = field(default_factory=dict)

    def level(self, x: int, y: int) -> int | None:
        """First round in which x and y are in different blocks (None: bisimilar)."""
        for k, blocks in enumerate(self.history):
            if blocks[x] != blocks[y]:
                return k
        return None

    def successors(self, a: str, w: int) -> list[int]:
        key = (a, w)
        hit = self._succ.get(key)
        if hit is None:
            hit = self._succ[key] = [int(v) for v in self.model.relations[a].successors(w)]
        return hit

    def formula(self, x: int, y: int) -> tuple[Formula, np.ndarray]:
        """(φ, truth vector of φ over the model) with φ true at x and false at y."""
        key = (x, y)
        hit = self._memo.get(key)
        if hit is not None:
            return hit
        k = self.level(x, y)
        if k is None:
            raise ValueError(f"worlds {x} and {y} are bisimilar")
        hit = self._literal(x, y) if k == 0 else self._modal(x, y, k)
        self._memo[key] = hit
        return hit

    def _literal(self, x: int, y: int) -> tuple[Formula, np.ndarray]:
        from delkit.formula import Prop

        val = self.model.valuation
        j = int(np.flatnonzero(val[x] != val[y])[0])
        p = Prop(self.model.props[j])
        return (p, val[:, j].copy()) if val[x, j] else (Not(p), ~val[:, j])

    def _cover(self, keep: int, avoid: list[int]) -> tuple[Formula, np.ndarray]:
        """A conjunction true at ``keep`` and false at every world of ``avoid`` (greedy set cover)."""
        parts = _greedy(avoid, lambda z: self.formula(keep, z), wanted=False)
        truth = np.ones(self.model.n_worlds, dtype=bool)
        for _, vec in parts:
            truth = truth & vec
        return conj([f for f, _ in parts]), truth

    def _modal(self, x: int, y: int, k: int) -> tuple[Formula, np.ndarray]:
        prev = self.history[k - 1]
        best: tuple[int, Formula, np.ndarray] | None = None
        for a in sorted(self.model.agents):
            rel = self.model.relations[a]
            sx, sy = self.successors(a, x), self.successors(a, y)
            bx, by = {int(prev[v]) for v in sx}, {int(prev[v]) for v in sy}
            # x sees a block y does not: <>_a chi, chi true there and false at all of y's successors
            for src, avoid, blocks_other, diamond in ((sx, sy, by, True), (sy, sx, bx, False)):
                tried = set()
                for v in src:
                    if int(prev[v]) in blocks_other or int(prev[v]) in tried or len(tried) >= 3:
                        continue
                    tried.add(int(prev[v]))
                    chi, chi_vec = self._cover(v, avoid)
                    f = split_formula(a, chi, diamond)
                    vec = rel.diamond(chi_vec) if diamond else rel.box(~chi_vec)
                    size = formula_size(f)
                    if best is None or size < best[0]:
                        best = (size, f, vec)
        if best is None:  # cannot happen: the blocks were split by some agent's successor blocks
            raise AssertionError(f"no agent splits worlds {x} and {y} in round {k}")
        return best[1], best[2]


def _negate(f: Formula) -> Formula:
    return f.arg if isinstance(f, Not) else Not(f)


def split_formula(a: str, chi: Formula, diamond: bool) -> Formula:
    """The modal step of a distinguishing formula: ``◇_a χ`` written ``¬K_a ¬χ`` (``¬K_a ⊥`` for χ = ⊤) when
    the world it must hold at sees a χ-world the other does not, else ``K_a ¬χ`` (shared with
    :mod:`delkit.bisimulation_symbolic`)."""
    if diamond:
        return Not(K(a, _negate(chi))) if chi != TOP else Not(K(a, BOT))
    return K(a, _negate(chi))


@dataclass(frozen=True)
class Diff:
    """Result of :func:`diff`.

    ``bisimilar``: whether the (multi-)pointed models are bisimilar. If they are, ``relation`` is the
    largest bisimulation between the parts generated by the designated worlds, as pairs (world of A,
    world of B). Otherwise ``formula`` holds at every designated world of the model ``true_in`` ("A" or
    "B") and fails at the designated world ``fails_at`` of the other one.
    """

    bisimilar: bool
    relation: tuple[tuple[int, int], ...] = ()
    formula: Formula | None = None
    true_in: str | None = None
    fails_at: int | None = None
    names: tuple[tuple[str, ...], tuple[str, ...]] = ((), ())

    def as_dict(self) -> dict[str, Any]:
        na, nb = self.names
        if self.bisimilar:
            return {"bisimilar": True, "relation": [[na[x], nb[y]] for x, y in self.relation]}
        other = "B" if self.true_in == "A" else "A"
        names = nb if self.true_in == "A" else na
        return {"bisimilar": False, "formula": show(self.formula), "true_in": self.true_in, "false_in": other,
                "fails_at": names[self.fails_at], "modal_depth": modal_depth(self.formula),
                "size": formula_size(self.formula)}


def _union(a: KripkeModel, b: KripkeModel, props: Sequence[str] | None) -> tuple[KripkeModel, int]:
    from delkit.bisim import disjoint_union

    if props is not None:
        a, b = _only(a, props, "A"), _only(b, props, "B")
    if set(a.agents) != set(b.agents):
        raise ModelError(f"the models have different agents ({sorted(a.agents)} vs {sorted(b.agents)}); "
                         "bisimulation compares models over the same agents")
    if set(a.props) != set(b.props):
        raise ModelError(f"the models have different propositions ({sorted(a.props)} vs {sorted(b.props)}); "
                         "compare them on common ones with props=[...] (CLI: --props p,q)")
    return disjoint_union(a, b)


def _only(m: KripkeModel, props: Sequence[str], which: str) -> KripkeModel:
    missing = sorted(set(props) - set(m.props))
    if missing:
        raise ModelError(f"model {which} has no proposition(s) {missing} (it has {list(m.props)})")
    idx = [m.props.index(p) for p in props]
    return KripkeModel(tuple(props), m.agents, m.valuation[:, idx], m.relations, m.designated, m.names)


def _names(m: KripkeModel) -> tuple[str, ...]:
    return tuple(m.world_name(w) for w in range(m.n_worlds))


def diff(a: Any, b: Any, *, props: Sequence[str] | None = None, max_worlds: int = MAX_WORLDS) -> Diff:
    """Compare two multi-pointed models (Kripke models or symbolic structures) by their designated worlds.

    ``props`` restricts the comparison to these propositions (both models must have them).
    """
    a, b = as_kripke(a, max_worlds=max_worlds, which="A"), as_kripke(b, max_worlds=max_worlds, which="B")
    if not a.designated or not b.designated:
        raise ModelError("both models need designated worlds to be compared")
    u, off = _union(a, b, props)
    history = refinement_history(u)
    final = history[-1]
    da = {int(final[d]): d for d in a.designated}
    db = {int(final[d + off]): d for d in b.designated}
    names = (_names(a), _names(b))
    if set(da) == set(db):
        reach_a = np.flatnonzero(a.reachable())
        reach_b = np.flatnonzero(b.reachable())
        pairs = tuple((int(x), int(y)) for x in reach_a for y in reach_b if final[x] == final[y + off])
        return Diff(True, relation=pairs, names=names)
    ex = _Explainer(u, history)
    # prefer a formula true in A: a designated world of B that no designated world of A matches
    missing_b = [d for c, d in sorted(db.items()) if c not in da]
    if missing_b:
        e = missing_b[0] + off
        f = _best(ex, [d for d in a.designated], e)
        return Diff(False, formula=f, true_in="A", fails_at=e - off, names=names)
    missing_a = [d for c, d in sorted(da.items()) if c not in db]
    d = missing_a[0]
    f = _best(ex, [e + off for e in b.designated], d)
    return Diff(False, formula=f, true_in="B", fails_at=d, names=names)


def _best(ex: _Explainer, keep: list[int], avoid: int) -> Formula:
    """A formula true at every world of ``keep`` and false at ``avoid``: a greedy disjunction of
    distinguishing formulas, or (one world to keep) the smaller of φ(keep, avoid) and ¬φ(avoid, keep)."""
    if len(keep) == 1:
        f1, _ = ex.formula(keep[0], avoid)
        f2 = _negate(ex.formula(avoid, keep[0])[0])
        return f1 if formula_size(f1) <= formula_size(f2) else f2
    return disj([f for f, _ in _greedy(keep, lambda x: ex.formula(x, avoid), wanted=True)])


def _greedy(worlds: Iterable[int], candidate: Any, *, wanted: bool) -> list[tuple[Formula, np.ndarray]]:
    """Greedy set cover: formulas ``candidate(z)`` for z among ``worlds`` until every world has a chosen
    formula whose truth there is ``wanted`` (each step takes the one covering most; ties: the smaller)."""
    left = set(worlds)
    parts = []
    while left:
        best = None
        for z in sorted(left):
            f, vec = candidate(z)
            gain = sum(1 for u in left if bool(vec[u]) == wanted)
            score = (-gain, formula_size(f))
            if best is None or score < best[0]:
                best = (score, f, vec)
        (neg_gain, _), f, vec = best
        if neg_gain == 0:  # cannot happen: candidate(z) has the wanted truth value at z
            raise AssertionError(f"no formula covers worlds {sorted(left)}")
        parts.append((f, vec))
        left = {u for u in left if bool(vec[u]) != wanted}
    return parts


def distinguishing_formula(m1: Any, w1: int | Iterable[int], m2: Any, w2: int | Iterable[int], *,
                           props: Sequence[str] | None = None, max_worlds: int = MAX_WORLDS) -> Formula | None:
    """A formula true at (m1, w1) and false at (m2, w2), or None if the pointed models are bisimilar.

    ``w1``/``w2`` are world indices (or sets of them: then the formula holds at every world of ``w1`` and
    fails at some world of ``w2``; None also when every world of ``w2`` is bisimilar to one of ``w1``).
    Symbolic structures are pointed by state indices of :func:`as_kripke`.
    """
    a = as_kripke(m1, max_worlds=max_worlds, which="A").with_designated(_points(w1))
    b = as_kripke(m2, max_worlds=max_worlds, which="B").with_designated(_points(w2))
    res = diff(a, b, props=props)
    # with sets of worlds, true_in == "B" means every world of w2 is matched in w1: no formula true at all
    # of w1 can then fail in w2
    return res.formula if not res.bisimilar and res.true_in == "A" else None


def _points(w: int | Iterable[int]) -> tuple[int, ...]:
    return (int(w),) if isinstance(w, (int, np.integer)) else tuple(int(x) for x in w)


def as_kripke(obj: Any, *, max_worlds: int = MAX_WORLDS, which: str = "") -> KripkeModel:
    """A Kripke model as it is; a knowledge or belief structure as its explicit model (one world per state,
    designated = the actual states, propositions = the vocabulary), refused above ``max_worlds`` states."""
    if isinstance(obj, KripkeModel):
        return obj
    if hasattr(obj, "to_kripke") and hasattr(obj, "count_states"):
        n = obj.count_states()
        if n > max_worlds:
            label = f"structure {which}" if which else "the structure"
            raise ModelError(f"{label} has {n} states, more than the {max_worlds} that the explicit comparison "
                             "accepts (the refinement is explicit); raise the limit (CLI: --max-worlds) if it "
                             "fits in memory")
        return obj.to_kripke()
    raise ModelError(f"cannot compare a {type(obj).__name__}: give a KripkeModel, a KnowledgeStructure or a "
                     "BeliefStructure")
