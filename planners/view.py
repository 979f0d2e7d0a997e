"""The planning layer's documents for ``delkit view`` (and the notebook stepper): a task with a plan, an
e-PICO mission result. Registered with the core viewer through ``VIEWERS`` in :mod:`planners.cli`.

* **Task + plan** (mA*, E-PDDL DOMAIN PROBLEM, EPDDL DOMAIN PROBLEM, then an optional plan file): frame 0 is
  the initial state; frame k shows step k's action — the state before it (with the worlds where its
  executability condition holds marked), its event model, the product M ⊗ E before contraction, the
  contracted model — and which of them is the state the checker carries on, the goal's truth there, what
  changed; the last frame gives ``delkit check``'s verdict. The states are :func:`planners.trace.trace_plan`'s,
  the same as ``delkit check --trace-json``.
* **e-PICO result.json** (``delkit epico run --out DIR``, the schema of ``MissionResult.to_json``; fields it
  does not know are ignored): one frame per executed arm step with the belief-log entries applied after it
  (:func:`assign_log`: an entry belongs to the last step of its own task) and, per robot, the knowledge
  formulas learnt at the step and all learnt so far (:func:`beliefs_by_frame`; the last frame adds the
  result's final ``beliefs``), beside the run's picture — the frame of the run's GIF nearest the step's
  simulated time (the final PNG for the last frame), read from the result's own directory only, resolved and
  confined there (:func:`_picture`).
"""

from __future__ import annotations

import io
import json
import math
import os
import re
import stat
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from delkit.errors import DelkitError
from delkit.view.document import Document, Frame, Panel

__all__ = ["task_viewer", "epico_viewer", "task_document", "epico_document", "stepper", "beliefs_by_frame",
           "assign_log"]

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
    from delkit.logic.formula import show
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
    if not isinstance(data, dict) or not {"belief_log", "steps", "goal"} <= set(data):
        return None
    if not isinstance(data["belief_log"], list) or not isinstance(data["steps"], list):
        raise DelkitError(f"{paths[0]}: not an e-PICO result: belief_log and steps must be lists (write it with "
                          f"delkit epico run --out DIR)")
    return epico_document(data, paths[0])


def _picture(base: Path, name: Any) -> tuple[Path | None, str | None]:
    """A picture the run wrote, looked up by file name in the result's own directory only: (path, None), or
    (None, why it is not shown). The path is resolved (symlinks followed) and must stay inside the result's
    directory — a ``final.png`` linking to a file elsewhere is refused — and be a regular PNG/GIF file of at
    most :data:`MAX_IMAGE` bytes with no other hard link."""
    if not isinstance(name, str) or not name:
        return None, None
    if "\x00" in name:
        return None, f"{name!r}: not shown: a file name with a NUL character"
    p = base / Path(name).name
    root = Path(os.path.realpath(base))
    real = Path(os.path.realpath(p))
    if not os.path.lexists(p):
        return None, None
    if not real.is_relative_to(root):
        return None, (f"{p.name}: not shown: it resolves to {real}, outside the result's folder {root} (the viewer "
                      f"shows only the run's own files)")
    try:
        st = os.stat(real)
    except OSError:
        return None, None
    if not stat.S_ISREG(st.st_mode):
        return None, f"{p.name}: not shown: not a regular file"
    if st.st_nlink > 1:  # a hard link: the same file may be one from elsewhere (the run writes its own, once)
        return None, f"{p.name}: not shown: it has {st.st_nlink} hard links (the run writes its pictures once)"
    if st.st_size > MAX_IMAGE:
        return None, f"{p.name}: not shown: {st.st_size} bytes, the viewer reads at most {MAX_IMAGE}"
    if p.suffix.lower() not in (".png", ".gif") or real.suffix.lower() not in (".png", ".gif"):
        return None, f"{p.name}: not shown: not a .png or .gif file"
    return real, None


