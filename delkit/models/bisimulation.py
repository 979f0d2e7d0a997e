"""Bisimulation of Kripke models (the explicit backend): partition refinement, contraction, canonical
forms and hashes, and distinguishing formulas.

**Refinement, contraction, canonical forms** (:func:`refine`, :func:`contract`, :func:`bisimilar`,
:func:`canonical_form`, :func:`canonical_hash`). Refinement starts from the partition by valuation and splits
blocks by the *signature* ``(block(w), {block(v) : w R_a v} for each agent a)`` until nothing changes (a
fixpoint — the coarsest bisimulation, not the result of a single pass). Block numbers are *canonical*: at
every round a block's number is the rank of its signature among all signatures, and signatures only mention
propositions and earlier ranks, never world indices. Bisimilar worlds therefore get equal numbers, even in
different models with the same generated bisimulation classes, which gives a canonical form (and hash) of a
pointed model: the table of its classes with their valuations and successor classes, plus the classes of its
designated worlds.

**Distinguishing formulas** (:func:`diff`, :func:`distinguishing_formula`): :func:`diff` compares two (multi-
pointed) models, :func:`distinguishing_formula` two pointed ones. Both run partition refinement on the
disjoint union and keep every round's partition:

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
is written ``~K_a ~χ`` (``show(f, diamonds=True)`` prints it ``M_a χ``). Multi-pointed models are compared by their
designated sets (as :func:`bisimilar`): they are bisimilar iff every designated world of each
has a bisimilar designated world in the other; otherwise the formula holds at every designated world of
one model and fails at a designated world of the other.

Symbolic structures (:class:`~delkit.backends.symbolic.KnowledgeStructure`,
:class:`~delkit.backends.symbolic_belief.BeliefStructure`) given to :func:`diff` are compared through their explicit
Kripke models (:func:`as_kripke`, refused above ``max_worlds`` states); the same refinement on BDDs, without
listing states, is :func:`delkit.backends.bisimulation_symbolic.symbolic_diff` (the symbolic backend).
"""

from __future__ import annotations

import hashlib
from collections.abc import Iterable, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from delkit.errors import ModelError
from delkit.logic.formula import BOT, TOP, Formula, K, Not, children, conj, disj, modal_depth, show
from delkit.models.kripke import KripkeModel
from delkit.models.relation import Relation

__all__ = ["refine", "bisimulation_classes", "contract", "quotient", "bisimilar", "canonical_form", "canonical_hash",
           "disjoint_union", "Diff", "diff", "distinguishing_formula", "refinement_history", "formula_size",
           "as_kripke", "MAX_WORLDS"]


def _successor_sets(rel: Relation, blocks: np.ndarray) -> list[tuple[int, ...]]:
    """For each world, the sorted tuple of blocks of its successors."""
    n = blocks.size
    if rel.labels is not None:
        lab = rel.labels
        # unique (class, block) pairs, then the set of blocks per class
        key = np.unique(lab.astype(np.int64) * (int(blocks.max(initial=0)) + 1) + blocks)
        base = int(blocks.max(initial=0)) + 1
        cls, blk = key // base, key % base
        per_class: dict[int, tuple[int, ...]] = {}
        if cls.size:
            splits = np.flatnonzero(np.diff(cls)) + 1
            for c_arr, b_arr in zip(np.split(cls, splits), np.split(blk, splits), strict=True):
                per_class[int(c_arr[0])] = tuple(int(b) for b in b_arr)
        return [per_class[int(c)] for c in lab]
    ptr, ind = rel.rows()  # numpy only (no scipy import)
    out: list[tuple[int, ...]] = []
    succ_blocks = blocks[ind]
    for w in range(n):
        seg = succ_blocks[ptr[w]:ptr[w + 1]]
        out.append(tuple(np.unique(seg).tolist()) if seg.size else ())
    return out


_M64 = np.uint64(0xFFFFFFFFFFFFFFFF)


def _mix(x: np.ndarray, salt: int) -> np.ndarray:
    """splitmix64 of ``x + salt``: a fixed, well-mixed 64-bit hash of block numbers (canonical, no state)."""
    with np.errstate(over="ignore"):
        z = x.astype(np.uint64) + np.uint64(salt)
        z = (z ^ (z >> np.uint64(30))) * np.uint64(0xBF58476D1CE4E5B9)
        z = (z ^ (z >> np.uint64(27))) * np.uint64(0x94D049BB133111EB)
        return z ^ (z >> np.uint64(31))


_SALTS = (0x9E3779B97F4A7C15, 0xD1B54A32D192ED03)


