"""The planning layer's documents for ``delkit view`` (and the notebook stepper): a task with a plan, an
e-PICO mission result. Registered with the core viewer through ``VIEWERS`` in :mod:`planners.cli`.

* **Task + plan** (mA*, E-PDDL DOMAIN PROBLEM, EPDDL DOMAIN PROBLEM, then an optional plan file): frame 0 is
  the initial state; frame k shows step k's action — the state before it (with the worlds where its
  executability condition holds marked), its event model, the product M ⊗ E before contraction, the
  contracted model — and which of them is the state the checker carries on, the goal's truth there, what
  changed; the last frame gives ``delkit check``'s verdict. The states are :func:`planners.trace.trace_plan`'s,
  the same as ``delkit check --trace-json``.
* **e-PICO result.json** (``delkit epico run --out DIR``): one frame per executed arm step with each robot's
  beliefs (block → colour) after it, from the run's belief log, beside the run's picture — the frame of the
  run's GIF nearest the step's simulated time, read from the result's own directory only (the final PNG for
  the last frame).
"""

from __future__ import annotations

import io
import json
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from delkit.errors import DelkitError
from delkit.view.document import Document, Frame, Panel

__all__ = ["task_viewer", "epico_viewer", "task_document", "epico_document", "stepper"]

_TASK_SUFFIXES = (".epddl", ".pddl")
_PLAN_SUFFIXES = (".plan", ".sol", ".txt")
#: the largest picture read from an e-PICO run's directory (bytes)
MAX_IMAGE = 20 * 1024 * 1024


def _split(paths: Sequence[Path]) -> tuple[list[Path], Path | None]:
    """(task files, plan file): a last file that is not a PDDL file is the plan (if there are two or more)."""
    ps = list(paths)
    if len(ps) >= 2 and ps[-1].suffix.lower() not in _TASK_SUFFIXES:
        return ps[:-1], ps[-1]
    return ps, None


def _is_task(path: Path) -> bool:
    if path.name.lower().endswith(".smcdel.txt") or path.suffix.lower() in (".json", ".dot", ".gv"):
        return False
    if path.suffix.lower() in _TASK_SUFFIXES:
        return True
    from planners.lang.detect import detect_text

    try:
        detect_text(path.read_text(encoding="utf-8", errors="replace")[:200_000], str(path))
        return True
    except DelkitError:
        return False


def task_viewer(paths: Sequence[Path], options: dict) -> Document | None:
    """A task (with an optional plan) named on the command line, else None."""
    if not paths or not _is_task(paths[0]):
        return None
    from planners.lang import load_task
    from planners.validate import read_plan

    files, plan_file = _split(paths)
    if len(files) > 2:
        raise DelkitError(f"{files[2]}: give SPEC [PLAN] or DOMAIN PROBLEM [PLAN]")
    task = load_task(files[0], files[1] if len(files) == 2 else None, list(options.get("library") or ()))
    plan = read_plan(plan_file) if plan_file is not None else []
    return task_document(task, plan, sources=[str(p) for p in paths], plan_source=str(plan_file or "plan"))


