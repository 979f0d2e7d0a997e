"""The compact backend's product constructions against each other and against the numpy reference.

``CompactEngine.apply_compiled`` builds s ⊗ E pair by pair (``_pair_product``) or, for an event model with a
skip event ε (mA*'s oblivious agents), on the other events only, sharing the old state's successor lists
for the copy (``_copy_product``). Both must give the very same canonical state (valuations, relations,
designated worlds — what keys and the parallel search's records are made of), and that state must be
bisimilar to ``delkit.models.update.product_update``'s.
"""

from __future__ import annotations

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

import delkit.backends.compact as compact
from delkit.backends.compact import CompactEngine
from delkit.logic.formula import Top
from delkit.models.bisimulation import bisimilar
from delkit.models.events import EventModel
from delkit.models.relation import Relation
from delkit.models.update import product_update
from delkit.testing import event_models, kripke_models

P, A = ("p", "q", "r"), ("a", "b", "c")


def _both(m, em):
    """(result with the copy product, result pair by pair) of a fresh engine each (no shared caches)."""
    e1 = CompactEngine(P, A)
    s1 = e1.from_kripke(m)
    r1 = e1.apply(s1, em)
    e2 = CompactEngine(P, A)
    s2 = e2.from_kripke(m)
    comp = e2.compile(em)
    r2 = e2.apply_compiled(s2, comp[:11] + (None,))  # no skip event: pair by pair
    return e1, e1.compile(em)[11], r1, r2


def _same(r1, r2) -> None:
    assert (r1 is None) == (r2 is None)
    if r1 is not None:
        assert (r1.val, r1.masks, r1.points) == (r2.val, r2.masks, r2.points)
        assert r1.key == r2.key


@settings(max_examples=200, deadline=None)
@given(data=st.data(), frame=st.sampled_from(["S5", "KD45", "K"]))
def test_copy_product_equals_pair_product_and_reference(data, frame) -> None:
    m = data.draw(kripke_models(P, A, 5, frame=frame, designated="some"))
    em = data.draw(event_models(P, A, 3, frame="mA*"))
    engine, copy, r1, r2 = _both(m, em)
    _same(r1, r2)
    assert (copy is not None) == ("eps" in em.events)
    if r1 is not None:
        assert bisimilar(engine.to_kripke(r1), product_update(m, em))


@settings(max_examples=100, deadline=None)
@given(data=st.data(), frame=st.sampled_from(["S5", "KD45", "K"]))
def test_skip_event_in_a_general_event_model(data, frame) -> None:
    """A random event model extended by a skip event that some events reach for some agents (besides
    other events: successor lists that mix copy worlds and new pairs), on K/KD45 models too, where the
    copy may generate only part of the old state (then its worlds are renumbered)."""
    m = data.draw(kripke_models(P, A, 5, frame=frame, designated="some"))
    base = data.draw(event_models(P, A, 3, frame="K"))
    k = base.n_events
    rels = {}
    for a in A:
        pairs = [(e, f) for e in range(k) for f in base.relations[a].successors(e)]
        pairs += [(e, k) for e in range(k) if data.draw(st.booleans())]
        pairs.append((k, k))
        rels[a] = Relation.from_pairs(k + 1, pairs)
    em = EventModel(base.events + ("skip",), A, base.pre + (Top(),), base.post + ({},), rels, base.designated,
                    "with skip")
    engine, copy, r1, r2 = _both(m, em)
    assert copy is not None and copy[0] == k
    _same(r1, r2)
    if r1 is not None:
        assert bisimilar(engine.to_kripke(r1), product_update(m, em))


def test_copy_product_is_taken_on_mastar_announcements() -> None:
    """An announcement with an oblivious agent on an S5 model: the copy product answers (not the pair one)."""
    from delkit.logic.formula import Prop
    from delkit.models.events import action
    from delkit.models.kripke import KripkeModel

    val = np.array([[True, False, False], [False, False, False], [True, True, False], [False, True, True]])
    rels = {"a": Relation.from_labels([0, 0, 1, 1]), "b": Relation.from_labels([0, 1, 0, 1]),
            "c": Relation.from_labels([0, 0, 0, 0])}
    m = KripkeModel(P, A, val, rels, (0,))
    em = action(A, [("yes", Prop("p"), {}), ("no", ~Prop("p"), {})], full=["a", "b"], designated=["yes"])
    calls = []
    real = compact._copy_product

    def spy(*args):
        out = real(*args)
        calls.append(out is not None)
        return out

    compact._copy_product = spy
    try:
        engine, copy, r1, r2 = _both(m, em)
    finally:
        compact._copy_product = real
    assert calls == [True]
    _same(r1, r2)
    assert bisimilar(engine.to_kripke(r1), product_update(m, em))


