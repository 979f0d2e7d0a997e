"""Distinguishing formulas (``delkit.models.bisimulation``, ``delkit model diff``).

Properties on random models of every frame class: either the models are bisimilar — then the returned
relation is a bisimulation (atoms, zig, zag, designated worlds covered) and random formulas up to modal
depth 3 cannot tell them apart — or the formula is checked by the model checker to be true in one model
and false in the other. The verdict is compared with ``bisimilar`` (a separate refinement in the same module,
with hashed signatures).
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from delkit import KripkeModel
from delkit.cli import main
from delkit.io.formats import dumps
from delkit.logic.formula import D, modal_depth, subformulas
from delkit.models.bisimulation import as_kripke, bisimilar, contract, diff, distinguishing_formula, formula_size
from delkit.testing import formulas, kripke_models, world_permutations

PROPS, AGENTS = ("p", "q"), ("a", "b")
#: probes that bisimilar models must agree on: D_G (distributed knowledge) is left out, it is invariant under
#: collective bisimulation only (a model and its contraction may differ on D_{a,b} p)
INVARIANT = formulas(PROPS, AGENTS, 3).filter(lambda f: not any(isinstance(g, D) for g in subformulas(f)))
SPECS = Path(__file__).resolve().parents[2] / "specs" / "smcdel"


def _is_bisimulation(a: KripkeModel, b: KripkeModel, pairs) -> bool:
    z = set(pairs)
    for x, y in z:
        if list(a.valuation[x]) != [b.valuation[y, b.props.index(p)] for p in a.props]:
            return False
        for ag in a.agents:
            sx, sy = a.successors(ag, x), b.successors(ag, y)
            if any(not any((x2, y2) in z for y2 in sy) for x2 in sx):  # zig
                return False
            if any(not any((x2, y2) in z for x2 in sx) for y2 in sy):  # zag
                return False
    left = {x for x, _ in z}
    right = {y for _, y in z}
    covered_a = all(any((d, e) in z for e in b.designated) for d in a.designated)
    covered_b = all(any((d, e) in z for d in a.designated) for e in b.designated)
    return covered_a and covered_b and bool(left) and bool(right)


def _check(a: KripkeModel, b: KripkeModel, probes: list) -> str:
    res = diff(a, b)
    assert res.bisimilar == bisimilar(a, b)
    if res.bisimilar:
        assert _is_bisimulation(a, b, res.relation)
        for f in probes:
            assert a.holds(f) == b.holds(f), f
        return "bisimilar"
    yes, no = (a, b) if res.true_in == "A" else (b, a)
    assert yes.holds(res.formula)
    assert not no.check(res.formula)[res.fails_at]
    assert res.fails_at in no.designated
    return "distinguished"


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.sampled_from(["S5", "KD45", "K"]).flatmap(
    lambda fr: st.tuples(kripke_models(PROPS, AGENTS, 5, frame=fr, designated="some"),
                         kripke_models(PROPS, AGENTS, 5, frame=fr, designated="some"))),
       st.lists(INVARIANT, min_size=5, max_size=5))
def test_random_pairs_are_bisimilar_or_told_apart(pair, probes):
    _check(*pair, probes)


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.sampled_from(["S5", "KD45", "K"]).flatmap(
    lambda fr: kripke_models(PROPS, AGENTS, 5, frame=fr, designated="one")), st.data(),
       st.lists(INVARIANT, min_size=5, max_size=5))
def test_bisimilar_copies_have_no_distinguishing_formula(m, data, probes):
    """A permuted copy and the contraction are bisimilar: the bisimilar branch is exercised on every run."""
    perm = data.draw(world_permutations(m.n_worlds))
    inv = np.argsort(perm)
    rels = {}
    from delkit.models.relation import Relation

    for ag, r in m.relations.items():
        rels[ag] = Relation.from_pairs(m.n_worlds, [(int(inv[x]), int(inv[y])) for x, y in r.pairs()])
    copy = KripkeModel(m.props, m.agents, m.valuation[perm], rels, tuple(int(inv[d]) for d in m.designated))
    assert _check(m, copy, probes) == "bisimilar"
    assert _check(m, contract(m), probes) == "bisimilar"
    assert distinguishing_formula(m, m.designated[0], copy, copy.designated[0]) is None


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.sampled_from(["S5", "KD45", "K"]).flatmap(
    lambda fr: kripke_models(PROPS, AGENTS, 6, frame=fr, designated="all")), st.data())
def test_pointed_formula_has_the_splitting_depth(m, data):
    """Between two worlds of one model: true at one, false at the other, and no deeper than needed (a
    formula of smaller modal depth never separates them: checked on the refinement round itself)."""
    x = data.draw(st.integers(0, m.n_worlds - 1))
    y = data.draw(st.integers(0, m.n_worlds - 1))
    f = distinguishing_formula(m, x, m, y)
    if f is None:
        assert bisimilar(m.with_designated([x]), m.with_designated([y]))
        return
    vec = m.check(f)
    assert vec[x] and not vec[y]
    from delkit.models.bisimulation import refinement_history

    history = refinement_history(m)
    split = next(k for k, blocks in enumerate(history) if blocks[x] != blocks[y])
    assert modal_depth(f) == split


def test_hand_example_depth_two():
    # both pointed models: p at the actual world; a cannot tell; in A some a-world is one where b knows ~p
    a = KripkeModel.build({"w": {"p"}, "v": set()}, {"a": [["w", "v"]], "b": [["w"], ["v"]]}, designated=["w"])
    b = KripkeModel.build({"x": {"p"}, "y": {"p"}, "z": set()}, {"a": [["x", "y", "z"]], "b": [["x"], ["y", "z"]]},
                          designated=["x"])
    res = diff(a, b)
    assert not res.bisimilar and modal_depth(res.formula) == 2 and formula_size(res.formula) <= 6
    assert a.holds(res.formula) and not b.holds(res.formula)


def test_knowledge_structure_against_its_kripke_model():
    from delkit.backends.symbolic import from_kripke
    from delkit.backends.symbolic_belief import belief_from_kripke

    m = KripkeModel.build({"w": {"p"}, "v": set(), "u": {"q"}}, {"a": [["w", "v"], ["u"]], "b": [["w"], ["v", "u"]]},
                          designated=["w"])
    ks, _ = from_kripke(m)
    assert diff(ks, m, props=m.props).bisimilar
    bs, _ = belief_from_kripke(m)
    assert diff(bs, m, props=m.props).bisimilar
    other = m.with_designated([1])
    res = diff(ks, other, props=m.props)
    assert not res.bisimilar and as_kripke(ks).holds(res.formula)
    with pytest.raises(Exception, match="more than the 2"):
        diff(ks, m, props=m.props, max_worlds=2)


def test_cli_diff_json_and_exit_codes(tmp_path, capsys):
    a = KripkeModel.build({"w": {"p"}, "v": set()}, {"a": [["w", "v"]]}, designated=["w"])
    b = KripkeModel.build({"x": {"p"}}, {"a": [["x"]]}, designated=["x"])
    c = KripkeModel.build({"s": {"p"}, "t": set(), "r": set()}, {"a": [["s", "t", "r"]]}, designated=["s"])
    for name, m in (("a", a), ("b", b), ("c", c)):
        (tmp_path / f"{name}.json").write_text(dumps(m))
    assert main(["model", "diff", str(tmp_path / "a.json"), str(tmp_path / "b.json"), "--json"]) == 1
    out = json.loads(capsys.readouterr().out)
    assert out["bisimilar"] is False and out["true_in"] == "A" and out["fails_at"] == "x"
    assert main(["model", "diff", str(tmp_path / "a.json"), str(tmp_path / "c.json"), "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["bisimilar"] is True and sorted(map(tuple, out["relation"])) == [("v", "r"), ("v", "t"), ("w", "s")]
    assert main(["model", "diff", str(tmp_path / "a.json"), str(tmp_path / "b.json")]) == 1
    text = capsys.readouterr().out
    assert "NOT bisimilar" in text and "~K_a p" in text
    (tmp_path / "bad.json").write_text("{")
    assert main(["model", "diff", str(tmp_path / "a.json"), str(tmp_path / "bad.json")]) == 2
    err = capsys.readouterr().err
    assert err.startswith("delkit: error: ") and "bad.json" in err


def test_cli_diff_smcdel_files(capsys):
    muddy = str(SPECS / "muddy3.smcdel.txt")
    assert main(["model", "diff", muddy, muddy, "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["bisimilar"] is True
    assert main(["model", "diff", muddy, muddy, "--world-a", "1,2,3", "--world-b", "1,2", "--json"]) == 1
    out = json.loads(capsys.readouterr().out)
    assert out["bisimilar"] is False and out["modal_depth"] == 0 and "symbolic" in out["note"]
    assert main(["model", "diff", muddy, muddy, "--world-a", "1,2,3", "--world-b", "1,2", "--engine", "explicit",
                 "--json"]) == 1
    assert "explicit Kripke models" in json.loads(capsys.readouterr().out)["note"]
    assert main(["model", "diff", muddy, muddy, "--world-a", "1,7"]) == 2
    assert "not in VARS" in capsys.readouterr().err
