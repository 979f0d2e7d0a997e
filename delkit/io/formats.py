"""Reading and writing Kripke and event models: JSON (a documented schema) and Graphviz DOT.

JSON schema, version 1 (formulas are text in the syntax of :func:`delkit.logic.formula.parse`)::

    {
      "delkit": "kripke-model", "version": 1,
      "props":  ["p", "q"],                        # all propositions (optional: taken from the worlds)
      "agents": ["a", "b"],                        # optional: taken from "relations"
      "worlds": [{"name": "w0", "true": ["p"]},    # a world: its name (optional) and its true props
                 {"name": "w1", "true": []}],
      "relations": {                               # one entry per agent
        "a": {"blocks": [["w0", "w1"]]},           # an equivalence (S5): its classes; missing = singleton
        "b": {"pairs":  [["w0", "w0"], ["w1", "w0"]]}   # any relation (K, KD45): its (from, to) pairs
      },
      "designated": ["w0"]                         # worlds by name or by index
    }

    {
      "delkit": "event-model", "version": 1, "name": "E",
      "agents": ["a", "b"],
      "events": [{"name": "e", "pre": "p", "post": {"p": "F"}},   # post: prop -> formula (default p -> p)
                 {"name": "f", "pre": "T"}],
      "relations": {"a": {"blocks": [["e"], ["f"]]}, "b": {"pairs": [["e", "f"], ["f", "f"]]}},
      "designated": ["e"]
    }

A bare list as a relation (``"a": [["w0", "w1"]]``) is read as blocks. Worlds and events may be named by
index instead of by name everywhere. :func:`load` reads either kind (by the ``"delkit"`` key).

DOT (:func:`to_dot`) draws worlds (or events) as nodes, designated ones with a double border, and one
edge per related pair and agent (equivalences undirected, without reflexive loops). The drawing carries
``delkit_*`` attributes so that :func:`from_dot` reads back exactly the model that was written; DOT from
other tools is not a supported input.

Malformed input raises :class:`~delkit.errors.ParseError` (JSON/DOT syntax, with line and column) or
:class:`ModelFileError` (schema), each naming the file, the offending entry and how to fix it.
"""

from __future__ import annotations

import json
import re
from collections.abc import Mapping
from functools import lru_cache
from pathlib import Path
from typing import Any

import numpy as np
from scipy.sparse.csgraph import connected_components

from delkit.errors import DelkitError, ModelError, ParseError
from delkit.logic.formula import TOP, Formula, parse, show
from delkit.models.events import EventModel
from delkit.models.kripke import KripkeModel
from delkit.models.relation import Relation

__all__ = [
    "ModelFileError", "MODEL_FORMATS", "sniff", "not_this_format", "SCHEMA_VERSION", "model_to_dict",
    "model_from_dict", "event_model_to_dict",
    "event_model_from_dict", "to_dict", "from_dict", "dumps", "loads", "save", "load", "load_model",
    "load_event_model", "to_dot", "from_dot", "save_dot", "load_dot",
]

SCHEMA_VERSION = 1
_KINDS = ("kripke-model", "event-model")
_CONSTANTS = frozenset({"T", "F", "true", "false"})
_OPERATOR_NAME = re.compile(r"(K|B|Kw)_[A-Za-z0-9]+$")
_MODEL_KEYS = ("delkit", "version", "props", "agents", "worlds", "relations", "designated")
_EVENT_KEYS = ("delkit", "version", "name", "agents", "events", "relations", "designated")


class ModelFileError(ModelError):
    """A model file that parses as JSON/DOT but does not follow the delkit schema."""


# ============================================================================ to dict


def _relation_dict(rel: Relation, names: list[str]) -> dict:
    if rel.is_partition:
        lab = rel.labels
        blocks: dict[int, list[str]] = {}
        for i, c in enumerate(lab):
            blocks.setdefault(int(c), []).append(names[i])
        return {"blocks": list(blocks.values())}  # in order of their first world
    return {"pairs": [[names[int(w)], names[int(v)]] for w, v in sorted(map(tuple, rel.pairs().tolist()))]}


def _world_names(m: KripkeModel) -> list[str]:
    """The model's world names, or w0, w1, … if it has none or they are not unique."""
    names = [m.world_name(w) for w in range(m.n_worlds)]
    return names if len(set(names)) == len(names) else [f"w{w}" for w in range(m.n_worlds)]


