"""What ``delkit view`` shows: a :class:`Document` of :class:`Frame` s, each with graph :class:`Panel` s.

A document is built once, when the viewer starts, by a *viewer*: a function ``(paths, options) -> Document |
None`` that recognises its files (None: not mine). The core's viewer reads Kripke and event models (JSON /
DOT, :mod:`delkit.io.formats`) and SMCDEL structures (``.smcdel.txt``, drawn explicitly up to ``max_worlds``); the
layers above the core add theirs — the planning layer reads tasks with a plan (one frame per step) and
e-PICO mission results — through the ``VIEWERS`` attribute of their ``delkit.commands`` module (see
:func:`viewers`), so the core never imports them.

Every truth value the page shows is computed here, in Python: :func:`evaluate` parses a formula with
delkit's parser (or the document's own parser, e.g. a task's that also reads mA* syntax) and evaluates it
with :meth:`KripkeModel.check`; :func:`possible` lists an agent's accessible worlds. The page only draws.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from delkit.errors import DelkitError, ModelError, ParseError

__all__ = ["Panel", "Frame", "Document", "Viewer", "viewers", "register_viewer", "load_document", "graph_json",
           "evaluate", "possible", "MAX_WORLDS", "MAX_FORMULA", "core_viewer", "document_json"]

#: the largest explicit model the viewer draws and evaluates on (a bigger one is refused, said)
MAX_WORLDS = 5000
#: the longest formula text the viewer parses
MAX_FORMULA = 2000


@dataclass
class Panel:
    """One graph of a frame: a Kripke model (formulas are evaluated on it) or an event model (drawn only).

    ``marks`` are precomputed world sets to show, e.g. ``{"precondition holds": [0, 2]}``."""

    key: str
    title: str
    model: Any
    marks: dict[str, list[int]] = field(default_factory=dict)

    @property
    def is_kripke(self) -> bool:
        from delkit.models.kripke import KripkeModel

        return isinstance(self.model, KripkeModel)


@dataclass
class Frame:
    """One step of a document: its graphs, text notes, an optional table and an optional picture."""

    title: str
    panels: list[Panel] = field(default_factory=list)
    notes: list[str] = field(default_factory=list)
    table: list[list[str]] | None = None
    image: bytes | None = None
    image_type: str = "image/png"
    data: dict = field(default_factory=dict)


@dataclass
class Document:
    """What the viewer shows: ``frames`` (one for a model; initial state + one per step for a plan)."""

    title: str
    kind: str
    sources: list[str]
    frames: list[Frame]
    notes: list[str] = field(default_factory=list)
    parse: Callable[[str], Any] | None = None

    def panel(self, frame: int, key: str) -> Panel:
        if not isinstance(frame, int) or isinstance(frame, bool) or not 0 <= frame < len(self.frames):
            raise DelkitError(f"frame {frame!r}: the document has frames 0..{len(self.frames) - 1}")
        for p in self.frames[frame].panels:
            if p.key == key:
                return p
        raise DelkitError(f"frame {frame} has no panel {key!r} (it has "
                          f"{', '.join(p.key for p in self.frames[frame].panels) or 'none'})")


Viewer = Callable[[Sequence[Path], dict], "Document | None"]
_REGISTERED: list[Viewer] = []


def register_viewer(viewer: Viewer) -> Viewer:
    """Add a viewer (tried before the core's own, in the order registered); returns it (decorator use)."""
    if viewer not in _REGISTERED:
        _REGISTERED.append(viewer)
    return viewer


def viewers() -> list[Viewer]:
    """The registered viewers, the installed layers' (``VIEWERS`` of each ``delkit.commands`` module), then the
    core's :func:`core_viewer`."""
    from delkit.cli.plugins import plugin_modules

    out = list(_REGISTERED)
    for _, module in plugin_modules():
        for v in getattr(module, "VIEWERS", ()):
            if v not in out:
                out.append(v)
    return [*out, core_viewer]


def load_document(paths: Sequence[str | Path], **options: Any) -> Document:
    """The document of the files named on the command line (the first viewer that recognises them)."""
    ps = [Path(p) for p in paths]
    if not ps:
        raise DelkitError("delkit view: name a model, structure, task (with a plan) or e-PICO result file")
    for p in ps:
        if not p.is_file():
            raise DelkitError(f"{p}: no such file; name a model (.json/.dot), a structure (.smcdel.txt), a task "
                              f"(with its plan) or an e-PICO result.json")
    for v in viewers():
        doc = v(ps, options)
        if doc is not None:
            _check_sizes(doc)
            return doc
    raise DelkitError(f"{ps[0]}: no viewer reads these files")  # pragma: no cover - core_viewer always answers


def _check_sizes(doc: Document) -> None:
    for f in doc.frames:
        for p in f.panels:
            n = _size(p.model)
            if n > MAX_WORLDS:
                raise ModelError(f"{doc.sources[0]}: {f.title}: {p.title} has {n} worlds; the viewer draws at most "
                                 f"{MAX_WORLDS} (use delkit model check / smcdel for bigger models)")


def _size(model: Any) -> int:
    n = getattr(model, "n_worlds", None)
    return int(n if n is not None else getattr(model, "n_events", 0))


def core_viewer(paths: Sequence[Path], options: dict) -> Document:
    """Kripke / event models (JSON, DOT) and SMCDEL structures: one frame."""
    from delkit.io.files import is_smcdel, load_any

    if len(paths) != 1:
        raise DelkitError(f"{paths[1]}: a model or structure file is viewed alone (a second file is a plan, "
                          f"which needs a planning task as the first file)")
    path = paths[0]
    obj = load_any(str(path))
    notes: list[str] = []
    if is_smcdel(str(path)):
        limit = int(options.get("max_worlds", 512))
        n = obj.count_states()
        if n > limit:
            raise ModelError(f"{path}: the structure has {n} states; the viewer draws its Kripke model up to "
                             f"{limit} (raise --max-worlds, at most {MAX_WORLDS})")
        from delkit.io.files import structure_model

        model = structure_model(obj, str(path), limit)
        notes.append(f"the structure's Kripke model, drawn explicitly ({n} states; limit {limit}, --max-worlds); "
                     f"each world is named by its true variables")
        from delkit.drawing.draw import structure_header

        notes.append("; ".join(structure_header(obj, limit=300)))  # θ and Ω_a as formulas (form_of)
        kind = "structure"
        parse = _smcdel_parser(path, model)
    else:
        parse = None
        model = obj
        kind = "kripke" if hasattr(obj, "valuation") else "event"
    title = path.name
    frame = Frame(title, [Panel("state", "model" if kind != "event" else "event model", model)])
    return Document(title, kind, [str(path)], [frame], notes, parse)


def _smcdel_parser(path: Path, model: Any) -> Callable[[str], Any]:
    """Formulas on a structure: delkit's syntax, else SMCDEL's (``amy knows whether 1``), read by delkit's
    SMCDEL parser after the file's own declarations (VARS, LAW, OBS/REL); errors point into the formula."""
    import re

    from delkit.io.smcdel import parse_smcdel
    from delkit.logic.formula import parse

    text = path.read_text(encoding="utf-8")
    m = re.search(r"^\s*(TRUE\?|VALID\?|WHERE\?)", text, flags=re.M)
    header = (text[:m.start()] if m else text).rstrip() + "\n"
    first_line = header.count("\n") + 1

    def read(formula: str) -> Any:
        try:
            f = parse(formula, source="formula")
            model.validate_symbols(f)
            return f
        except DelkitError as first:
            if "\n" in formula:
                raise first from None
            try:
                spec = parse_smcdel(header + "VALID? " + formula + "\n", source="formula")
            except ParseError as exc:
                if exc.line == first_line:
                    col = (exc.column or 8) - 7
                    if col > (getattr(first, "column", None) or 0):  # an unknown symbol has no column
                        raise ParseError(str(exc).split(": ", 1)[-1].strip() + " (SMCDEL syntax)",
                                         source="formula", line=1, column=col) from None
                raise first from None
            return spec.queries[0].formula

    return read


# ------------------------------------------------------------------------------------------ JSON


def graph_json(model: Any) -> dict:
    """The drawing of a model for the page: positions from :mod:`delkit.drawing.draw` (the static pictures' layout),
    worlds with their valuations, one edge per drawn arrow (agents listed), S5 agents whose loops are hidden."""
    from delkit.drawing import draw

    pic = draw.picture(model)
    kripke = hasattr(model, "valuation")
    nodes = []
    for i, nd in enumerate(pic.nodes):
        item = {"id": i, "name": nd.name, "lines": nd.lines, "x": round(nd.x, 1), "y": round(nd.y, 1),
                "r": round(nd.r, 1), "designated": nd.designated}
        if kripke:
            item["props"] = sorted(model.true_props(i))
        nodes.append(item)
    edges = []
    for e in pic.edges:
        lx, ly = pic.label_xy(e)
        edges.append({"u": e.u, "v": e.v, "agents": e.label.split(","), "both": e.both, "bend": e.bend,
                      "color": e.color, "lx": round(lx, 1), "ly": round(ly, 1),
                      "loop": round(math.degrees(math.atan2(e.loop[0], -e.loop[1])), 1)})
    s5 = [a for a in model.agents if _equivalence(model.relations[a])]
    return {"nodes": nodes, "edges": edges, "agents": list(model.agents), "s5": s5,
            "colors": {a: draw.agent_color(i) for i, a in enumerate(model.agents)},
            "caption": pic.caption, "kripke": kripke}


def _equivalence(rel: Any) -> bool:
    return rel.labels is not None or (rel.is_reflexive() and rel.is_symmetric() and rel.is_transitive())


def document_json(doc: Document) -> dict:
    """The whole document for the page (graphs of every frame; images are fetched by frame number)."""
    frames = []
    for i, f in enumerate(doc.frames):
        frames.append({"index": i, "title": f.title, "notes": f.notes, "table": f.table,
                       "image": f.image is not None,
                       "panels": [{"key": p.key, "title": p.title, "kripke": p.is_kripke,
                                   "marks": p.marks, "graph": graph_json(p.model)} for p in f.panels],
                       "data": f.data})
    return {"title": doc.title, "kind": doc.kind, "sources": doc.sources, "notes": doc.notes, "frames": frames,
            "limits": {"formula_chars": MAX_FORMULA, "worlds": MAX_WORLDS}}


# ------------------------------------------------------------------------------------------ semantics


def parse_for(doc: Document, panel: Panel, text: str) -> Any:
    """The formula ``text`` parsed by delkit's parser (or the document's), its symbols checked on the model."""
    if not isinstance(text, str):
        raise ParseError("the formula must be a string", source="formula")
    if len(text) > MAX_FORMULA:
        raise ParseError(f"the formula has {len(text)} characters; the viewer parses at most {MAX_FORMULA}",
                         source="formula")
    if doc.parse is not None:
        return doc.parse(text)
    from delkit.logic.formula import parse

    f = parse(text, source="formula")
    panel.model.validate_symbols(f)
    return f


def evaluate(doc: Document, frame: int, key: str, text: str) -> dict:
    """Where the formula holds on a frame's Kripke panel: per world, and at the designated world(s)."""
    from delkit.logic.formula import show

    panel = doc.panel(frame, key)
    if not panel.is_kripke:
        raise DelkitError(f"{panel.title} is an event model: formulas are evaluated on Kripke models")
    f = parse_for(doc, panel, text)
    vec = panel.model.check(f)
    truth = [bool(x) for x in vec]
    return {"ok": True, "formula": show(f), "truth": truth,
            "worlds": [panel.model.world_name(w) for w, t in enumerate(truth) if t],
            "holds": bool(panel.model.holds(f)), "designated": [int(d) for d in panel.model.designated]}


def possible(doc: Document, frame: int, key: str, agent: Any, world: Any) -> dict:
    """The worlds ``agent`` considers possible from ``world`` (its successors in the panel's model)."""
    panel = doc.panel(frame, key)
    m = panel.model
    if not isinstance(agent, str) or agent not in m.agents:
        raise DelkitError(f"agent {agent!r}: the model's agents are {', '.join(m.agents)}")
    n = _size(m)
    if not isinstance(world, int) or isinstance(world, bool) or not 0 <= world < n:
        raise DelkitError(f"world {world!r}: give a world number 0..{n - 1}")
    succ = [int(v) for v in m.relations[agent].successors(world)]
    name = m.world_name(world) if hasattr(m, "world_name") else m.events[world]
    names = [m.world_name(v) if hasattr(m, "world_name") else m.events[v] for v in succ]
    return {"ok": True, "agent": agent, "world": world, "name": name, "worlds": succ, "names": names}
