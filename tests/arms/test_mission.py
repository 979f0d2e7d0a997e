"""The closed loop (arms.mission): friction grasps, line-of-sight sensing, DEL beliefs, monitor, replanning."""

from __future__ import annotations

import numpy as np
import pytest

from arms.beliefs import Beliefs
from arms.executor import Executor
from arms.mission import (
    GOALS,
    GoalUnreachable,
    Mission,
    parse_fault,
    random_world,
    simple_replanner,
    world_from_layout,
)
from arms.plan import parse_plan, symbolic_trace
from arms.world import ArmsError

# α with 2 colours: robot2 must tell robot1 the colour of one of its blocks. green (robot2, stack 0)
# lies under red; the hand-written α-like plan (what e-PICO's pipeline emits for α: sense, pick, put on
# the shared table, announce) uses the top block.
STACKS = {"robot1": [["b1"], ["b2", "b3"], []], "robot2": [["g1", "r1"], [], ["g2"]]}
COLOURS = {"b1": "red", "b2": "green", "b3": "red", "g1": "green", "r1": "red", "g2": "green"}
ALPHA_PLAN = [
    {"robot": "robot2", "action": "sense", "stack": 0},
    {"robot": "robot2", "action": "pick", "args": ["r1", "g1", 1, 0]},
    {"robot": "robot2", "action": "put_on_barrier", "args": ["r1"]},
    {"robot": "robot2", "action": "announce", "args": ["r1"], "to": ["robot1"], "color": "red"},
]


def _origin(world):
    return {b: r for r in world.robots for st in world.stacks[r] for b in st}


@pytest.fixture(scope="module")
def alpha_run():
    world = world_from_layout(STACKS, COLOURS)
    plan = {"world": world.to_json(), "actions": ALPHA_PLAN}
    m = Mission(world, "alpha", simple_replanner("alpha", _origin(world)), plan=plan)
    return world, m, m.run()


def test_alpha_two_colours_end_to_end_with_friction_grasps(alpha_run):
    world, m, res = alpha_run
    assert res.grasp == "friction"
    assert res.success, res.reason
    assert res.replans == 0 and res.goal_in_world and res.goal_in_beliefs
    assert res.arm_contacts == 0 and res.max_block_error < 0.01
    # independent re-check of the final poses against the plan's symbolic end state
    final = symbolic_trace(parse_plan({"world": world.to_json(), "actions": ALPHA_PLAN}))[-1]
    for b, loc in final.places.items():
        assert np.linalg.norm(m.executor.block_position(b) - world.position(loc)) < 0.01, b
    assert m.executor.block_position("r1")[1] == pytest.approx(0.0, abs=0.01)  # on the shared table
    # robot1 learnt red from the announcement only: the belief log has the sensing and the announcement
    kinds = [(e["kind"], e["robot"], e["block"], e["colour"]) for e in res.belief_log]
    assert kinds == [("sense", "robot2", "r1", "red"), ("announce", "robot2", "r1", "red")]
    assert res.beliefs["robot1"] == {"r1": "red"} and res.beliefs["robot2"] == {"r1": "red"}
    assert res.belief_log[1]["t_sim_s"] > res.belief_log[0]["t_sim_s"] > 0
    assert res.sim_seconds > 3.0  # the arms moved; nothing was teleported


def test_sensing_cannot_see_a_covered_block():
    world = world_from_layout(STACKS, COLOURS)
    ex = Executor(world)
    seen = ex.sense_columns("robot2", ex.columns("robot2"), 0.25)
    assert [(s.block, s.level, s.colour) for s in seen] == [("r1", 1, "red"), (None, -1, None), ("g2", 0, "green")]
    assert "g1" not in {s.block for s in seen}  # g1 is under r1
    # the colour comes from the rendered geom, not from the world description: repaint r1 and look again
    ex.model.geom_rgba[ex.model.geom("block/r1").id] = (0.1, 0.3, 0.9, 1.0)
    again = ex.sense_columns("robot2", ex.columns("robot2", [0]), 0.25)
    assert again[0].block == "r1" and again[0].colour == "blue"


def test_sensed_colour_contradicting_the_belief_triggers_a_replan():
    world = world_from_layout(STACKS, COLOURS)
    plan = {"world": world.to_json(), "actions": ALPHA_PLAN}  # swap-colours swaps r1 (picked first) and b2
    calls = []

    def replan(world_json, known):
        calls.append((world_json, known))
        raise GoalUnreachable("stop here (test)")

    m = Mission(world, "alpha", replan, plan=plan, faults=(parse_fault("swap-colours"),))
    res = m.run()
    assert not res.success and res.replans == 1 and "unreachable" in res.reason
    assert "r1 looks green, the plan believes it is red" in res.steps[0].message
    # the replan is asked from what was observed: r1 green (swapped), and robot2 knows it
    world_json, known = calls[0]
    assert world_json["colors"]["r1"] == "green" and known["robot2"]["r1"] == "green"
    assert world_json["stacks"] == STACKS
    assert [s.text for s in res.steps if s.task not in ("re-sense", "recovery")] == ["robot2: sense()"]


def test_beliefs_are_del_updates():
    b = Beliefs(("robot1", "robot2"), ("x",), ("red", "green"))
    assert b.believed("robot1", "x") is None
    b.sense("robot2", "x", "green", 1.0)
    assert (b.believed("robot2", "x"), b.believed("robot1", "x")) == ("green", None)
    assert b.models["x"].holds("K{robot1} (K{robot2} col_x_green | K{robot2} col_x_red)")  # saw that it looked
    with pytest.raises(ValueError, match="does not believe"):
        b.announce("robot1", ("robot2",), "x", "green", 2.0)
    b.announce("robot2", ("robot1",), "x", "green", 2.0)
    assert b.believed("robot1", "x") == "green"


def test_simple_replanner_plans_every_goal_symbolically():
    world = random_world(2, 3)
    for g in GOALS:
        obj = simple_replanner(g, _origin(world))(world.to_json(), {})
        symbolic_trace(parse_plan(obj))  # applicable
    with pytest.raises(GoalUnreachable):
        one = random_world(1, 0)
        simple_replanner("gamma", _origin(one))(one.to_json(), {})


def test_fault_syntax():
    assert str(parse_fault("drop@3")) == "drop@3" and parse_fault("swap-colors").kind == "swap-colours"
    with pytest.raises(ArmsError, match="unknown fault"):
        parse_fault("explode@1")


@pytest.mark.slow
@pytest.mark.parametrize("fault", ["drop@0", "misplace@0"])
def test_fault_is_detected_and_the_mission_recovers(fault):
    world = random_world(2, 0)
    m = Mission(world, "alpha", simple_replanner("alpha", _origin(world)), faults=(parse_fault(fault),))
    res = m.run()
    assert res.success, res.reason
    assert res.replans == 1 and res.faults and res.arm_contacts == 0
    bad = [s for s in res.steps if not s.ok]
    assert len(bad) == 1 and ("no longer in the hand" in bad[0].message or "is not at" in bad[0].message)


def test_a_fault_without_a_suitable_action_is_reported_as_not_fired():
    world = world_from_layout(STACKS, COLOURS)
    plan = {"world": world.to_json(), "actions": ALPHA_PLAN[:1]}  # only a sense: nothing to drop

    def replan(world_json, known):
        raise GoalUnreachable("stop here (test)")

    res = Mission(world, "alpha", replan, plan=plan, faults=(parse_fault("drop@0"),), max_replans=0).run()
    assert not res.success and "gave up" in res.reason and "does not hold" in res.reason
    assert res.faults == ["drop@0: not fired (no pick at or after action 0)"]