def test_copy_of_part_of_the_state_after_an_oblivious_update() -> None:
    """After an announcement that c does not observe, c's beliefs at the designated world point into the
    old copy: a second such announcement reaches a copy of only part of the state (its worlds are
    renumbered, and the copy is kept on the state for the next action that reaches it). Both results equal
    the pair-by-pair construction and the reference, along random chains of such updates."""
    from delkit.logic.formula import Prop
    from delkit.models.events import action
    from delkit.models.kripke import KripkeModel

    val = np.array([[True, False, False], [False, False, False], [True, True, False], [False, True, True]])
    rels = {"a": Relation.from_labels([0, 0, 1, 1]), "b": Relation.from_labels([0, 1, 0, 1]),
            "c": Relation.from_labels([0, 0, 0, 0])}
    m = KripkeModel(P, A, val, rels, (0,))
    tell_p = action(A, [("yes", Prop("p"), {}), ("no", ~Prop("p"), {})], full=["a", "b"], designated=["yes"])
    tell_nq = action(A, [("yes", ~Prop("q"), {}), ("no", Prop("q"), {})], full=["b"], partial=["a"],
                     designated=["yes"])
    e1, e2 = CompactEngine(P, A), CompactEngine(P, A)
    s1, s2 = e1.from_kripke(m), e2.from_kripke(m)
    used = []
    for em in (tell_p, tell_nq, tell_p):
        n1 = e1.apply(s1, em)
        n2 = e2.apply_compiled(s2, e2.compile(em)[:11] + (None,))
        _same(n1, n2)
        used.append(bool(s1.copies))
        m = product_update(m, em)
        assert bisimilar(e1.to_kripke(n1), m)
        s1, s2 = n1, n2
    assert used == [False, True, True]


@settings(max_examples=80, deadline=None)
@given(data=st.data(), frame=st.sampled_from(["S5", "KD45", "K"]))
def test_chains_of_oblivious_updates(data, frame) -> None:
    """Random chains of mA* updates (from S5 models the states become KD45; the copy often covers part of
    the state only): the copy construction, the pair-by-pair one and the reference agree at every step;
    and so does the shape cache, asked for a twin state (the same frame, valuations redrawn) right after."""
    from delkit.backends.compact import CompactState

    m = data.draw(kripke_models(P, A, 4, frame=frame, designated="one"))
    e1, e2 = CompactEngine(P, A), CompactEngine(P, A)
    s1, s2 = e1.from_kripke(m), e2.from_kripke(m)
    for _ in range(data.draw(st.integers(1, 4))):
        em = data.draw(event_models(P, A, 2, frame="mA*", postconditions=data.draw(st.booleans())))
        n1 = e1.apply(s1, em)
        n2 = e2.apply_compiled(s2, e2.compile(em)[:11] + (None,))
        _same(n1, n2)
        again = CompactState(s1.val, s1.masks, s1.points, s1.fid)  # the same state anew: from the shape cache
        _same(e1.apply(again, em), n2)
        twin_val = tuple(data.draw(st.lists(st.integers(0, 7), min_size=s1.n, max_size=s1.n)))
        twin = CompactState(twin_val, s1.masks, s1.points, s1.fid)  # same frame: the shape cache may answer
        t1 = e1.apply(twin, em)
        e3 = CompactEngine(P, A)
        t2 = e3.apply_compiled(twin, e3.compile(em)[:11] + (None,))
        _same(t1, t2)
        if t1 is not None:
            assert bisimilar(e1.to_kripke(t1), product_update(e1.to_kripke(twin), em))
        if n1 is None:
            break
        m = product_update(m, em)
        assert bisimilar(e1.to_kripke(n1), m)
        s1, s2 = n1, n2


def test_copy_reached_through_a_successor_set_no_world_of_the_copy_has() -> None:
    """K frame: c's successors of the designated w0 are {w1, w2}, but inside the copy's part X = {w1, w2}
    both have {w2}: the built pair's list for c is one of s's lists that no world of X has (it is added to
    the copy's lists for this product)."""
    from delkit.logic.formula import Prop
    from delkit.models.events import action
    from delkit.models.kripke import KripkeModel

    val = np.array([[True, False, False], [False, True, False], [False, False, True]])
    ident = Relation.identity(3)
    rels = {"a": ident, "b": ident, "c": Relation.from_pairs(3, [(0, 1), (0, 2), (1, 2), (2, 2)])}
    m = KripkeModel(P, A, val, rels, (0,))
    em = action(A, [("yes", Prop("p"), {}), ("no", ~Prop("p"), {})], full=["a", "b"], designated=["yes"])
    engine, copy, r1, r2 = _both(m, em)
    _same(r1, r2)
    assert r1.n == 3 and bisimilar(engine.to_kripke(r1), product_update(m, em))


@settings(max_examples=150, deadline=None)
@given(data=st.data(), frame=st.sampled_from(["S5", "KD45", "K"]))
def test_copy_product_with_undesignated_events(data, frame) -> None:
    """mA* frames with some outcomes not designated (an announcement's "no" event): the copy product builds
    the rows of the undesignated events its pairs reach (through partial observers) and only those."""
    from delkit.models.events import action
    from delkit.testing import formulas

    m = data.draw(kripke_models(P, A, 5, frame=frame, designated="some"))
    k = data.draw(st.integers(2, 3))
    outcomes = [(f"e{i}", data.draw(formulas(P, (), max_depth=1)), {}) for i in range(k)]
    kinds = [data.draw(st.sampled_from(["full", "partial", "oblivious"])) for _ in A]
    des = data.draw(st.lists(st.sampled_from([o[0] for o in outcomes]), min_size=1, max_size=k - 1, unique=True))
    em = action(A, outcomes, full=[a for a, kd in zip(A, kinds, strict=True) if kd == "full"],
                partial=[a for a, kd in zip(A, kinds, strict=True) if kd == "partial"], designated=des)
    engine = CompactEngine(P, A)
    s = engine.from_kripke(m)
    comp = engine.compile(em)
    # scratch states (no frame number): the shape cache, which computes every event's row, is not consulted
    r1 = engine.apply_compiled(compact.CompactState(s.val, s.masks, s.points), comp)
    r2 = engine.apply_compiled(compact.CompactState(s.val, s.masks, s.points), comp[:11] + (None,))
    _same(r1, r2)
    if r1 is not None:
        assert bisimilar(engine.to_kripke(r1), product_update(m, em))
