"""The numpy-free path of small tasks (start-up): the readers' PlainModel initial states and the compact
backend's PlainEvents are the same models as the numpy reference builds (finitary_s5's KripkeModel,
``planners.task.build_event_model`` by the ``delkit.models.events`` constructors), on every shared mA* and EPDDL
(2026) instance small enough, and planning on them gives the same results."""

from __future__ import annotations

import csv
import itertools

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import planners.lang.initial as initial
from delkit.backends.compact import PlainEvents, PlainModel
from delkit.logic.formula import TOP, And, Not, Or, Prop
from planners.epistemic import Limits, bfs
from planners.lang import load_task, shared_benchmarks
from planners.spaces import CompactSpace
from planners.task import ActionSpec, build_event_model, plain_event_model

BENCH = shared_benchmarks()
MASTAR = sorted((BENCH / "mastar").rglob("*.txt")) if BENCH else []


def _numpy_only(monkeypatch) -> None:
    monkeypatch.setattr(initial, "plain_models", lambda *a, **k: None)


def _same_model(a, b) -> None:
    assert a.props == b.props and a.agents == b.agents
    assert np.array_equal(np.asarray(a.valuation), np.asarray(b.valuation))
    assert list(a.designated) == list(b.designated)
    for ag in a.agents:
        ra, rb = a.relations[ag], b.relations[ag]
        assert (ra.labels is None) == (rb.labels is None)
        assert [ra.successors(w).tolist() for w in range(a.n_worlds)] == \
               [rb.successors(w).tolist() for w in range(b.n_worlds)]


def _same_events(p: PlainEvents, em) -> None:
    ref = em.event_model() if isinstance(em, PlainEvents) else em
    got = p.event_model()
    assert got.events == ref.events and got.agents == ref.agents and got.designated == ref.designated
    assert got.pre == ref.pre and [dict(m) for m in got.post] == [dict(m) for m in ref.post]
    for ag in ref.agents:
        assert (got.relations[ag].labels is None) == (ref.relations[ag].labels is None), ag
        assert [got.relations[ag].successors(e).tolist() for e in range(ref.n_events)] == \
               [ref.relations[ag].successors(e).tolist() for e in range(ref.n_events)], ag


@pytest.mark.skipif(BENCH is None, reason="../shared/benchmarks is not available")
@pytest.mark.parametrize("path", MASTAR, ids=lambda p: p.name)
def test_mastar_plain_initial_and_events_equal_reference(path, monkeypatch) -> None:
    task = load_task(path)
    plain = task.plain_initial
    assert plain is not None  # every shared mA* instance is small
    monkeypatch.undo()
    _numpy_only(monkeypatch)
    ref = load_task(path)
    assert ref.plain_initial is None
    _same_model(plain.kripke(), ref.initial)
    _same_model(task.initial, ref.initial)
    # every action's event model, for every observer configuration it can meet (full / partial / oblivious
    # per agent, sensed formulas active or not)
    ags = task.agents
    for act in task.actions:
        assert isinstance(act, ActionSpec)
        kinds = ("full", "obl") if act.kind == "ontic" else ("full", "partial", "obl")
        for obs in itertools.islice(itertools.product(kinds, repeat=len(ags)), 27):
            full = frozenset(a for a, k in zip(ags, obs, strict=True) if k == "full")
            part = frozenset(a for a, k in zip(ags, obs, strict=True) if k == "partial")
            for n in range(len(act.sensed) + 1):
                sensed = tuple(f for f, _ in act.sensed[:n])
                _same_events(plain_event_model(act, ags, full, part, sensed),
                             build_event_model(act, ags, full, part, sensed))


@pytest.mark.skipif(BENCH is None, reason="../shared/benchmarks is not available")
def test_epddl_plain_events_and_search_equal_reference(monkeypatch) -> None:
    rows = list(csv.DictReader((BENCH / "epddl2026" / "expected.csv").open()))
    base = BENCH / "epddl2026"
    done = 0
    for row in rows:
        if "Coin" not in row["problem"] and "Muddy" not in row["problem"]:
            continue
        libs = [base / row["libraries"]] if row["libraries"] else []
        task = load_task(base / row["domain"], base / row["problem"], libs)
        assert task.plain_initial is not None
        monkeypatch.setattr(initial, "plain_models", lambda *a, **k: None)
        ref = load_task(base / row["domain"], base / row["problem"], libs)
        monkeypatch.undo()
        _same_model(task.initial, ref.initial)
        for act in task.actions[:40]:
            for bits in itertools.product((False, True), repeat=min(len(act.conditions), 3)):
                bits = bits + (False,) * (len(act.conditions) - len(bits))
                _same_events(task.events_for_bits(act, bits), ref.event_model_for_bits(act, bits))
        # the search over the plain models (compact backend) and over the converted ones agree
        a = bfs(CompactSpace(task, allow_inconsistent=True), Limits(timeout=30))
        del task.__dict__["_initial"]
        object.__setattr__(task, "initial", ref.initial)   # the same task from a KripkeModel
        b = bfs(CompactSpace(task, allow_inconsistent=True), Limits(timeout=30))
        assert (a.status, a.length, a.expanded) == (b.status, b.length, b.expanded)
        done += 1
    assert done >= 5


_ATOMS = [Prop(p) for p in "pqrs"]
_FORMULA = st.recursive(st.sampled_from([*_ATOMS, TOP]),
                        lambda ch: st.one_of(ch.map(Not), st.lists(ch, min_size=2, max_size=3).map(
                            lambda xs: And(tuple(xs))), st.lists(ch, min_size=2, max_size=3).map(
                            lambda xs: Or(tuple(xs)))), max_leaves=6)


@settings(max_examples=150, deadline=None)
@given(st.lists(_FORMULA, max_size=3), st.dictionaries(st.sampled_from("pqrst"), st.booleans(), max_size=2),
       st.lists(_FORMULA, max_size=2))
def test_plain_models_equal_numpy_models(constraints, fixed, kw) -> None:
    props = ("p", "q", "r", "s", "t")
    got = initial.plain_models(props, constraints, fixed=fixed)
    want = initial.models(props, constraints, fixed=fixed)
    assert got is not None
    assert [[bool((v >> j) & 1) for j in range(len(props))] for v in got] == want.tolist()
    if got:
        pidx = {p: i for i, p in enumerate(props)}
        rel = initial._kw_relations(want, pidx, ["a"], {"a": kw}, None)["a"]
        assert initial.plain_labels(got, pidx, kw) == rel.labels.tolist()
        m = PlainModel(props, ("a",), got, {"a": initial.plain_labels(got, pidx, kw)}, (0,))
        assert m.kripke().relations["a"].labels.tolist() == rel.labels.tolist()
