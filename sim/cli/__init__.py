"""The simulation layer's commands: ``delkit explore`` (communication-restricted exploration) and ``delkit
consistency`` (VERIFYAC / ENFORCEAC on the search-and-rescue grid). Registered through the
``delkit.commands`` entry point ``sim``."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

__all__ = ["register", "DEMO_SECTIONS", "EXTRA", "REQUIRES"]

EXTRA = "sim"
REQUIRES = ("matplotlib", "scipy")


def register(app: Any) -> None:
    """Attach ``delkit explore`` and ``delkit consistency``."""
    from sim.cli import consistency_cmd, explore_cmd

    consistency_cmd.register(app)
    explore_cmd.register(app)


def _consistency(out: Path) -> dict[str, Any]:
    from sim.sar import SARConfig, run_episode

    cfg = SARConfig(epochs=200, seed=1)
    runs = {alg: run_episode(cfg, alg) for alg in ("enforce", "baseline1", "baseline2")}
    (out / "consistency.json").write_text(json.dumps({k: v.as_dict() for k, v in runs.items()}, default=str))
    e, b1, b2 = runs["enforce"], runs["baseline1"], runs["baseline2"]
    ok = e.not_ac == 0 and e.violations == 0 and e.comms < b1.comms
    summary = (f"search-and-rescue, 2 robots, 200 steps: ENFORCEAC Not-AC {e.not_ac} with {e.comms} one-way "
               f"messages vs Baseline-I {b1.comms} ({100 * (1 - e.comms / b1.comms):.0f}% fewer); Baseline-II "
               f"(never talks) Not-AC {b2.not_ac}; Theorem 3.3 violations {e.violations}; {e.time_s:.2f} s")
    return {"ok": ok, "summary": summary}


def _explore(out: Path) -> dict[str, Any]:
    from sim.demo import run_demo as explore_demo

    row = explore_demo(out)
    checks = row.get("epistemic_checks", {})
    ok = all(str(v).split("/")[0] == str(v).split("/")[-1] for v in checks.values())
    summary = ", ".join(f"{k}={row[k]}" for k in ("mission_time", "distance", "tasks_done", "communications")
                        if k in row)
    row.setdefault("ok", ok)
    row["summary"] = f"{summary}; picture {row.get('png')}"
    return row


DEMO_SECTIONS = [
    (40, "Action consistency (VERIFYAC/ENFORCEAC)", _consistency),
    (50, "Exploration with epistemic task allocation", _explore),
]
