"""The symbolic (BDD) backend agrees with the explicit engine on translated models."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from delkit.backends.symbolic import KnowledgeStructure, Transformer, from_kripke, muddy_symbolic
from delkit.errors import ModelError, UnknownSymbolError
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
    parse,
)
from delkit.models.bisimulation import bisimilar
from delkit.models.events import EventModel, ontic, public_announcement, semi_private_announcement
from delkit.models.kripke import KripkeModel
from delkit.models.relation import Relation
from delkit.models.update import product_update
from delkit.puzzles.muddy import solve_muddy

PROPS = ("p", "q")
AGENTS = ("a", "b", "c")

# ----------------------------------------------------------------------------- strategies


@st.composite
def s5_models(draw, max_worlds: int = 6) -> KripkeModel:
    n = draw(st.integers(1, max_worlds))
    val = np.array(draw(st.lists(st.booleans(), min_size=2 * n, max_size=2 * n)), dtype=bool).reshape(n, 2)
    rels = {a: Relation.from_labels(draw(st.lists(st.integers(0, n - 1), min_size=n, max_size=n))) for a in AGENTS}
    des = draw(st.lists(st.integers(0, n - 1), min_size=1, max_size=n, unique=True))
    return KripkeModel(PROPS, AGENTS, val, rels, tuple(des))


def _formulas(depth: int, dynamic: st.SearchStrategy[Formula] | None = None) -> st.SearchStrategy[Formula]:
    leaves = st.sampled_from([Prop("p"), Prop("q"), TOP, BOT])
    groups = st.lists(st.sampled_from(AGENTS), min_size=1, max_size=3, unique=True)
    if depth == 0:
        return leaves
    sub = _formulas(depth - 1, dynamic)
    opts = [leaves, sub.map(Not), st.lists(sub, min_size=2, max_size=3).map(And),
            st.lists(sub, min_size=2, max_size=3).map(Or), st.builds(Implies, sub, sub), st.builds(Iff, sub, sub),
            st.builds(K, st.sampled_from(AGENTS), sub), st.builds(Kw, st.sampled_from(AGENTS), sub),
            st.builds(E, groups, sub), st.builds(C, groups, sub), st.builds(D, groups, sub),
            st.builds(Announce, sub, sub)]
    return st.one_of(opts + ([dynamic] if dynamic is not None else []))


_prop_formulas = st.recursive(st.sampled_from([Prop("p"), Prop("q"), TOP, BOT]),
                              lambda s: st.one_of(s.map(Not), st.builds(lambda a, b: a & b, s, s),
                                                  st.builds(lambda a, b: a | b, s, s)), max_leaves=4)


@st.composite
def s5_event_models(draw) -> EventModel:
    k = draw(st.integers(1, 3))
    pres = tuple(draw(_prop_formulas) for _ in range(k))
    posts = tuple({p: draw(_prop_formulas) for p in draw(st.lists(st.sampled_from(PROPS), unique=True))}
                  for _ in range(k))
    rels = {a: Relation.from_labels(draw(st.lists(st.integers(0, k - 1), min_size=k, max_size=k))) for a in AGENTS}
    des = draw(st.lists(st.integers(0, k - 1), min_size=1, max_size=k, unique=True))
    return EventModel(tuple(f"e{i}" for i in range(k)), AGENTS, pres, posts, rels, tuple(des), "E")


@st.composite
def updates(draw, depth: int = 1) -> Formula:
    em = draw(s5_event_models())
    return Update(em, draw(st.integers(0, em.n_events - 1)), draw(_formulas(depth)), "E")


def _agree(model: KripkeModel, formula: Formula) -> None:
    ks, states = from_kripke(model)
    explicit = model.check(formula)
    symbolic = [ks.truth(formula, s) for s in states]
    assert list(explicit) == symbolic, formula
    assert ks.holds(formula) == model.holds(formula)


# ----------------------------------------------------------------------------- properties


@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(s5_models(), _formulas(3))
def test_symbolic_agrees_with_explicit_on_random_formulas(model: KripkeModel, formula: Formula) -> None:
    _agree(model, formula)


@settings(max_examples=80, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(s5_models(max_worlds=4), _formulas(2, dynamic=updates()))
def test_symbolic_agrees_with_explicit_on_updates_with_factual_change(model: KripkeModel, formula: Formula) -> None:
    _agree(model, formula)


@settings(max_examples=60, deadline=None)
@given(s5_models())
def test_round_trip_is_bisimilar(model: KripkeModel) -> None:
    ks, _ = from_kripke(model)
    back = ks.to_kripke(model.props)
    assert back.n_worlds <= model.n_worlds
    assert bisimilar(model, back)


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(s5_models(max_worlds=4), s5_event_models())
def test_transform_matches_product_update(model: KripkeModel, events: EventModel) -> None:
    from delkit.backends.symbolic import transformer_from_event_model

    ks, _ = from_kripke(model)
    x, _ = transformer_from_event_model(events, ks)
    product = product_update(model, events)
    after = ks.transform(x)
    assert bisimilar(product, after.to_kripke(model.props))


@settings(max_examples=80, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(_prop_formulas, st.lists(st.lists(st.sampled_from(PROPS), unique=True), min_size=3, max_size=3),
       _prop_formulas, s5_event_models())
def test_transform_of_structure_observing_propositions(law: Formula, obs: list[list[str]], actual: Formula,
                                                       events: EventModel) -> None:
    """Agents that observe changed variables keep observing their *old* values (copies), as in M ⊗ E."""
    from delkit.backends.symbolic import transformer_from_event_model

    ks = KnowledgeStructure.create(PROPS, law, dict(zip(AGENTS, obs, strict=True)), actual=actual)
    model = ks.to_kripke()
    x, _ = transformer_from_event_model(events, ks)
    assert bisimilar(product_update(model, events), ks.transform(x).to_kripke(PROPS))


# ----------------------------------------------------------------------------- fixed examples


def test_knowledge_structure_by_hand() -> None:
    # a observes p, b observes q; law: p -> q
    ks = KnowledgeStructure.create(["p", "q"], "p -> q", {"a": ["p"], "b": ["q"]}, actual="p & q")
    assert ks.count_states() == 3
    assert ks.holds("K_a q")  # p is true, and a knows p -> q
    assert not ks.holds("K_b p")  # (~p, q) is a state too
    assert ks.valid("C{a,b} (p -> q)")
    assert ks.holds("D{a,b} (p & q)")
    after = ks.announce("~K_a q")  # a observes p: only the two ¬p states survive
    assert after.count_states() == 2 and not after.valid("p")
    explicit = ks.to_kripke().announce(parse("~K_a q"))
    assert explicit.n_worlds == 2


def test_transformer_with_factual_change_by_hand() -> None:
    # a privately flips p; b sees that something happened but not whether p was flipped
    ks = KnowledgeStructure.create(["p"], "T", {"a": ["p"], "b": ["p"]}, actual="p")
    flip = Transformer(("f",), parse("T"), {"p": parse("~(p <-> f)")}, {"a": ("f",), "b": ()}, parse("f"))
    after = ks.transform(flip)
    assert after.count_states() == 4
    assert after.holds("~p & K_a ~p")
    assert after.holds("~Kw_b p")


def test_transformer_copies_sit_next_to_their_variables() -> None:
    # every p_i is flipped or kept by a private coin f: the product's law relates each p_i to its copy p_i'
    # (p_i <-> (p_i' xor f)); with the copies next to their variables the law is linear in n, with the copies
    # below all of V it has a node per subset of the p_i (order p_1..p_n, p_1'..p_n': the classic 2^n)
    n = 12
    ps = [f"p{i}" for i in range(n)]
    ks = KnowledgeStructure.create(ps, "T", {"a": ps, "b": []})
    flip = Transformer(("f",), parse("T"), {p: parse(f"~({p} <-> f)") for p in ps}, {"a": ("f",), "b": ()})
    after = ks.transform(flip)
    assert after.count_states() == 2 ** (n + 1)
    assert len(after.law) <= 8 * n, len(after.law)  # ≈ 2^(n+1) nodes with the copies at the bottom
    assert after.holds("~Kw_b p0") and after.valid("K_a (p0 | ~p0)")


def test_semi_private_and_public_announcement_via_update_formulas() -> None:
    model = KripkeModel.build([{"p"}, set()], {"a": [[0, 1]], "b": [[0, 1]], "c": [[0], [1]]}, designated=[0])
    for em in (public_announcement("p", AGENTS), semi_private_announcement("p", ["a"], AGENTS)):
        f = Update(em, 0, K("a", Prop("p")) & Not(K("b", Prop("p"))))
        _agree(model, f)


def test_non_s5_inputs_are_rejected() -> None:
    m = KripkeModel.build([{"p"}, set()], {"a": {"pairs": [(0, 1), (1, 1)]}}, designated=[0])
    with pytest.raises(ModelError, match="S5"):
        from_kripke(m)
    s5 = KripkeModel.build([{"p"}, set()], {"a": [[0, 1]]}, designated=[0])
    ks, _ = from_kripke(s5)
    oblivious = ontic({"p": False}, ["a"], full=[])  # a is oblivious: a KD45, not S5, event model
    with pytest.raises(ModelError, match="S5"):
        ks.evaluate(Update(oblivious, 0, TOP))
    with pytest.raises(UnknownSymbolError):
        ks.evaluate(parse("K_z p"))
    with pytest.raises(UnknownSymbolError):
        ks.evaluate(parse("r"))


# ----------------------------------------------------------------------------- muddy children


@pytest.mark.parametrize(("n", "m"), [(3, 2), (6, 6), (7, 3)])
def test_symbolic_muddy_matches_explicit(n: int, m: int) -> None:
    s, e = muddy_symbolic(n, m), solve_muddy(n, m)
    assert (s.nobody_knows_rounds, s.muddy_know_round, s.clean_know_round) == \
        (e.nobody_knows_rounds, e.muddy_know_round, e.clean_know_round)


@pytest.mark.parametrize(("n", "m"), [(20, 20), (40, 7)])
def test_symbolic_muddy_large(n: int, m: int) -> None:
    r = muddy_symbolic(n, m)
    assert r.nobody_knows_rounds == m - 1
    assert r.muddy_know_round == m
    assert r.clean_know_round == (None if m == n else m + 1)


# ----------------------------------------------------------------------------- puzzles on both engines


def test_cheryl_and_sum_product_announcements_agree_symbolically() -> None:
    from delkit.puzzles._common import knows_which
    from delkit.puzzles.cheryl import cheryl_model
    from delkit.puzzles.sum_product import sum_product_model

    m = cheryl_model()
    ka, kb = knows_which("Albert", m.props), knows_which("Bernard", m.props)
    script = [Not(ka) & K("Albert", Not(kb)), kb, ka]
    m2 = sum_product_model(100)
    kp, ks_ = knows_which("P", m2.props), knows_which("S", m2.props)
    for model, steps in ((m, script), (m2, [K("S", Not(kp)), kp, ks_])):
        ks, _ = from_kripke(model)
        for phi in steps:
            model, ks = model.announce(phi), ks.announce(phi)
            assert ks.count_states() == model.n_worlds
        assert bisimilar(model.with_designated(range(model.n_worlds)),
                         KnowledgeStructure(ks.bdd, ks.vocabulary, ks.law, ks.observed, ks.law).to_kripke(model.props))


@pytest.mark.slow
@settings(max_examples=3000, deadline=None, suppress_health_check=list(HealthCheck))
@given(s5_models(max_worlds=4), _formulas(3, dynamic=updates()))
def test_symbolic_agrees_with_explicit_many(model: KripkeModel, formula: Formula) -> None:
    """S5 knowledge structures (observational): 3,000 random (model, formula) cases with announcements and
    S5 event models with factual change (with the 10,200 belief-structure cases of
    test_symbolic_belief.py: 13,200 in the slow suite)."""
    _agree(model, formula)


@settings(max_examples=40, deadline=None, suppress_health_check=list(HealthCheck))
@given(s5_models(max_worlds=4), s5_event_models())
def test_transformer_back_to_event_model_round_trip(model: KripkeModel, events: EventModel) -> None:
    """event model → transformer → event model: the product updates are bisimilar."""
    from delkit.backends.symbolic import event_model_from_transformer, transformer_from_event_model

    ks, _ = from_kripke(model)
    x, _ = transformer_from_event_model(events, ks)
    back = event_model_from_transformer(x, ks)
    assert bisimilar(product_update(model, events), product_update(model, back))


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(_prop_formulas, st.lists(st.lists(st.sampled_from(PROPS), unique=True), min_size=3, max_size=3),
       _prop_formulas, s5_event_models(), st.lists(_formulas(2), min_size=1, max_size=3))
def test_warm_caches_agree_after_products_and_announcements(law: Formula, obs: list[list[str]], actual: Formula,
                                                            events: EventModel, formulas: list[Formula]) -> None:
    """What evaluation keeps between structures (propositional truth sets shared through the manager;
    unobserved sets, cubes and the "Kw_a x with x hidden from a" decisions shared by announcements) is
    reused only where it still holds: after warming every cache on F, F × E and (F × E)|φ agree with the
    explicit engine (products change the observations, announcements do not)."""
    from delkit.backends.symbolic import transformer_from_event_model
    from delkit.errors import DelkitError

    ks = KnowledgeStructure.create(PROPS, law, dict(zip(AGENTS, obs, strict=True)), actual=actual)
    if ks.count_states() == 0 or ks.actual == ks.bdd.false:
        return  # (no assume: its exception would keep BDDs alive past their manager in a reference cycle)
    model = ks.to_kripke()
    queries = [Kw(a, Prop(p)) for a in AGENTS for p in PROPS] + [K(a, Not(Prop(p))) for a in AGENTS for p in PROPS]
    queries += [And((Kw(a, Prop("p")), Not(Prop("q")))) for a in AGENTS]
    queries += [Or((K(a, Prop("q")), Prop("p"))) for a in AGENTS]
    queries += formulas
    for f in queries:
        ks.evaluate(f)
    try:
        explicit = product_update(model, events)
    except DelkitError:
        return
    x, _ = transformer_from_event_model(events, ks)
    after = ks.transform(x)
    for f in queries:
        assert after.holds(f) == explicit.holds(f), f
    said = formulas[0]
    if not explicit.holds(said):
        return
    for f in queries:
        assert after.announce(said).holds(f) == explicit.announce(said).holds(f), f