def model_to_dict(model: KripkeModel) -> dict:
    """The JSON-ready dict of a Kripke model (schema in the module docstring)."""
    if model.n_worlds == 0:  # the reader rejects such a file: do not write one that cannot be read back
        raise ModelError("a Kripke model with no worlds cannot be written (the file format needs at least one "
                         "world); it is what an update gives when no event applies: check the preconditions")
    names = _world_names(model)
    return {
        "delkit": "kripke-model", "version": SCHEMA_VERSION,
        "props": list(model.props), "agents": list(model.agents),
        "worlds": [{"name": names[w], "true": [p for p in model.props if model.valuation[w, model.prop_index(p)]]}
                   for w in range(model.n_worlds)],
        "relations": {a: _relation_dict(model.relations[a], names) for a in model.agents},
        "designated": [names[d] for d in model.designated],
    }


def event_model_to_dict(events: EventModel) -> dict:
    """The JSON-ready dict of an event model (schema in the module docstring)."""
    names = list(events.events)
    evs = []
    for i, e in enumerate(names):
        item: dict[str, Any] = {"name": e, "pre": show(events.pre[i])}
        if events.post[i]:
            item["post"] = {p: show(v) for p, v in sorted(events.post[i].items())}
        evs.append(item)
    return {
        "delkit": "event-model", "version": SCHEMA_VERSION, "name": events.name, "agents": list(events.agents),
        "events": evs, "relations": {a: _relation_dict(events.relations[a], names) for a in events.agents},
        "designated": [names[d] for d in events.designated],
    }


def to_dict(obj: KripkeModel | EventModel) -> dict:
    if isinstance(obj, KripkeModel):
        return model_to_dict(obj)
    if isinstance(obj, EventModel):
        return event_model_to_dict(obj)
    raise TypeError(f"cannot serialise {type(obj).__name__}; expected a KripkeModel or an EventModel")


# ============================================================================ from dict


