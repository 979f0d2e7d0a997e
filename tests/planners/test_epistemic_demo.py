"""The planner section of ``delkit demo``."""

from __future__ import annotations

import json

from planners.demo import run_demo


def test_run_demo_plans_and_checks(tmp_path) -> None:
    rec = run_demo(tmp_path)
    assert rec["ok"] is True
    assert rec["search"]["length"] == 5 and rec["check"] == {"valid": True, "steps": 5}
    assert "C{a,b,c} tail" in rec["summary"]
    assert json.loads((tmp_path / "planner.json").read_text())["ok"] is True
