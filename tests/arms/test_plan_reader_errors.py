"""A hand-written primitive plan with a value of the wrong JSON type is an ArmsError that
names the field (was TypeError / AttributeError / ValueError tracebacks from the reader)."""

from __future__ import annotations

import copy
import json
from pathlib import Path

import pytest

from arms.plan import parse_plan, symbolic_trace
from arms.world import ArmsError

DEMO = json.loads((Path(__file__).resolve().parents[2] / "arms" / "demo_plan.json").read_text())


def _set(path: tuple, value):
    obj = copy.deepcopy(DEMO)
    node = obj
    for key in path[:-1]:
        node = node[key]
    node[path[-1]] = value
    return obj


@pytest.mark.parametrize(("path", "value", "fragment"), [
    (("world", "robots"), 1, "'robots' must be a list of two robot names"),
    (("world", "robots"), [[0.1], "robot2"], "'robots' must be a list of two robot names"),
    (("world", "stacks", "robot2"), 2.5, "stacks of robot2 must be a list of stacks"),
    (("world", "stacks", "robot1", 2), 1, "stacks of robot1 must be a list of stacks"),
    (("world", "barrier"), 2.5, "'barrier' must be a list of block names"),
    (("world", "colors"), ["zz"], "'colors' must map block names to colours"),
    (("world", "colors", "red"), 2.5, "colour of block 'red': a colour is a name"),
    (("world", "colors", "black"), {"a": 1}, "colour of block 'black': a colour is a name"),
    (("world", "layout"), {"base_y": "a"}, "bad 'layout'"),
    (("actions", 1, "action"), ["pick"], "unknown action ['pick']"),
    (("actions", 1, "robot"), ["robot1"], "'robot' must be one of"),
    (("actions", 1, "args", 0), {"b": 1}, "'block' must be a block name"),
])
def test_wrong_json_types_are_arms_errors(path, value, fragment) -> None:
    with pytest.raises(ArmsError) as info:
        symbolic_trace(parse_plan(_set(path, value), source="p.json"))
    assert str(info.value).startswith("p.json") and fragment in str(info.value)


def test_the_demo_plan_still_reads_and_traces() -> None:
    plan = parse_plan(copy.deepcopy(DEMO), source="demo")
    assert len(symbolic_trace(plan)) == len(plan.actions) + 1


def test_result_json_is_strict_json_when_an_action_failed() -> None:
    """A failed action has no measured block error (NaN inside); its JSON must still be valid JSON."""
    from arms.executor import ActionOutcome, RunResult

    failed = ActionOutcome(0, "pick", "robot1", "robot1: pick(red)", False, "IK failed", float("nan"), None, 0.5)
    result = RunResult(success=False, actions=(failed,), final_poses={}, sim_seconds=0.5, wall_seconds=0.0,
                       arm_contacts=0, failure="IK failed", grasp="weld")
    obj = json.loads(json.dumps(result.to_json(), allow_nan=False))
    assert obj["actions"][0]["max_block_error_m"] is None and obj["realtime_factor"] is None
    ok = ActionOutcome(1, "place", "robot1", "t", True, "ok", 0.002, "red", 1.0)
    assert ok.to_json()["max_block_error_m"] == 0.002