class _Reader:
    """Schema checks with messages that name the file and the entry."""

    def __init__(self, source: str) -> None:
        self.source = source

    def fail(self, what: str, fix: str) -> ModelFileError:
        return ModelFileError(f"{self.source}: {what}; {fix}")

    def get(self, d: Mapping, key: str, typ: type | tuple[type, ...], where: str, default: Any = ...) -> Any:
        if key not in d:
            if default is not ...:
                return default
            raise self.fail(f"{where} has no {key!r} entry", f"add \"{key}\" (see the schema in delkit.io.formats)")
        val = d[key]
        if not isinstance(val, typ) or isinstance(val, bool) and typ is not bool:
            tn = typ.__name__ if isinstance(typ, type) else " or ".join(t.__name__ for t in typ)
            raise self.fail(f"{where}: {key!r} must be a {_json_type(tn)}, got {json.dumps(val)[:60]}",
                            "fix the entry's type")
        return val

    def symbols(self, d: Mapping, key: str, where: str, default: list[str]) -> list[str]:
        """A list of distinct non-empty strings (the "props" or "agents" entry)."""
        val = self.get(d, key, list, where, default=default)
        bad = [x for x in val if not isinstance(x, str) or not x]
        if bad:
            raise self.fail(f"{where}: {key!r} must list names as strings, got {json.dumps(bad[0])[:40]}",
                            f"write \"{key}\": [\"{'p' if key == 'props' else 'a'}\", ...]")
        dup = sorted({x for x in val if val.count(x) > 1})
        if dup:
            raise self.fail(f"{where}: {key!r} lists {dup} more than once", "list each name once")
        if key == "props":
            self.plain_props(val, where)
        return val

    def plain_props(self, props: list[str], where: str) -> None:
        """A proposition must read back as itself in a formula: ``T`` would be read as the constant true."""
        for p in props:
            if p in _CONSTANTS or _OPERATOR_NAME.match(p):
                what = "a constant" if p in _CONSTANTS else "a modal operator"
                raise self.fail(f"{where}: proposition {p!r} would be read as {what} in formulas",
                                "rename it (e.g. \"" + p.lower() + "_\")")

    def keys(self, d: Mapping, allowed: tuple[str, ...], where: str) -> None:
        """Unknown entries are errors, not ignored (a misspelt key would silently change the model)."""
        extra = [k for k in d if k not in allowed]
        if extra:
            raise self.fail(f"{where}: unknown entry {extra[0]!r}", f"the entries are {', '.join(allowed)}")

    def names(self, items: list, kind: str) -> list[str]:
        out = []
        for i, it in enumerate(items):
            if not isinstance(it, Mapping):
                raise self.fail(f"{kind} #{i} must be an object like {{\"name\": ..., ...}}, got "
                                f"{json.dumps(it)[:60]}", f"write each {kind} as a JSON object")
            nm = it.get("name", f"w{i}" if kind == "world" else f"e{i}")
            if not isinstance(nm, str) or not nm:
                raise self.fail(f"{kind} #{i}: name must be a non-empty string", "give it a name like \"w0\"")
            out.append(nm)
        dup = sorted({n for n in out if out.count(n) > 1})
        if dup:
            raise self.fail(f"duplicate {kind} name(s) {dup}", f"give every {kind} its own name")
        return out

    def ref(self, x: Any, index: dict[str, int], kind: str, where: str) -> int:
        if isinstance(x, bool):
            pass
        elif isinstance(x, int):
            if 0 <= x < len(index):
                return x
            raise self.fail(f"{where}: {kind} index {x} out of range 0..{len(index) - 1}",
                            f"refer to an existing {kind}")
        elif isinstance(x, str):
            if x in index:
                return index[x]
            raise self.fail(f"{where}: unknown {kind} {x!r} (known: {', '.join(list(index)[:10])})",
                            f"use the name of a {kind} listed in the file")
        raise self.fail(f"{where}: {kind} reference must be a name or an index, got {json.dumps(x)[:40]}",
                        f"write the {kind}'s name as a string")

    def relation(self, spec: Any, index: dict[str, int], kind: str, where: str) -> Relation:
        n = len(index)
        if isinstance(spec, list):
            spec = {"blocks": spec}
        if not isinstance(spec, Mapping) or len(set(spec) & {"blocks", "pairs"}) != 1:
            raise self.fail(f"{where} must be {{\"blocks\": [[...], ...]}} or {{\"pairs\": [[x, y], ...]}}",
                            "give exactly one of the two forms")
        if "blocks" in spec:
            blocks = self.get(spec, "blocks", list, where)
            out: list[list[int]] = []
            seen: dict[int, int] = {}
            for bi, blk in enumerate(blocks):
                if not isinstance(blk, list):
                    raise self.fail(f"{where}: block #{bi} must be a list of {kind}s", "write [\"w0\", \"w1\"]")
                cur = [self.ref(x, index, kind, f"{where} block #{bi}") for x in blk]
                for w in cur:
                    if w in seen:
                        raise self.fail(f"{where}: {kind} {list(index)[w]!r} is in blocks #{seen[w]} and #{bi}",
                                        "blocks of an equivalence must be disjoint")
                    seen[w] = bi
                out.append(cur)
            return Relation.from_blocks(n, out)
        pairs = self.get(spec, "pairs", list, where)
        out_p = []
        for pi, pr in enumerate(pairs):
            if not isinstance(pr, list) or len(pr) != 2:
                raise self.fail(f"{where}: pair #{pi} must be a two-element list [from, to]",
                                "write [\"w0\", \"w1\"]")
            out_p.append((self.ref(pr[0], index, kind, f"{where} pair #{pi}"),
                          self.ref(pr[1], index, kind, f"{where} pair #{pi}")))
        return Relation.from_pairs(n, out_p)

    def relations(self, data: Mapping, index: dict[str, int], kind: str) -> tuple[list[str], dict[str, Relation]]:
        """The agents and one relation per agent (the "agents" and "relations" entries)."""
        what = "the model" if kind == "world" else "the event model"
        rel_specs = self.get(data, "relations", dict, what)
        agents = self.symbols(data, "agents", what, default=list(rel_specs))
        missing = [a for a in agents if a not in rel_specs]
        if missing:
            raise self.fail(f"no relation for agent(s) {missing}", "add an entry for each agent under \"relations\"")
        extra = [a for a in rel_specs if a not in agents]
        if extra:
            raise self.fail(f"relation(s) for agent(s) {extra} not in \"agents\"", "add them to \"agents\"")
        return agents, {a: self.relation(rel_specs[a], index, kind, f"relation of {a!r}") for a in agents}

    def formula(self, text: Any, where: str) -> Formula:
        if isinstance(text, bool):
            return TOP if text else parse("F")
        if not isinstance(text, str):
            raise self.fail(f"{where} must be a formula as text, got {json.dumps(text)[:40]}",
                            "write it like \"p & ~q\"")
        return parse(text, source=f"{self.source} ({where})")

    def header(self, data: Any, kind: str | None) -> str:
        if not isinstance(data, Mapping):
            raise self.fail("the top level must be a JSON object", "see the schema in delkit.io.formats")
        got = data.get("delkit")
        if got not in _KINDS:
            raise self.fail(f"\"delkit\" must be one of {list(_KINDS)}, got {json.dumps(got)}",
                            "add \"delkit\": \"kripke-model\" (or \"event-model\") at the top level")
        if kind is not None and got != kind:
            raise self.fail(f"expected a {kind}, the file holds a {got}", f"pass a {kind} file")
        ver = data.get("version", SCHEMA_VERSION)
        if ver != SCHEMA_VERSION:
            raise self.fail(f"schema version {ver} is not supported", f"write \"version\": {SCHEMA_VERSION}")
        return got


