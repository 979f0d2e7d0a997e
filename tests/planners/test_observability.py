"""Who learns what: the mA* observability cases on tiny hand-checked models.

A three-agent coin-in-the-box: the coin shows tail (not known to anybody); a holds the key and looks; b
looks iff ``looking_b``; c does not look. Expected beliefs are derived by hand from the mA* frames (fully
observant: sees action and outcome; partially: sees the action, not the outcome; oblivious: believes
nothing happened) and checked in both state representations.
"""

from __future__ import annotations

import pytest

from delkit.logic.formula import parse
from delkit.models.update import product_update
from planners.lang.mastar import parse_mastar
from planners.spaces import CompactSpace
from planners.validate import check_plan

COIN = """
fluent tail, opened, looking_b;
action open, peek, shout;
agent a, b, c;
executable open if B(a, -opened);
open causes opened;
a observes open;
b observes open if looking_b;
executable peek if B(a, opened), opened;
peek determines tail;
a observes peek;
b aware_of peek if looking_b;
executable shout if B(a, tail), tail;
shout announces tail;
a observes shout;
b observes shout if looking_b;
initially C([a,b,c], -opened);
initially C([a,b,c], LOOK);
initially tail, -opened, LOOK;
goal B(a, tail);
"""


def _task(b_looks: bool):
    return parse_mastar(COIN.replace("LOOK", "looking_b" if b_looks else "-looking_b"), "coin-mini")


def _states(task, steps):
    """Replay with delkit's product update and with CompactSpace; yield (delkit model, fast state) pairs."""
    space = CompactSpace(task)
    s, _ = space.initial()
    m = task.initial
    for name in steps:
        act = task.action(name)
        assert m.holds(act.executable), name
        m = product_update(m, task.event_model(act, m))
        s = space.step(s, name)
        yield m, s, space


def _final(task, steps):
    return list(_states(task, steps))[-1]


def _both(m, s, space, text: str) -> bool:
    f = parse(text)
    a, b = m.holds(f), space.holds(s, f)
    assert a == b, text
    return a


@pytest.mark.parametrize("b_looks", [True, False])
def test_open_full_vs_oblivious(b_looks: bool) -> None:
    m, s, sp = _final(_task(b_looks), ["open"])
    assert _both(m, s, sp, "K_a opened")
    assert _both(m, s, sp, "K_b opened") == b_looks
    # c is oblivious: it wrongly believes the box is still closed (a false belief: the model is KD45, not S5)
    assert _both(m, s, sp, "K_c ~opened")
    assert _both(m, s, sp, "K_a K_c ~opened")  # a sees that c did not look
    assert m.is_kd45() and not m.is_s5()
    if not b_looks:
        assert _both(m, s, sp, "K_b ~opened & K_a K_b ~opened")


@pytest.mark.parametrize("b_looks", [True, False])
def test_peek_full_partial_oblivious(b_looks: bool) -> None:
    m, s, sp = _final(_task(b_looks), ["open", "peek"])
    assert _both(m, s, sp, "K_a tail")
    # a partial observer learns that a knows whether tail, not the value itself
    assert _both(m, s, sp, "K_b (K_a tail | K_a ~tail)") == b_looks
    assert not _both(m, s, sp, "K_b tail")
    assert not _both(m, s, sp, "K_b ~tail")
    # c believes nothing happened: the box closed and a ignorant
    assert _both(m, s, sp, "K_c ~opened & K_c (~K_a tail & ~K_a ~tail)")
    # a knows that b knows that a knows whether (iff b looked), and that c does not know
    assert _both(m, s, sp, "K_a K_b (K_a tail | K_a ~tail)") == b_looks
    assert _both(m, s, sp, "K_a ~K_c tail")


@pytest.mark.parametrize("b_looks", [True, False])
def test_announce_full_vs_oblivious(b_looks: bool) -> None:
    m, s, sp = _final(_task(b_looks), ["open", "peek", "shout"])
    assert _both(m, s, sp, "K_b tail") == b_looks
    assert _both(m, s, sp, "C{a,b} tail") == b_looks
    assert not _both(m, s, sp, "K_c tail")
    assert _both(m, s, sp, "K_c ~K_b tail")  # c believes b never heard anything


def test_oblivious_chain_cb_oblivious() -> None:
    """CB_oblivious: peek_a (ontic "causes tails") is seen by a and c; b is oblivious. Then b believes a
    still does not believe tails, c believes a does, and c believes that b believes that a does not."""
    text = """
    fluent opened_a, tails;
    action peek_a;
    agent a, b, c;
    executable peek_a if B(a, opened_a), opened_a;
    peek_a causes tails;
    c observes peek_a;
    a observes peek_a;
    initially C([a,b,c], opened_a);
    initially opened_a, tails;
    goal B(a, tails);
    """
    task = parse_mastar(text, "cb-chain")
    m, s, sp = _final(task, ["peek_a"])
    assert _both(m, s, sp, "K_a tails")
    assert _both(m, s, sp, "K_b ~K_a tails")
    assert _both(m, s, sp, "K_c K_a tails")
    assert _both(m, s, sp, "K_c K_b ~K_a tails")
    assert _both(m, s, sp, "K_a K_c K_b ~K_a tails")
    assert not _both(m, s, sp, "C{a,b} tails")
    assert _both(m, s, sp, "C{a,c} tails")


def test_conditional_observability_is_decided_at_the_pointed_world() -> None:
    """b observes open if looking_b: with b actually looking, b observes even in worlds it considers
    possible where it does not look (mA* / EFP: conditions evaluated at the pointed world)."""
    text = COIN.replace("initially C([a,b,c], LOOK);", "").replace("LOOK", "looking_b")
    task = parse_mastar(text, "coin-unsure")
    assert not task.initial.holds(parse("K_a looking_b"))
    m, s, sp = _final(task, ["open"])
    assert _both(m, s, sp, "K_b opened")


def test_sensing_against_a_false_belief_is_a_dead_end() -> None:
    """a wrongly believes p (it missed b's flip); sensing p leaves a with no accessible world: B_a ⊥. The
    planner does not expand that state, and the checker reports the step and the agent."""
    text = """
    fluent p;
    action flip, look;
    agent a, b;
    executable flip if p;
    flip causes -p;
    b observes flip;
    executable look if T;
    look determines p;
    a observes look;
    initially C([a,b], p);
    initially p;
    goal B(a, -p);
    """.replace("executable look if T;", "")
    from planners.epistemic import Limits, plan

    task = parse_mastar(text, "false-belief")
    m, s, sp = _final(task, ["flip", "look"])
    assert m.inconsistent_agents() == [("a", m.designated[0])]
    assert sp.inconsistent(s) == ["a"]
    assert m.holds(parse("K_a ~p")) and m.holds(parse("K_a p"))  # vacuous: a believes everything
    res = check_plan(task, ["flip", "look"])
    assert not res.valid and res.step == 2 and res.agent == "a" and res.kind == "inconsistent-belief"
    strict = plan(task, limits=Limits(timeout=10))
    assert strict.status == "unsolvable" and strict.dead_ends > 0
    lax = plan(task, allow_inconsistent=True)
    assert lax.plan == ("flip", "look")
