"""Bodies of ``delkit model diff`` and ``delkit model draw`` (registered in :mod:`delkit.cli.model_cmd`).

Both read Kripke/event model files (JSON or DOT, schema of :mod:`delkit.io.formats`) and SMCDEL files
(``*.smcdel.txt``: knowledge structures, and belief structures with delkit's ``REL`` extension, see
:mod:`delkit.io.smcdel`). Heavy imports stay inside the functions.
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

__all__ = ["load_any", "run_diff", "run_draw"]


# (delkit.view reads them)
from delkit.io.files import ANY_FORMATS, is_smcdel, load_any, structure_model  # noqa: E402,F401


def _core_format(path: str) -> bool:
    """A file the core reads itself (model JSON / DOT, SMCDEL structure)."""
    p = str(path).lower()
    return is_smcdel(p) or p.endswith((".json", ".dot", ".gv"))


def _task_state(paths: list[str], plan: Path | None, step: int):
    """The state after ``step`` steps of ``plan`` on the task in ``paths`` (frames of :mod:`delkit.view`)."""
    from delkit.errors import DelkitError
    from delkit.view.document import load_document

    doc = load_document([*paths, *([plan] if plan is not None else [])])
    if doc.kind != "task" and plan is None and step == 0 and len(paths) == 1:
        return load_any(paths[0]), ""  # a model file with an unusual suffix
    if doc.kind != "task":
        raise DelkitError(f"{paths[0]}: --plan/--step draw a planning task's states; this file is a {doc.kind}")
    if step >= len(doc.frames):
        raise DelkitError(f"--step {step}: the plan has {len(doc.frames) - 1} step(s)"
                          + ("" if len(doc.frames) > 1 or plan is not None else "; give the plan with --plan")
                          + (f" and fails at step {len(doc.frames) - 1}" if doc.frames[-1].data.get("carried")
                             == "before" else ""))
    frame = doc.frames[step]
    carried = frame.data.get("carried", "state")
    if carried == "before":
        raise DelkitError(f"--step {step}: the plan fails at this step ({frame.notes[-1]}); draw --step {step - 1}")
    panel = next(p for p in frame.panels if p.key == carried)
    return panel.model, (f"{doc.title}: {'initial state' if step == 0 else 'state after step ' + frame.title}")


def _pointed(path: str, world: str | None, max_worlds: int):
    from delkit.errors import ModelError
    from delkit.models.kripke import KripkeModel

    obj = load_any(path)
    if is_smcdel(path):
        m = structure_model(obj, path, max_worlds)
        if world is not None:
            wanted = "{" + ",".join(x for x in world.strip().strip("{}").replace(" ", "").split(",") if x) + "}"
            want_set = set(wanted.strip("{}").split(",")) - {""}
            hits = [w for w in range(m.n_worlds) if set(m.world_name(w).strip("{}").split(",")) - {""} == want_set]
            if not hits:
                raise ModelError(f"{path}: no state {wanted} (a state lists its true variables, e.g. 1,3; the "
                                 f"file's states are {', '.join(m.world_name(w) for w in range(m.n_worlds))})")
            m = m.with_designated(hits)
        return m
    if not isinstance(obj, KripkeModel):
        raise ModelError(f"{path}: holds an event model; model diff compares Kripke models or structures")
    if world is not None:
        names = [obj.world_name(w) for w in range(obj.n_worlds)]
        if world not in names:
            raise ModelError(f"{path}: no world {world!r}; the worlds are {', '.join(names)}")
        obj = obj.with_designated([names.index(world)])
    if not obj.designated:
        raise ModelError(f"{path}: the model has no designated world; list the actual world(s) in \"designated\" "
                         "or pick one with --world-a/--world-b")
    return obj


def _pointed_structure(path: str, world: str | None):
    """The structure of an SMCDEL file, its actual states = all states or the state ``world`` (e.g. 1,3)."""
    import dataclasses

    from delkit.errors import ModelError

    obj = load_any(path)
    if world is None:
        return obj
    true = {x for x in world.strip().strip("{}").replace(" ", "").split(",") if x}
    unknown = sorted(true - set(obj.vocabulary))
    if unknown:
        raise ModelError(f"{path}: state {{{world}}} names variable(s) {unknown} not in VARS")
    state = obj.bdd.cube({v: v in true for v in obj.vocabulary}) & obj.law
    if state == obj.bdd.false:
        raise ModelError(f"{path}: {{{','.join(sorted(true))}}} is not a state (it does not satisfy the LAW)")
    return dataclasses.replace(obj, actual=state)


def run_diff(a_path: str, b_path: str, world_a: str | None, world_b: str | None, props: str | None,
             max_worlds: int, as_json: bool, engine: str = "auto") -> int:
    """``delkit model diff``: exit 0 bisimilar, 1 told apart (2, bad input, comes from the exception)."""
    from delkit.errors import DelkitError
    from delkit.logic.formula import show
    from delkit.models.bisimulation import diff

    if engine not in ("auto", "symbolic", "explicit"):
        raise DelkitError(f"--engine {engine!r}: use auto, symbolic or explicit")
    both = is_smcdel(a_path) and is_smcdel(b_path)
    if engine == "symbolic" and not both:
        raise DelkitError("--engine symbolic compares two structures (.smcdel.txt files); use --engine explicit "
                          "for Kripke model files")
    prop_list = [p.strip() for p in props.split(",") if p.strip()] if props is not None else None
    if prop_list == []:  # compared on no propositions everything is bisimilar: not what --props "" means
        raise DelkitError(f"--props {props!r} names no proposition; give a comma-separated list such as "
                          f"--props p,q, or leave --props out to compare on all of them")
    if both and engine != "explicit":
        from delkit.backends.bisimulation_symbolic import symbolic_diff

        res = symbolic_diff(_pointed_structure(a_path, world_a), _pointed_structure(b_path, world_b),
                            props=prop_list)
        des_a, des_b = (world_a or "all states"), (world_b or "all states")
        note = "structures compared by symbolic partition refinement on BDDs (delkit.backends.bisimulation_symbolic)"
    else:
        a = _pointed(a_path, world_a, max_worlds)
        b = _pointed(b_path, world_b, max_worlds)
        res = diff(a, b, props=prop_list)
        des_a = ", ".join(a.world_name(d) for d in a.designated)
        des_b = ", ".join(b.world_name(d) for d in b.designated)
        note = None
        if is_smcdel(a_path) or is_smcdel(b_path):
            note = ("symbolic structures compared through their explicit Kripke models (one world per state; "
                    f"limit --max-worlds {max_worlds})")
    out = res.as_dict()
    if note:
        out["note"] = note
    explicit = bool(note)
    if as_json:
        print(json.dumps({"a": a_path, "b": b_path, **out}))
        return 0 if res.bisimilar else 1
    if res.bisimilar:
        print(f"bisimilar: ({a_path}, {des_a}) and ({b_path}, {des_b})")
        print("bisimulation (world of A ~ world of B, on the parts generated by the designated worlds):")
        for x, y in out["relation"]:
            print(f"  {x} ~ {y}")
    else:
        yes, no = (a_path, b_path) if res.true_in == "A" else (b_path, a_path)
        print(f"NOT bisimilar: {show(res.formula)}")
        print(f"  holds at every designated world of {yes}, fails at {out['fails_at']} of {no} "
              f"(modal depth {out['modal_depth']}, size {out['size']})")
    for what, text in out.get("explanation", {}).items():
        print(f"  {what}: {text}")
    if explicit:
        print(f"note: {out['note']}")
    return 0 if res.bisimilar else 1


#: the most nodes + edges drawn as PNG (matplotlib: ~10 ms CPU per element measured; SVG/TikZ are text)
PNG_MAX = 2000


def _lone_problem(path: str) -> bool:
    """Whether ``path`` is a (E-)PDDL problem file, which a task needs its domain for."""
    import re

    try:
        from delkit.paths import read_input

        head = read_input(path, "input", errors="replace")[:4096]
    except OSError:
        return False
    return re.search(r"\(\s*define\s*\(\s*problem\b", head, re.I) is not None and \
        re.search(r"\(\s*define\s*\(\s*domain\b", head, re.I) is None


def run_draw(path: str | list[str], output: Path, max_worlds: int, layout: str, seed: int, *,
             plan: Path | None = None, step: int = 0) -> None:
    """``delkit model draw``: the picture in the format of the output's suffix (.svg, .png, .tex). A planning
    task (read by the layer that registers it, :func:`delkit.view.load_document`) draws its state after
    ``step`` steps of ``plan`` (the state ``delkit check --trace`` prints)."""
    from delkit.drawing import draw
    from delkit.errors import DelkitError

    suffix = output.suffix.lower()
    if suffix not in (".svg", ".png", ".tex"):
        raise DelkitError(f"{output}: cannot tell the picture format; name the output *.svg, *.png or *.tex")
    paths = [path] if isinstance(path, str) else list(path)
    from delkit.resources import check_outputs

    check_outputs([output], [*paths, *([plan] if plan is not None else [])], option="-o")
    if plan is None and step == 0 and len(paths) == 1 and _core_format(paths[0]):
        obj = load_any(paths[0])
        pic = draw.picture(obj, max_worlds=max_worlds, layout=layout, seed=seed)
    else:
        if len(paths) == 1 and _lone_problem(paths[0]):
            raise DelkitError(f"{paths[0]}: an E-PDDL/EPDDL planning problem; model draw reads it with its domain "
                              f"(delkit model draw DOMAIN PROBLEM [--plan PLAN --step K]), and reads by itself "
                              f"{ANY_FORMATS}")
        obj, what = _task_state(paths, plan, step)
        pic = draw.picture(obj, max_worlds=max_worlds, layout=layout, seed=seed)
        pic.header = [what] * bool(what) + pic.header
    if suffix == ".png" and len(pic.nodes) + len(pic.edges) > PNG_MAX:
        # matplotlib draws each node and edge as its own patch: ~10 ms each, minutes for thousands
        raise DelkitError(f"{output}: {len(pic.nodes)} worlds and {len(pic.edges)} edges are more than the "
                          f"{PNG_MAX} elements a PNG is drawn with in reasonable time; write *.svg or *.tex "
                          f"instead (fast at any size), or draw a contracted model (delkit model contract)")
    try:
        output.parent.mkdir(parents=True, exist_ok=True)  # like the other commands' --out
        if suffix == ".svg":
            output.write_text(pic.svg(), encoding="utf-8")
        elif suffix == ".tex":
            output.write_text(pic.tikz(standalone=True), encoding="utf-8")
        else:
            pic.png(output)
    except OSError as exc:
        raise DelkitError(f"{output}: cannot write the picture ({exc.strerror}); check the directory") from None
    print(f"wrote {output} ({pic.summary})", file=sys.stderr)