def _read_confined(path: Path) -> bytes | None:
    """The bytes of a picture :func:`_picture` accepted (not following a link swapped in since: O_NOFOLLOW)."""
    try:
        fd = os.open(path, os.O_RDONLY | os.O_NOFOLLOW | os.O_NONBLOCK)
    except OSError:
        return None
    with os.fdopen(fd, "rb") as fh:
        if not stat.S_ISREG(os.fstat(fh.fileno()).st_mode):
            return None
        data = fh.read(MAX_IMAGE + 1)
    return data if len(data) <= MAX_IMAGE else None


_KNOWS = re.compile(r"^K_(\S+) ")


def _entry_formulas(e: dict) -> tuple[list[str], list[str]]:
    """(formulas an entry of the belief log added, formulas it removed): ``learnt`` of the current schema
    (``no longer: F`` removes F); an entry of the older schema (block, colour) reads as ``block is colour``."""
    added, removed = [], []
    learnt = e.get("learnt")
    if isinstance(learnt, list):
        for f in learnt:
            f = str(f)
            if f.startswith("no longer: "):
                removed.append(f[len("no longer: "):])
            else:
                added.append(f)
    elif e.get("block") is not None:
        added.append(f"{e.get('block')} is {e.get('colour')}")
    return added, removed


def _owner(formula: str, e: dict) -> list[str]:
    """Whose knowledge a formula of the log is: ``K_robot2 …`` → robot2; else the entry's robot and receivers."""
    m = _KNOWS.match(formula)
    if m:
        return [m.group(1)]
    return [str(r) for r in [e.get("robot"), *(e.get("to") or [])] if r]


def assign_log(log: list[dict], steps: list[dict]) -> list[list[int]]:
    """Which belief-log entries belong to which frame (frame 0: before any step; frame i: after step i): an
    entry goes to the last step of its own task whose simulated time is not after the entry's (the belief
    state is updated once a task's last primitive action is done), else to the last step before it; entries
    keep the log's order."""
    out: list[list[int]] = [[] for _ in range(len(steps) + 1)]
    cur = 0
    times = [_num(s.get("t_sim_s")) for s in steps]
    for k, e in enumerate(log):
        t = _num(e.get("t_sim_s"))
        cands = [j for j in range(max(cur, 1), len(steps) + 1) if times[j - 1] <= t + 1e-6]
        same = [j for j in cands if steps[j - 1].get("task") == e.get("task")]
        j = max(same) if same else max(cands) if cands else cur
        out[j].append(k)
        cur = j
    return out


def _num(x: Any) -> float:
    try:
        v = float(x)
    except (TypeError, ValueError):
        return 0.0
    return v if math.isfinite(v) else 0.0


def beliefs_by_frame(data: dict) -> list[dict]:
    """Per frame: ``known`` (robot → formulas the belief log has added so far and not removed), ``learnt``
    (robot → formulas added at this frame), ``entries`` (the log entries of this frame)."""
    log = [e for e in data.get("belief_log") or [] if isinstance(e, dict)]
    steps = [s for s in data.get("steps") or [] if isinstance(s, dict)]
    known: dict[str, list[str]] = {}
    frames = []
    for idx in assign_log(log, steps):
        learnt: dict[str, list[str]] = {}
        for k in idx:
            added, removed = _entry_formulas(log[k])
            for f in removed:
                for r in _owner(f, log[k]):
                    if f in known.get(r, []):
                        known[r].remove(f)
            for f in added:
                for r in _owner(f, log[k]):
                    if f not in known.setdefault(r, []):
                        known[r].append(f)
                    learnt.setdefault(r, []).append(f)
        frames.append({"known": {r: list(v) for r, v in known.items()}, "learnt": learnt,
                       "entries": [log[k] for k in idx]})
    return frames


def _final_beliefs(data: dict) -> dict[str, list[str]]:
    """The result's ``beliefs`` (robot → knowledge formulas at the end; older schema: block → colour)."""
    b = data.get("beliefs")
    out: dict[str, list[str]] = {}
    if isinstance(b, dict):
        for r, v in b.items():
            if isinstance(v, list):
                out[str(r)] = [str(x) for x in v]
            elif isinstance(v, dict):
                out[str(r)] = [f"{k} is {c}" for k, c in sorted(v.items())]
    return out


