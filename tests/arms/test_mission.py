"""The closed loop on the planner's own DEL belief state (arms.mission + arms.beliefs): shield, per-task checks,
belief updates by the tasks' event models, faults only beliefs can catch, and --no-shield going wrong."""

from __future__ import annotations

import json

import numpy as np
import pytest

pytest.importorskip("planners.hierarchy")

from arms.beliefs import BeliefError, BeliefState  # noqa: E402
from arms.cli import epico_run  # noqa: E402
from arms.mission import parse_fault  # noqa: E402
from arms.world import ArmsError  # noqa: E402


def _executed_steps_hold(res, m) -> None:
    """Every executed step's precondition held in the belief state: the run's JSON says so per step, and an
    independent replay of the belief log (a fresh belief state from the task's initial state, every logged
    event re-applied; each task's precondition evaluated before it) agrees, and ends in the goal."""
    obj = res.to_json()
    json.dumps(obj)
    for s in obj["steps"]:
        if s["task"] in ("recovery",):
            continue
        assert s["precondition"], s
        if s["executed"]:
            assert s["precondition_holds"] is True, s
    assert obj["unsafe_steps"] == []
    b = m.model.initial_belief()
    for e in obj["belief_log"]:
        if e["kind"] in ("forget", "revision"):
            b.forget(e["forgot"])
            continue
        if e["kind"] in ("look", "observation"):
            b.look(e["robot"], e["observed"], public=e["kind"] == "observation")
            continue
        assert b.holds(m.model.task.action(e["task"]).executable), e
        b.apply(e["task"], robot=e["robot"], observed=e["observed"], heard=e["heard"])
    assert b.key() == m.belief.key() and b.holds(m.model.task.goal)
    executed = [s["task"] for s in obj["steps"] if s["executed"] and s["task"] not in ("recovery", "final look")]
    logged = [e["task"] for e in obj["belief_log"] if e["kind"] not in ("forget", "revision", "look", "observation")]
    assert set(executed) <= set(logged)


@pytest.fixture(scope="module")
def alpha2():
    return epico_run.run_mission("alpha", 2, None, symmetric=True)


def test_alpha_two_colours_acts_on_the_belief_state(alpha2):
    inst, res, m = alpha2
    assert res.success, res.reason
    assert res.goal_in_world and res.goal_in_beliefs and res.replans == 0 and res.shield
    assert res.backend == "compact" and len(inst.owners) == 2
    _executed_steps_hold(res, m)
    # the belief state IS the planner's: its task, its space; the goal holds in it
    assert m.belief.task is m.model.task and m.belief.space is m.model.space
    assert m.belief.holds(m.model.task.goal)
    # the log prints formulas of that state; the learner knows the announced colour, which is true
    learnt = [x for e in res.belief_log for x in e["learnt"]]
    assert "K_robot1 hold(robot1, red)" in learnt and "K_robot2 hold(robot1, red)" in learnt
    assert "K_robot2 hold(robot1, red)" in res.beliefs["robot2"]
    assert inst.layout.has("robot1", "red")
    # sensing saw the covered red block (under black): the camera sees every block of the stacks
    sense = next(s for s in res.steps if s.task == "sense_table_robot1")
    assert sense.observed["seen"].get("red") == "red" and sense.observed["seen"].get("black") == "black"
    # after every task: the acting robot's look and the bisimulation check ran; at the end both robots looked
    last = [s for s in res.steps if s.checks and s.task != "final look"]
    assert all("look" in s.checks and "bisimilar" in s.checks for s in last) and len(last) == len(res.plans[0])
    assert sorted(s.robot for s in res.steps if s.task == "final look") == ["robot1", "robot2"]
    # the judge (ground truth, written into the JSON only) agrees with the beliefs at the end
    assert res.audit["final"]["agrees"] and res.to_json()["audit"]["final"]["false_beliefs"] == []
    assert res.arm_contacts == 0 and res.max_block_error < 0.01 and res.sim_seconds > 3.0


