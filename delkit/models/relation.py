"""Accessibility relations over worlds 0..n-1, for Kripke and event models alike.

A relation is stored either as a *partition* (an equivalence relation, S5: one integer label per world,
two worlds related iff their labels are equal) or as a sparse boolean matrix (K, KD45: row w holds
the successors of w). Partitions keep every operation linear in the number of worlds; matrices are used
as soon as a relation is not an equivalence (e.g. after a private announcement).
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass
from typing import Any

import numpy as np

from delkit._lazy import lazy_module
from delkit.errors import ModelError

sp = lazy_module("scipy.sparse")  # imported on first use (start-up time)

__all__ = ["Relation", "RelationError"]


class RelationError(ModelError, ValueError):
    """A relation given with worlds outside 0..n-1 or with overlapping blocks (also a ``ValueError``)."""


def _check_points(n: int, points: np.ndarray, what: str) -> None:
    """Every point must be a world 0..n-1 (a negative index would silently wrap around in numpy)."""
    bad = points[(points < 0) | (points >= n)]
    if bad.size:
        raise RelationError(f"{what}: world {int(bad[0])} out of range 0..{n - 1} (the model has {n} world(s))")


@dataclass(frozen=True, eq=False)
class Relation:
    """An accessibility relation on ``n`` points, as a partition (``labels``) or a CSR matrix."""

    n: int
    labels: np.ndarray | None = None
    _csr: Any = None  # the CSR matrix (built on first use when the relation came from pairs)
    _rows: Any = None  # (indptr, indices) of the CSR form, computed with numpy only (no scipy import)

    @property
    def matrix(self) -> sp.csr_matrix | None:
        """The relation as a CSR boolean matrix (None for a partition: see :meth:`to_matrix`)."""
        if self._csr is None and self._rows is not None:
            indptr, indices = self._rows
            m = sp.csr_matrix((np.ones(indices.size, dtype=bool), indices, indptr), shape=(self.n, self.n))
            object.__setattr__(self, "_csr", m)
        return self._csr

    # ------------------------------------------------------------------ constructors
    @staticmethod
    def from_labels(labels: Iterable[int] | np.ndarray) -> Relation:
        """Equivalence relation: points with equal labels are related (labels are renumbered 0..k-1)."""
        arr = np.asarray(labels, dtype=np.int64).ravel()
        if arr.size:
            _, arr = np.unique(arr, return_inverse=True)
        return Relation(n=int(arr.size), labels=arr.astype(np.int64))

    @staticmethod
    def from_blocks(n: int, blocks: Iterable[Iterable[int]]) -> Relation:
        """Equivalence relation from its classes; points not in any block form singleton classes."""
        labels = np.full(n, -1, dtype=np.int64)
        k = 0
        for block in blocks:
            block = list(block)
            _check_points(n, np.asarray(block, dtype=np.int64), f"block #{k}")
            for w in block:
                if labels[w] != -1:
                    raise RelationError(f"world {w} is in two blocks (#{labels[w]} and #{k}); an S5 relation "
                                        f"is a partition: put each world in one block")
                labels[w] = k
            k += 1
        missing = np.flatnonzero(labels == -1)
        labels[missing] = np.arange(k, k + missing.size)
        return Relation.from_labels(labels)

    @staticmethod
    def from_pairs(n: int, pairs: Iterable[tuple[int, int]]) -> Relation:
        """Arbitrary relation from (source, target) pairs."""
        arr = np.asarray(list(pairs), dtype=np.int64).reshape(-1, 2)
        _check_points(n, arr.ravel(), "relation pair")
        # sorted, duplicate-free CSR rows in numpy: scipy is imported only if the matrix itself is used
        keys = np.sort(arr[:, 0] * max(n, 1) + arr[:, 1])
        keys = keys[np.concatenate(([True], keys[1:] != keys[:-1]))] if keys.size else keys  # np.unique: numpy.ma
        src, dst = np.divmod(keys, max(n, 1))
        indptr = np.searchsorted(src, np.arange(n + 1)).astype(np.int64)
        return Relation(n=n, _rows=(indptr, dst.astype(np.int64)))

    @staticmethod
    def from_matrix(m: sp.spmatrix | np.ndarray) -> Relation:
        mat = sp.csr_matrix(m, dtype=bool)
        mat.eliminate_zeros()
        mat.sum_duplicates()
        mat.sort_indices()
        return Relation(n=mat.shape[0], _csr=mat)

    @staticmethod
    def identity(n: int) -> Relation:
        return Relation(n=n, labels=np.arange(n, dtype=np.int64))

    @staticmethod
    def total(n: int) -> Relation:
        return Relation(n=n, labels=np.zeros(n, dtype=np.int64))

    # ------------------------------------------------------------------ views
    @property
    def is_partition(self) -> bool:
        return self.labels is not None

    def to_matrix(self) -> sp.csr_matrix:
        """The relation as a CSR boolean matrix (built once for partitions, then cached)."""
        if self.matrix is not None:
            return self.matrix
        cached = self.__dict__.get("_matrix")
        if cached is None:
            lab = self.labels
            order = np.argsort(lab, kind="stable")
            counts = np.bincount(lab)
            starts = np.concatenate([[0], np.cumsum(counts)])
            rows, cols = [], []
            # group members: pair all members of each class (vectorised by class size)
            for size in np.unique(counts):
                cls = np.flatnonzero(counts == size)
                if size == 0:
                    continue
                members = order[(starts[cls][:, None] + np.arange(size)[None, :])]  # (c, size)
                rows.append(np.repeat(members, size, axis=1).ravel())
                cols.append(np.tile(members, (1, size)).ravel())
            r = np.concatenate(rows) if rows else np.zeros(0, dtype=np.int64)
            c = np.concatenate(cols) if cols else np.zeros(0, dtype=np.int64)
            cached = sp.csr_matrix((np.ones(r.size, dtype=bool), (r, c)), shape=(self.n, self.n), dtype=bool)
            cached.sort_indices()
            object.__setattr__(self, "_matrix", cached)
        return cached

    def rows(self) -> tuple[np.ndarray, np.ndarray]:
        """(indptr, indices) of the CSR form, sorted rows, computed with numpy only (partitions included)."""
        if self._csr is not None:
            return self._csr.indptr, self._csr.indices
        if self._rows is not None:
            return self._rows
        cached = self.__dict__.get("_label_rows")
        if cached is None:
            lab = self.labels
            order = np.argsort(lab, kind="stable")
            counts = np.bincount(lab) if lab.size else np.zeros(0, dtype=np.int64)
            starts = np.concatenate([[0], np.cumsum(counts)]).astype(np.int64)
            deg = counts[lab]
            indptr = np.concatenate([[0], np.cumsum(deg)]).astype(np.int64)
            off = np.arange(int(indptr[-1]), dtype=np.int64) - np.repeat(indptr[:-1], deg)
            cached = (indptr, order[np.repeat(starts[lab], deg) + off].astype(np.int64))
            object.__setattr__(self, "_label_rows", cached)
        return cached

    def successors(self, w: int) -> np.ndarray:
        if self.labels is not None:
            return np.flatnonzero(self.labels == self.labels[w])
        if self._csr is None and self._rows is not None:
            indptr, indices = self._rows
            return indices[indptr[w]:indptr[w + 1]].copy()
        m = self.matrix
        return m.indices[m.indptr[w]:m.indptr[w + 1]].copy()

    def pairs(self) -> np.ndarray:
        m = self.to_matrix().tocoo()
        return np.stack([m.row, m.col], axis=1)

    def box(self, truth: np.ndarray) -> np.ndarray:
        """Vector of worlds all of whose successors satisfy ``truth`` (the modal box)."""
        truth = np.asarray(truth, dtype=bool)
        if self.labels is not None:
            bad = np.bincount(self.labels[~truth], minlength=int(self.labels.max(initial=-1)) + 1)
            return bad[self.labels] == 0
        indptr, indices = self.rows()  # numpy only: no scipy import for a replay of small models
        cs = np.concatenate(([0], np.cumsum(~truth[indices], dtype=np.int64)))
        return cs[indptr[1:]] == cs[indptr[:-1]]

    def diamond(self, truth: np.ndarray) -> np.ndarray:
        """Vector of worlds with at least one successor satisfying ``truth``."""
        return ~self.box(~np.asarray(truth, dtype=bool))

    def has_successor(self) -> np.ndarray:
        if self.labels is not None:
            return np.ones(self.n, dtype=bool)
        return np.diff(self.rows()[0]) > 0

    # ------------------------------------------------------------------ transformations
    def restrict(self, keep: np.ndarray) -> Relation:
        """Relation on the points ``keep`` (an index array, in that order)."""
        keep = np.asarray(keep, dtype=np.int64)
        if self.labels is not None:
            # labels stay as they are (not renumbered): they only need to be equal within a class and
            # bounded by the original size, which keeps restriction a single gather
            return Relation(n=int(keep.size), labels=self.labels[keep])
        # numpy only: the kept rows, their targets renumbered, targets outside ``keep`` dropped
        indptr, indices = self.rows()
        new = np.full(self.n, -1, dtype=np.int64)
        new[keep] = np.arange(keep.size, dtype=np.int64)
        deg = indptr[keep + 1] - indptr[keep]
        off = np.arange(int(deg.sum()), dtype=np.int64) - np.repeat(np.cumsum(deg) - deg, deg)
        tgt = new[indices[np.repeat(indptr[keep], deg) + off]]
        src = np.repeat(np.arange(keep.size, dtype=np.int64), deg)
        ok = tgt >= 0
        flat = np.sort(src[ok] * max(keep.size, 1) + tgt[ok])
        src, tgt = np.divmod(flat, max(keep.size, 1))
        return Relation(n=int(keep.size), _rows=(np.searchsorted(src, np.arange(keep.size + 1)).astype(np.int64),
                                                 tgt.astype(np.int64)))

    def product(self, other: Relation, pairs: np.ndarray) -> Relation:
        """Relation on pairs (w, e): (w,e) ~ (v,f) iff w ~self v and e ~other f; ``pairs`` is (k, 2)."""
        w, e = pairs[:, 0], pairs[:, 1]
        if self.labels is not None and other.labels is not None:
            base = int(other.labels.max(initial=-1)) + 1
            return Relation.from_labels(self.labels[w] * base + other.labels[e])
        # numpy only: for each new world i = (w_i, e_i) the candidates (v, f) with w_i R v and e_i R' f, kept
        # where (v, f) is a new world (binary search in the sorted keys of ``pairs``)
        k, ne = int(pairs.shape[0]), max(other.n, 1)
        if k == 0:
            return Relation(n=0, _rows=(np.zeros(1, dtype=np.int64), np.zeros(0, dtype=np.int64)))
        ipa, ixa = self.rows()
        ipb, ixb = other.rows()
        db = ipb[e + 1] - ipb[e]
        cnt = (ipa[w + 1] - ipa[w]) * db
        off = np.arange(int(cnt.sum()), dtype=np.int64) - np.repeat(np.cumsum(cnt) - cnt, cnt)
        dbr = np.maximum(np.repeat(db, cnt), 1)
        q = ixa[np.repeat(ipa[w], cnt) + off // dbr] * ne + ixb[np.repeat(ipb[e], cnt) + off % dbr]
        keys = w.astype(np.int64) * ne + e
        order = np.argsort(keys, kind="stable")
        sk = keys[order]
        pos = np.minimum(np.searchsorted(sk, q), k - 1)
        hit = sk[pos] == q
        flat = np.sort(np.repeat(np.arange(k, dtype=np.int64), cnt)[hit] * k + order[pos[hit]])
        src, dst = np.divmod(flat, k)
        return Relation(n=k, _rows=(np.searchsorted(src, np.arange(k + 1)).astype(np.int64), dst.astype(np.int64)))

    def intersect(self, other: Relation) -> Relation:
        if self.labels is not None and other.labels is not None:
            base = int(other.labels.max(initial=-1)) + 1
            return Relation.from_labels(self.labels * base + other.labels)
        return Relation.from_matrix(self.to_matrix().multiply(other.to_matrix()))

    def union(self, others: Iterable[Relation]) -> Relation:
        """The union with ``others`` (numpy only)."""
        parts = [self, *others]
        src, dst = [], []
        for r in parts:
            indptr, indices = r.rows()
            src.append(np.repeat(np.arange(self.n, dtype=np.int64), np.diff(indptr)))
            dst.append(indices.astype(np.int64))
        n = max(self.n, 1)
        flat = np.sort(np.concatenate(src) * n + np.concatenate(dst))
        flat = flat[np.concatenate(([True], flat[1:] != flat[:-1]))] if flat.size else flat  # no numpy.ma
        s, d = np.divmod(flat, n)
        return Relation(n=self.n, _rows=(np.searchsorted(s, np.arange(self.n + 1)).astype(np.int64), d))

    def union_matrix(self, others: Iterable[Relation]) -> sp.csr_matrix:
        m = self.to_matrix().astype(np.int8)
        for o in others:
            m = m + o.to_matrix().astype(np.int8)
        return sp.csr_matrix(m > 0)

    # ------------------------------------------------------------------ frame properties
    def is_reflexive(self) -> bool:
        if self.labels is not None:
            return True
        return bool(self.matrix.diagonal().all()) if self.n else True

    def is_serial(self) -> bool:
        return bool(self.has_successor().all())

    def is_transitive(self) -> bool:
        if self.labels is not None:
            return True
        m = self.matrix.astype(np.int32)
        two = (m @ m) > 0
        return (two > self.matrix).nnz == 0

    def is_euclidean(self) -> bool:
        """w R v and w R u imply v R u, i.e. R^T R ⊆ R."""
        if self.labels is not None:
            return True
        m = self.matrix.astype(np.int32)
        two = (m.T @ m) > 0
        return (two > self.matrix).nnz == 0

    def is_symmetric(self) -> bool:
        if self.labels is not None:
            return True
        return (self.matrix != self.matrix.T).nnz == 0

    def as_partition(self) -> Relation:
        """The same relation stored as a partition, if it is an equivalence (else ``self``)."""
        if self.labels is not None or not (self.is_reflexive() and self.is_symmetric() and self.is_transitive()):
            return self
        from scipy.sparse.csgraph import connected_components

        _, lab = connected_components(self.matrix, directed=False)
        return Relation.from_labels(lab)

    def equals(self, other: Relation) -> bool:
        if self.n != other.n:
            return False
        if self.labels is not None and other.labels is not None:
            # same partition iff the label pairs are in bijection
            pairs = np.unique(np.stack([self.labels, other.labels], 1), axis=0)
            return len(pairs) == len(np.unique(self.labels)) == len(np.unique(other.labels))
        return (self.to_matrix() != other.to_matrix()).nnz == 0
