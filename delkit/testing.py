"""Hypothesis strategies for property-based tests of DEL models (public API).

Use them to write property suites for your own models and actions, e.g. that an action never makes an
agent lose knowledge of a fact::

    from hypothesis import given, settings
    from delkit import K, Prop, product_update
    from delkit.testing import event_models, s5_models

    @settings(max_examples=50, deadline=None)
    @given(s5_models(["p", "q"], ["a", "b"], max_worlds=5),
           event_models(["p", "q"], ["a", "b"], max_events=2, postconditions=False))
    def test_pure_announcements_preserve_knowledge_of_p(m, e):
        if m.holds(K("a", Prop("p"))):
            assert product_update(m, e).holds(K("a", Prop("p")))

Strategies:

* :func:`formulas` – random formulas over given propositions and agents (optionally with C/E/D, public
  announcements and [E,e] with small random event models);
* :func:`propositional_formulas` – Boolean formulas only (for pre/postconditions);
* :func:`kripke_models` – models of a frame class: ``"S5"`` (partitions), ``"KD45"`` (serial, transitive,
  euclidean; every KD45 relation has this shape: worlds fall into clusters, and each cluster has a
  non-empty set of believed worlds that every world of the cluster points to), ``"K"`` (any relation);
* :func:`s5_models`, :func:`kd45_models`, :func:`pointed_models` – shorthands;
* :func:`event_models` – event models with propositional pre/postconditions, S5 (partitions), KD45 or K
  frames, or the mA* observability frames (full / partial / oblivious observers, via
  :func:`delkit.models.events.action`);
* :func:`world_permutations` – a permutation of worlds to build isomorphic copies.

Every strategy is shrinkable (it is built from hypothesis primitives, not from a seeded RNG).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

try:
    from hypothesis import strategies as st
except ImportError as exc:  # hypothesis comes with the test extra, not with the core
    raise ImportError("delkit.testing needs hypothesis: pip install 'delkit[test]' (or pip install hypothesis)") \
        from exc

from delkit.logic.formula import (
    BOT,
    TOP,
    And,
    Announce,
    C,
    D,
    E,
    Formula,
    Iff,
    Implies,
    K,
    Kw,
    Not,
    Or,
    Prop,
    Update,
)
from delkit.models.events import EventModel
from delkit.models.kripke import KripkeModel
from delkit.models.relation import Relation

__all__ = [
    "formulas", "propositional_formulas", "kripke_models", "s5_models", "kd45_models", "pointed_models",
    "event_models", "relations", "kd45_relation", "world_permutations", "refinement_inputs", "FRAMES",
    "EVENT_FRAMES",
]

FRAMES = ("S5", "KD45", "K")
EVENT_FRAMES = (*FRAMES, "mA*")


def _check_frame(frame: str) -> str:
    f = frame.upper()
    if f not in FRAMES:
        raise ValueError(f"unknown frame {frame!r}; use one of {FRAMES}")
    return f


# ============================================================================ formulas


def propositional_formulas(props: Sequence[str], max_depth: int = 2) -> st.SearchStrategy[Formula]:
    """Boolean formulas over ``props`` (and ⊤, ⊥) of connective depth at most ``max_depth``."""
    return formulas(props, (), max_depth, allow_common=False, allow_group=False)


def formulas(props: Sequence[str], agents: Sequence[str], max_depth: int = 3, *, allow_common: bool = True,
             allow_group: bool = True, allow_announce: bool = False, allow_dynamic: bool = False,
             max_events: int = 2) -> st.SearchStrategy[Formula]:
    """Random formulas of depth (nesting of all operators) at most ``max_depth``.

    Operators: ¬ ∧ ∨ → ↔ always; K_a and Kw_a if ``agents``; E_G, D_G (and C_G if ``allow_common``) if
    ``allow_group``; [!φ]ψ if ``allow_announce``; [E,e]ψ with a random event model of at most
    ``max_events`` events (propositional pre/post) if ``allow_dynamic``.
    """
    props, agents = list(props), list(agents)
    if not props:
        raise ValueError("formulas() needs at least one proposition")
    n_leaf = 4 * len(props)  # propositions four times as likely as the constants ⊤, ⊥ together
    leaves = st.integers(0, n_leaf + 1).map(
        lambda i: Prop(props[i % len(props)]) if i < n_leaf else (TOP, BOT)[i - n_leaf])
    groups = (st.lists(st.sampled_from(agents), min_size=1, max_size=len(agents), unique=True)
              if agents else st.nothing())
    # the operator is drawn first (leaf first, so that shrinking simplifies), then its arguments
    ops = ["leaf", "and", "or", "implies", "iff", "not"]
    if agents:
        ops += ["K", "Kw"]
        if allow_group:
            ops += ["E", "D"] + (["C"] if allow_common else [])
    if allow_announce:
        ops.append("announce")
    if allow_dynamic and agents:
        ops.append("update")
    op_s = st.sampled_from(ops)
    agent_s = st.sampled_from(agents) if agents else st.nothing()

    @st.composite
    def at(draw, depth: int) -> Formula:
        op = draw(op_s) if depth > 0 else "leaf"
        if op == "leaf":
            return draw(leaves)
        sub = at(depth - 1)
        if op in ("and", "or"):
            return (And if op == "and" else Or)(draw(st.lists(sub, min_size=2, max_size=3)))
        if op in ("implies", "iff"):
            return (Implies if op == "implies" else Iff)(draw(sub), draw(sub))
        if op == "not":
            return Not(draw(sub))
        if op in ("K", "Kw"):
            return (K if op == "K" else Kw)(draw(agent_s), draw(sub))
        if op in ("E", "D", "C"):
            return {"E": E, "D": D, "C": C}[op](draw(groups), draw(sub))
        if op == "announce":
            return Announce(draw(sub), draw(sub))
        return draw(_updates(props, agents, max_events, sub))

    return at(max_depth)


def _updates(props, agents, max_events, sub) -> st.SearchStrategy[Formula]:
    @st.composite
    def build(draw):
        em = draw(event_models(props, agents, max_events=max_events,
                               frame=draw(st.sampled_from(["S5", "KD45"]))))
        e = draw(st.integers(0, em.n_events - 1))
        return Update(em, e, draw(sub), em.name)

    return build()


# ============================================================================ relations and models


def relations(n: int, frame: str = "S5") -> st.SearchStrategy[Relation]:
    """A relation on n points of the frame class (S5 as a partition, KD45/K as a matrix)."""
    frame = _check_frame(frame)
    if n == 0:
        return st.just(Relation(0, labels=np.zeros(0, dtype=np.int64)))
    if frame == "S5":
        return st.lists(st.integers(0, n - 1), min_size=n, max_size=n).map(Relation.from_labels)
    if frame == "K":
        return st.lists(st.booleans(), min_size=n * n, max_size=n * n).map(
            lambda bits: Relation.from_matrix(np.array(bits, dtype=bool).reshape(n, n)))

    return st.tuples(st.lists(st.integers(0, n - 1), min_size=n, max_size=n),
                     st.lists(st.booleans(), min_size=n, max_size=n)).map(lambda cb: kd45_relation(*cb))


def kd45_relation(cluster: Sequence[int], believed: Sequence[bool]) -> Relation:
    """The KD45 relation with w R v iff w, v are in the same cluster and v is believed in it.

    A cluster without a believed world believes its first world. Every KD45 relation arises so: take
    clusters = classes of "same successor set" closed under successors, believed = the successor sets.
    """
    cl = np.asarray(cluster, dtype=np.int64)
    bel = np.asarray(believed, dtype=bool).copy()
    for c in np.unique(cl):  # every cluster believes at least one of its worlds (seriality)
        members = np.flatnonzero(cl == c)
        if not bel[members].any():
            bel[members[0]] = True
    return Relation.from_matrix((cl[:, None] == cl[None, :]) & bel[None, :])


def kripke_models(props: Sequence[str], agents: Sequence[str], max_worlds: int = 5, *, frame: str = "S5",
                  min_worlds: int = 1, designated: str = "one") -> st.SearchStrategy[KripkeModel]:
    """Random Kripke models of the frame class ``frame`` ("S5", "KD45" or "K").

    ``designated``: "one" (a single designated world), "some" (a non-empty set) or "all".
    """
    frame = _check_frame(frame)
    props, agents = tuple(props), tuple(agents)
    if designated not in ("one", "some", "all"):
        raise ValueError(f"designated must be 'one', 'some' or 'all', got {designated!r}")

    @st.composite
    def build(draw):
        n = draw(st.integers(min_worlds, max_worlds))
        bits = draw(st.lists(st.booleans(), min_size=n * len(props), max_size=n * len(props)))
        val = np.array(bits, dtype=bool).reshape(n, len(props))
        rels = {a: draw(relations(n, frame)) for a in agents}
        if designated == "one":
            des: tuple[int, ...] = (draw(st.integers(0, n - 1)),)
        elif designated == "some":
            des = tuple(draw(st.lists(st.integers(0, n - 1), min_size=1, max_size=n, unique=True)))
        else:
            des = tuple(range(n))
        return KripkeModel(props, agents, val, rels, des)

    return build()


def s5_models(props: Sequence[str], agents: Sequence[str], max_worlds: int = 5, **kw) -> st.SearchStrategy[
        KripkeModel]:
    """S5 models (every relation a partition)."""
    return kripke_models(props, agents, max_worlds, frame="S5", **kw)


def kd45_models(props: Sequence[str], agents: Sequence[str], max_worlds: int = 5, **kw) -> st.SearchStrategy[
        KripkeModel]:
    """KD45 (belief) models."""
    return kripke_models(props, agents, max_worlds, frame="KD45", **kw)


def pointed_models(props: Sequence[str], agents: Sequence[str], max_worlds: int = 5, *, frame: str = "S5"
                   ) -> st.SearchStrategy[KripkeModel]:
    """Models with exactly one designated world."""
    return kripke_models(props, agents, max_worlds, frame=frame, designated="one")


@st.composite
def refinement_inputs(draw, max_worlds: int = 40, max_relations: int = 4, max_lists: int = 8):
    """``(val, dist, cls, points)`` as the compact engine hands them to its partition refinement
    (``delkit.backends.compact._refine``, ``delkit.backends.compact_np.refine``): valuations, per relation the distinct
    successor
    lists (numbered in order of first use) and each world's list, designated worlds. Valuations from a narrow
    range (rounds that split) or a wide one (mostly distinct: discrete from round 0; beyond 63 bits)."""
    n = draw(st.integers(1, max_worlds))
    top = draw(st.sampled_from([0, 1, 3, 15, 2**40]))
    val = draw(st.lists(st.integers(0, top), min_size=n, max_size=n))
    dist, cls = [], []
    for _ in range(draw(st.integers(1, max_relations))):
        lists = draw(st.lists(st.lists(st.integers(0, n - 1), max_size=8), min_size=1, max_size=max_lists))
        use = draw(st.lists(st.integers(0, len(lists) - 1), min_size=n, max_size=n))
        first = list(dict.fromkeys(use))  # every list is some world's, numbered in order of first use
        dist.append([lists[i] for i in first])
        cls.append([first.index(i) for i in use])
    points = draw(st.lists(st.integers(0, n - 1), min_size=1, max_size=3))
    return val, dist, cls, points


def world_permutations(n: int) -> st.SearchStrategy[list[int]]:
    """A permutation of 0..n-1 (for isomorphic copies of a model)."""
    return st.permutations(list(range(n)))


# ============================================================================ event models


def event_models(props: Sequence[str], agents: Sequence[str], max_events: int = 3, *, frame: str = "S5",
                 pre_depth: int = 2, postconditions: bool = True, min_events: int = 1,
                 name: str = "E") -> st.SearchStrategy[EventModel]:
    """Event models with propositional preconditions (depth ≤ ``pre_depth``) and, if ``postconditions``,
    random propositional postconditions on some propositions; a non-empty set of designated events.

    ``frame``: "S5" (partitions), "KD45" or "K" (any relation of that class), or "mA*": the observability
    frames of :func:`delkit.models.events.action` — every agent is drawn fully observant, partially observant or
    oblivious; with oblivious agents the skip event ``eps`` is added (then ``max_events`` + 1 events).
    """
    if frame.upper() == "MA*":
        return _ma_star_models(tuple(props), tuple(agents), max_events, pre_depth, postconditions, min_events,
                               name)
    frame = _check_frame(frame)
    props, agents = tuple(props), tuple(agents)
    pre_s = propositional_formulas(props, pre_depth)

    @st.composite
    def build(draw):
        k = draw(st.integers(min_events, max_events))
        pres = tuple(draw(pre_s) for _ in range(k))
        posts = tuple(draw(_posts(props, postconditions)) for _ in range(k))
        rels = {a: draw(relations(k, frame)) for a in agents}
        des = tuple(draw(st.lists(st.integers(0, k - 1), min_size=1, max_size=k, unique=True)))
        return EventModel(tuple(f"e{i}" for i in range(k)), agents, pres, posts, rels, des, name)

    return build()


def _posts(props: tuple[str, ...], enabled: bool) -> st.SearchStrategy[dict[str, Formula]]:
    if not enabled:
        return st.just({})
    return st.dictionaries(st.sampled_from(props), propositional_formulas(props, 1), max_size=len(props))


def _ma_star_models(props, agents, max_events, pre_depth, postconditions, min_events, name):
    from delkit.models.events import action

    pre_s = propositional_formulas(props, pre_depth)

    @st.composite
    def build(draw):
        k = draw(st.integers(min_events, max_events))
        outcomes = [(f"e{i}", draw(pre_s), draw(_posts(props, postconditions))) for i in range(k)]
        kinds = [draw(st.sampled_from(["full", "partial", "oblivious"])) for _ in agents]
        full = [a for a, kd in zip(agents, kinds, strict=True) if kd == "full"]
        partial = [a for a, kd in zip(agents, kinds, strict=True) if kd == "partial"]
        return action(agents, outcomes, full=full, partial=partial, name=name)

    return build()

