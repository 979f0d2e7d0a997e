"""EPDDL formulas mean what plank's model checker says (the traps in reading it): ``<G>φ`` is a conjunction of
diamonds, ``[C. G]`` the transitive (not reflexive) closure, and a state satisfies φ iff every designated world
does. A table of hand-checked cases on a non-reflexive K model, then a property: on random K models and random
formulas, the reader's formulas evaluated by delkit agree with a naive evaluator written from plank's
definitions (``model_checker::holds_in``)."""

from __future__ import annotations

from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from planners.lang.epddl2026 import load_epddl2026

DOMAIN = "(define (domain sem) (:predicates (p) (q)) (:event e) (:action act :action-type (basic (e))))"


def _task(tmp: Path, worlds: list[str], rel: dict[str, list[tuple[str, str]]], labels: dict[str, list[str]],
          designated: list[str], goal: str):
    d, p = tmp / "d.epddl", tmp / "p.epddl"
    d.write_text(DOMAIN)
    rels = " ".join(f"{a} (:and {' '.join(f'({x} {y})' for x, y in pairs)})" for a, pairs in rel.items())
    labs = " ".join(f"{w} (:and {' '.join(f'({x})' for x in labels.get(w, []))})" for w in worlds)
    p.write_text(f"(define (problem t) (:domain sem) (:agents a b)\n (:init :worlds ({' '.join(worlds)})\n"
                 f" :relations ({rels})\n :labels ({labs})\n :designated ({' '.join(designated)}))\n"
                 f" (:goal {goal}))")
    return load_epddl2026(d, p)


# w1 (nothing true) -a-> w2 (p), w3 (q); a loops on w2, w3; b loops everywhere. Not reflexive for a at w1.
W = ["w1", "w2", "w3"]
R = {"a": [("w1", "w2"), ("w1", "w3"), ("w2", "w2"), ("w3", "w3")],
     "b": [("w1", "w1"), ("w2", "w2"), ("w3", "w3")]}
L = {"w2": ["p"], "w3": ["q"]}

TABLE = [
    # formula at w1                           expected  why
    ("(<(a b)> (p))",                           False,  "conjunction of diamonds: b has no p-successor"),
    ("(not ([(a b)] (not (p))))",               True,   "the dual of [G] would say True"),
    ("(<a> (p))",                               True,   "a reaches w2"),
    ("([a] (p))",                               False,  "a reaches w3"),
    ("([All] (or (p) (q) (not (p))))",          True,   "[All] is a conjunction of boxes"),
    ("(<All> (p))",                             False,  "<All> needs a p-successor for b too"),
    ("(<Kw. a> (p))",                           True,   "a sees p and not p"),
    ("([Kw. a] (p))",                           False,  ""),
    ("([Kw. b] (p))",                           True,   "b only sees w1"),
    ("([Kw. (a b)] (p))",                       False,  "conjunction over the group"),
    ("(<Kw. (a b)> (p))",                       False,  "b knows whether p"),
    ("([C. a] (or (p) (q)))",                   True,   "closure from w1 is {w2,w3}, w1 not in it"),
    ("([C. (a b)] (or (p) (q)))",               False,  "b's loop puts w1 in the closure"),
    ("(<C. a> (q))",                            True,   ""),
    ("(<C. b> (p))",                            False,  ""),
    ("([a] ([a] (or (p) (q))))",                True,   "nested boxes"),
    ("(imply (p) (q))",                         True,   "p is false at w1"),
    ("(exists (?x - agent) (<?x> (q)))",        True,   "quantifier over agents"),
    ("(forall (?x - agent | (/= ?x b)) ([?x] (or (p) (q))))", True, "filtered quantifier: only a"),
]


@pytest.mark.parametrize("formula,expected,why", TABLE, ids=[t[0] for t in TABLE])
def test_trap_table(tmp_path, formula: str, expected: bool, why: str) -> None:
    task = _task(tmp_path, W, R, L, ["w1"], formula)
    assert task.initial.holds(task.goal) is expected, why


@pytest.mark.parametrize("formula,expected", [("(p)", False), ("(not (p))", False), ("(or (p) (q))", True),
                                              ("([a] (or (p) (q)))", True)])
def test_multi_pointed_state_satisfies_iff_every_designated_world_does(tmp_path, formula, expected) -> None:
    task = _task(tmp_path, W, R, L, ["w2", "w3"], formula)
    assert task.initial.holds(task.goal) is expected


# ----------------------------------------------------------------------------- property vs plank's definitions
AG = ("a", "b")


def _formulas():
    atom = st.sampled_from(["p", "q"]).map(lambda x: (f"({x})", ("atom", x)))

    def ext(children):
        un = st.tuples(st.sampled_from(["not"]), children)
        bi = st.tuples(st.sampled_from(["and", "or", "imply"]), children, children)
        grp = st.sampled_from([("a",), ("b",), ("a", "b")])
        mod = st.tuples(st.sampled_from(["box", "dia", "kwbox", "kwdia", "cbox", "cdia"]), grp, children)

        def show_un(t):
            return f"(not {t[1][0]})", ("not", t[1][1])

        def show_bi(t):
            return f"({t[0]} {t[1][0]} {t[2][0]})", (t[0], t[1][1], t[2][1])

        def show_mod(t):
            kind, g, (text, tree) = t
            gt = g[0] if len(g) == 1 else "(" + " ".join(g) + ")"
            pre = {"box": "[", "dia": "<", "kwbox": "[Kw. ", "kwdia": "<Kw. ", "cbox": "[C. ", "cdia": "<C. "}[kind]
            close = "]" if pre.startswith("[") else ">"
            return f"({pre}{gt}{close} {text})", (kind, g, tree)
        return st.one_of(un.map(show_un), bi.map(show_bi), mod.map(show_mod))
    return st.recursive(atom, ext, max_leaves=6)