def _set_hashes(rel: Relation, blocks: np.ndarray) -> np.ndarray:
    """(n, 2) uint64: for each world, two independent 64-bit hashes of the *set* of its successors' blocks.

    A set hash is the sum (mod 2^64) of a fixed hash of each distinct block, so it depends only on the
    set of block numbers — never on world indices — and stays canonical. Two different sets collide with
    probability about 2^-128.
    """
    n = blocks.size
    out = np.zeros((n, 2), dtype=np.uint64)
    base = np.int64(int(blocks.max(initial=0)) + 1)
    if rel.labels is not None:
        lab = rel.labels
        key = np.unique(lab.astype(np.int64) * base + blocks)
        cls, blk = key // base, key % base
        k = int(lab.max(initial=-1)) + 1
        per = np.zeros((k, 2), dtype=np.uint64)
        for j, salt in enumerate(_SALTS):
            np.add.at(per[:, j], cls, _mix(blk, salt))
        return per[lab]
    indptr, indices = rel.rows()  # numpy only (no scipy import)
    rows = np.repeat(np.arange(n, dtype=np.int64), np.diff(indptr))
    key = np.unique(rows * base + blocks[indices])
    r, blk = key // base, key % base
    for j, salt in enumerate(_SALTS):
        np.add.at(out[:, j], r, _mix(blk, salt))
    # an empty successor set hashes to 0; a non-empty one almost surely not, but keep them apart exactly
    return out


def refine(model: KripkeModel, agents: Sequence[str] | None = None, *, exact: bool = False,
           history: list[np.ndarray] | None = None) -> np.ndarray:
    """Canonical block number of every world under the coarsest bisimulation (w.r.t. ``agents``).

    Partition refinement to the fixpoint. Each round, a world's signature is its block plus, per agent,
    the set of its successors' blocks; the new block number is the rank of the signature in sorted
    order. The default compares successor sets by 128-bit set hashes (fully vectorised);
    ``exact=True`` compares the sets themselves (tuples, slower) — tests check that both agree.
    ``history``, if given, receives the partition of every round up to the last one that split a block (round 0
    is the partition by valuation; the last entry is the coarsest bisimulation).
    """
    ags = list(model.agents if agents is None else agents)
    n = model.n_worlds
    if n == 0:
        if history is not None:
            history.append(np.zeros(0, dtype=np.int64))
        return np.zeros(0, dtype=np.int64)
    # round 0: rank of the valuation row (canonical: rows compared as bit strings)
    _, blocks = np.unique(model.valuation, axis=0, return_inverse=True)
    blocks = blocks.astype(np.int64).ravel()
    if history is not None:
        history.append(blocks)
    n_blocks = int(blocks.max()) + 1
    nonempty = [model.relations[a].has_successor() for a in ags]
    while True:
        if exact:
            succ = [_successor_sets(model.relations[a], blocks) for a in ags]
            sigs = [(int(blocks[w]), *(s[w] for s in succ)) for w in range(n)]
            uniq = sorted(set(sigs))
            rank = {s: i for i, s in enumerate(uniq)}
            new = np.fromiter((rank[s] for s in sigs), dtype=np.int64, count=n)
            count = len(uniq)
        else:
            cols = [blocks.astype(np.uint64)[:, None]]
            for a, ne in zip(ags, nonempty, strict=True):
                cols.append(_set_hashes(model.relations[a], blocks))
                cols.append(ne.astype(np.uint64)[:, None])
            sig = np.ascontiguousarray(np.hstack(cols))
            _, new = np.unique(sig, axis=0, return_inverse=True)
            new = new.astype(np.int64).ravel()
            count = int(new.max()) + 1
        if count == n_blocks:
            # no block split: the partition is stable (ranks are a monotone renaming of the old blocks)
            return new
        if history is not None:
            history.append(new)
        blocks, n_blocks = new, count


def bisimulation_classes(model: KripkeModel) -> list[list[int]]:
    """The classes of the coarsest bisimulation on ``model`` as lists of worlds."""
    blocks = refine(model)
    out: dict[int, list[int]] = {}
    for w, b in enumerate(blocks):
        out.setdefault(int(b), []).append(w)
    return [out[k] for k in sorted(out)]


def _quotient_labels(blocks: np.ndarray, labels: np.ndarray, k: int) -> np.ndarray:
    """Class of each block in the quotient of the partition ``labels`` by ``blocks`` (k blocks): the connected
    components of "same block or same class" (numpy min-label propagation; blocks that respect the relation
    settle it in two rounds, and no scipy import)."""
    from delkit.logic.semantics import _components

    comp = _components(int(blocks.size), [np.asarray(blocks, dtype=np.int64), labels])
    rep = np.zeros(k, dtype=np.int64)
    rep[blocks[::-1]] = np.arange(blocks.size)[::-1]
    return comp[rep]


