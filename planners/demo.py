"""The planner part of ``delkit demo``: plan Coin in the Box from ``specs/`` and check the plan."""

from __future__ import annotations

from pathlib import Path
from typing import Any

__all__ = ["run_demo", "specs_dir"]


def specs_dir() -> Path:
    """The project's ``specs/``: ``planners/specs``, a link to the checkout's ``specs/`` in a source tree and
    the packaged copy in an installed wheel (package data of ``planners``)."""
    return Path(__file__).resolve().parent / "specs"


def run_demo(out: Path | None = None, timeout: float = 10.0) -> dict[str, Any]:
    """Plan Coin in the Box (E-PDDL, common knowledge of tail) with BFS, then replay the plan with delkit's
    product update and check goal and the spec's properties. Returns a JSON-ready summary (< 1 s); with
    ``out`` (a directory) also writes it to ``out/planner.json``."""
    from planners.epistemic import Limits, plan
    from planners.lang import load_task
    from planners.validate import check_plan, parse_property

    d = specs_dir() / "coin_in_the_box"
    task = load_task(d / "domain.epddl", d / "common.epddl")
    res = plan(task, search="bfs", limits=Limits(timeout=timeout))
    props = [parse_property(line, task) for line in (d / "common.props").read_text().splitlines()
             if line.strip() and not line.lstrip().startswith("#")]
    check = check_plan(task, list(res.plan or ()), props) if res.solved else None
    ok = bool(res.solved and check is not None and check.valid)
    if res.solved:
        summary = (f"Coin in the Box: optimal plan of {res.length} steps ({', '.join(res.plan or ())}) found by "
                   f"BFS in {res.seconds:.2f} s ({res.expanded} expanded); replayed with product update: "
                   f"goal C{{a,b,c}} tail {'reached' if ok else 'NOT reached'}, {len(props)} properties "
                   f"{'hold' if ok else 'checked'}")
    else:
        summary = f"Coin in the Box: no plan ({res.status}: {res.reason})"
    record = {
        "task": task.name,
        "search": res.to_json(),
        "check": check.to_json() if check is not None else None,
        "properties": [str(p) for p in props],
        "ok": ok,
        "summary": summary,
    }
    if out is not None:
        import json

        out = Path(out)
        out.mkdir(parents=True, exist_ok=True)
        (out / "planner.json").write_text(json.dumps(record, indent=2))
    return record
