"""The compact backend's refinement and compiled event models.

* ``_refine`` reads the successor masks of a discrete round off without ranking the next round: its
  output must be the round-by-round definition's (every round ranked until none splits) exactly — the
  canonical numbering is what keys and the parallel search's records are made of.
* Event models equal as data share one compiled model (``CompactEngine.compile``), and ``CompactSpace``
  builds one successor per compiled model and state: the successors must be those of each action alone.
"""

from __future__ import annotations

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from delkit.backends.compact import CompactEngine, CompactState, PlainEvents, PlainModel, _refine
from delkit.logic.formula import Not, Prop, Top
from delkit.testing import refinement_inputs
from planners.lang import load_task, shared_benchmarks
from planners.spaces import CompactSpace


def rounds_refine(val, dist, cls, points):
    """The definition (written out round by round): round 0 ranks the valuations, every round
    ranks the signatures (block, per relation the successor blocks as a bit mask) until no block splits;
    the stable round's sorted signatures are the quotient's blocks and masks."""
    n = len(val)
    uniq = sorted(set(val))
    rank = {v: i for i, v in enumerate(uniq)}
    blk = [rank[v] for v in val]
    nb = len(uniq)
    while True:
        cols = []
        for lists, c in zip(dist, cls, strict=True):
            t = []
            for lst in lists:
                m = 0
                for v in lst:
                    m |= 1 << blk[v]
                t.append(m)
            cols.append([t[c[w]] for w in range(n)])
        sigs = list(zip(blk, *cols, strict=True))
        us = sorted(set(sigs))
        if len(us) == nb:
            break
        r = {sg: i for i, sg in enumerate(us)}
        blk = [r[sg] for sg in sigs]
        nb = len(us)
    of = dict(zip(blk, val, strict=True))
    return blk, [of[b] for b in range(nb)], tuple(zip(*us, strict=True))[1:], tuple(sorted({blk[p] for p in points}))


@settings(max_examples=400, deadline=None)
@given(refinement_inputs())
def test_refine_equals_the_round_by_round_definition(model) -> None:
    val, dist, cls, points = model
    got = _refine(val, dist, cls, points)
    want = rounds_refine(val, dist, cls, points)
    assert (list(got[0]), list(got[1]), got[2], got[3]) == (want[0], want[1], want[2], want[3])


def test_refine_discrete_after_splitting_rounds() -> None:
    """A chain w0 → w1 → … → w9 with equal valuations: every round splits one block off, the last round is
    discrete; masks as in the definition (world i's successor is block of world i+1)."""
    n = 10
    val = [0] * n
    dist = [[[w + 1] for w in range(n - 1)] + [[]]]
    cls = [list(range(n))]
    got = _refine(val, dist, cls, [0])
    assert got == rounds_refine(val, dist, cls, [0])
    assert len(got[1]) == n


def _events(name: str, pre, rows, designated=(0,)) -> PlainEvents:
    return PlainEvents(("yes", "no", "eps"), ("a", "b"), pre, ({}, {}, {}), rows, designated, name)


ROWS = {"a": [(0,), (1,), (2,)], "b": [(2,), (2,), (2,)]}


def test_equal_event_models_share_one_compiled_model() -> None:
    eng = CompactEngine(("p", "q"), ("a", "b"))
    pre = (Prop("p"), Not(Prop("p")), Top())
    c1 = eng.compile(_events("a tells p", pre, ROWS))
    c2 = eng.compile(_events("b tells p", pre, ROWS))
    assert c1 is c2
    # any difference in the data: a model of its own
    assert eng.compile(_events("tells q", (Prop("q"), Not(Prop("q")), Top()), ROWS)) is not c1
    assert eng.compile(_events("both see", pre, {"a": ROWS["a"], "b": ROWS["a"]})) is not c1
    assert eng.compile(_events("sensing", pre, ROWS, designated=(0, 1))) is not c1
    post = PlainEvents(("yes", "no", "eps"), ("a", "b"), pre, ({"q": Top()}, {}, {}), ROWS, (0,), "sets q")
    assert eng.compile(post) is not c1
    s = eng.from_plain(PlainModel(("p", "q"), ("a", "b"), [1, 0, 3], {"a": [0, 1, 1], "b": [0, 0, 0]}, (0,)))
    r1, r2 = eng.apply_compiled(s, c1), eng.apply(s, _events("again", pre, ROWS))
    assert r1 is not None and (r1.val, r1.masks, r1.points) == (r2.val, r2.masks, r2.points)


