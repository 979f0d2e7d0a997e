"""World description, plan format and symbolic effects (no physics)."""

from __future__ import annotations

import json

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from arms.demo import demo_plan
from arms.plan import load_plan, parse_plan, symbolic_trace
from arms.world import ArmsError, Layout, PlanError, World, initial_state


def _plan(actions, stacks=None):
    stacks = stacks or {"robot1": [["green"], ["red", "black"], []], "robot2": [["blue"], [], []]}
    return {"world": {"stacks": stacks}, "actions": actions}


def test_demo_plan_symbolic_trace_moves_red_to_robot2():
    plan = demo_plan()
    states = symbolic_trace(plan)
    assert len(states) == len(plan.actions) + 1
    end = states[-1].places
    assert (end["red"].kind, end["red"].robot, end["red"].stack, end["red"].level) == ("stack", "robot2", 1, 0)
    assert (end["black"].robot, end["black"].stack, end["black"].level) == ("robot1", 0, 1)
    # after put_on_barrier, red is on the shared table
    i = next(k for k, a in enumerate(plan.actions) if a.name == "put_on_barrier")
    assert states[i + 1].places["red"].kind == "barrier"


def test_listing5_positional_and_keyword_args_agree():
    pos = parse_plan(_plan([{"robot": "robot1", "action": "pick", "args": ["black", "red", 1, 1]}]))
    kw = parse_plan(_plan([{"robot": "robot1", "action": "pick", "block": "black", "on": "red", "level": 1,
                            "stack": 1}]))
    assert pos.actions == kw.actions
    assert str(pos.actions[0]) == "robot1: pick(black, red, 1, 1)"


@pytest.mark.parametrize("action, fragment", [
    ({"robot": "robot1", "action": "pick", "args": ["red", "table", 0, 1]}, "covered by 'black'"),
    ({"robot": "robot1", "action": "pick", "args": ["black", "green", 1, 1]}, "lies on 'red'"),
    ({"robot": "robot2", "action": "pick", "args": ["black", "red", 1, 1]}, "not on robot2's table"),
    ({"robot": "robot1", "action": "put_on_barrier", "args": ["green"]}, "does not hold"),
    ({"robot": "robot1", "action": "take_from_barrier", "args": ["green"]}, "not on the shared table"),
])
def test_preconditions_are_checked(action, fragment):
    plan = parse_plan(_plan([action]))
    with pytest.raises(PlanError, match="action 0") as exc:
        symbolic_trace(plan)
    assert fragment in str(exc.value)


@pytest.mark.parametrize("obj, fragment", [
    (_plan([], {"robot1": [["red"]], "robot2": [["red"]]}), "unique"),
    (_plan([], {"robot1": [["mauve"]], "robot2": [[]]}), "unknown colour"),
    (_plan([{"robot": "robot3", "action": "sense"}]), "'robot' must be one of"),
    (_plan([{"robot": "robot1", "action": "fly"}]), "unknown action"),
    (_plan([{"robot": "robot1", "action": "pick", "args": ["black", "red", "x", 1]}]), "integer"),
    ({"world": {}}, "needs both"),
])
def test_bad_plans_are_rejected_with_a_reason(obj, fragment):
    with pytest.raises(ArmsError, match=fragment):
        parse_plan(obj)


def test_load_plan_reports_json_position(tmp_path):
    p = tmp_path / "bad.json"
    p.write_text('{"world": [1, 2,,]}')
    with pytest.raises(ArmsError, match=r"bad.json:1:\d+"):
        load_plan(p)


def test_plan_json_round_trip():
    plan = demo_plan()
    again = parse_plan(json.loads(json.dumps(plan.to_json())))
    assert again.actions == plan.actions
    assert again.world.blocks == plan.world.blocks


def test_layout_mirrors_the_two_robots():
    lay = Layout()
    for s in range(3):
        a, b = lay.stack_xy(0, s), lay.stack_xy(1, s)
        assert np.allclose(a, b * np.array([1, -1]))
    assert np.allclose(lay.base_pos(0), lay.base_pos(1) * np.array([1, -1, 1]))


@settings(max_examples=40, deadline=None)
@given(st.integers(0, 2), st.integers(0, 2))
def test_pick_then_place_back_restores_the_state(src, dst):
    """pick(top of stack src) ; place(stack dst) ; pick ; place(stack src) = identity on places."""
    world = World.from_json({"stacks": {"robot1": [["a", "b"], ["c"], ["d", "e", "f"]], "robot2": [[]]},
                             "colors": {b: "red" for b in "abcdef"}})
    s0 = initial_state(world)
    top = s0.on_top("stack", "robot1", src)[-1][1]
    acts = [{"robot": "robot1", "action": "pick", "block": top},
            {"robot": "robot1", "action": "place", "block": top, "stack": dst},
            {"robot": "robot1", "action": "pick", "block": top},
            {"robot": "robot1", "action": "place", "block": top, "stack": src}]
    plan = parse_plan({"world": world.to_json(), "actions": acts})
    states = symbolic_trace(plan)
    assert dict(states[-1].places) == dict(s0.places)
    assert states[2].places[top].stack == dst
