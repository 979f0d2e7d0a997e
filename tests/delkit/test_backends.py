"""Differential tests of delkit's backends in one place: numpy (KripkeModel) ≡ compact (bit sets) ≡ BDDs.

Each property draws random models (S5, KD45, K; single- and multi-pointed), formulas and event models and
asks every backend the same question: truth of a formula, bisimilarity (canonical keys), and the product
update followed by contraction. The numpy backend is the reference.
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from delkit.backends.compact import CompactEngine
from delkit.errors import ModelError
from delkit.logic.formula import D, Not, subformulas
from delkit.models.bisimulation import bisimilar, contract
from delkit.models.kripke import KripkeModel
from delkit.models.relation import Relation
from delkit.models.update import product_update
from delkit.testing import event_models, formulas, kripke_models

P, A = ("p", "q"), ("a", "b")
ENGINE = CompactEngine(P, A)
FRAMES = st.sampled_from(["S5", "KD45", "K"])


def _no_group_d(f) -> bool:
    """D of a group of ≥ 2 agents is not bisimulation-invariant: contracted backends may not preserve it."""
    return not any(isinstance(g, D) and len(g.group) > 1 for g in subformulas(f))


def _models(frame: str, designated: str = "some", max_worlds: int = 5):
    return kripke_models(P, A, max_worlds, frame=frame, designated=designated)


@settings(max_examples=120, deadline=None)
@given(data=st.data(), frame=FRAMES, f=formulas(P, A, 3, allow_dynamic=True).filter(_no_group_d))
def test_truth_compact_equals_numpy(data, frame, f) -> None:
    """φ holds in every designated world: the same answer on both backends (after the compact backend's
    contraction, so this also checks that contraction preserves every formula of the language but group D)."""
    m = data.draw(_models(frame))
    s = ENGINE.from_kripke(m)
    assert ENGINE.holds(s, f) == m.holds(f)
    # per world, through the round trip to an explicit model
    back = ENGINE.to_kripke(s)
    assert bisimilar(back, m)


@settings(max_examples=100, deadline=None)
@given(data=st.data(), frame=FRAMES)
def test_key_equal_iff_bisimilar(data, frame) -> None:
    m1 = data.draw(_models(frame, max_worlds=4))
    m2 = data.draw(_models(frame, max_worlds=4))
    k1, k2 = ENGINE.from_kripke(m1).key, ENGINE.from_kripke(m2).key
    assert (k1 == k2) == bisimilar(m1, m2)
    assert k1 == ENGINE.from_kripke(contract(m1)).key


@settings(max_examples=150, deadline=None)
@given(data=st.data(), frame=FRAMES, eframe=st.sampled_from(["S5", "KD45", "K", "mA*"]))
def test_update_compact_equals_numpy(data, frame, eframe) -> None:
    """apply(s, E) ≅ contract(M ⊗ E) for general event models (several designated events, any relations),
    on multi-pointed models; None exactly when some designated world has no designated event possible."""
    m = data.draw(_models(frame, max_worlds=4))
    em = data.draw(event_models(P, A, 3, frame=eframe))
    checked = _check_update(ENGINE, m, em)
    if checked is None:
        return
    new, ref = checked
    f = data.draw(formulas(P, A, 2).filter(_no_group_d))
    assert ENGINE.holds(new, f) == ref.holds(f)
    assert sorted(ENGINE.inconsistent(new)) == sorted({ag for ag, _ in ref.inconsistent_agents()})


def _check_update(engine: CompactEngine, m: KripkeModel, em):
    """apply(s, E) is None exactly when some designated world has no designated event possible, else it is
    bisimilar to M ⊗ E with the same key; returns (compact result, reference) in that case, else None."""
    new = engine.apply(engine.from_kripke(m), em)
    ref = product_update(m, em)
    covered = {int(w) for w in m.designated if any(m.check(em.pre[e])[int(w)] for e in em.designated)}
    if covered != {int(w) for w in m.designated}:
        assert new is None
        return None
    assert new is not None
    assert bisimilar(engine.to_kripke(new), ref)
    assert new.key == engine.from_kripke(ref).key
    return new, ref


@settings(max_examples=100, deadline=None)
@given(data=st.data(), frame=FRAMES, eframe=st.sampled_from(["S5", "KD45", "K", "mA*"]))
def test_update_through_the_shape_cache_equals_numpy(data, frame, eframe) -> None:
    """One event model applied to several models of one frame (valuations redrawn, so preconditions and
    postconditions come out differently): after the first application the engine answers from its cache of
    transition shapes whenever the frame, the precondition pattern and the order of the new valuations
    repeat — every answer equal to the reference update."""
    engine = CompactEngine(P, A)  # fresh caches, filled by this example only
    m = data.draw(_models(frame, max_worlds=4))
    em = data.draw(event_models(P, A, 3, frame=eframe))
    for _ in range(8):
        bits = data.draw(st.lists(st.booleans(), min_size=m.valuation.size, max_size=m.valuation.size))
        val = np.array(bits, dtype=bool).reshape(m.valuation.shape)
        _check_update(engine, KripkeModel(P, A, val, m.relations, m.designated), em)


def test_shape_cache_hit_hand_checked() -> None:
    """Two states with one frame and the same order of valuations after the update share the cached shape
    (the very same relation tuples) and each has the reference result: a public ontic event q := ¬q on a
    two-world model where a cannot tell p and b can."""
    from delkit.logic.formula import Prop, Top
    from delkit.models.events import EventModel

    em = EventModel(("e",), A, (Top(),), ({"q": Not(Prop("q"))},), {a: Relation.identity(1) for a in A}, (0,),
                    "flip q")
    engine = CompactEngine(P, A)
    rel = {"a": Relation.from_labels([0, 0]), "b": Relation.identity(2)}
    m1 = KripkeModel(P, A, np.array([[True, False], [False, False]]), rel, (0,))
    m2 = KripkeModel(P, A, np.array([[True, True], [False, True]]), rel, (0,))
    n1 = engine.apply(engine.from_kripke(m1), em)
    n2 = engine.apply(engine.from_kripke(m2), em)
    assert n1 is not None and n2 is not None and n2.masks is n1.masks  # the second came from the cache
    for m, new in ((m1, n1), (m2, n2)):
        assert bisimilar(engine.to_kripke(new), product_update(m, em))
        assert len(new.val) == 2
    assert n1.val != n2.val


def test_shape_cache_tells_a_failed_precondition_from_a_small_valuation() -> None:
    """Same frame, same event (pre p, q := ⊤): in the first state the precondition fails at the world a
    cannot tell from the designated one (the result has one world), in the second it holds there and the new
    valuation is the smallest (two worlds). The shape key must not confuse "fails" with "smallest"."""
    from delkit.logic.formula import Prop, Top
    from delkit.models.events import EventModel

    p3, a2 = ("p", "q", "r"), ("a", "b")
    em = EventModel(("e",), a2, (Prop("p"),), ({"q": Top()},), {a: Relation.identity(1) for a in a2}, (0,), "set q")
    engine = CompactEngine(p3, a2)
    rel = {"a": Relation.from_labels([0, 0]), "b": Relation.identity(2)}
    first = KripkeModel(p3, a2, np.array([[False, False, False], [True, False, False]]), rel, (1,))
    second = KripkeModel(p3, a2, np.array([[True, False, False], [True, False, True]]), rel, (1,))
    sizes = []
    for m in (first, second):
        new = engine.apply(engine.from_kripke(m), em)
        assert new is not None and bisimilar(engine.to_kripke(new), product_update(m, em))
        sizes.append(new.n)
    assert sizes == [1, 2]


@settings(max_examples=60, deadline=None)
@given(data=st.data())
def test_truth_compact_equals_symbolic_on_s5(data) -> None:
    """The third backend: BDD knowledge structures agree with the compact one on S5 models."""
    from delkit.backends.symbolic import from_kripke

    m = data.draw(_models("S5", designated="one", max_worlds=4))
    f = data.draw(formulas(P, A, 2, allow_common=True).filter(_no_group_d))
    ks, states = from_kripke(m)
    assert ks.truth(f, states[m.designated[0]]) == ENGINE.holds(ENGINE.from_kripke(m), f)


# ----------------------------------------------------------------------------- collective bisimulation (group D)

G = ("a", "b")
GENGINE = CompactEngine(P, A, groups=[G])


def _naive_collective_bisimilar(m1, m2) -> bool:
    """Greatest fixpoint over world pairs, written out naively: same valuation and the zig/zag conditions for
    R_a, R_b and R_a ∩ R_b; multi-pointed: every designated world has a partner on the other side."""
    import numpy as np

    def rels(m):
        r = {a: [set(int(x) for x in m.relation(a).successors(w)) for w in range(m.n_worlds)] for a in A}
        r["ab"] = [r["a"][w] & r["b"][w] for w in range(m.n_worlds)]
        return r

    r1, r2 = rels(m1), rels(m2)
    z = {(u, v) for u in range(m1.n_worlds) for v in range(m2.n_worlds)
         if np.array_equal(m1.valuation[u], m2.valuation[v])}
    while True:
        keep = {(u, v) for (u, v) in z
                if all(all(any((x, y) in z for y in r2[k][v]) for x in r1[k][u])
                       and all(any((x, y) in z for x in r1[k][u]) for y in r2[k][v]) for k in r1)}
        if keep == z:
            break
        z = keep
    return (all(any((u, v) in z for v in m2.designated) for u in m1.designated)
            and all(any((u, v) in z for u in m1.designated) for v in m2.designated))


def test_group_d_hand_checked() -> None:
    """w0 (p) sees itself and w1 for a, itself and w2 for b; w1, w2 (¬p) only themselves. D_{a,b} p holds at
    w0 (R_a ∩ R_b = {w0}), K_a p and K_b p do not. w1 and w2 are bisimilar, so a plain contraction merges them
    and its quotient has R_a ∩ R_b = {w0, w1w2}: D_{a,b} p would become false. Collective bisimulation merges
    them too but keeps R_{ab} = {(w0, w0), ...} as a relation of its own, so D_{a,b} p stays true."""
    from delkit.logic.formula import parse

    m = KripkeModel.build([{"p"}, set(), set()], {"a": {"pairs": [(0, 0), (0, 1), (1, 1), (2, 2)]},
                                                    "b": {"pairs": [(0, 0), (0, 2), (1, 1), (2, 2)]}},
                          designated=[0])
    d = parse("D{a,b} p")
    assert m.holds(d) and not m.holds(parse("K_a p | K_b p"))
    assert not contract(m).holds(d)  # plain contraction loses it: why the planner needs the group relation
    s = GENGINE.from_kripke(m)
    assert GENGINE.holds(s, d) and s.n == 2
    assert ENGINE.from_kripke(m).n == 2
    with pytest.raises(ModelError, match="declare the group"):
        ENGINE.holds(ENGINE.from_kripke(m), d)


@settings(max_examples=100, deadline=None)
@given(data=st.data(), frame=FRAMES)
def test_collective_key_iff_naive_collective_bisimilar(data, frame) -> None:
    m1 = data.draw(_models(frame, max_worlds=4))
    m2 = data.draw(_models(frame, max_worlds=4))
    assert (GENGINE.from_kripke(m1).key == GENGINE.from_kripke(m2).key) == _naive_collective_bisimilar(m1, m2)


@settings(max_examples=120, deadline=None)
@given(data=st.data(), frame=FRAMES, f=formulas(P, A, 3))
def test_group_d_truth_and_update_with_collective_contraction(data, frame, f) -> None:
    """Every formula, group D included, has the same truth on the numpy model and on the collective
    compact state — before and after an update."""
    m = data.draw(_models(frame, max_worlds=4))
    s = GENGINE.from_kripke(m)
    fs = (f, D(G, f), Not(D(G, Not(f))))
    assert [GENGINE.holds(s, g) for g in fs] == [m.holds(g) for g in fs]
    em = data.draw(event_models(P, A, 3, frame="K"))
    new = GENGINE.apply(s, em)
    ref = product_update(m, em)
    if new is not None and ref.designated:
        assert [GENGINE.holds(new, g) for g in fs] == [ref.holds(g) for g in fs]
