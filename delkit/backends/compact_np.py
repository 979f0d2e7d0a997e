"""The compact backend's partition refinement vectorised with numpy, for products with many worlds.

:func:`refine` computes exactly what :func:`delkit.backends.compact._refine` computes — the coarsest bisimulation of
a model given by valuations and successor lists, its blocks numbered canonically, the quotient's
valuations, successor masks and designated blocks — so the states it builds have the very keys and records
of the pure-Python path (a state found on one path is a duplicate of the same state found on the other).

The canonical numbering is the pure-Python one: round 0 ranks the valuations; every round ranks the
signatures (block, per relation the *set* of successor blocks), sets ordered as the bit masks the Python
path builds (an int mask compares by its highest differing bit: the sets' members in descending order,
lexicographically, a proper prefix first). Here a set is a row of its members in descending order padded
with -1, rows are ranked lexicographically by successive stable int64 rankings of their columns, and a
signature is the tuple of those ranks — the same order, hence the same ranks, as the Python tuples of ints.

numpy is imported by this module only; :mod:`delkit.backends.compact` imports it only for products above
:data:`delkit.backends.compact.NP_REFINE_MIN` worlds (small tasks never load numpy: ``tests/cli/test_startup.py``).
"""

from __future__ import annotations

from collections.abc import Sequence
from itertools import chain

import numpy as np

__all__ = ["refine"]


def _ranks(cols: Sequence[np.ndarray]) -> tuple[np.ndarray, int]:
    """Dense ranks (0..r-1) of the rows of the columns ``cols`` (int64, equal lengths) in lexicographic
    order, and r: one lexicographic sort, equal neighbours share a rank."""
    if len(cols) == 1:
        return _dense(cols[0])
    m = np.stack(cols, axis=1)
    order = np.lexsort(m.T[::-1])
    srt = m[order]
    step = np.empty(len(order), dtype=np.int64)
    if len(order):
        step[0] = 0
        step[1:] = np.any(srt[1:] != srt[:-1], axis=1)
    r = np.empty(len(order), dtype=np.int64)
    r[order] = np.cumsum(step)
    return r, int(r.max()) + 1 if len(r) else 0


def _dense(x: np.ndarray) -> tuple[np.ndarray, int]:
    u, inv = np.unique(x, return_inverse=True)
    return inv.astype(np.int64, copy=False).reshape(-1), len(u)


class _Lists:
    """One relation's distinct successor lists as flat arrays: members and the list of each member."""

    __slots__ = ("n_lists", "members", "owner", "cls")

    def __init__(self, lists: Sequence[Sequence[int]], cls: Sequence[int]) -> None:
        lens = np.fromiter(map(len, lists), dtype=np.int64, count=len(lists))
        total = int(lens.sum())
        self.n_lists = len(lists)
        self.members = np.fromiter(chain.from_iterable(lists), dtype=np.int64, count=total)
        self.owner = np.repeat(np.arange(len(lists), dtype=np.int64), lens)
        self.cls = np.asarray(cls, dtype=np.int64)

    def block_sets(self, blk: np.ndarray, nb: int) -> tuple[np.ndarray, np.ndarray]:
        """The distinct (list, block) pairs, sorted by list then block: (lists, blocks)."""
        if not len(self.members):
            e = np.zeros(0, dtype=np.int64)
            return e, e
        u = np.unique(self.owner * nb + blk[self.members])
        return u // nb, u % nb

    def set_ranks(self, ul: np.ndarray, ub: np.ndarray) -> np.ndarray:
        """Per list, the rank of its block set in the order of the Python path's int masks."""
        n_lists = self.n_lists
        counts = np.bincount(ul, minlength=n_lists)
        width = int(counts.max()) if n_lists else 0
        if width == 0:
            return np.zeros(n_lists, dtype=np.int64)
        start = np.zeros(n_lists, dtype=np.int64)
        np.cumsum(counts[:-1], out=start[1:])
        pos = counts[ul] - 1 - (np.arange(len(ul), dtype=np.int64) - start[ul])  # descending within a list
        rows = np.zeros((n_lists, width), dtype=np.int64)  # block + 1, 0 = padding (below every block)
        rows[ul, pos] = ub + 1
        return _ranks([rows[:, j] for j in range(width)])[0]


def refine(val: Sequence[int], dist: Sequence[Sequence[Sequence[int]]], cls: Sequence[Sequence[int]],
           points: Sequence[int]) -> tuple[list[int], list[int], tuple, tuple[int, ...]] | None:
    """:func:`delkit.backends.compact._refine` on numpy arrays: (block of each world, valuation of each block,
    successor masks per relation and block, designated blocks) — equal to it; None when a valuation does
    not fit in 63 bits (the caller refines in Python)."""
    n = len(val)
    if max(val) >= 1 << 62 or min(val) < 0:
        return None
    v = np.asarray(val, dtype=np.int64)
    blk, nb = _dense(v)
    rels = [_Lists(d, c) for d, c in zip(dist, cls, strict=True)]
    while True:
        sets = [r.block_sets(blk, nb) for r in rels]
        cols = [blk] + [r.set_ranks(ul, ub)[r.cls] for r, (ul, ub) in zip(rels, sets, strict=True)]
        nblk, count = _ranks(cols)
        if count == nb:
            break
        blk, nb = nblk, count
    # stable: block b's signature is (b, its successor sets), the quotient's relations in canonical order
    rep = np.full(nb, n, dtype=np.int64)
    np.minimum.at(rep, blk, np.arange(n, dtype=np.int64))
    cval = v[rep].tolist()
    masks = []
    for r, (ul, ub) in zip(rels, sets, strict=True):
        lm = _list_masks(r.n_lists, ul, ub, nb)
        masks.append(tuple(lm[i] for i in r.cls[rep].tolist()))
    blk_l = blk.tolist()
    cps = tuple(sorted({blk_l[p] for p in points}))
    return blk_l, cval, tuple(masks), cps


def _list_masks(n_lists: int, ul: np.ndarray, ub: np.ndarray, nb: int) -> list[int]:
    """Per list, its block set as a Python int bit mask."""
    if nb <= 62:
        m = np.zeros(n_lists, dtype=np.int64)
        np.bitwise_or.at(m, ul, np.left_shift(1, ub))
        return m.tolist()
    member = np.zeros((n_lists, nb), dtype=bool)
    member[ul, ub] = True
    packed = np.packbits(member, axis=1, bitorder="little")
    return [int.from_bytes(row.tobytes(), "little") for row in packed]