def contract(model: KripkeModel, *, generated: bool = True) -> KripkeModel:
    """Bisimulation contraction: the quotient of (the designated-generated submodel of) ``model``.

    Worlds of the result are the bisimulation classes in canonical order; X R_a Y iff some w ∈ X and
    v ∈ Y have w R_a v. Partitions stay partitions. The result is bisimilar to the input and minimal.
    """
    m = model.generated() if generated else model
    return quotient(m, refine(m))


def quotient(m: KripkeModel, blocks: np.ndarray, *, keep_names: bool = False) -> KripkeModel:
    """The quotient of ``m`` by the partition ``blocks`` (world -> block, blocks numbered 0..k-1 in order of
    their least world, as :func:`refine` gives them): X R_a Y iff some w ∈ X and v ∈ Y have w R_a v.
    ``keep_names``: each block is named after its least world (else the worlds are unnamed)."""
    k = int(blocks.max()) + 1 if blocks.size else 0
    rep = np.zeros(k, dtype=np.int64)
    rep[blocks[::-1]] = np.arange(m.n_worlds)[::-1]  # first world of each block
    rels: dict[str, Relation] = {}
    for a, r in m.relations.items():
        if r.labels is not None:
            # X R Y iff some w ∈ X and v ∈ Y share a class. Because bisimulation classes respect R this
            # quotient is again an equivalence: the components of the bipartite block–class graph.
            rels[a] = Relation.from_labels(_quotient_labels(blocks, r.labels, k))
        else:
            indptr, indices = r.rows()
            src = np.repeat(np.arange(m.n_worlds, dtype=np.int64), np.diff(indptr))
            rels[a] = Relation.from_pairs(k, np.stack([blocks[src], blocks[indices]], axis=1))
    des = sorted({int(blocks[d]) for d in m.designated})
    names = tuple(m.names[int(r)] for r in rep) if keep_names and m.names else None
    return KripkeModel(m.props, m.agents, m.valuation[rep], rels, tuple(des), names)


def canonical_form(model: KripkeModel, *, generated: bool = True, exact: bool = False) -> tuple:
    """A hashable canonical form: equal for two pointed models iff they are bisimilar.

    (Provided both have the same propositions and agents.) It lists, for every bisimulation class of
    the generated submodel in canonical order, its valuation and its successor classes per agent (as
    128-bit set hashes, or as exact tuples with ``exact=True``), then the set of designated classes.
    """
    m = model.generated() if generated else model
    blocks = refine(m, exact=exact)
    k = int(blocks.max()) + 1 if blocks.size else 0
    rep = np.zeros(k, dtype=np.int64)
    rep[blocks[::-1]] = np.arange(m.n_worlds)[::-1]
    agents = sorted(m.agents)
    if exact:
        succ = {a: _successor_sets(m.relations[a], blocks) for a in agents}
        table = tuple((m.valuation[rep[b]].tobytes(), tuple(succ[a][rep[b]] for a in agents)) for b in range(k))
    else:
        parts = [np.packbits(m.valuation[rep], axis=1).view(np.uint8)]
        for a in agents:
            rel = m.relations[a]
            parts.append(_set_hashes(rel, blocks)[rep].view(np.uint8))
            parts.append(rel.has_successor()[rep].astype(np.uint8)[:, None])
        table = np.hstack(parts).tobytes() if k else b""
    des = tuple(sorted({int(blocks[d]) for d in m.designated}))
    return (tuple(m.props), tuple(agents), k, table, des)


def canonical_hash(model: KripkeModel, *, generated: bool = True) -> str:
    """SHA-256 hex digest of :func:`canonical_form`; bisimilar pointed models get equal hashes."""
    return hashlib.sha256(repr(canonical_form(model, generated=generated)).encode()).hexdigest()


def disjoint_union(a: KripkeModel, b: KripkeModel) -> tuple[KripkeModel, int]:
    """Disjoint union (worlds of ``b`` shifted by ``len(a)``); designated = both. Returns (model, offset)."""
    if a.props != b.props or set(a.agents) != set(b.agents):
        if set(a.props) != set(b.props) or set(a.agents) != set(b.agents):
            from delkit.errors import ModelError

            raise ModelError("disjoint union needs the same propositions and agents")
        b = _reorder_props(b, a.props)
    off = a.n_worlds
    val = np.vstack([a.valuation, b.valuation])
    rels = {}
    for ag in a.agents:
        ra, rb = a.relations[ag], b.relations[ag]
        if ra.labels is not None and rb.labels is not None:
            rels[ag] = Relation.from_labels(np.concatenate([ra.labels, rb.labels + int(ra.labels.max(initial=-1)) + 1]))
        else:
            import scipy.sparse as sp

            rels[ag] = Relation.from_matrix(sp.block_diag([ra.to_matrix(), rb.to_matrix()], format="csr"))
    des = tuple(a.designated) + tuple(d + off for d in b.designated)
    return KripkeModel(a.props, a.agents, val, rels, des), off


