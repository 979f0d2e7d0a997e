"""Hand-checked cases of the explicit engine: every expected value below was worked out on paper."""

from __future__ import annotations

import numpy as np
import pytest

from delkit import (
    KripkeModel,
    ModelError,
    ParseError,
    UnknownSymbolError,
    announcement,
    bisimilar,
    canonical_hash,
    compose,
    contract,
    ontic,
    parse,
    private_announcement,
    product_update,
    public_announcement,
    semi_private_announcement,
    sensing,
    show,
)
from delkit.logic.formula import Update
from delkit.models.events import EventModel
from delkit.models.relation import Relation


def coin() -> KripkeModel:
    """A coin lies heads (p) or tails; neither a nor b can tell. Actual: heads."""
    return KripkeModel.build([{"p"}, set()], {"a": [[0, 1]], "b": [[0, 1]]}, [0])


# ----------------------------------------------------------------------------- parsing


def test_parse_error_reports_line_and_column():
    with pytest.raises(ParseError) as err:
        parse("K_a p &\n  & q", source="spec.txt")
    assert err.value.line == 2 and err.value.column == 3
    assert "spec.txt:2:3" in str(err.value)


def test_parse_error_at_end_points_past_last_character():
    with pytest.raises(ParseError) as err:
        parse("p & (q |")
    assert (err.value.line, err.value.column) == (1, 9)


def test_precedence_and_printing():
    f = parse("~p & q | r -> s <-> t")
    assert f == parse("(((~p) & q) | r -> s) <-> t")
    assert show(f) == "~p & q | r -> s <-> t"
    assert parse("[!p] K_a p & q") == parse("([!p] K_a p) & q")
    assert parse("p -> q -> r") == parse("p -> (q -> r)")


# ----------------------------------------------------------------------------- static semantics


def test_knowledge_on_coin():
    m = coin()
    assert m.holds("p & ~K_a p & ~K_b p & ~Kw_a p")
    assert m.holds("C{a,b} (~Kw_a p & ~Kw_b p)")
    assert m.holds("K_a (p | ~p)")


def test_distributed_knowledge():
    # w0: p q, w1: p ~q, w2: ~p q. a confuses w0/w1 (knows p), b confuses w0/w2 (knows q)
    m = KripkeModel.build([{"p", "q"}, {"p"}, {"q"}], {"a": [[0, 1], [2]], "b": [[0, 2], [1]]}, [0])
    assert m.holds("K_a p & ~K_a q & K_b q & ~K_b p")
    assert m.holds("D{a,b} (p & q)")
    assert not m.holds("E{a,b} (p & q)")
    assert np.array_equal(m.check("D{a} q"), m.check("K_a q"))


def test_common_knowledge_is_a_full_fixpoint_not_depth_one():
    # a line of 7 worlds alternating a/b links; p fails only at the far end (6 steps away)
    n = 7
    worlds = [{"p"}] * (n - 1) + [set()]
    a_blocks = [[i, i + 1] for i in range(0, n - 1, 2)]
    b_blocks = [[0]] + [[i, i + 1] for i in range(1, n - 1, 2)]
    m = KripkeModel.build(worlds, {"a": a_blocks, "b": b_blocks}, [0], props=["p"])
    assert m.holds("E{a,b} p")  # depth 1: everybody knows p at w0
    assert m.holds("E{a,b} E{a,b} p")
    assert not m.holds("C{a,b} p")  # but p fails 6 steps away
    assert list(m.check("C{a,b} p")) == [False] * n


def test_common_belief_is_transitive_not_reflexive_closure():
    # KD45: at w0 (p false) both agents believe p (they only consider w1 possible)
    m = KripkeModel.build([set(), {"p"}], {"a": {"pairs": [(0, 1), (1, 1)]}, "b": {"pairs": [(0, 1), (1, 1)]}},
                          [0], props=["p"])
    assert m.is_kd45() and not m.is_s5()
    assert m.holds("C{a,b} p & ~p")
    assert m.holds("C{a} p & K_a p")