def _json_type(tn: str) -> str:
    return {"list": "list", "dict": "object", "str": "string", "int": "integer", "Mapping": "object"}.get(tn, tn)


def model_from_dict(data: Any, *, source: str = "<data>") -> KripkeModel:
    """Build a :class:`KripkeModel` from the JSON schema (see the module docstring)."""
    r = _Reader(source)
    r.header(data, "kripke-model")
    r.keys(data, _MODEL_KEYS, "the model")
    worlds = r.get(data, "worlds", list, "the model")
    if not worlds:
        raise r.fail("the model has no worlds", "list at least one world")
    names = r.names(worlds, "world")
    index = {n: i for i, n in enumerate(names)}
    truths = []
    for i, w in enumerate(worlds):
        r.keys(w, ("name", "true"), f"world {names[i]!r}")
        t = r.get(w, "true", list, f"world {names[i]!r}", default=[])
        if not all(isinstance(p, str) for p in t):
            raise r.fail(f"world {names[i]!r}: \"true\" must list proposition names", "write [\"p\", \"q\"]")
        truths.append(t)
    props = r.symbols(data, "props", "the model", default=sorted({p for t in truths for p in t}))
    unknown = sorted({p for t in truths for p in t} - set(props))
    if unknown:
        raise r.fail(f"world(s) make proposition(s) {unknown} true that are not in \"props\"",
                     "add them to \"props\"")
    agents, rels = r.relations(data, index, "world")
    des = [r.ref(x, index, "world", "designated") for x in r.get(data, "designated", list, "the model")]
    pidx = {p: i for i, p in enumerate(props)}
    val = np.zeros((len(names), len(props)), dtype=bool)
    for w, t in enumerate(truths):
        val[w, [pidx[p] for p in t]] = True
    default_names = all(n == f"w{i}" for i, n in enumerate(names))
    try:
        return KripkeModel(tuple(props), tuple(agents), val, rels, tuple(des),
                           None if default_names else tuple(names))
    except DelkitError as exc:
        raise ModelFileError(f"{source}: {exc}") from None


def event_model_from_dict(data: Any, *, source: str = "<data>") -> EventModel:
    """Build an :class:`EventModel` from the JSON schema (see the module docstring)."""
    r = _Reader(source)
    r.header(data, "event-model")
    r.keys(data, _EVENT_KEYS, "the event model")
    events = r.get(data, "events", list, "the event model")
    if not events:
        raise r.fail("the event model has no events", "list at least one event")
    names = r.names(events, "event")
    index = {n: i for i, n in enumerate(names)}
    pres, posts = [], []
    for i, ev in enumerate(events):
        r.keys(ev, ("name", "pre", "post"), f"event {names[i]!r}")
        pres.append(r.formula(ev.get("pre", "T"), f"precondition of event {names[i]!r}"))
        post = r.get(ev, "post", dict, f"event {names[i]!r}", default={})
        if any(not p.strip() for p in post):  # the empty name: no proposition a formula could ever mention
            raise r.fail(f"event {names[i]!r}: its postcondition names the empty proposition \"\"",
                         "name the proposition the event changes, e.g. \"post\": {\"p\": \"F\"}")
        r.plain_props([p for p in post], f"event {names[i]!r}'s postcondition")
        posts.append({p: r.formula(v, f"postcondition of {p!r} in event {names[i]!r}") for p, v in post.items()})
    agents, rels = r.relations(data, index, "event")
    des = [r.ref(x, index, "event", "designated") for x in r.get(data, "designated", list, "the event model")]
    name = r.get(data, "name", str, "the event model", default="E")
    try:
        return EventModel(tuple(names), tuple(agents), tuple(pres), tuple(posts), rels, tuple(des), name)
    except DelkitError as exc:
        raise ModelFileError(f"{source}: {exc}") from None


