"""e-PICO plans executed in closed loop on the planner's DEL belief state (delkit epico run): the CLI's JSON in
the fast suite, the 14 defined cells of Table 1 (seed 004, both-robot instances) in the slow suite."""

from __future__ import annotations

import json

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
    assert res.arm_contacts == 0 and res.max_block_error < 0.01
    from tests.arms.test_mission import _executed_steps_hold

    _executed_steps_hold(res, m)


def test_cli_json_lists_every_step_with_its_precondition_and_truth(capsys):
    from delkit.cli import main

    code = main(["epico", "run", "--goal", "alpha", "--colors", "1", "--symmetric", "--json"])
    obj = json.loads(capsys.readouterr().out)
    assert code == 0 and obj["success"] and obj["shield"] and obj["belief_backend"] == "compact"
    steps = [s for s in obj["steps"] if s["executed"]]
    assert steps and all(s["precondition"] and s["precondition_holds"] is True for s in steps)
    put = next(s for s in steps if s["task"].startswith("put_on_shared"))
    assert "K_robot1 hold(robot1, red)" in put["precondition"]
    assert any("K_robot2 hold(robot1, red)" in e["learnt"] for e in obj["belief_log"])


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
def test_table1_cell_executed_on_the_belief_state(goal, colors):
    """Every defined (G, N ≤ 4) on the both-robot instance: goal in the world and in the belief state, every
    executed step's precondition true in the acting robot's belief state."""
    assert len(CELLS) == 14
    inst, res, m = epico_run.run_mission(goal, colors, None, symmetric=True)
    assert len(inst.owners) == 2
    _check_mission(res, m)
    assert res.replans == 0


def test_delkit_epico_run_is_registered_and_errors_are_one_line(capsys):
    from delkit.cli import main

    assert main(["epico", "run", "--goal", "alpha", "--colors", "1", "--fault", "melt@2"]) == 2
    err = capsys.readouterr().err
    assert err.startswith("delkit: error:") and "unknown fault" in err and len(err.strip().splitlines()) == 1


def test_cli_sensing_and_takes_readings_and_whole_process_times(capsys):
    from delkit.cli import main

    code = main(["epico", "run", "--goal", "alpha", "--colors", "1", "--sensing", "color", "--takes", "handover",
                 "--json"])
    obj = json.loads(capsys.readouterr().out)
    assert code == 0 and obj["success"], obj["reason"]
    assert obj["instance"]["reading"]["sensing"] == "color" and obj["instance"]["reading"]["takes"] == "handover"
    assert any(s["task"].startswith("sense_color_") for s in obj["steps"])
    # whole-process CPU and wall: at least the mission's own, start-up and imports included
    assert obj["process"]["cpu_s"] >= obj["cpu_s"] and obj["process"]["wall_s"] >= obj["wall_s"]
    assert obj["audit"]["final"]["agrees"]
    assert main(["epico", "run", "--goal", "alpha", "--colors", "1", "--takes", "given"]) == 2
    err = capsys.readouterr().err
    assert "--takes must be seen or handover" in err and len(err.strip().splitlines()) == 1