def _entry_text(e: dict) -> str:
    added, removed = _entry_formulas(e)
    what = ", ".join(added + [f"no longer {f}" for f in removed]) or "nothing new"
    who = f" by {e.get('robot')}" if e.get("robot") else ""
    return f"t = {_num(e.get('t_sim_s')):.2f} s: {e.get('kind', '?')}{who} ({e.get('chosen', '')}): {what}"


def epico_document(data: dict, path: Path) -> Document:
    base = path.parent
    files = data.get("files") if isinstance(data.get("files"), dict) else {}
    (video, why_v), (final, why_f) = _picture(base, files.get("video")), _picture(base, files.get("png"))
    refused = [w for w in (why_v, why_f) if w]
    gif = _gif_count(video) if video is not None else None
    sim = _num(data.get("sim_seconds"))
    per = beliefs_by_frame(data)
    end = _final_beliefs(data)
    robots = sorted(set(end) | {r for f in per for r in f["known"]})

    def table(k: int, last: bool) -> list[list[str]]:
        f = per[k]
        head = ["robot", "learnt at this step", "known so far (belief log)"] + (["at the end (result)"] if last
                                                                                   else [])
        rows = [head]
        for r in robots:
            row = [r, "\n".join(f["learnt"].get(r, [])) or "—", "\n".join(f["known"].get(r, [])) or "nothing yet"]
            if last:
                row.append("\n".join(end.get(r, [])) or "nothing")
            rows.append(row)
        return rows

    def image(t: float, last: bool) -> bytes | None:
        if last and final is not None:
            return _read_confined(final)
        if gif is None or video is None:
            return None
        k = 0 if sim <= 0 else round(min(max(t / sim, 0.0), 1.0) * (gif - 1))
        return _gif_frame(video, k)

    steps = [s for s in data.get("steps") or [] if isinstance(s, dict)]
    log_notes = [_entry_text(e) for e in per[0]["entries"]]
    frames = [Frame("0: start", [], ["no arm step yet", *log_notes], table(0, not steps), image(0.0, not steps),
                    data={"beliefs": per[0]})]
    for i, s in enumerate(steps, 1):
        t = _num(s.get("t_sim_s"))
        notes = [f"{s.get('text')} (task {s.get('task')}, plan {s.get('plan')}), t = {t:.2f} s simulated",
                 ("ok" if s.get("ok") else "DIVERGED") + (f": {s.get('message')}" if s.get("message") else "")]
        seen = (s.get("observed") or {}).get("seen") if isinstance(s.get("observed"), dict) else None
        if isinstance(seen, dict) and seen:
            notes.append("observed: " + ", ".join(f"{k} is {v}" for k, v in seen.items()))
        if s.get("fault"):
            notes.append(f"fault: {s['fault']}")
        notes += ["belief log: " + _entry_text(e) for e in per[i]["entries"]]
        if i == len(steps):
            notes.append(f"mission: {'SUCCESS' if data.get('success') else 'FAILURE'}: {data.get('reason', '')}")
        frames.append(Frame(f"{i}: {s.get('text')}", [], notes, table(i, i == len(steps)),
                            image(t, i == len(steps)), data={"beliefs": per[i]}))
    pic = ("the run's GIF frame nearest each step's simulated time; the last frame: its final PNG"
           if gif is not None else "the run wrote no picture next to result.json" if final is None else
           "the run's final PNG on the last frame")
    notes = [f"e-PICO goal {data.get('goal')}: {'SUCCESS' if data.get('success') else 'FAILURE'}; "
             f"{len(steps)} arm step(s), {data.get('replans', 0)} replan(s)", f"pictures: {pic}",
             "beliefs: what the run's belief log added (K_a p, K_a ¬p), step by step; knowledge held from the "
             "start is not in the log — the last step also lists the result's final beliefs", *refused]
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