def from_dict(data: Any, *, source: str = "<data>") -> KripkeModel | EventModel:
    """Either kind, chosen by the ``"delkit"`` key."""
    kind = _Reader(source).header(data, None)
    return model_from_dict(data, source=source) if kind == "kripke-model" else event_model_from_dict(
        data, source=source)


# ============================================================================ JSON text and files


def dumps(obj: KripkeModel | EventModel, *, indent: int | None = 2) -> str:
    """JSON text: one line per top-level entry, world, event and relation (``indent=None``: one line)."""
    d = to_dict(obj)
    if indent is None:
        return json.dumps(d)
    pad = " " * indent
    lines = []
    for k, v in d.items():
        if isinstance(v, list) and v and isinstance(v[0], dict):
            inner = (",\n" + pad * 2).join(json.dumps(x) for x in v)
            text = f"[\n{pad * 2}{inner}\n{pad}]"
        elif isinstance(v, dict) and v:
            inner = (",\n" + pad * 2).join(f"{json.dumps(a)}: {json.dumps(x)}" for a, x in v.items())
            text = f"{{\n{pad * 2}{inner}\n{pad}}}"
        else:
            text = json.dumps(v)
        lines.append(f"{pad}{json.dumps(k)}: {text}")
    return "{\n" + ",\n".join(lines) + "\n}"


def loads(text: str, *, source: str = "<string>") -> KripkeModel | EventModel:
    """Parse JSON text; syntax errors become :class:`ParseError` with line and column."""
    try:
        data = json.loads(text)
    except json.JSONDecodeError as exc:
        raise ParseError(f"invalid JSON: {exc.msg}", source=source, line=exc.lineno, column=exc.colno) from None
    return from_dict(data, source=source)


def _read(path: str | Path) -> str:
    from delkit.paths import read_input

    p = Path(path)
    try:
        return read_input(p, "model file")
    except ParseError as exc:  # not a regular file (a directory, a FIFO, a device) or over the size cap
        raise ModelFileError(str(exc)) from None
    except FileNotFoundError:
        raise ModelFileError(f"{p}: no such file; check the path") from None
    except IsADirectoryError:
        raise ModelFileError(f"{p}: is a directory, expected a model file") from None
    except UnicodeDecodeError as exc:
        raise ModelFileError(f"{p}: not UTF-8 text ({exc.reason} at byte {exc.start}); is it a model file?") from None
    except OSError as exc:
        raise ModelFileError(f"{p}: cannot read ({exc.strerror})") from None


def save(obj: KripkeModel | EventModel, path: str | Path) -> None:
    Path(path).write_text(dumps(obj) + "\n", encoding="utf-8")


#: what :func:`load` reads, for messages about a file in another format
MODEL_FORMATS = "delkit's JSON model format (.json) or DOT (.dot/.gv)"


def sniff(text: str) -> str | None:
    """Which input language ``text`` is in, told by its first words: ``"json"``, ``"dot"``, ``"smcdel"``
    (SMCDEL's ``VARS … LAW …``), ``"pddl"`` (an E-PDDL/EPDDL domain or problem), ``"mastar"`` (an mA* task)
    or None (none of these)."""
    import re

    body = "\n".join(line for line in text.splitlines() if not line.lstrip().startswith(("--", "%", ";", "//")))
    head = body.lstrip()[:1]
    if head in ("{", "["):
        return "json"
    if re.match(r"\s*(strict\s+)?(di)?graph\b", body, re.IGNORECASE):
        return "dot"
    if re.search(r"^\s*VARS\b", body, re.MULTILINE) and re.search(r"\bLAW\b", body):
        return "smcdel"
    if re.match(r"\s*\(\s*define\b", body, re.IGNORECASE):
        return "pddl"
    if re.search(r"^\s*(fluent|action|agent)s?\b", body, re.MULTILINE):
        return "mastar"
    return None


