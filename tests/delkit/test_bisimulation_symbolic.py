"""Symbolic partition refinement (``delkit.backends.bisimulation_symbolic``) against the explicit one.

Random S5 models as knowledge structures and random KD45/K models as belief structures: the verdict equals
the explicit refinement's on the translated models, the formula is checked by the explicit model checker
(true at every actual state of one, false at some actual state of the other), and its modal depth equals
the explicit one's (both are the round of the split)."""

from __future__ import annotations

from pathlib import Path

from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from delkit.backends.bisimulation_symbolic import symbolic_diff
from delkit.backends.symbolic import KnowledgeStructure, from_kripke
from delkit.backends.symbolic_belief import belief_from_kripke
from delkit.io.smcdel import parse_smcdel, structure
from delkit.logic.formula import modal_depth
from delkit.models.bisimulation import as_kripke, diff
from delkit.testing import kripke_models

PROPS, AGENTS = ("p", "q"), ("a", "b")
SPECS = Path(__file__).resolve().parents[2] / "specs" / "smcdel"


def _encode(m, frame):
    return from_kripke(m)[0] if frame == "S5" else belief_from_kripke(m)[0]


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.sampled_from(["S5", "KD45", "K"]).flatmap(
    lambda fr: st.tuples(st.just(fr), kripke_models(PROPS, AGENTS, 4, frame=fr, designated="some"),
                         kripke_models(PROPS, AGENTS, 4, frame=fr, designated="some"))))
def test_symbolic_diff_agrees_with_explicit(case):
    frame, m1, m2 = case
    s1, s2 = _encode(m1, frame), _encode(m2, frame)
    res = symbolic_diff(s1, s2, props=PROPS)
    ref = diff(m1, m2)
    assert res.bisimilar == ref.bisimilar
    if res.bisimilar:
        assert res.relation
        return
    k1, k2 = as_kripke(s1), as_kripke(s2)
    yes, no = (k1, k2) if res.true_in == "A" else (k2, k1)
    assert yes.holds(res.formula) and not no.holds(res.formula)
    if len(m1.designated) == len(m2.designated) == 1:
        assert modal_depth(res.formula) == modal_depth(ref.formula)


def test_obs_and_rel_files_are_bisimilar_and_rounds_are_symbolic():
    obs = structure(parse_smcdel((SPECS / "muddy3.smcdel.txt").read_text()))
    rel = structure(parse_smcdel((SPECS / "muddy3-belief.smcdel.txt").read_text()))
    assert symbolic_diff(obs, rel).bisimilar


def test_large_structures_beyond_the_explicit_limit():
    """Muddy children, 14 children (16,384 states, over the explicit limit of 4,096): before and after the
    father's announcement. Someone's ignorance tells them apart; the formula is checked on BDDs."""
    from delkit.logic.formula import Prop, disj

    n = 14
    kids = [str(i) for i in range(1, n + 1)]
    ks = KnowledgeStructure.create(kids, "T", {f"c{i}": [k for k in kids if k != i] for i in kids})
    someone = disj([Prop(k) for k in kids])
    after = ks.announce(someone)
    res = symbolic_diff(ks, after)
    assert not res.bisimilar
    yes, no = (ks, after) if res.true_in == "A" else (after, ks)
    assert yes.holds(res.formula) and not no.holds(res.formula)
    same = symbolic_diff(ks, ks.announce(disj([someone, ~someone])))
    assert same.bisimilar and len(same.relation) == 1000  # listed up to max_pairs


def test_back_condition_matters():
    """B's actual state has an extra ¬p successor that A's lacks: a simulation, not a bisimulation (the
    refinement must check both directions)."""
    from delkit import KripkeModel

    a = KripkeModel.build({"w": {"p"}}, {"a": {"pairs": [("w", "w")]}}, designated=["w"])
    b = KripkeModel.build({"x": {"p"}, "y": set()}, {"a": {"pairs": [("x", "x"), ("x", "y")]}}, designated=["x"])
    for first, second in ((a, b), (b, a)):
        res = symbolic_diff(belief_from_kripke(first)[0], belief_from_kripke(second)[0], props=["p"])
        assert not res.bisimilar and modal_depth(res.formula) == 1


@settings(max_examples=30, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.sampled_from(["S5", "K"]).flatmap(
    lambda fr: st.tuples(st.just(fr), kripke_models(PROPS, AGENTS, 3, frame=fr, designated="some"),
                         kripke_models(PROPS, AGENTS, 3, frame=fr, designated="some"))))
def test_diff_explanation_formulas_denote_the_sets(case):
    """The explanation's readable formulas (form_of) denote exactly the sets they name, in each structure."""
    from delkit.logic.formula import parse

    frame, m1, m2 = case
    a, b = _encode(m1, frame), _encode(m2, frame)
    res = symbolic_diff(a, b, props=PROPS)
    lines = dict(res.explanation)
    want = {"actual states of A": (a, a.actual), "actual states of B": (b, b.actual)}
    if not res.bisimilar:
        yes, no = (a, b) if res.true_in == "A" else (b, a)
        other = "B" if res.true_in == "A" else "A"
        want[f"states of {res.true_in} where the formula holds"] = (yes, yes.law & yes.evaluate(res.formula))
        want[f"actual states of {other} where it fails"] = (no, no.actual & ~no.evaluate(res.formula))
    assert set(lines) == set(want)
    for what, (s, node) in want.items():
        assert s.evaluate(parse(lines[what])) == node, (what, lines[what])