def _ref(tree, w: int, succ: dict, lab: dict) -> bool:
    """plank's ``model_checker::holds_in``, transcribed."""
    op = tree[0]
    if op == "atom":
        return tree[1] in lab[w]
    if op == "not":
        return not _ref(tree[1], w, succ, lab)
    if op in ("and", "or", "imply"):
        x, y = _ref(tree[1], w, succ, lab), _ref(tree[2], w, succ, lab)
        return (x and y) if op == "and" else (x or y) if op == "or" else ((not x) or y)
    _, g, sub = tree
    if op in ("cbox", "cdia"):
        todo = {v for i in g for v in succ[i][w]}
        seen: set[int] = set()
        while todo:
            v = todo.pop()
            seen.add(v)
            todo |= {u for i in g for u in succ[i][v]} - seen
        vals = [_ref(sub, v, succ, lab) for v in seen]
        return all(vals) if op == "cbox" else any(vals)
    out = True
    for i in g:
        vals = [_ref(sub, v, succ, lab) for v in succ[i][w]]
        out &= {"box": all(vals), "dia": any(vals), "kwbox": all(vals) or not any(vals),
                "kwdia": any(vals) and not all(vals)}[op]
    return out


@settings(max_examples=60, deadline=None)
@given(f=_formulas(), pairs=st.lists(st.tuples(st.sampled_from(AG), st.integers(0, 2), st.integers(0, 2)),
                                     max_size=10),
       labels=st.lists(st.sets(st.sampled_from(["p", "q"])), min_size=3, max_size=3),
       des=st.sets(st.integers(0, 2), min_size=1))
def test_formulas_agree_with_plank_definitions(tmp_path_factory, f, pairs, labels, des) -> None:
    text, tree = f
    tmp = tmp_path_factory.mktemp("sem")
    rel = {a: [(f"w{x}", f"w{y}") for b, x, y in pairs if b == a] or [] for a in AG}
    succ = {a: {w: {y for b, x, y in pairs if b == a and x == w} for w in range(3)} for a in AG}
    task = _task(tmp, ["w0", "w1", "w2"], rel, {f"w{i}": sorted(s) for i, s in enumerate(labels)},
                 [f"w{d}" for d in sorted(des)], text)
    lab = dict(enumerate(labels))
    assert task.initial.holds(task.goal) == all(_ref(tree, d, succ, lab) for d in des), text


def test_agent_groups_in_modalities(tmp_path) -> None:
    """``(:agent-groups (G (a b)))``: [G] is the conjunction of [a] and [b], <G> of the diamonds."""
    d, p = tmp_path / "d.epddl", tmp_path / "p.epddl"
    d.write_text(DOMAIN)
    rels = " ".join(f"{a} (:and {' '.join(f'({x} {y})' for x, y in pairs)})" for a, pairs in R.items())
    p.write_text(f"(define (problem t) (:domain sem) (:agents a b) (:agent-groups (G (a b)) (H (:and a)))\n"
                 f" (:init :worlds (w1 w2 w3) :relations ({rels})\n"
                 f" :labels (w1 (:and) w2 (:and (p)) w3 (:and (q))) :designated (w1))\n"
                 f" (:goal (and (not (<G> (p))) (<H> (p)) ([C. H] (or (p) (q))))))")
    task = load_epddl2026(d, p)
    assert task.initial.holds(task.goal)


def test_library_plan_uses_epddl_semantics_like_the_cli(tmp_path) -> None:
    """``planners.epistemic.plan`` on an EPDDL task keeps states where an agent believes ⊥ (EPDDL's and plank's
    semantics), as ``delkit plan`` does: b has no accessible world, and one step makes p true."""
    from delkit.cli import main
    from planners.epistemic import plan

    d, p = tmp_path / "d.epddl", tmp_path / "p.epddl"
    d.write_text("(define (domain flip) (:predicates (p)) (:event e :effects (p))"
                 " (:action act :action-type (basic (e))))")
    p.write_text("(define (problem f) (:domain flip) (:agents a b)\n (:init :worlds (w1)\n"
                 " :relations (a (:and (w1 w1)))\n :labels (w1 (:and))\n :designated (w1))\n (:goal (p)))")
    task = load_epddl2026(d, p)
    assert [a for a, _ in task.initial.inconsistent_agents()] == ["b"]
    assert plan(task).plan == ("act",)
    assert main(["plan", str(d), str(p)]) == 0
    assert plan(task, allow_inconsistent=False).plan == ("act",)   # False: the task's default, not a pruning
    assert plan(task, consistent_beliefs=True).status == "unsolvable"   # the pruning, asked for explicitly