def test_the_shield_stops_an_action_whose_precondition_is_false(alpha2):
    inst, _res, m = alpha2
    b = m.model.initial_belief()
    # robot1 has not sensed: K_robot1 hold(robot1, red) is false, so put_on_shared may not run
    pre = m.model.task.action("put_on_shared_robot1_red").executable
    assert not b.holds(pre)
    with pytest.raises(BeliefError, match="precondition"):
        b.apply("put_on_shared_robot1_red", robot="robot1")
    # an observation that contradicts the actual world is never discarded: a named revision of exactly the
    # contradicted fluent, then the sensing event; the robot believes what it saw
    b.apply("sense_table_robot1", robot="robot1", observed={"hold_robot1_red": False, "hold_robot1_black": True})
    rev = [e for e in b.log if e.kind == "revision"]
    assert len(rev) == 1 and rev[0].forgot == ("hold_robot1_red",) and "seen false" in rev[0].revised[0]
    assert "K_robot1 ¬hold(robot1, red)" in b.knowledge() and "K_robot1 hold(robot1, black)" in b.knowledge()


def test_both_backends_give_bisimilar_belief_states(alpha2):
    from delkit.models.bisimulation import canonical_form, contract
    from planners.spaces import make_space

    _inst, _res, m = alpha2
    task = m.model.task
    states = []
    for eng in ("compact", "del"):
        b = BeliefState(task, make_space(task, engine=eng))
        b.apply("sense_table_robot1", robot="robot1", observed={"hold_robot1_red": True, "hold_robot1_black": True})
        b.apply("put_on_shared_robot1_red", robot="robot1")
        b.apply("announce_block_on_barrier_robot1_red", robot="robot1", heard=False)
        states.append(b)
    assert states[0].backend == "compact" and states[1].backend == "numpy"
    k = [canonical_form(contract(s.kripke()), generated=False) for s in states]
    assert k[0] == k[1]
    assert states[0].knowledge() == states[1].knowledge()
    assert "K_robot2 hold(robot1, red)" not in states[0].knowledge()  # the message was lost


@pytest.mark.parametrize("fault", ["drop-msg@0", "repaint@0", "occlusion"])
def test_belief_faults_are_caught_and_repaired(fault):
    _inst, res, m = epico_run.run_mission("alpha", 2, None, symmetric=True, faults=(parse_fault(fault),))
    assert res.success, res.reason
    _executed_steps_hold(res, m)
    fired = [x for x in res.faults if "fired" in x and "never" not in x]
    caught = [x for x in res.faults if "caught" in x]
    assert fired and caught and not res.unfired and not any("NOT caught" in x for x in res.faults), res.faults


@pytest.mark.parametrize("fault", ["drop-msg@0", "repaint@0", "occlusion"])
def test_without_the_shield_the_same_run_goes_wrong(fault):
    _inst, res, _m = epico_run.run_mission("alpha", 2, None, symmetric=True, faults=(parse_fault(fault),),
                                           shield=False)
    assert not res.success
    # the wrong step: an action executed on a belief the robot does not hold, or a divergence nobody acted on,
    # or the run ends with the goal false in the belief state
    assert res.unsafe_steps or res.unheeded or not res.audit["final"]["agrees"] or not res.goal_in_beliefs, \
        res.to_json()
    assert not res.shield


def test_a_fault_whose_step_never_comes_is_reported_never_fired():
    _inst, res, _m = epico_run.run_mission("alpha", 1, None, symmetric=True,
                                           faults=(parse_fault("drop@99999999999999999999"),))
    assert res.unfired == ["drop@99999999999999999999"]
    assert any("never fired" in x for x in res.faults) and "never fired" in res.reason


def test_fault_syntax():
    assert str(parse_fault("drop-msg@3")) == "drop-msg@3" and parse_fault("swap-colors").kind == "swap-colours"
    assert str(parse_fault("occlusion")) == "occlusion" and parse_fault("repaint@0").kind == "repaint"
    with pytest.raises(ArmsError, match="unknown fault"):
        parse_fault("explode@1")