def task_document(task: Any, plan: list[str], *, sources: list[str] | None = None,
                  plan_source: str = "plan") -> Document:
    """The frames of ``plan`` on ``task`` (see the module docstring)."""
    from delkit.formula import show
    from planners.trace import changes, trace_plan
    from planners.validate import parse_formula

    tr = trace_plan(task, plan, plan_source=plan_source)
    goal = show(task.goal)
    frames: list[Frame] = []
    for s in tr.steps:
        goal_worlds = [int(w) for w in range(s.state.n_worlds) if s.state.check(task.goal)[w]]
        note_goal = f"goal {goal}: {'holds' if s.goal else 'does not hold'} at the designated world(s) of this state"
        if s.action is None:
            frames.append(Frame("0: initial state", [Panel("state", "initial state M₀", s.state,
                                                           {"goal holds": goal_worlds})],
                                [note_goal], data={"carried": "state", "step": 0}))
            continue
        pre = show(s.precondition) if s.precondition is not None else "⊤"
        panels = [Panel("before", f"M{_sub(s.index - 1)} (before; marked: executable)", s.before,
                        {f"executable: {pre}": s.pre_worlds})]
        for j, em in enumerate(s.events):
            label = s.parts[j] if len(s.parts) > 1 else s.action
            panels.append(Panel(f"event{j}" if j else "event", f"event model of {label}", em))
        notes = [f"executable if {pre}: holds at "
                 f"{', '.join(s.before.world_name(w) for w in s.pre_worlds) or 'no world'} of M{_sub(s.index - 1)}"]
        carried = "state"
        if s.failed:
            notes.append(f"delkit check: INVALID at step {s.index}: {s.failed}")
            carried = "before"
        else:
            carried = "product" if s.carried == "product" else "contracted"
            panels.append(Panel("product", f"M{_sub(s.index - 1)} ⊗ E (before contraction)"
                                + (" = M" + _sub(s.index) if carried == "product" else ""), s.product,
                                {"goal holds": goal_worlds} if carried == "product" else {}))
            if s.contracted is not None:
                panels.append(Panel("contracted", "after bisimulation contraction"
                                    + (" = M" + _sub(s.index) if carried == "contracted" else ""), s.contracted,
                                    {"goal holds": goal_worlds} if carried == "contracted" else {}))
            ch = changes(tr.steps[s.index - 1].state, s.state)
            what = [f"{p}: {a} → {b}" for p, (a, b) in ch["facts"].items()] + ch["learned"] + ch["forgot"]
            notes.append(f"M{_sub(s.index)} is the {'product' if carried == 'product' else 'contracted model'} "
                         f"(what delkit check carries on: it contracts above 64 worlds, never EPDDL states)")
            notes.append("changed: " + ("; ".join(what) if what else "nothing at the designated world(s)"))
            notes.append(note_goal)
        if s.index == len(tr.steps) - 1:
            v = tr.verdict
            notes.append("delkit check: " + (f"valid: {v['steps']} step(s), goal reached" if v["valid"] else
                                             f"INVALID at step {v.get('step')}: {v.get('reason')}"))
        frames.append(Frame(f"{s.index}: {s.action}", panels, notes, data={"carried": carried, "step": s.index}))
    if not plan:
        frames[0].notes.append("no plan given: the initial state only (delkit view SPEC [PROBLEM] PLAN)")
    doc = Document(f"{task.name}" + (f" — {len(plan)}-step plan" if plan else ""), "task",
                   sources or [task.source], frames,
                   [f"goal: {goal}", "formulas: delkit syntax or mA* syntax, over the task's fluents"])
    doc.parse = lambda text: parse_formula(text, task, source="formula")
    return doc


def _sub(k: int) -> str:
    return str(k).translate(str.maketrans("0123456789", "₀₁₂₃₄₅₆₇₈₉"))


# ------------------------------------------------------------------------------------------ e-PICO


def epico_viewer(paths: Sequence[Path], options: dict) -> Document | None:
    """An e-PICO ``result.json`` (``delkit epico run --out DIR``), else None."""
    if len(paths) != 1 or paths[0].suffix.lower() != ".json":
        return None
    try:
        data = json.loads(paths[0].read_text(encoding="utf-8"))
    except (OSError, UnicodeDecodeError, json.JSONDecodeError):
        return None
    if not isinstance(data, dict) or not {"belief_log", "steps", "goal", "beliefs"} <= set(data):
        return None
    return epico_document(data, paths[0])


def _picture(base: Path, name: Any) -> Path | None:
    """A picture the run wrote, looked up by file name in the result's own directory only."""
    if not isinstance(name, str) or not name:
        return None
    p = base / Path(name).name
    if p.is_file() and p.stat().st_size <= MAX_IMAGE and p.suffix.lower() in (".png", ".gif"):
        return p
    return None