def test_moore_sentence_becomes_false_when_announced():
    m = coin()
    moore = parse("p & ~K_a p")
    assert m.holds(moore)
    assert m.holds(parse("[!(p & ~K_a p)] ~(p & ~K_a p)"))
    assert m.announce(moore).holds("K_a p & C{a,b} p")


def test_unknown_symbols_are_named():
    with pytest.raises(UnknownSymbolError, match="unknown agent 'c'"):
        coin().holds("K_c p")
    with pytest.raises(UnknownSymbolError, match="unknown proposition 'zz'"):
        coin().holds("zz")


def test_model_errors_say_what_is_wrong():
    with pytest.raises(ModelError, match="unknown world 'w9'"):
        KripkeModel.build({"w0": {"p"}}, {"a": [["w0", "w9"]]}, ["w0"])
    with pytest.raises(ModelError, match="no accessibility relation for agent"):
        KripkeModel(("p",), ("a", "b"), np.zeros((1, 1), bool), {"a": Relation.identity(1)}, (0,))


# ----------------------------------------------------------------------------- updates and observability


def test_public_announcement_equals_restriction():
    m = coin()
    upd = product_update(m, public_announcement("p", ["a", "b"]))
    assert bisimilar(upd, m.announce("p"))
    assert upd.holds("C{a,b} p")


def test_private_announcement_leaves_oblivious_agent_with_old_beliefs():
    m = product_update(coin(), private_announcement("p", ["a"], ["a", "b"]))
    assert m.holds("K_a p & ~K_b p & ~K_b K_a p & K_b ~Kw_a p")  # b wrongly believes a is ignorant
    assert m.is_kd45() and not m.is_s5()


def test_semi_private_announcement_b_knows_that_a_knows_whether():
    m = product_update(coin(), semi_private_announcement("p", ["a"], ["a", "b"]))
    assert m.holds("K_a p & ~Kw_b p & K_b Kw_a p & C{a,b} Kw_a p")
    assert m.is_s5()


def test_sensing_with_full_partial_and_oblivious_observers():
    m = KripkeModel.build([{"p"}, set()], {"a": [[0, 1]], "b": [[0, 1]], "c": [[0, 1]]}, [0])
    peek = sensing("p", ["a", "b", "c"], full=["a"], partial=["b"])
    after = product_update(m, peek)
    assert after.holds("K_a p")
    assert after.holds("~Kw_b p & K_b Kw_a p")
    assert after.holds("~Kw_c p & K_c ~Kw_a p")  # c is oblivious: believes nobody looked
    # the same action when the coin shows tails: a learns ~p
    tails = product_update(m.with_designated([1]), peek)
    assert tails.holds("K_a ~p & K_b Kw_a p")


def test_announcement_to_partial_observer():
    m = KripkeModel.build([{"p"}, set()], {"a": [[0, 1]], "b": [[0, 1]]}, [0])
    after = product_update(m, announcement("p", ["a", "b"], full=["a"], partial=["b"]))
    assert after.holds("K_a p & ~Kw_b p & K_b Kw_a p")


def test_ontic_action_seen_and_unseen():
    m = KripkeModel.build([set()], {"a": [[0]], "b": [[0]]}, [0], props=["p"])
    flip = ontic({"p": True}, ["a", "b"], full=["a"])
    after = product_update(m, flip)
    assert after.holds("p & K_a p & K_b ~p & K_a K_b ~p")  # b did not see it: false belief


def test_postconditions_are_simultaneous_and_conditional():
    m = KripkeModel.build([{"p"}, {"q"}], {"a": [[0, 1]]}, [0, 1], props=["p", "q"])
    swap = EventModel.build({"e": {"pre": "T", "post": {"p": "q", "q": "p"}}}, {"a": [["e"]]}, ["e"])
    after = product_update(m, swap)
    assert [after.true_props(w) for w in range(2)] == [{"q"}, {"p"}]
    cond = ontic([("q", True, "p")], ["a"], full=["a"])
    after2 = product_update(m, cond)
    assert [after2.true_props(w) for w in range(2)] == [{"p", "q"}, {"q"}]