_KIND = {
    "smcdel": ("SMCDEL's input language", "`delkit smcdel FILE` answers its queries; `delkit model draw` and "
                                          "`model diff` read it too"),
    "pddl": ("an E-PDDL/EPDDL planning domain or problem", "`delkit plan`, `check` and `convert` read it"),
    "mastar": ("an mA* planning task", "`delkit plan`, `check` and `convert` read it"),
}


def not_this_format(path: str | Path, text: str, formats: str) -> ModelFileError | None:
    """The one-line error for a file that is not in one of ``formats`` but in a language delkit knows
    elsewhere (which command reads it), or None when the file may be meant as JSON."""
    kind = sniff(text)
    if kind not in _KIND:
        return None
    what, hint = _KIND[kind]
    return ModelFileError(f"{path}: this is {what}, not a model file; this command reads {formats} ({hint})")


def load(path: str | Path, *, formats: str = MODEL_FORMATS) -> KripkeModel | EventModel:
    """Read a model file: JSON, or the DOT that :func:`to_dot` writes (by extension ``.dot``/``.gv``, or by
    its first word ``digraph``). A file in another language delkit reads (SMCDEL, E-PDDL/EPDDL, mA*) is
    refused with a :class:`ModelFileError` naming ``formats`` and the command that reads it."""
    p = Path(path)
    text = _read(p)
    if p.suffix.lower() in (".dot", ".gv"):
        return from_dot(text, source=str(p))
    kind = sniff(text)
    if kind == "dot":
        return from_dot(text, source=str(p))
    if kind != "json" and p.suffix.lower() != ".json":
        wrong = not_this_format(p, text, formats)
        if wrong is not None:
            raise wrong
        first = next((line.strip() for line in text.splitlines() if line.strip()), "")
        raise ModelFileError(f"{p}: not a file this command reads ({formats}): it starts with "
                             f"{first[:40]!r}, not '{{' (JSON) or 'digraph' (DOT)" if first else
                             f"{p}: the file is empty; this command reads {formats}")
    return loads(text, source=str(p))


def load_model(path: str | Path) -> KripkeModel:
    obj = load(path)
    if not isinstance(obj, KripkeModel):
        raise ModelFileError(f"{path}: holds an event model, expected a Kripke model")
    return obj


def load_event_model(path: str | Path) -> EventModel:
    obj = load(path)
    if not isinstance(obj, EventModel):
        raise ModelFileError(f"{path}: holds a Kripke model, expected an event model")
    return obj


# ============================================================================ DOT


def _q(s: str) -> str:
    return '"' + s.replace("\\", "\\\\").replace('"', '\\"') + '"'


def _qlabel(s: str) -> str:
    """A quoted label; newlines become the DOT escape ``\\n``."""
    return '"' + "\\n".join(part.replace("\\", "\\\\").replace('"', '\\"') for part in s.split("\n")) + '"'


def to_dot(obj: KripkeModel | EventModel) -> str:
    """Graphviz DOT text of a model; :func:`from_dot` reads it back."""
    d = to_dict(obj)
    kind = d["delkit"]
    items = d["worlds"] if kind == "kripke-model" else d["events"]
    des = set(d["designated"])
    parts = [a for a, spec in d["relations"].items() if "blocks" in spec]
    head = {"delkit_kind": kind, "delkit_agents": json.dumps(d["agents"]), "delkit_partitions": json.dumps(parts)}
    if kind == "kripke-model":
        head["delkit_props"] = json.dumps(d["props"])
    else:
        head["delkit_name"] = d["name"]
    lines = [f"digraph {_q(d.get('name', 'M'))} {{",
             "  graph [" + ", ".join(f"{k}={_q(v)}" for k, v in head.items()) + "];",
             "  node [shape=ellipse];"]
    for it in items:
        nm = it["name"]
        attrs: dict[str, str] = {}
        if kind == "kripke-model":
            attrs["label"] = nm + "\n" + (", ".join(it["true"]) or "∅")
            attrs["delkit_true"] = json.dumps(it["true"])
        else:
            post = it.get("post", {})
            effects = "; ".join(f"{p} := {v}" for p, v in post.items())
            attrs["label"] = nm + "\npre: " + it["pre"] + ("\npost: " + effects if post else "")
            attrs["delkit_pre"] = it["pre"]
            attrs["delkit_post"] = json.dumps(post)
        if nm in des:
            attrs["peripheries"] = "2"
            attrs["delkit_designated"] = "true"
        lines.append(f"  {_q(nm)} [" + ", ".join(
            f"{k}={_qlabel(v) if k == 'label' else _q(v)}" for k, v in attrs.items()) + "];")
    for a, spec in d["relations"].items():
        if "blocks" in spec:
            for blk in spec["blocks"]:
                for i, x in enumerate(blk):
                    for y in blk[i + 1:]:
                        lines.append(f"  {_q(x)} -> {_q(y)} [label={_q(a)}, delkit_agent={_q(a)}, dir=none];")
        else:
            for x, y in spec["pairs"]:
                lines.append(f"  {_q(x)} -> {_q(y)} [label={_q(a)}, delkit_agent={_q(a)}];")
    lines.append("}")
    return "\n".join(lines) + "\n"


