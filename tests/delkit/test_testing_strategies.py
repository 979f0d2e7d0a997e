"""The strategies of delkit.testing generate what they promise (frames, depths, symbols)."""

from __future__ import annotations

import itertools

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from delkit import Announce, Update
from delkit.logic.formula import agents_of, is_propositional, modal_depth, props_of, subformulas
from delkit.models.relation import Relation
from delkit.testing import (
    event_models,
    formulas,
    kd45_relation,
    kripke_models,
    pointed_models,
    propositional_formulas,
    relations,
)

CFG = settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])


def depth(f) -> int:
    from delkit.logic.formula import children

    return 1 + max((depth(c) for c in children(f)), default=-1)


@CFG
@given(formulas(["p", "q"], ["a", "b"], 3, allow_announce=True))
def test_formulas_respect_depth_and_symbols(f):
    assert depth(f) <= 3
    assert props_of(f) <= {"p", "q"} and agents_of(f) <= {"a", "b"}


@CFG
@given(formulas(["p"], ["a", "b"], 3, allow_common=False, allow_dynamic=True))
def test_formulas_without_common_knowledge_and_with_updates(f):
    assert not any(type(g).__name__ == "C" for g in subformulas(f))
    for g in subformulas(f):
        if isinstance(g, Update):
            assert all(is_propositional(p) for p in g.model.pre)


@CFG
@given(propositional_formulas(["p", "q", "r"], 3))
def test_propositional_formulas_are_propositional(f):
    assert is_propositional(f) and modal_depth(f) == 0


def test_formulas_reach_every_operator():
    seen: set[str] = set()

    @settings(max_examples=300, deadline=None, database=None)
    @given(formulas(["p"], ["a", "b"], 2, allow_announce=True, allow_dynamic=True))
    def collect(f):
        seen.update(type(g).__name__ for g in subformulas(f))

    collect()
    assert {"Prop", "Not", "And", "Or", "Implies", "Iff", "K", "Kw", "E", "C", "D", "Announce", "Update"} <= seen


@CFG
@given(st.sampled_from(["S5", "KD45", "K"]).flatmap(
    lambda fr: st.tuples(st.just(fr), kripke_models(["p"], ["a", "b"], 5, frame=fr, designated="some"))))
def test_models_are_in_their_frame_class(frame_model):
    frame, m = frame_model
    assert not m.frame_violations(frame)
    assert 1 <= m.n_worlds <= 5 and m.designated
    if frame == "S5":
        assert all(r.is_partition for r in m.relations.values())


@CFG
@given(pointed_models(["p", "q"], ["a"], 4, frame="KD45"))
def test_pointed_models_have_one_designated_world(m):
    assert len(m.designated) == 1 and m.is_kd45()


def brute_force_kd45(n: int) -> set[bytes]:
    out = set()
    for bits in itertools.product([False, True], repeat=n * n):
        r = Relation.from_matrix(np.array(bits, dtype=bool).reshape(n, n))
        if r.is_serial() and r.is_transitive() and r.is_euclidean():
            out.add(np.array(bits, dtype=bool).tobytes())
    return out


@pytest.mark.parametrize("n", [1, 2, 3])
def test_kd45_construction_yields_exactly_the_kd45_relations(n):
    made = set()
    for cluster in itertools.product(range(n), repeat=n):
        for believed in itertools.product([False, True], repeat=n):
            r = kd45_relation(cluster, believed)
            assert r.is_serial() and r.is_transitive() and r.is_euclidean()
            made.add(r.to_matrix().toarray().astype(bool).tobytes())
    assert made == brute_force_kd45(n)  # surjective: every KD45 relation can be generated


@CFG
@given(relations(4, "K"))
def test_k_relations_are_arbitrary_matrices(r):
    assert r.n == 4 and not r.is_partition


@CFG
@given(st.sampled_from(["S5", "KD45"]).flatmap(
    lambda fr: st.tuples(st.just(fr), event_models(["p", "q"], ["a", "b"], 3, frame=fr))))
def test_event_models(frame_model):
    frame, e = frame_model
    assert 1 <= e.n_events <= 3 and e.designated
    assert all(is_propositional(p) for p in e.pre)
    assert all(is_propositional(v) and k in ("p", "q") for post in e.post for k, v in post.items())
    for r in e.relations.values():
        if frame == "S5":
            assert r.is_partition
        else:
            assert r.is_serial() and r.is_transitive() and r.is_euclidean()


def test_bad_arguments():
    with pytest.raises(ValueError, match="unknown frame"):
        kripke_models(["p"], ["a"], frame="S4")
    with pytest.raises(ValueError, match="designated"):
        kripke_models(["p"], ["a"], designated="two")
    with pytest.raises(ValueError, match="at least one proposition"):
        formulas([], ["a"])


def test_announce_is_only_generated_when_allowed():
    @settings(max_examples=100, deadline=None, database=None)
    @given(formulas(["p"], ["a"], 3))
    def check(f):
        assert not any(isinstance(g, (Announce, Update)) for g in subformulas(f))

    check()


@CFG
@given(event_models(["p", "q"], ["a", "b", "c"], 2, frame="mA*"))
def test_ma_star_event_models_follow_the_observability_frames(e):
    real = [i for i, n in enumerate(e.events) if n != "eps"]
    assert 1 <= len(real) <= 2 and e.designated == tuple(real)
    for a in e.agents:
        r = e.relation(a)
        assert r.is_serial() and r.is_transitive() and r.is_euclidean()  # KD45 (S5 without oblivious)
        if "eps" in e.events and not r.is_partition:  # oblivious: every event points to eps only
            eps = e.events.index("eps")
            assert all(list(r.successors(i)) == [eps] for i in range(e.n_events))
