"""The numpy-only relation operations (a plan check must not pay scipy's import) agree with the
scipy sparse-matrix formulas they replace, on random relations and partitions."""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp
from hypothesis import given, settings
from hypothesis import strategies as st

from delkit.models.relation import Relation


@st.composite
def relations(draw, n: int | None = None):
    n = draw(st.integers(1, 7)) if n is None else n
    if draw(st.booleans()):
        return Relation.from_labels(draw(st.lists(st.integers(0, 3), min_size=n, max_size=n)))
    pairs = draw(st.lists(st.tuples(st.integers(0, n - 1), st.integers(0, n - 1)), max_size=3 * n))
    return Relation.from_pairs(n, pairs)


def dense(r: Relation) -> np.ndarray:
    return r.to_matrix().toarray().astype(bool)


@settings(max_examples=200, deadline=None)
@given(st.data())
def test_product_restrict_union_box_agree_with_the_matrix_formulas(data):
    a = data.draw(relations())
    b = data.draw(relations())
    n, m = a.n, b.n
    app = np.array(data.draw(st.lists(st.booleans(), min_size=n * m, max_size=n * m)), dtype=bool).reshape(n, m)
    w, e = np.nonzero(app)
    pairs = np.stack([w, e], axis=1).astype(np.int64)
    if data.draw(st.booleans()):  # product does not rely on the pairs being sorted
        pairs = pairs[data.draw(st.permutations(list(range(len(pairs)))))] if len(pairs) else pairs
    if a.labels is None or b.labels is None:
        w, e = pairs[:, 0], pairs[:, 1]
        want = (sp.csr_matrix(dense(a))[w][:, w].multiply(sp.csr_matrix(dense(b))[e][:, e])).toarray().astype(bool)
        assert np.array_equal(dense(a.product(b, pairs)), want)
    keep = np.array(sorted(set(data.draw(st.lists(st.integers(0, n - 1), max_size=n)))), dtype=np.int64)
    assert np.array_equal(dense(a.restrict(keep)), dense(a)[np.ix_(keep, keep)])
    c = data.draw(relations(n))
    assert np.array_equal(dense(a.union([c])), dense(a) | dense(c))
    truth = np.array(data.draw(st.lists(st.booleans(), min_size=n, max_size=n)), dtype=bool)
    assert np.array_equal(a.box(truth), ~(dense(a) & ~truth[None, :]).any(axis=1))
    assert np.array_equal(a.has_successor(), dense(a).any(axis=1))