_DOT_GRAMMAR = r"""
start: "strict"i? GRAPHKIND id? "{" stmt* "}"
GRAPHKIND: "digraph"i | "graph"i
?stmt: (attr_stmt | edge_stmt | node_stmt | assign) ";"?
attr_stmt: ATTRKIND attr_list
ATTRKIND.2: /(graph|node|edge)(?=\s*\[)/i
edge_stmt: id (EDGEOP id)+ attr_list?
node_stmt: id attr_list?
assign: id "=" id
attr_list: ("[" (attr [","|";"])* "]")+
attr: id "=" id
EDGEOP: "->" | "--"
id: STRING | ID | NUMERAL
STRING: /"(\\.|[^"\\])*"/s
ID: /[A-Za-z_\x80-\uffff][A-Za-z0-9_\x80-\uffff]*/
NUMERAL: /-?(\.[0-9]+|[0-9]+(\.[0-9]*)?)/
%ignore /[ \t\r\n]+/
%ignore /\/\/[^\n]*/
%ignore /#[^\n]*/
%ignore /\/\*(.|\n)*?\*\//
"""


@lru_cache(maxsize=1)
def _dot_parser():
    from lark import Lark

    return Lark(_DOT_GRAMMAR, parser="lalr", propagate_positions=True)


def _unquote(tok: Any) -> str:
    s = str(tok.children[0]) if hasattr(tok, "children") else str(tok)
    if s.startswith('"'):
        out, i, body = [], 0, s[1:-1]
        while i < len(body):
            if body[i] == "\\" and i + 1 < len(body) and body[i + 1] in '"\\':
                out.append(body[i + 1])
                i += 2
            else:
                out.append(body[i])
                i += 1
        return "".join(out)
    return s


