"""Hand-checked tests of delkit.verify: textbook validities, reductions, macro checks, model search."""

from __future__ import annotations

import pytest

from delkit import (
    K,
    KripkeModel,
    Not,
    Prop,
    Update,
    compose,
    compose_all,
    ontic,
    parse,
    private_announcement,
    public_announcement,
    semi_private_announcement,
    sensing,
    show,
)
from delkit.logic.formula import Iff, is_propositional
from delkit.models.events import EventModel
from delkit.verify import (
    VerificationError,
    check_macro,
    counterexample,
    equivalent,
    find_model,
    prove,
    reduce,
    s5_single_agent_bound,
    satisfiable,
    to_z3,
    valid,
)

AG = ["a", "b"]


# ----------------------------------------------------------------------------- propositional


def test_propositional_validity_and_satisfiability():
    assert valid("p | ~p") and valid("(p -> q) & p -> q") and valid("~(p & q) <-> ~p | ~q")
    assert not valid("p -> q")
    assert satisfiable("p & ~q") and not satisfiable("p & ~p") and not satisfiable("F")
    assert equivalent("p -> q", "~q -> ~p") and not equivalent("p -> q", "q -> p")
    cex = counterexample("p -> q")
    assert cex == {"p": True, "q": False}
    assert counterexample("T") is None


def test_to_z3_refuses_modal_formulas_with_a_hint():
    with pytest.raises(VerificationError, match="not propositional.*prove"):
        to_z3("K_a p")
    with pytest.raises(VerificationError):
        valid("C{a,b} p")


# ----------------------------------------------------------------------------- bounded search


@pytest.mark.parametrize("axiom", ["K_a p -> p", "K_a p -> K_a K_a p", "~K_a p -> K_a ~K_a p",
                                   "K_a (p -> q) -> K_a p -> K_a q", "C{a,b} p -> K_a K_b p",
                                   "C{a,b} p <-> E{a,b} (p & C{a,b} p)", "K_a p -> D{a,b} p"])
def test_s5_validities_have_no_small_counter_model(axiom):
    v = prove(axiom, logic="S5", worlds=4)
    assert v.valid and v.counter_model is None
    # a proof for one agent (small-model bound), a bounded answer for several
    assert v.exact == (s5_single_agent_bound(axiom) is not None)
    assert v.exact == (axiom in ("K_a p -> p", "K_a p -> K_a K_a p", "~K_a p -> K_a ~K_a p",
                                 "K_a (p -> q) -> K_a p -> K_a q"))


@pytest.mark.parametrize(("formula", "logic", "n_worlds"), [
    ("K_a p -> p", "KD45", 2),            # belief may be false
    ("K_a p -> ~K_a ~p", "K", 1),         # D fails without seriality: a dead end world
    ("K_a p -> K_a K_a p", "K", 2),       # 4 fails without transitivity (w0 <-> w1, p only at w1)
    ("C{a,b} p -> p", "KD45", 2),         # common belief is not truth
    ("K_a p & K_b p -> C{a,b} p", "S5", 3),  # mutual knowledge is not common knowledge
    ("~(p & ~K_a p)", "S5", 2),           # the Moore sentence is satisfiable
])
def test_invalid_formulas_get_a_minimal_counter_model(formula, logic, n_worlds):
    v = prove(formula, logic=logic, worlds=4)
    assert not v.valid and v.exact
    m = v.counter_model
    assert m.n_worlds == n_worlds
    assert not m.frame_violations(logic)
    assert not m.holds(formula)  # explicit checker, at the designated world 0
    assert m.designated == (0,)


def test_small_model_bound_for_one_agent():
    assert s5_single_agent_bound("K_a p -> p") == 2
    assert s5_single_agent_bound("Kw_a p & C{a} q") == 4
    assert s5_single_agent_bound("K_a p -> K_b p") is None
    assert s5_single_agent_bound("[!p] K_a p") is None
    assert s5_single_agent_bound("p | q") == 1
    v = prove("K_a p -> K_a K_a p", worlds=2)  # bound 3 > 2 worlds: not a proof
    assert v.valid and not v.exact and v.stats["small_model_bound"] == 3


def test_moore_sentence_is_unsuccessful():
    # announcing "p, and a does not know p" makes it false: [!(p & ~K_a p)] ~(p & ~K_a p)
    assert prove("[!(p & ~K_a p)] ~(p & ~K_a p)", worlds=4).valid
    assert not prove("[!(p & ~K_a p)] (p & ~K_a p)", worlds=4).valid


