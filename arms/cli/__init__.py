"""The arms layer's commands: ``delkit arms`` (run, demo, bench-ik, scene) and ``delkit epico run`` (an e-PICO
mission executed on the two simulated Pandas). Registered through the ``delkit.commands`` entry point
``arms``; they need ``delkit[arms]``."""

from __future__ import annotations

from pathlib import Path
from typing import Any

__all__ = ["register", "DEMO_SECTIONS", "EXTRA", "REQUIRES"]

EXTRA = "arms"
REQUIRES = ("mujoco", "mink", "pinocchio", "frankik")


def register(app: Any) -> None:
    """Attach ``delkit arms ...`` and ``delkit epico run``."""
    from arms.cli import arms_cmd, epico_run
    from delkit.cli.plugins import group

    arms_cmd.register(app)
    epico_run.register(group(app, "epico"))


def _arms(out: Path) -> dict[str, Any]:
    from delkit.cli.plugins import require_extra

    require_extra(EXTRA, *REQUIRES, what="the arms demo")
    from arms.demo import run_demo as arms_demo

    res = arms_demo(out / "arms")
    res["ok"] = bool(res.get("success"))
    res["summary"] = (f"built-in two-robot plan {'succeeded' if res['ok'] else 'FAILED'}; max block error "
                      f"{1000 * float(res.get('max_block_error_m', 0.0)):.2f} mm; "
                      f"{res.get('realtime_factor', 0):.1f}x real time; picture: {res.get('png') or res.get('note')}")
    return res


DEMO_SECTIONS = [(60, "Two Franka Pandas execute a plan", _arms)]