def test_update_modality_matches_explicit_product():
    m = coin()
    peek = sensing("p", ["a", "b"], full=["a"])
    f = Update(peek, peek.event_index("yes"), parse("K_a p"), "peek")
    assert m.holds(f)
    assert m.holds(parse("[peek,yes] (K_a p & ~K_b K_a p)", events={"peek": peek}))
    # at the tails world the "yes" event is not executable: the box holds vacuously there
    assert list(m.check(f)) == [True, True]


# ----------------------------------------------------------------------------- bisimulation and composition


def test_contraction_collapses_copies_and_hash_ignores_world_order():
    m = KripkeModel.build([{"p"}, set(), {"p"}, set()], {"a": [[0, 1, 2, 3]], "b": [[0, 1], [2, 3]]}, [0])
    c = contract(m)
    assert c.n_worlds == 2
    assert bisimilar(c, m)
    perm = KripkeModel.build([set(), {"p"}, set(), {"p"}], {"a": [[0, 1, 2, 3]], "b": [[0, 1], [2, 3]]}, [3])
    assert canonical_hash(perm) == canonical_hash(m)
    other = KripkeModel.build([{"p"}, set()], {"a": [[0], [1]], "b": [[0, 1]]}, [0])
    assert canonical_hash(other) != canonical_hash(m)
    assert not bisimilar(other, m)


def test_refinement_needs_more_than_one_pass():
    # two chains that agree for 3 steps and differ at the 4th world: a single pass cannot split them
    def chain(last: set[str]) -> KripkeModel:
        return KripkeModel.build([set(), set(), set(), last], {"a": {"pairs": [(0, 1), (1, 2), (2, 3), (3, 3)]}},
                                 [0], props=["p"])

    assert not bisimilar(chain({"p"}), chain(set()))
    assert bisimilar(chain(set()), KripkeModel.build([set()], {"a": {"pairs": [(0, 0)]}}, [0], props=["p"]))


def test_composition_theorem_with_epistemic_precondition():
    m = coin()
    peek = sensing("p", ["a", "b"], full=["a"])
    tell = public_announcement("K_a p", ["a", "b"], name="tell")  # needs the peek to have happened
    seq = product_update(product_update(m, peek), tell)
    macro = product_update(m, compose(peek, tell))
    assert bisimilar(seq, macro)
    assert macro.holds("C{a,b} p")


def test_contraction_of_partitions_merges_classes_through_bisimilar_worlds():
    # b links w0-w3 and w1-w2; w0~w1 and w2~w3 are bisimilar, so in the quotient b links the two classes
    m = KripkeModel.build([set(), set(), {"p"}, {"p"}], {"a": [[0, 1, 2, 3]], "b": [[0, 3], [1, 2]]}, [0])
    c = contract(m)
    assert c.n_worlds == 2 and bisimilar(c, m)
    assert c.holds("~Kw_b p") and m.holds("~Kw_b p")
    assert canonical_hash(c) == canonical_hash(m)


def test_update_with_composed_event_names_round_trips():
    peek = sensing("p", ["a", "b"], full=["a"])
    macro = compose(peek, public_announcement("K_a p", ["a", "b"], name="tell"), name="M")
    f = Update(macro, 0, parse("K_a p"), "M")
    assert show(f) == '[M,"yes;e"] K_a p'
    assert parse(show(f), events={"M": macro}) == f


def test_props_of_update_includes_postconditions():
    from delkit.logic.formula import props_of

    flip = ontic([("q", True, "r")], ["a"], full=["a"])
    assert props_of(Update(flip, 0, parse("p"))) == {"p", "q", "r"}
