"""No oracle in the closed loop (arms.mission): beliefs come only from the robots' own sensors, the audit is a
separate judge, and each guard has a mutation that makes a fast test fail (the mutation tests below apply the
broken form with monkeypatch and assert that the same assertions then fail)."""

from __future__ import annotations

import ast
import inspect

import pytest

pytest.importorskip("planners.hierarchy")

from arms import mission  # noqa: E402
from arms.cli import epico_run  # noqa: E402
from arms.mission import Mission, parse_fault  # noqa: E402
from arms.world import World  # noqa: E402
from planners.epico import generate  # noqa: E402


# -- the assertions the fast tests make (the mutation tests show each can fail) --------------------------------
def assert_repaint_caught_by_a_later_look(res) -> None:
    """repaint@0 fires right after robot1's sensing task; the next look that could see the block catches it
    (not the same step: nothing reads the painted colour), the belief state is revised by name, and at the
    end the audit (ground truth) agrees with the beliefs."""
    assert res.success, res.reason
    fired = next(s for s in res.steps if s.fault.startswith("repaint"))
    catch = [c for c in res.caught_by if c["fault"].startswith("repaint")]
    assert len(catch) == 1 and catch[0]["by"] == "look", res.faults
    assert catch[0]["step"] > fired.index, (catch, fired.index)
    assert any(s.observed.get("columns") for s in res.steps if s.index == catch[0]["step"]), \
        "the catching step had no look"
    assert any(e["kind"] == "revision" and e["revised"] for e in res.belief_log)
    assert res.audit["final"]["agrees"], res.audit["final"]


def assert_shield_stopped_the_unsensed_put(res) -> None:
    first = res.steps[0]
    assert first.task == "put_on_shared_robot1_red" and not first.executed and first.precondition_holds is False
    assert "K_robot1 hold(robot1, red)" in first.message
    assert res.success and not res.unsafe_steps, res.reason


def assert_occlusion_caught_by_the_camera(res) -> None:
    assert res.success, res.reason
    assert [c["by"] for c in res.caught_by] == ["look"], res.caught_by
    assert any("occlusion" in s.checks for s in res.steps)


class _Forgetful(epico_run.EpicoModel):
    """A planner that forgets the sensing task in its first plan."""

    calls = 0

    def plan(self, belief, world_json):
        tasks, meta = super().plan(belief, world_json)
        type(self).calls += 1
        return ([t for t in tasks if not t.name.startswith("sense_")] if type(self).calls == 1 else tasks), meta


def _forgetful_mission():
    _Forgetful.calls = 0
    inst = generate("alpha", 2)
    return Mission(World.from_json(inst.layout.to_world()), inst.goal, _Forgetful(inst)).run()


@pytest.fixture(scope="module")
def repaint_run():
    return epico_run.run_mission("alpha", 2, None, faults=(parse_fault("repaint@0"),))


def test_a_repaint_is_caught_by_the_next_look(repaint_run):
    assert_repaint_caught_by_a_later_look(repaint_run[1])


def test_an_occlusion_is_caught_by_the_camera():
    _i, res, _m = epico_run.run_mission("alpha", 2, None, faults=(parse_fault("occlusion"),))
    assert_occlusion_caught_by_the_camera(res)


def test_the_shield_stops_the_unsensed_put():
    assert_shield_stopped_the_unsensed_put(_forgetful_mission())


# -- mutation tests ----------------------------------------------------------------------------------------------
def test_mutation_shield_always_true_is_detected(monkeypatch):
    """The shield always true: the unsensed put passes the shield (only the classical level, which has seen
    no red block, refuses to break it down), and the shield assertion fails."""
    monkeypatch.setattr(Mission, "_shield", staticmethod(lambda belief, act: True))
    res = _forgetful_mission()
    assert res.steps[0].precondition_holds is True and "no primitive actions" in res.steps[0].message
    with pytest.raises(AssertionError):
        assert_shield_stopped_the_unsensed_put(res)


def _truth_observation(self, views, robot, props):
    """Mutation: the observation from the generator's colours and start map, not from the camera."""
    out = {}
    for p in props:
        kind, owner, c = mission._fluent(p)
        if kind == "hold" and owner == robot:
            out[p] = any(mission._colour_names(self.world)[b] == c for st in self.world.stacks[robot] for b in st)
        elif kind == "occup_by":
            out[p] = False
    return out


def test_mutation_observation_from_true_colours_is_detected(monkeypatch):
    """The observation taken from the generator's colours: the repaint is never caught."""
    monkeypatch.setattr(Mission, "observation", _truth_observation)
    _i, res, _m = epico_run.run_mission("alpha", 2, None, faults=(parse_fault("repaint@0"),))
    with pytest.raises(AssertionError):
        assert_repaint_caught_by_a_later_look(res)


def test_mutation_world_check_reading_geom_rgba_is_detected(monkeypatch):
    """The check after a task reading the painted colours (the old all-knowing world check): the repaint is
    caught at the sensing step itself, before any look could see it."""
    orig = Mission._check_look

    def oracle_check(self, ex, belief, robot, rec, where, views=None):
        world = self._audit_world(ex, set())  # geom_rgba
        val = belief.valuation()
        bad = tuple(p for p in world if val.get(p) is not None and world[p] != val[p])
        if bad:
            raise mission._Divergence(f"{where}: oracle: {bad}", bad, looker=robot,
                                      seen={p: world[p] for p in bad}, by="look")
        return orig(self, ex, belief, robot, rec, where, views)

    monkeypatch.setattr(Mission, "_check_look", oracle_check)
    _i, res, _m = epico_run.run_mission("alpha", 2, None, faults=(parse_fault("repaint@0"),))
    with pytest.raises(AssertionError):
        assert_repaint_caught_by_a_later_look(res)