def from_dot(text: str, *, source: str = "<dot>") -> KripkeModel | EventModel:
    """Read DOT written by :func:`to_dot` back into the model (raises :class:`ParseError` on bad syntax and
    :class:`ModelFileError` on DOT that lacks the ``delkit_*`` attributes)."""
    from lark.exceptions import UnexpectedCharacters, UnexpectedInput, UnexpectedToken

    try:
        tree = _dot_parser().parse(text)
    except UnexpectedToken as exc:
        raise ParseError(f"invalid DOT: unexpected {str(exc.token)!r}", source=source, line=exc.line,
                         column=exc.column) from None
    except UnexpectedCharacters as exc:
        raise ParseError(f"invalid DOT: unexpected character {text[exc.pos_in_stream]!r}", source=source,
                         line=exc.line, column=exc.column) from None
    except UnexpectedInput as exc:
        raise ParseError(f"invalid DOT: {exc}", source=source) from None
    r = _Reader(source)
    graph_attrs: dict[str, str] = {}
    nodes: dict[str, dict[str, str]] = {}
    edges: list[tuple[str, str, dict[str, str], int]] = []

    def attrs_of(node: Any) -> dict[str, str]:
        out: dict[str, str] = {}
        for al in node.find_data("attr"):
            out[_unquote(al.children[0])] = _unquote(al.children[1])
        return out

    for st in tree.children:
        if not hasattr(st, "data"):
            continue
        if st.data == "attr_stmt" and str(st.children[0]).lower() == "graph":
            graph_attrs.update(attrs_of(st.children[1]))
        elif st.data == "node_stmt":
            nm = _unquote(st.children[0])
            nodes.setdefault(nm, {}).update(attrs_of(st.children[1]) if len(st.children) > 1 else {})
        elif st.data == "edge_stmt":
            ids = [c for c in st.children if hasattr(c, "data") and c.data == "id"]
            al = [c for c in st.children if hasattr(c, "data") and c.data == "attr_list"]
            at = attrs_of(al[0]) if al else {}
            for x, y in zip(ids, ids[1:], strict=False):
                edges.append((_unquote(x), _unquote(y), at, st.meta.line))
    kind = graph_attrs.get("delkit_kind")
    if kind not in _KINDS:
        raise r.fail("the graph has no delkit_kind attribute", "only DOT written by delkit.io.formats.to_dot can be "
                                                               "read "
                     "back; convert other drawings to the JSON schema")

    def js(val: str | None, what: str, default: Any = None, typ: type = list) -> Any:
        if val is None:
            if default is not None:
                return default
            raise r.fail(f"missing {what} attribute", "only DOT written by delkit.io.formats.to_dot can be read back")
        try:
            out = json.loads(val)
        except json.JSONDecodeError as exc:
            raise r.fail(f"attribute {what} is not valid JSON ({exc.msg})", "re-export the model") from None
        if not isinstance(out, typ) or typ is list and not all(isinstance(x, str) for x in out):
            shape = "a JSON list of names" if typ is list else "a JSON object"
            raise r.fail(f"attribute {what} must be {shape}, got {val[:40]!r}", "re-export the model")
        return out

    agents = js(graph_attrs.get("delkit_agents"), "delkit_agents")
    partitions = set(js(graph_attrs.get("delkit_partitions"), "delkit_partitions", []))
    names = list(nodes)
    index = {n: i for i, n in enumerate(names)}
    rel_pairs: dict[str, list[list[str]]] = {a: [] for a in agents}
    for x, y, at, line in edges:
        a = at.get("delkit_agent")
        if a not in rel_pairs:
            raise r.fail(f"edge {x} -> {y} (line {line}) has agent {a!r}, not one of {agents}",
                         "give each edge a delkit_agent attribute naming an agent")
        for z in (x, y):
            if z not in index:
                raise r.fail(f"edge {x} -> {y} (line {line}) names undeclared node {z!r}", "declare every node")
        rel_pairs[a].append([x, y])
    relations: dict[str, Any] = {}
    for a in agents:
        if a in partitions:
            n = len(names)
            import scipy.sparse as sp

            rows = [index[x] for x, _ in rel_pairs[a]]
            cols = [index[y] for _, y in rel_pairs[a]]
            g = sp.csr_matrix((np.ones(len(rows)), (rows, cols)), shape=(n, n))
            _, lab = connected_components(g, directed=False)
            blocks: dict[int, list[str]] = {}
            for i, c in enumerate(lab):
                blocks.setdefault(int(c), []).append(names[i])
            relations[a] = {"blocks": list(blocks.values())}
        else:
            relations[a] = {"pairs": rel_pairs[a]}
    designated = [n for n in names if nodes[n].get("delkit_designated") == "true"]
    if kind == "kripke-model":
        data = {"delkit": kind, "props": js(graph_attrs.get("delkit_props"), "delkit_props"), "agents": agents,
                "worlds": [{"name": n, "true": js(nodes[n].get("delkit_true"), f"delkit_true of {n!r}", [])}
                           for n in names],
                "relations": relations, "designated": designated}
        return model_from_dict(data, source=source)
    data = {"delkit": kind, "name": graph_attrs.get("delkit_name", "E"), "agents": agents,
            "events": [{"name": n, "pre": nodes[n].get("delkit_pre", "T"),
                        "post": js(nodes[n].get("delkit_post"), f"delkit_post of {n!r}", {}, dict)} for n in names],
            "relations": relations, "designated": designated}
    return event_model_from_dict(data, source=source)


def save_dot(obj: KripkeModel | EventModel, path: str | Path) -> None:
    Path(path).write_text(to_dot(obj), encoding="utf-8")


def load_dot(path: str | Path) -> KripkeModel | EventModel:
    return from_dot(_read(path), source=str(path))