def beliefs_after(log: list[dict], t: float) -> dict[str, dict[str, str]]:
    """Each robot's beliefs (block → colour) from the belief-log entries up to simulated time ``t``: a sensing
    robot learns the colour it saw; an announcement's receivers learn it too."""
    out: dict[str, dict[str, str]] = {}
    for e in log:
        if float(e.get("t_sim_s", 0.0)) > t + 1e-9:
            break
        for r in [e.get("robot"), *(e.get("to") or [])]:
            if r:
                out.setdefault(str(r), {})[str(e.get("block"))] = str(e.get("colour"))
    return out


def epico_document(data: dict, path: Path) -> Document:
    base = path.parent
    files = data.get("files") or {}
    video, final = _picture(base, files.get("video")), _picture(base, files.get("png"))
    gif = _gif_count(video) if video is not None else None
    sim = float(data.get("sim_seconds") or 0.0)
    robots = sorted({str(r) for e in data["belief_log"] for r in [e.get("robot"), *(e.get("to") or [])] if r}
                    | set(data.get("beliefs") or {}))

    def table(t: float) -> list[list[str]]:
        b = beliefs_after(data["belief_log"], t)
        rows = [["robot", "believes (block: colour)"]]
        for r in robots:
            rows.append([r, ", ".join(f"{k}: {v}" for k, v in sorted(b.get(r, {}).items())) or "nothing yet"])
        return rows

    def image(t: float, last: bool) -> bytes | None:
        if last and final is not None:
            return final.read_bytes()
        if gif is None:
            return None
        k = 0 if sim <= 0 else round(min(max(t / sim, 0.0), 1.0) * (gif - 1))
        return _gif_frame(video, k)

    frames = [Frame("0: start", [], ["no arm step yet"], table(-1.0), image(0.0, False))]
    steps = data["steps"]
    for i, s in enumerate(steps, 1):
        t = float(s.get("t_sim_s") or 0.0)
        notes = [f"{s.get('text')} (task {s.get('task')}, plan {s.get('plan')}), t = {t:.2f} s simulated",
                 ("ok: " if s.get("ok") else "DIVERGED: ") + str(s.get("message", ""))]
        seen = (s.get("observed") or {}).get("seen")
        if seen:
            notes.append("observed: " + ", ".join(f"{k} is {v}" for k, v in seen.items()))
        if s.get("fault"):
            notes.append(f"fault: {s['fault']}")
        if i == len(steps):
            notes.append(f"mission: {'SUCCESS' if data.get('success') else 'FAILURE'}: {data.get('reason', '')}")
        frames.append(Frame(f"{i}: {s.get('text')}", [], notes, table(t), image(t, i == len(steps))))
    pic = ("the run's GIF frame nearest each step's simulated time; the last frame: its final PNG"
           if gif is not None else "the run wrote no picture next to result.json" if final is None else
           "the run's final PNG on the last frame")
    notes = [f"e-PICO goal {data.get('goal')}: {'SUCCESS' if data.get('success') else 'FAILURE'}; "
             f"{len(steps)} arm step(s), {data.get('replans', 0)} replan(s)", f"pictures: {pic}"]
    return Document(f"e-PICO run ({path.parent.name}/{path.name})", "mission", [str(path)], frames, notes)


def _gif_count(path: Path) -> int | None:
    """The number of frames of the GIF (Pillow, which matplotlib already needs), None if unreadable."""
    try:
        from PIL import Image

        with Image.open(path) as im:
            return int(getattr(im, "n_frames", 1)) or None
    except (ImportError, OSError, ValueError):
        return None


def _gif_frame(path: Path, k: int) -> bytes | None:
    """Frame ``k`` of the GIF as PNG bytes."""
    from PIL import Image

    try:
        with Image.open(path) as im:
            im.seek(k)
            buf = io.BytesIO()
            im.convert("RGB").save(buf, format="PNG")
            return buf.getvalue()
    except (OSError, EOFError, ValueError):
        return None


# ------------------------------------------------------------------------------------------ notebook


def stepper(task: Any, plan: list[str]) -> Any:
    """The plan's frames as a self-contained notebook widget (:class:`delkit.view.notebook.Stepper`)."""
    from delkit.view.notebook import Stepper

    return Stepper(task_document(task, list(plan)))