def _reorder_props(m: KripkeModel, props: tuple[str, ...]) -> KripkeModel:
    idx = [m.props.index(p) for p in props]
    return KripkeModel(props, m.agents, m.valuation[:, idx], m.relations, m.designated, m.names)


def bisimilar(a: KripkeModel, b: KripkeModel) -> bool:
    """Are the pointed models (a, a.designated) and (b, b.designated) bisimilar?

    Multi-pointed: every designated world of each has a bisimilar designated world in the other.
    """
    if set(a.props) != set(b.props) or set(a.agents) != set(b.agents):
        return False
    u, off = disjoint_union(a, b)
    blocks = refine(u)
    da = {int(blocks[d]) for d in a.designated}
    db = {int(blocks[d + off]) for d in b.designated}
    return da == db


# ============================================================================================ distinguishing formulas

MAX_WORLDS = 4096  # explicit translation of symbolic structures is refused above this many states


def formula_size(f: Formula) -> int:
    """Number of nodes of the formula tree (atoms, connectives and modalities)."""
    return 1 + sum(formula_size(c) for c in children(f))


def refinement_history(model: KripkeModel) -> list[np.ndarray]:
    """The partition of every refinement round (block number per world), until it is stable.

    Round 0 is the partition by valuation; the last entry is the coarsest bisimulation.
    """
    history: list[np.ndarray] = []
    # the hashed signatures (128-bit set hashes; tests check they agree with exact=True): the exact tuples cost
    # O(worlds × class size), hours on the explicit model of a 16-variable structure
    refine(model, sorted(model.agents), exact=False, history=history)
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
        from delkit.logic.formula import Prop

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
    :mod:`delkit.backends.bisimulation_symbolic`)."""
    if diamond:
        return Not(K(a, _negate(chi))) if chi != TOP else Not(K(a, BOT))
    return K(a, _negate(chi))


@dataclass(frozen=True)
class Diff:
    """Result of :func:`diff`.

    ``bisimilar``: whether the (multi-)pointed models are bisimilar. If they are, ``relation`` is the
    largest bisimulation between the parts generated by the designated worlds, as pairs (world of A,
    world of B). Otherwise ``formula`` holds at every designated world of the model ``true_in`` ("A" or
    "B") and fails at the designated world ``fails_at`` of the other one. ``explanation``: (what, formula
    text) lines describing sets of states as readable formulas (symbolic structures: ``form_of``).
    """

    bisimilar: bool
    relation: tuple[tuple[int, int], ...] = ()
    formula: Formula | None = None
    true_in: str | None = None
    fails_at: int | None = None
    names: tuple[tuple[str, ...], tuple[str, ...]] = ((), ())
    explanation: tuple[tuple[str, str], ...] = ()

    def as_dict(self) -> dict[str, Any]:
        na, nb = self.names
        extra = {"explanation": dict(self.explanation)} if self.explanation else {}
        if self.bisimilar:
            return {"bisimilar": True, "relation": [[na[x], nb[y]] for x, y in self.relation]} | extra
        other = "B" if self.true_in == "A" else "A"
        names = nb if self.true_in == "A" else na
        return {"bisimilar": False, "formula": show(self.formula), "true_in": self.true_in, "false_in": other,
                "fails_at": names[self.fails_at], "modal_depth": modal_depth(self.formula),
                "size": formula_size(self.formula)} | extra


def _union(a: KripkeModel, b: KripkeModel, props: Sequence[str] | None) -> tuple[KripkeModel, int]:
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
        # the pairs of reachable worlds in one class, by sorting (a loop over all pairs is quadratic: hours on
        # the explicit model of a 16-variable structure); the order is (x, then y) ascending as before
        cb = final[reach_b + off]
        order = np.argsort(cb, kind="stable")
        cb_sorted = cb[order]
        ca = final[reach_a]
        lo, hi = np.searchsorted(cb_sorted, ca, "left"), np.searchsorted(cb_sorted, ca, "right")
        pairs = tuple((int(x), int(reach_b[order[j]])) for x, lo_x, hi_x in zip(reach_a, lo, hi, strict=True)
                      for j in range(lo_x, hi_x))
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
