"""e-PICO plans executed in closed loop (delkit epico run): the α/2-colour mission in the fast suite, the
14 defined cells of Table 1 (seed 004) in the slow suite."""

from __future__ import annotations

import json

import numpy as np
import pytest
import typer
from typer.testing import CliRunner

from arms.world import ArmsError

pytest.importorskip("planners.hierarchy")

from arms.cli import epico_run  # noqa: E402


def _check_mission(res, m) -> None:
    assert res.success, res.reason
    assert res.grasp == "friction"
    assert res.goal_in_world and res.goal_in_beliefs
    assert res.arm_contacts == 0
    ex = m.executor
    if res.replans == 0:  # independent re-check: replay the plan symbolically; every block within 1 cm
        from arms.plan import parse_plan, symbolic_trace

        world = m.world
        final = symbolic_trace(parse_plan({"world": world.to_json(),
                                           "actions": [_action_json(t) for t in res.plans[0]]}))[-1]
        for b, loc in final.places.items():
            want = world.position(loc) if loc.kind != "held" else ex.tcp_actual(loc.robot)[:3, 3]
            assert np.linalg.norm(ex.block_position(b) - want) < 0.01, b


def _action_json(entry: dict) -> dict:
    robot, call = entry["text"].split(": ", 1)
    name, _, rest = call.partition("(")
    args = [a.strip() for a in rest.rstrip(")").split(",") if a.strip()]
    args = [int(a) if a.isdigit() else a for a in args]
    return {"robot": robot, "action": name, "args": args}


def test_alpha_two_colours_planned_and_executed_end_to_end():
    inst, res, m = epico_run.run_mission("alpha", 2, None)
    _check_mission(res, m)
    assert res.replans == 0 and len(res.planning_seconds) == 1
    # the learner knows the announced colour through the DEL update, and it is the block's true colour
    ann = [e for e in res.belief_log if e["kind"] == "announce"]
    assert len(ann) == 1
    learner = ann[0]["to"][0]
    assert res.beliefs[learner][ann[0]["block"]] == inst.layout.colors[ann[0]["block"]]
    tasks = res.tasks()
    assert [t["task"] for t in tasks][0].startswith("sense_table") and all(t["ok"] for t in tasks)


def test_cli_rejects_an_unknown_fault_before_simulating():
    app = typer.Typer()
    app.callback()(lambda: None)
    epico_run.register(app)
    r = CliRunner().invoke(app, ["run", "--goal", "alpha", "--colors", "1", "--fault", "melt@2"])
    assert isinstance(r.exception, ArmsError) and "unknown fault" in str(r.exception)


CELLS = [(g, n) for g in ("alpha", "beta", "gamma", "delta") for n in (1, 2, 3, 4)
         if not (g in ("gamma", "delta") and n == 1)]


@pytest.mark.slow
@pytest.mark.parametrize(("goal", "colors"), CELLS)
def test_table1_cell_executed_in_physics(goal, colors):
    assert len(CELLS) == 14
    inst, res, m = epico_run.run_mission(goal, colors, None)
    _check_mission(res, m)
    assert res.replans == 0
    json.dumps(res.to_json())  # the report is strict JSON


@pytest.mark.slow
@pytest.mark.parametrize("fault", ["drop@0", "misplace@0", "swap-colours"])
def test_injected_fault_is_detected_and_replanned_with_epico(fault):
    from arms.mission import parse_fault

    inst, res, m = epico_run.run_mission("alpha", 2, None, faults=(parse_fault(fault),))
    assert res.success, res.reason
    assert res.replans == 1 and len(res.planning_seconds) == 2 and res.faults
    assert sum(not s.ok for s in res.steps) == 1
    assert res.arm_contacts == 0 and res.max_block_error < 0.01


def test_delkit_epico_run_is_registered_and_errors_are_one_line(capsys):
    from delkit.cli import main

    assert main(["epico", "run", "--goal", "alpha", "--colors", "1", "--fault", "melt@2"]) == 2
    err = capsys.readouterr().err
    assert err.startswith("delkit: error:") and "unknown fault" in err and len(err.strip().splitlines()) == 1