@pytest.mark.slow
@pytest.mark.parametrize("fault", ["drop@0", "misplace@0", "swap-colours"])
def test_physical_faults_are_detected_and_repaired(fault):
    _inst, res, m = epico_run.run_mission("alpha", 2, None, symmetric=True, faults=(parse_fault(fault),))
    assert res.success, res.reason
    # swapped paint needs no replan: no plan was made from the generator's colours, the first look sees them
    assert (res.replans >= 1 if fault != "swap-colours" else [c["by"] for c in res.caught_by] == ["look"])
    assert res.arm_contacts == 0 and res.max_block_error < 0.01
    _executed_steps_hold(res, m)
    assert np.isfinite(res.sim_seconds)


def test_the_shield_stops_a_plan_step_the_robot_has_no_belief_for():
    """A planner that forgets the sensing task: the shield stops robot1's put_on_shared (robot1 does not
    know it has a red block), names the failed conjunct, and the loop replans from the belief state."""
    from arms.mission import Mission
    from arms.world import World
    from planners.epico import generate

    inst = generate("alpha", 2, symmetric=True)

    class Forgetful(epico_run.EpicoModel):
        calls = 0

        def plan(self, belief, world_json):
            tasks, meta = super().plan(belief, world_json)
            Forgetful.calls += 1
            return ([t for t in tasks if not t.name.startswith("sense_table")] if Forgetful.calls == 1 else tasks), meta

    m = Mission(World.from_json(inst.layout.to_world()), inst.goal, Forgetful(inst))
    res = m.run()
    first = res.steps[0]
    assert first.task == "put_on_shared_robot1_red" and not first.executed and first.precondition_holds is False
    assert "shield" in first.message and "K_robot1 hold(robot1, red)" in first.message and "robot1" in first.message
    assert res.success and res.replans == 1 and Forgetful.calls == 2, res.reason
    _executed_steps_hold(res, m)


SEEDED = [(c, s, f) for c in (1, 2, 3, 4) for s in range(20) for f in ("drop-msg@0", "repaint@0", "occlusion")]


@pytest.mark.slow
@pytest.mark.parametrize(("colors", "seed", "fault"), SEEDED)
def test_seeded_belief_faults_are_caught_and_repaired(colors, seed, fault):
    """20 seeded layouts × 1–4 colours × each belief fault: the fault fires, is caught and repaired; with
    --no-shield the same mission goes wrong (bench/arms_mission.py --no-shield-too prints the table)."""
    _inst, res, m = epico_run.run_mission("alpha", colors, seed, symmetric=True, faults=(parse_fault(fault),))
    assert res.success, res.reason
    assert not res.unfired and not any("NOT caught" in x for x in res.faults), res.faults
    assert any("caught" in x for x in res.faults), res.faults
    _executed_steps_hold(res, m)
    _inst, bad, _m = epico_run.run_mission("alpha", colors, seed, symmetric=True, faults=(parse_fault(fault),),
                                           shield=False)
    assert not bad.success and (bad.unsafe_steps or bad.unheeded or not bad.audit["final"]["agrees"]
                                or not bad.goal_in_beliefs)


@pytest.mark.slow
@pytest.mark.parametrize(("colors", "seed"), [(c, s) for c in (1, 2, 3, 4) for s in range(20)])
def test_seeded_duplicate_colour_layouts_with_a_repaint(colors, seed):
    """Several blocks of one colour per robot (arms.mission.duplicate_layout) and a repaint after the first
    sensing: caught by a look, the audit agrees with the beliefs at the end, no unsafe step."""
    from arms.mission import duplicate_layout

    _inst, res, m = epico_run.run_mission("alpha", colors, seed, layout=duplicate_layout(colors, seed),
                                          faults=(parse_fault("repaint@0"),))
    assert res.success, res.reason
    assert not any("NOT caught" in x for x in res.faults), res.faults
    assert all(c["by"] in ("look", "shield", "ack", "pose") for c in res.caught_by), res.caught_by
    assert res.audit["final"]["agrees"], res.audit["final"]
    _executed_steps_hold(res, m)
