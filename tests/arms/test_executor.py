"""End to end: the two-robot plan runs in physics and every block ends within 1 cm of its symbolic place."""

from __future__ import annotations

import numpy as np
import pytest

from arms.demo import demo_plan
from arms.executor import Executor, run_plan
from arms.plan import parse_plan, symbolic_trace


@pytest.fixture(scope="module")
def demo_run():
    plan = demo_plan()
    result, ex = run_plan(plan)  # friction grasp (the default)
    return plan, result, ex


def test_two_robot_plan_completes_with_blocks_within_1cm(demo_run):
    plan, result, ex = demo_run
    assert result.success, result.failure
    assert [a.success for a in result.actions] == [True] * len(plan.actions)
    final = symbolic_trace(plan)[-1]
    for b, loc in final.places.items():  # independent re-check of the executor's own verification
        assert loc.kind == "stack"
        got = np.array(result.final_poses[b]["pos"])
        assert np.linalg.norm(got - plan.world.position(loc)) < 0.01, b
    # red really travelled from robot1's table over the shared table to robot2's table
    assert final.places["red"].robot == "robot2"
    assert result.final_poses["red"]["pos"][1] > 0.25
    assert result.arm_contacts == 0
    assert 0.0 < result.fk_disagreement < 1e-9  # every move's IK solution was checked with pinocchio
    assert result.sim_seconds > 5.0  # it was moved by the arms, not teleported
    # sensing is line of sight from above: black (on top) is seen, red (under black) is not
    sensed = result.actions[0].observed
    assert sensed == {"black": "black"}
    assert [(x.column, x.block, x.level) for x in ex.sightings] == [("robot1 stack 1", "black", 1)]
    announced = next(a for a in result.actions if a.action == "announce").observed
    assert announced == {"block": "red", "to": "robot2"}


def test_friction_grasp_slips_less_than_the_tolerance(demo_run):
    _, result, ex = demo_run
    assert result.grasp == "friction"
    assert len(ex.slips) == 3
    assert 0.0 < result.max_slip < 0.01


@pytest.mark.slow
def test_weld_grasp_debug_option_holds_the_block_to_a_fraction_of_a_millimetre(demo_run):
    plan, friction, _ = demo_run
    result, ex = run_plan(plan, grasp="weld")
    assert result.success, result.failure
    assert len(ex.slips) == 3
    assert result.max_slip < 2e-4 < friction.max_slip


def test_displaced_block_stops_the_run_with_a_clear_report():
    plan = demo_plan()
    ex = Executor(plan.world)

    def knock_over_yellow(i, action):
        if i == 2:  # somebody moves yellow by 3 cm while robot1 is busy
            adr = ex.model.jnt_qposadr[ex.model.body_jntadr[ex.scene.block_body("yellow")]]
            ex.data.qpos[adr] += 0.03

    result = ex.run(plan, progress=knock_over_yellow)
    assert not result.success
    last = result.actions[-1]
    assert last.index == 2 and not last.success and last.worst_block == "yellow"
    assert "yellow" in result.failure and "action 2" in result.failure and "cm" in result.failure
    assert 0.025 < last.max_block_error < 0.035
    assert len(result.actions) == 3  # stopped there


def test_symbolically_wrong_action_fails_before_moving():
    obj = demo_plan().to_json()
    obj["actions"] = [{"robot": "robot1", "action": "pick", "args": ["red", "table", 0, 1]}]
    result, ex = run_plan(parse_plan(obj))
    assert not result.success and "covered" in result.failure and "precondition" in result.failure
    assert ex.data.time == 0.0


@pytest.mark.slow
def test_long_plan_with_round_trips_and_a_four_block_tower():
    """14 actions: both robots use the shared table in both directions; a 4-block tower is built."""
    from pathlib import Path

    from arms.plan import load_plan

    plan = load_plan(Path(__file__).with_name("long_plan.json"))
    result, _ = run_plan(plan)
    assert result.success, result.failure
    final = symbolic_trace(plan)[-1]
    assert final.places["yellow"].level == 3
    for b, loc in final.places.items():
        assert np.linalg.norm(np.array(result.final_poses[b]["pos"]) - plan.world.position(loc)) < 0.01
    assert result.arm_contacts == 0


def test_arms_in_physics_do_not_collide_when_sent_to_the_same_point():
    """robot2 goes above the shared table, then robot1 is sent to the very same point: the QP's
    collision avoidance stops robot1 short (MotionError: residual), and the arms never touch."""
    from arms.executor import MotionError
    from arms.ik import pose

    plan = demo_plan()
    ex = Executor(plan.world)
    spot = np.append(plan.world.layout.barrier_xy(), 0.15)
    ex.move("robot2", pose(spot))
    with pytest.raises(MotionError, match="cannot reach"):
        ex.move("robot1", pose(spot))
    assert ex.arm_contacts == 0
    assert ex.ik.min_arm_distance(ex.q_ik) > 0.005
    # robot2 held its place meanwhile
    assert np.linalg.norm(ex.tcp_actual("robot2")[:3, 3] - spot) < 0.01


def test_robot_names_come_from_the_world_description():
    obj = {"world": {"robots": ["left", "right"],
                     "stacks": {"left": [["red", "black"], [], []], "right": [[], [], []]}},
           "actions": [{"robot": "left", "action": "pick", "args": ["black", "red", 1, 0]},
                       {"robot": "left", "action": "put_on_barrier", "args": ["black"]},
                       {"robot": "right", "action": "take_from_barrier", "args": ["black"]},
                       {"robot": "right", "action": "place", "args": ["black", "table", 0, 2]}]}
    plan = parse_plan(obj)
    result, ex = run_plan(plan)
    assert result.success, result.failure
    assert ex.model.body("right/panda_hand_tcp").id >= 0
    want = plan.world.position(symbolic_trace(plan)[-1].places["black"])
    assert np.linalg.norm(np.array(result.final_poses["black"]["pos"]) - want) < 0.01


def test_arm_arm_contacts_are_counted_when_the_arms_do_touch():
    """Both arms swung towards each other over the shared table: the contact counter sees it (so the 0
    reported by every run is a measurement, not a default)."""
    import mujoco

    from arms.scene import HOME_Q

    ex = Executor(demo_plan().world)
    for r, sign in (("robot1", 1.0), ("robot2", -1.0)):
        q = HOME_Q.copy()
        q[0], q[1], q[3] = sign * np.pi / 2, 0.6, -1.2
        ex.data.qpos[ex._arm_adr[r]] = q
        ex.data.ctrl[ex._arm_act[r]] = q
    mujoco.mj_forward(ex.model, ex.data)
    ex._physics(5)
    assert ex.arm_contacts > 0