def test_common_knowledge_after_announcement_is_encoded_directly():
    # public announcement of p makes p common knowledge (no reduction axiom needed)
    assert prove("[!p] C{a,b} p", worlds=4).valid
    # announcing that a knows p makes p (hence K_b p) true in every remaining world
    assert prove("[!K_a p] C{a,b} K_b p", worlds=4).valid
    # but a Moore sentence announced does not become common knowledge
    f = "[!(p & ~K_b p)] C{a,b} (p & ~K_b p)"
    v = prove(f, worlds=4)
    assert not v.valid and not v.counter_model.holds(f)


def test_find_model_returns_none_for_unsatisfiable_formulas():
    assert find_model("K_a p & ~p", logic="S5", worlds=3) is None
    assert find_model("K_a F", logic="KD45", worlds=3) is None
    m = find_model("K_a F", logic="K", worlds=3)
    assert m is not None and m.holds("K_a F") and m.inconsistent_agents() == [("a", 0)]


def test_find_model_rechecks_with_the_explicit_checker(monkeypatch):
    import numpy as np

    import delkit.verify as V

    real = V._Encoding.model

    def wrong(self, solution):
        m = real(self, solution)
        return KripkeModel(m.props, m.agents, np.zeros_like(m.valuation), m.relations, m.designated)

    monkeypatch.setattr(V._Encoding, "model", wrong)
    with pytest.raises(VerificationError, match="explicit checker rejects"):
        find_model("p & K_a p", worlds=2)


def test_find_model_rejects_bad_arguments():
    with pytest.raises(VerificationError, match="unknown logic"):
        find_model("p", logic="S4")
    with pytest.raises(VerificationError, match="at least 1 world"):
        find_model("p", worlds=0)


def test_verdict_to_dict_carries_the_counter_model():
    d = prove("K_a p -> K_b p", worlds=3).to_dict()
    assert d["valid"] is False and d["counter_model"]["delkit"] == "kripke-model"
    assert d["formula"] == "K_a p -> K_b p"


# ----------------------------------------------------------------------------- reduction axioms


def test_public_announcement_reduction_is_the_textbook_one():
    r = reduce("[!p] K_a p")
    assert show(r) == "p -> K_a (p -> p)"
    assert reduce("[!q] p") == parse("q -> p")


def test_private_announcement_reduction_for_the_oblivious_agent():
    e = private_announcement("p", ["a"], AG)
    # b is oblivious: [E,e] K_b q  <->  (p -> K_b q), and a learns: [E,e] K_a p is valid
    r = reduce(Update(e, 0, K("b", Prop("q"))))
    assert prove(Iff(r, parse("p -> K_b q")), logic="K", worlds=3).valid
    assert prove(Update(e, 0, K("a", Prop("p"))), logic="K", worlds=3).valid
    # ... and b's knowledge of p is unchanged, so [E,e] K_b p is not valid
    assert not prove(Update(e, 0, K("b", Prop("p"))), worlds=3).valid


def test_ontic_reduction_uses_postconditions():
    e = ontic({"p": False, "q": "p"}, AG, full=AG, pre="r")
    assert reduce(Update(e, 0, Prop("p"))) == parse("r -> F")
    assert valid(reduce(Update(e, 0, Iff(Prop("q"), Prop("q")))))
    r = reduce(Update(e, 0, Prop("q")))
    assert is_propositional(r) and equivalent(r, "r -> p")


def test_reduction_of_sensing_matches_the_explicit_checker():
    e = sensing("p", AG, full=["a"], partial=["b"])
    f = Update(e, 0, parse("K_a p & ~K_b p & K_b (K_a p | K_a ~p)"))
    m = KripkeModel.build([{"p"}, set()], {"a": [[0, 1]], "b": [[0, 1]]})
    assert (m.check(f) == m.check(reduce(f))).all()
    assert m.holds(f)


def test_reduction_refuses_c_in_event_preconditions():
    e = public_announcement("C{a,b} p", AG)
    with pytest.raises(VerificationError, match="common knowledge"):
        reduce(Update(e, 0, Prop("q")))


# ----------------------------------------------------------------------------- macros


def test_macro_equals_its_sequence():
    e1 = sensing("p", AG, full=["a"], partial=["b"], name="look")
    e2 = ontic({"q": "p"}, AG, full=AG, name="copy")
    e3 = semi_private_announcement("q", ["b"], AG, name="tell")
    for macro in (compose_all([e1, e2, e3]), compose_all([e1, e2, e3], prune=True)):
        res = check_macro(macro, [e1, e2, e3])
        assert res.equivalent, res.problems
        assert res.events_compared == macro.n_events


def test_pruned_macro_drops_only_impossible_events():
    e1 = public_announcement("p", AG, name="p!")
    e2 = semi_private_announcement("p", ["a"], AG, name="ask")
    full, pruned = compose(e1, e2), compose(e1, e2, prune=True)
    assert pruned.n_events < full.n_events
    assert check_macro(pruned, [e1, e2]).equivalent


