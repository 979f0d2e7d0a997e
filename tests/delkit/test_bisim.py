"""The vectorised (set-hash) refinement agrees with the exact tuple refinement, on random models."""

from __future__ import annotations

import numpy as np
import pytest

from delkit import KripkeModel, bisimilar, canonical_hash, contract
from delkit.models.bisimulation import canonical_form, refine
from delkit.models.relation import Relation


def random_model(rng: np.random.Generator, n: int, kind: str) -> KripkeModel:
    val = rng.random((n, 2)) < 0.5
    rels = {}
    for a in ("a", "b"):
        if kind == "S5":
            rels[a] = Relation.from_labels(rng.integers(0, max(1, n // 2), n))
        else:
            rels[a] = Relation.from_matrix(rng.random((n, n)) < 2.0 / n)
    return KripkeModel(("p", "q"), ("a", "b"), val, rels, (0,))


def same_partition(x: np.ndarray, y: np.ndarray) -> bool:
    return len(np.unique(np.stack([x, y], 1), axis=0)) == len(np.unique(x)) == len(np.unique(y))


@pytest.mark.parametrize("kind", ["S5", "K"])
def test_hashed_refinement_equals_exact(kind):
    rng = np.random.default_rng(7)
    for _ in range(60):
        m = random_model(rng, int(rng.integers(1, 25)), kind)
        fast, exact = refine(m), refine(m, exact=True)
        assert same_partition(fast, exact)
        # and the numbering is canonical in both: a permuted copy gets the same numbers per world
        perm = rng.permutation(m.n_worlds)
        pm = m.restrict(perm).with_designated([int(np.flatnonzero(perm == 0)[0])])
        assert np.array_equal(refine(pm), fast[perm])
        assert canonical_form(pm, exact=True) == canonical_form(m, exact=True)
        assert canonical_hash(pm) == canonical_hash(m)


def test_contraction_is_minimal_and_bisimilar():
    rng = np.random.default_rng(3)
    for _ in range(40):
        m = random_model(rng, int(rng.integers(1, 20)), "K")
        c = contract(m)
        assert bisimilar(c, m)
        assert contract(c).n_worlds == c.n_worlds
        assert len(np.unique(refine(c))) == c.n_worlds  # no two worlds of c are bisimilar

