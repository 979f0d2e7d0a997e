"""``delkit arms ...`` in-process."""

from __future__ import annotations

import json
from pathlib import Path

from arms.demo import demo_plan
from delkit.cli import main


def _small_plan(tmp_path: Path) -> Path:
    """One pick-and-place by robot2 only (fast)."""
    obj = demo_plan().to_json()
    obj["actions"] = [{"robot": "robot2", "action": "pick", "args": ["yellow", "table", 0, 2]},
                      {"robot": "robot2", "action": "place", "args": ["yellow", "blue", 1, 0]}]
    p = tmp_path / "plan.json"
    p.write_text(json.dumps(obj))
    return p


def test_arms_run_json(tmp_path, capsys):
    rc = main(["arms", "run", str(_small_plan(tmp_path)), "--json"])
    out = json.loads(capsys.readouterr().out)
    assert rc == 0 and out["success"] is True
    assert [a["success"] for a in out["actions"]] == [True, True]
    yellow = out["final_poses"]["yellow"]["pos"]
    blue = out["final_poses"]["blue"]["pos"]
    assert abs(yellow[0] - blue[0]) < 0.01 and abs(yellow[1] - blue[1]) < 0.01
    assert abs(yellow[2] - blue[2] - 0.04) < 0.005


def test_arms_run_bad_plan_is_one_line_error(tmp_path, capsys):
    p = tmp_path / "bad.json"
    p.write_text(json.dumps({"world": {"stacks": {"robot1": [["red"]], "robot2": [[]]}},
                             "actions": [{"robot": "robot1", "action": "place", "args": ["red"]}]}))
    rc = main(["arms", "run", str(p)])
    err = capsys.readouterr().err
    assert rc == 2 and "place needs a 'stack'" in err and "Traceback" not in err


def test_arms_run_inapplicable_plan_is_rejected_before_simulating(tmp_path, capsys):
    obj = demo_plan().to_json()
    obj["actions"] = [{"robot": "robot1", "action": "put_on_barrier", "args": ["red"]}]
    p = tmp_path / "p.json"
    p.write_text(json.dumps(obj))
    assert main(["arms", "run", str(p), "--json"]) == 2
    assert "does not hold" in capsys.readouterr().err


def test_bench_ik_json(capsys):
    rc = main(["arms", "bench-ik", "--targets", "15", "--budget-ms", "20", "--clock", "cpu", "--json"])
    out = json.loads(capsys.readouterr().out)
    assert rc == 0 and out["targets"] == 15
    names = [s["solver"] for s in out["solvers"]]
    assert any("mink" in n for n in names) and any("CLIK" in n for n in names)
    assert names[0].startswith("analytic")
    for s in out["solvers"]:
        assert 0.0 <= s["success_rate"] <= 1.0 and s["median_ms"] > 0
    clik = next(s for s in out["solvers"] if "CLIK" in s["solver"])
    assert clik["success_rate"] >= 0.8
    analytic = out["solvers"][0]
    assert analytic["success_rate"] == 1.0 and analytic["failures"] == []


def test_arms_scene_writes_mjcf(tmp_path):
    out = tmp_path / "scene.xml"
    assert main(["arms", "scene", str(out)]) == 0
    text = out.read_text()
    assert "robot1/panda_hand_tcp" in text and "block/red" in text