def test_tampered_macros_are_caught():
    e1 = ontic({"p": True}, AG, full=AG, name="set")
    e2 = sensing("p", AG, full=["a"], name="look")
    good = compose(e1, e2)
    # wrong order
    assert not check_macro(compose(e2, e1).renamed("x"), [e1, e2]).equivalent
    # a postcondition changed
    posts = list(good.post)
    posts[0] = {**posts[0], "p": parse("q")}
    bad_post = EventModel(good.events, good.agents, good.pre, tuple(posts), good.relations, good.designated)
    res = check_macro(bad_post, [e1, e2])
    assert not res.equivalent and any("postcondition of 'p'" in p and "e.g. where" in p for p in res.problems)
    # a precondition weakened
    pres = list(good.pre)
    pres[1] = parse("T")
    res = check_macro(EventModel(good.events, good.agents, tuple(pres), good.post, good.relations,
                                 good.designated), [e1, e2])
    assert not res.equivalent and any("precondition" in p for p in res.problems)
    # a relation changed: b now tells the sensing outcomes apart
    from delkit.models.relation import Relation

    rels = dict(good.relations)
    rels["b"] = Relation.identity(good.n_events)
    res = check_macro(EventModel(good.events, good.agents, good.pre, good.post, rels, good.designated), [e1, e2])
    assert not res.equivalent and any("relation of 'b'" in p for p in res.problems)


def test_macro_with_modal_preconditions_is_checked_after_reduction():
    e1 = public_announcement("K_a p", AG, name="a_knows")
    e2 = public_announcement("K_b p", AG, name="b_knows")
    macro = compose(e1, e2)
    res = check_macro(macro, [e1, e2], worlds=2)
    assert res.equivalent and res.bounded
    # pre(e;e) = K_a p & [a_knows,e] K_b p = K_a p & (K_a p -> K_b (K_a p -> p)), which is K_a p in S5 (by T)
    # but not in K; and it is not K_b p in either
    def with_pre(text):
        return EventModel(macro.events, macro.agents, (parse(text),), macro.post, macro.relations, macro.designated)

    assert check_macro(with_pre("K_a p"), [e1, e2], logic="S5", worlds=3).equivalent
    res = check_macro(with_pre("K_a p"), [e1, e2], logic="K", worlds=3)
    assert not res.equivalent and res.bounded
    assert not check_macro(with_pre("K_b p"), [e1, e2], logic="S5", worlds=3).equivalent


def test_satisfiable_is_what_compose_prune_uses():
    e1 = public_announcement("p", AG, name="p!")
    e2 = public_announcement("~p", AG, name="notp!")
    c = compose(e1, e2, prune=True)  # the only event is impossible; kept to stay well-formed
    assert c.n_events == 1 and not satisfiable(c.pre[0])
    assert Not(c.pre[0]) is not None


def test_run_demo(tmp_path):
    from delkit.demo import proofs
    from delkit.io.formats import load_model

    res = proofs(tmp_path)
    assert res["ok"], res
    assert "KD45 false-belief counter-model 2 worlds" in res["summary"]
    assert "mutual≠common counter-model 3 worlds" in res["summary"]
    m = load_model(tmp_path / "mutual_not_common.json")
    assert m.holds("K_a p & K_b p & ~C{a,b} p")


def test_macro_designated_events_are_reported_whole():
    """Regression: a macro whose events are not the sequence's was told the sequence designates [] (the
    sequence's designated events were filtered by the macro's names before being printed)."""
    look = sensing("p", AG, full=["a"], name="look")
    flip = ontic({"q": "p"}, AG, full=AG, name="copy")
    ref = compose(look, flip)
    seq_des = sorted(ref.events[d] for d in ref.designated)
    assert len(seq_des) == 2  # both outcomes of sensing are designated
    renamed = EventModel(tuple(f"x{i}" for i in range(ref.n_events)), ref.agents, ref.pre, ref.post,
                         ref.relations, ref.designated)
    res = check_macro(renamed, [look, flip])
    line = [p for p in res.problems if p.startswith("designated events differ")]
    assert line == [f"designated events differ: macro {sorted(renamed.events[d] for d in renamed.designated)} "
                    f"vs sequence {seq_des}"]
    # one designated event dropped from the designated set, the events kept: caught on the common events
    fewer = EventModel(ref.events, ref.agents, ref.pre, ref.post, ref.relations, ref.designated[:1])
    res = check_macro(fewer, [look, flip])
    assert f"designated events differ: macro {[ref.events[ref.designated[0]]]} vs sequence {seq_des}" in res.problems
    assert check_macro(ref, [look, flip]).equivalent
