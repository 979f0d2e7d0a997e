"""Macros: declaration, grounding, z3 proof of composition = sequence, Listing 4's counterexample."""

from __future__ import annotations

from pathlib import Path

import pytest

from delkit.errors import ParseError
from planners.epico import generate
from planners.hierarchy import epistemic_task
from planners.macros import (
    check_handwritten,
    flatten,
    ground_handwritten,
    ground_macros,
    parse_macros,
    prove_macro,
    sequence_states,
)

LISTING4 = Path(__file__).resolve().parents[2] / "specs" / "epico" / "listing4.txt"


@pytest.fixture(scope="module")
def alpha2():
    inst = generate("alpha", 2)
    task, ptask, ms = epistemic_task(inst)
    return inst, task, ms


def test_grounding_and_flatten(alpha2):
    _, task, ms = alpha2
    # the paper's reading (the default): both robots' colours are modelled, so both robots' macros
    assert {m.name for m in ms} == {f"pspb_and_announce_{r}_{c}" for r in ("robot1", "robot2")
                                    for c in ("red", "black")}
    reduced = generate("alpha", 2, owners=("robot1",))
    assert {m.name for m in epistemic_task(reduced)[2]} == {f"pspb_and_announce_robot1_{c}" for c in ("red", "black")}
    m = ms[0]
    assert m.step_names == ("put_on_shared_robot1_red", "announce_block_on_barrier_robot1_red")
    assert flatten(["sense_table_robot1", m.name], ms) == ["sense_table_robot1", *m.step_names]


def test_composition_proved_equal(alpha2):
    _, task, ms = alpha2
    s = sequence_states(task, [task.action("sense_table_robot1")], task.initial)[1][-1]
    proof = prove_macro(task, ms[0], s)
    assert proof.equal and proof.obligations > 0 and proof.bisimilar_on_state, proof.problems


def test_proof_can_fail(alpha2):
    """Swap a macro's steps for a different pair: the composed model of the swapped macro differs from the
    declared sequence (so prove_macro is not vacuous)."""
    from dataclasses import replace

    from delkit.logic.formula import Not
    from delkit.models.compose import compose_all
    from delkit.models.events import EventModel
    from delkit.verify import check_macro

    _, task, ms = alpha2
    s = sequence_states(task, [task.action("sense_table_robot1")], task.initial)[1][-1]
    ems = sequence_states(task, ms[0].steps, s)[0]
    wrong = compose_all([ems[0]])  # the ontic step alone, renamed like the pair's designated event
    bad = check_macro(wrong, ems)
    assert not bad.equivalent
    assert prove_macro(task, replace(ms[0], steps=ms[0].steps[:1]), s).equal  # a one-step macro is its step
    # a composed model with one postcondition wrong: the z3 obligations catch it
    good = compose_all(ems)
    p = next(iter(good.post[0]))
    posts = (dict(good.post[0]) | {p: Not(good.post[0][p])},) + tuple(good.post[1:])
    broken = EventModel(good.events, good.agents, good.pre, posts, good.relations, good.designated, good.name)
    proof = prove_macro(task, ms[0], s, composed=broken)
    assert not proof.equal and any(p in x for x in proof.problems)


def test_listing4_inconsistent():
    inst = generate("alpha", 2)
    htask, hand = ground_handwritten(inst.domain_text, inst.problem_text, LISTING4.read_text())
    macros = ground_macros(htask, parse_macros(inst.domain_text), inst.problem_text)
    res = check_handwritten(htask, hand, macros)
    assert not res.consistent
    cex = res.counterexample
    assert cex["plan"] and "applicable" in cex["difference"] or "after" in cex["difference"]
    # replaying the counterexample: exactly one of the two is applicable / results differ
    m = htask.initial
    for name in cex["plan"]:
        m = sequence_states(htask, [htask.action(name)], m)[1][-1]
    h = htask.action(cex["handwritten"])
    mac = next(x for x in macros if x.name == cex["macro"])
    assert htask.executable(h, m) != (sequence_states(htask, mac.steps, m) is not None) or \
        "after" in cex["difference"]


def test_bad_declarations():
    dom = generate("alpha", 1).domain_text
    with pytest.raises(ParseError, match="not one of its parameters"):
        parse_macros(dom.replace("(announce_block_on_barrier ?ag ?c)", "(announce_block_on_barrier ?ag ?z)"))
    with pytest.raises(ParseError, match=":steps"):
        parse_macros(dom.replace(":steps ((put", ":stepz ((put"))
    inst = generate("alpha", 1)
    task, _, _ = epistemic_task(inst, macros=False)
    bad = parse_macros(dom.replace("(put_on_shared ?ag ?c)", "(put_on_sharde ?ag ?c)"))
    with pytest.raises(ParseError, match="not an action"):
        ground_macros(task, bad, inst.problem_text)


def test_cli_macros(capsys):
    from delkit.cli import main

    assert main(["epico", "macros", "--colors", "2", "--json"]) == 0
    import json

    rep = json.loads(capsys.readouterr().out)
    assert rep["all_equal"] and len(rep["proofs"]) == 2
    assert not rep["handwritten_check"]["consistent"]


def test_macro_reference_is_the_planners_transition():
    """A macro's reference sequence (used by its z3 proof) and the planner's transition agree on applicability:
    an announcement false in one of several designated worlds makes the step inapplicable in both (a copy that
    only required *some* designated world to survive once accepted it)."""
    from delkit.logic.formula import Prop
    from delkit.models.kripke import KripkeModel
    from planners.task import ActionSpec, MacroSpec, Task, apply_action

    agents = ("a", "b")
    m = KripkeModel.build([{"p"}, set()], {ag: [[0, 1]] for ag in agents}, designated=[0, 1], props=["p"])
    ann = ActionSpec("tell_p", "announcement", sensed=((Prop("p"), Prop("p") | ~Prop("p")),),
                     full=(("a", Prop("p") | ~Prop("p")), ("b", Prop("p") | ~Prop("p"))))
    task = Task("t", ("p",), agents, m, (ann, MacroSpec("twice", (ann, ann))), Prop("p"))
    assert apply_action(task, ann, m) is None
    assert sequence_states(task, [ann], m) is None
    assert sequence_states(task, [ann, ann], m) is None and apply_action(task, task.action("twice"), m) is None
    single = KripkeModel.build([{"p"}, set()], {ag: [[0, 1]] for ag in agents}, designated=[0], props=["p"])
    seq = sequence_states(task, [ann, ann], single)
    assert seq is not None and apply_action(task, task.action("twice"), single) is not None
    end = seq[1][-1]
    assert end.designated and all(end.valuation[w, end.props.index("p")] for w in end.designated)