def test_mutation_ownership_from_the_start_map_is_detected(monkeypatch):
    """Ownership kept from the start map (never updated from poses): after a hand-over the mission's own
    observation is wrong (the property of tests/arms/test_sensing.py fails on a hand-over layout)."""
    from tests.arms.test_sensing import check_reached

    monkeypatch.setattr(Mission, "_stand", lambda self, state: self.stands.update(
        {b: loc.robot for b, loc in state.places.items() if loc.kind == "stack" and b not in self.stands}))
    with pytest.raises(AssertionError):
        check_reached(2, HANDOVER_START, HANDOVER_MOVES)


from tests.arms.test_sensing import HANDOVER_MOVES, HANDOVER_START  # noqa: E402


# -- nothing in the loop reads ground truth ----------------------------------------------------------------------
def _functions_using(tree: ast.AST, attr: str) -> set[str]:
    out = set()
    for fn in ast.walk(tree):
        if isinstance(fn, (ast.FunctionDef,)):
            for node in ast.walk(fn):
                if isinstance(node, ast.Attribute) and node.attr == attr:
                    out.add(fn.name)
    return out


def test_ground_truth_is_read_only_by_the_judge_and_the_fault_injector():
    """In arms/mission.py the painted colours (``geom_rgba``) are read only by ``_true_colour`` and written
    by the repaint fault; ``_true_colour`` is called only by the audit and the repaint fault; the start map
    (``model.owner``) and the generator's colours (``world.colors``) are read by no function of the loop."""
    tree = ast.parse(inspect.getsource(mission))
    assert _functions_using(tree, "geom_rgba") <= {"_true_colour", "_repaint"}
    assert _functions_using(tree, "_true_colour") <= {"_audit_world", "_repaint"}
    assert _functions_using(tree, "owner") == set()
    assert _functions_using(tree, "colors") <= {"_colour_names", "_swap_colours", "world_from_layout",
                                                "random_world", "duplicate_layout", "_swapped_blocks"}
    assert _functions_using(tree, "_colour_names") <= {"_fault_block", "_swap_colours"}


def test_the_loop_never_calls_the_ground_truth_readers(monkeypatch):
    """At run time: the painted colours and the start map raise if read while the loop decides (outside the
    audit and the fault injector); a mission with a repaint still succeeds."""
    state = {"judge": 0}
    orig_true, orig_audit, orig_repaint = Mission._true_colour, Mission.audit, Mission._repaint

    def true_colour(self, ex, b):
        assert state["judge"], "the loop read a painted colour"
        return orig_true(self, ex, b)

    def judged(fn):
        def wrapper(*a, **kw):
            state["judge"] += 1
            try:
                return fn(*a, **kw)
            finally:
                state["judge"] -= 1
        return wrapper

    class NoStartMap(dict):
        def __getitem__(self, k):
            raise AssertionError("the loop read the start map")

        get = __getitem__

    monkeypatch.setattr(Mission, "_true_colour", true_colour)
    monkeypatch.setattr(Mission, "audit", judged(orig_audit))
    monkeypatch.setattr(Mission, "_repaint", judged(orig_repaint))
    inst = generate("alpha", 2)
    model = epico_run.EpicoModel(inst)
    model.owner = NoStartMap(model.owner)
    res = Mission(World.from_json(inst.layout.to_world()), inst.goal, model, faults=(parse_fault("repaint@0"),)).run()
    assert_repaint_caught_by_a_later_look(res)


# -- hold after takes, evidence never discarded -------------------------------------------------------------------
def test_a_take_of_the_other_robots_block_makes_its_hold_unknown():
    """``hold(owner, c)`` means a block of colour c lies in front of the owner: after the other robot takes
    the owner's block onto its own table the mission's update says hold(owner, c) may have changed."""
    inst = generate("beta", 1)
    model = epico_run.EpicoModel(inst)
    m = Mission(World.from_json(inst.layout.to_world()), inst.goal, model)
    b = model.initial_belief()
    b.apply("sense_table_robot1", robot="robot1", observed={"hold_robot1_red": True})
    b.apply("put_on_shared_robot1_red", robot="robot1")
    b.apply("announce_block_on_barrier_robot1_red", robot="robot1")
    assert b.holds(mission._k("robot2", "hold_robot1_red", True))
    m._apply_task(b, "take_from_shared_robot2_robot1_red", "robot2")
    assert not b.holds(mission._k("robot2", "hold_robot1_red", True))
    assert b.valuation()["hold_robot1_red"] is None and b.log[-1].kind == "forget"


def test_delta_two_repaint_and_lost_message_end_without_stale_belief():
    """δ/2 with repaint@0 and drop-msg@6: both caught (a look, the acknowledgement), the observation that
    contradicted the state was revised by name (never discarded), and at the end no belief is false in the
    simulation."""
    _i, res, _m = epico_run.run_mission("delta", 2, None, faults=(parse_fault("repaint@0"), parse_fault("drop-msg@6")))
    assert res.success, res.reason
    assert sorted(c["by"] for c in res.caught_by) == ["ack", "look"], res.caught_by
    assert res.audit["final"]["agrees"] and not res.audit["final"]["false_beliefs"], res.audit["final"]
    assert any(e["kind"] == "revision" for e in res.belief_log)
    assert not any("contradicts" in s.message and "refused" in s.message for s in res.steps)
