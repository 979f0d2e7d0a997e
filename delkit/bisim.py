"""Bisimulation: coarsest bisimulation by partition refinement, contraction, canonical hashes.

Refinement starts from the partition by valuation and splits blocks by the *signature*
``(block(w), {block(v) : w R_a v} for each agent a)`` until nothing changes (a fixpoint — the coarsest
bisimulation, not the result of a single pass). Block numbers are *canonical*: at every round a block's
number is the rank of its signature among all signatures, and signatures only mention propositions and
earlier ranks, never world indices. Bisimilar worlds therefore get equal numbers, even in different
models with the same generated bisimulation classes, which gives a canonical form (and hash) of a
pointed model: the table of its classes with their valuations and successor classes, plus the classes
of its designated worlds.
"""

from __future__ import annotations

import hashlib
from collections.abc import Sequence

import numpy as np

from delkit.kripke import KripkeModel
from delkit.relation import Relation

__all__ = ["refine", "bisimulation_classes", "contract", "quotient", "bisimilar", "canonical_form", "canonical_hash",
           "disjoint_union"]


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
    from delkit.semantics import _components

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