@settings(max_examples=100, deadline=None)
@given(st.data())
def test_union_of_relations(data) -> None:
    n = data.draw(st.integers(1, 12))
    vals = data.draw(st.lists(st.integers(0, 3), min_size=n, max_size=n))
    labels = {a: data.draw(st.lists(st.integers(0, 3), min_size=n, max_size=n)) for a in ("a", "b")}
    eng = CompactEngine(("p", "q"), ("a", "b"))
    s = eng.from_plain(PlainModel(("p", "q"), ("a", "b"), vals, labels, (0,)))
    assert s.union == [x | y for x, y in zip(*s.masks, strict=True)]


BENCH = shared_benchmarks()


@pytest.mark.skipif(BENCH is None, reason="the shared benchmarks are not available")
def test_actions_sharing_a_compiled_model_have_their_own_successors() -> None:
    """Grapevine: agents in one room who believe one secret announce it by one event model. On the states a
    BFS meets, the successors ``successors`` yields (one product per compiled model and state) are the ones
    ``step`` computes for each action alone on another space — and the sharing does happen."""
    task = load_task(BENCH / "mastar" / "Grapevine" / "Grapevine_4" / "Grapevine_4__pl_4.txt")
    space, alone = CompactSpace(task), CompactSpace(task)
    s0, k0 = space.initial()
    seen, frontier, shared, checked = {k0}, [s0], 0, 0
    for _ in range(3):
        nxt = []
        for s in frontier[:30]:
            comps: dict = {}
            for name, new, key in space.successors(s):
                # a fresh copy of s (frame numbers are process-wide, memos are per engine)
                t = alone.step(CompactState(s.val, s.masks, s.points, s.fid), name)
                assert t is not None and t.key == key, name
                checked += 1
                em = space.event_model_named(s, name)
                comps.setdefault(id(space.engine.compile(em)), []).append(name)
                if key not in seen:
                    seen.add(key)
                    nxt.append(new)
            shared += sum(len(v) > 1 for v in comps.values())
        frontier = nxt
    assert shared > 0 and checked > 100


@pytest.mark.skipif(BENCH is None, reason="the shared benchmarks are not available")
@pytest.mark.parametrize("name", ["Grapevine/Grapevine_3/Grapevine_3__pl_4.txt",
                                  "Grapevine/Grapevine_4/Grapevine_4__pl_4.txt",
                                  "Coin_In_The_Box/Coin_in_the_Box__pl_5.txt"])
def test_loop_test_memo_per_observer_set(name) -> None:
    """The loop test's closure of the observers, memoised on the state: asked in any order for the actions
    of a state, each answer is the one a fresh copy of the state (empty memo) gives."""
    task = load_task(BENCH / "mastar" / name)
    space = CompactSpace(task)
    s0, k0 = space.initial()
    seen, frontier, compared = {k0}, [s0], 0
    for _ in range(4):
        nxt = []
        for s in frontier[:25]:
            tests = [t for e in space._acts if (t := space._loop_test(s, e)) is not None and not t[3]]
            for t in tests + tests[::-1]:
                fresh = CompactState(s.val, s.masks, s.points, s.fid)
                assert space._is_loop(s, t) == space._is_loop(fresh, t)
                compared += 1
            for _name, new, key in space.successors(s):
                if key not in seen:
                    seen.add(key)
                    nxt.append(new)
        frontier = nxt
    assert compared > 0
