"""Hypothesis strategies that produce fuzz :class:`fuzzkit.Case` objects for every ``delkit`` command.

Sources: the shared benchmark files (``../shared/benchmarks``, read in place) and ``specs/``; models drawn
by :mod:`delkit.testing`; the arms demo plan. Mutations are grammar-aware where a grammar exists
(s-expression trees for E-PDDL, tokens for mA*, JSON trees for models/plans, attributes for DOT, header
fields for MovingAI maps), plus byte-level truncation/corruption, boundary numbers for every numeric
option and deep nesting.
"""

from __future__ import annotations

import json
import re
from functools import lru_cache
from pathlib import Path

from fuzzkit import Case
from hypothesis import strategies as st

REPO = Path(__file__).resolve().parents[2]
SPECS = REPO / "specs"

# ----------------------------------------------------------------------------- vocabularies

INTS = ["-9223372036854775809", "-9223372036854775808", "-2147483649", "-1", "0", "1", "2", "3", "7",
        "2147483648", "9223372036854775808", "100000000000000000000000000000", "1e3", "0x10", "", "abc", "1.5"]
FLOATS = INTS + ["nan", "inf", "-inf", "1e308", "-1e308", "1e-320", "-0.0", "0.001"]
WORDS = ["", " ", "T", "F", "true", "false", "a", "b", "zz", "~", "K_a", "C{a,b}", "robot9", "é", "x" * 300,
         ",", ",,", "1,2", "-1", "all", "none"]
SEXP_WORDS = ["T", "t", "true", "false", "top", "-", "?x", "?ag", "agent", "object", "and", "or", "not",
              "imply", "when", "forall", "exists", "diff", ":precond", ":precondition", ":effect",
              ":observers", ":p_observers", ":act_type", ":parameters", ":init", ":goal", ":agents",
              ":objects", ":predicates", ":requirements", ":action", ":domain", "sensing", "ontic",
              "announcement", "(sensing)", "a", "b", "c", "zz", "[", "]", "0", "-1", "99999", "é", '"q"']


def _bench() -> Path | None:
    p = REPO.parent / "shared" / "benchmarks"
    return p if p.is_dir() else None


@lru_cache(maxsize=1)
def epddl_pairs() -> tuple[tuple[Path, Path | None, Path | None], ...]:
    """(domain, problem, plan) triples: ``specs/`` and the 2021-dialect shared benchmarks."""
    out: list[tuple[Path, Path | None, Path | None]] = []
    for d in sorted(SPECS.iterdir()):
        if (d / "domain.epddl").exists():
            for prob in sorted(d.glob("*.epddl")):
                if prob.name == "domain.epddl":
                    continue
                plan = prob.with_suffix(".plan")
                out.append((d / "domain.epddl", prob, plan if plan.exists() else None))
    b = _bench()
    if b is not None:
        cb = b / "epddl" / "coin_in_the_box"
        if (cb / "coininthebox.epddl").exists():
            for prob in ("pb1.epddl",):
                if (cb / prob).exists():
                    out.append((cb / "coininthebox.epddl", cb / prob, None))
    return tuple(out)


@lru_cache(maxsize=1)
def mastar_files() -> tuple[Path, ...]:
    b = _bench()
    if b is None:
        return ()
    files = sorted((b / "mastar").rglob("*.txt"))
    # the small ones: their plans are found in well under a second
    return tuple(f for f in files if f.stat().st_size < 6000)


@lru_cache(maxsize=1)
def arms_plan() -> dict:
    return json.loads((REPO / "arms" / "demo_plan.json").read_text())


def _plan_line(path: Path | None) -> list[str]:
    if path is None:
        return []
    from planners.validate import read_plan

    return read_plan(path)


# ----------------------------------------------------------------------------- s-expressions (E-PDDL)

def _sexp_parse(text: str):
    from planners.lang.epddl import Atom, read_sexps

    def conv(x):
        return x.text if isinstance(x, Atom) else [conv(i) for i in x.items]

    return [conv(x) for x in read_sexps(text, "<fuzz>")]


def _sexp_show(x) -> str:
    if isinstance(x, str):
        return x
    if x and x[0] == "@@NEST":  # a later mutation may have edited the marker itself: then drop the nesting
        if len(x) == 3 and isinstance(x[1], str) and x[1].isdigit():
            return "(not " * int(x[1]) + _sexp_show(x[2]) + ")" * int(x[1])
        x = x[1:]
    return "(" + " ".join(_sexp_show(i) for i in x) + ")"


def _paths(tree, prefix=()):
    yield prefix
    if isinstance(tree, list):
        for i, c in enumerate(tree):
            yield from _paths(c, (*prefix, i))


def _get(tree, path):
    for i in path:
        tree = tree[i]
    return tree


@st.composite
def sexp_mutation(draw, trees: list) -> str:
    """One to three tree edits (delete, duplicate, replace, wrap, swap, deep nest, contradiction) of a file."""
    import copy

    root = copy.deepcopy(trees)
    for _ in range(draw(st.integers(0, 3))):  # 0: the file as it is (a valid input; the oracle must agree)
        paths = [p for p in _paths(root) if len(p) > 2] or [p for p in _paths(root) if p]
        path = draw(st.sampled_from(paths))
        parent, i = _get(root, path[:-1]), path[-1]
        node = parent[i]
        op = draw(st.sampled_from(["delete", "dup", "word", "wrap_not", "empty", "swap", "nest", "keyword",
                                   "list_of_word", "graft"]))
        if op == "delete":
            del parent[i]
        elif op == "dup":
            parent.insert(i, copy.deepcopy(node))
        elif op == "word":
            parent[i] = draw(st.sampled_from(SEXP_WORDS))
        elif op == "wrap_not":
            parent[i] = ["not", node]
        elif op == "empty":
            parent[i] = []
        elif op == "swap" and len(parent) > 1:
            j = draw(st.integers(0, len(parent) - 1))
            parent[i], parent[j] = parent[j], parent[i]
        elif op == "nest":  # expanded by _sexp_show (a deep Python list would overflow the walks here)
            parent[i] = ["@@NEST", str(draw(st.sampled_from([3, 50, 400, 5000]))), node]
        elif op == "keyword" and isinstance(node, str) and node.startswith(":"):
            parent[i] = draw(st.sampled_from([":precond", ":effects", ":observer", ":act-type", ":init",
                                              ":p_observers", ":goal", ":parameters", node.upper()]))
        elif op == "list_of_word" and isinstance(node, str):
            parent[i] = [node]
        elif op == "graft":
            other = _get(root, draw(st.sampled_from(paths)))
            parent.insert(i, copy.deepcopy(other))
    return "\n".join(_sexp_show(x) for x in root)


@st.composite
def text_mutation(draw, text: str) -> bytes:
    """Byte-level: truncation, a random byte string spliced in, or invalid UTF-8."""
    data = text.encode()
    op = draw(st.sampled_from(["truncate", "splice", "binary", "nul", "bom"]))
    if op == "truncate":
        return data[:draw(st.integers(0, max(0, len(data) - 1)))]
    if op == "splice":
        i = draw(st.integers(0, len(data)))
        return data[:i] + draw(st.binary(min_size=1, max_size=8)) + data[i:]
    if op == "binary":
        return draw(st.binary(min_size=0, max_size=200))
    if op == "nul":
        return data.replace(b" ", b"\x00", 1)
    return b"\xef\xbb\xbf" + data


# ----------------------------------------------------------------------------- planning cases

PLAN_OPTS = ["--timeout", "3", "--max-nodes", "3000", "--json"]


@st.composite
def plan_cases(draw) -> Case:
    """``delkit plan`` on mutated E-PDDL / mA* files (the oracle: a found plan must pass ``delkit check``)."""
    kind = draw(st.sampled_from(["epddl", "epddl", "epddl", "mastar", "options"]))
    if kind == "mastar" and mastar_files():
        f = draw(st.sampled_from(mastar_files()))
        text = f.read_text()
        extra = draw(st.sampled_from([[], ["--search", "astar"], ["--engine", "del"]]))
        return Case("plan", ("plan", "{d}/spec.txt", *PLAN_OPTS, *extra),
                    (("spec.txt", draw(token_mutation(text))),), oracle="plan", note=f"mutated {f.name}")
    dom, prob, _ = draw(st.sampled_from(epddl_pairs()))
    if kind == "options":
        opt = draw(st.sampled_from(["--timeout", "--max-nodes", "--max-memory", "--search", "--engine"]))
        val = draw(st.sampled_from(FLOATS if opt != "--search" and opt != "--engine" else WORDS + ["bfs", "astar"]))
        argv = ["plan", str(dom), str(prob), "--json", opt, val]
        if opt != "--timeout":
            argv += ["--timeout", "3"]
        if opt != "--max-nodes":
            argv += ["--max-nodes", "3000"]
        return Case("plan", tuple(argv), oracle="plan", note="option boundary")
    which = draw(st.sampled_from(["domain", "problem", "both"]))
    files = []
    dtext, ptext = dom.read_text(), prob.read_text()
    if which in ("domain", "both"):
        dtext = _mutate_epddl(draw, dtext)
    if which in ("problem", "both"):
        ptext = _mutate_epddl(draw, ptext)
    files = [("domain.epddl", dtext if isinstance(dtext, bytes) else dtext.encode()),
             ("problem.epddl", ptext if isinstance(ptext, bytes) else ptext.encode())]
    extra = draw(st.sampled_from([[], [], ["--search", "gbfs"], ["--search", "astar"], ["--engine", "del"],
                                  ["--allow-inconsistent"]]))
    return Case("plan", ("plan", "{d}/domain.epddl", "{d}/problem.epddl", *PLAN_OPTS, *extra), tuple(files),
                oracle="plan", note=f"mutated {which} of {dom.parent.name}/{prob.name} {' '.join(extra)}")


def _mutate_epddl(draw, text: str):
    if draw(st.integers(0, 9)) == 0:
        return draw(text_mutation(text))
    return draw(sexp_mutation(_sexp_parse(text)))


_TOKEN = re.compile(r"[A-Za-z0-9_]+|[^\sA-Za-z0-9_]|\s+")
MASTAR_WORDS = ["fluent", "action", "agent", "executable", "if", "causes", "observes", "aware_of", "determines",
                "announces", "initially", "goal", "B", "C", "(", ")", "[", "]", ",", ";", "-", "T", "true",
                "zz", "99999999999999999999", "%%%"]


MASTAR_LINES = st.sampled_from(["initially C([a,b], x);", "goal zz;", "fluent T;", "agent a;", "action a;"]).map(
    lambda line: "\n" + line + "\n")


@st.composite
def token_mutation(draw, text: str, words: list[str] = MASTAR_WORDS, insert=MASTAR_LINES,
                   bytes_one_in: int = 10) -> bytes:
    """One to four token edits (delete, duplicate, replace by one of ``words``, insert a draw of ``insert``),
    or, one time in ``bytes_one_in``, a byte-level mutation."""
    toks = _TOKEN.findall(text)
    if draw(st.integers(0, bytes_one_in - 1)) == 0:
        return draw(text_mutation(text))
    for _ in range(draw(st.integers(1, 4))):
        i = draw(st.integers(0, len(toks) - 1))
        op = draw(st.sampled_from(["delete", "dup", "replace", "insert"]))
        if op == "delete":
            del toks[i]
        elif op == "dup":
            toks.insert(i, toks[i])
        elif op == "replace":
            toks[i] = draw(st.sampled_from(words))
        else:
            toks.insert(i, draw(insert))
    return "".join(toks).encode()


@st.composite
def check_cases(draw) -> Case:
    """``delkit check`` with random plans (long ones too), mutated specs and random properties."""
    dom, prob, plan = draw(st.sampled_from(epddl_pairs()))
    task = _task(dom, prob)
    names = [a.name for a in task.actions]
    kind = draw(st.sampled_from(["random-plan", "long-plan", "property", "mutated-plan", "mutated-spec"]))
    files: list[tuple[str, bytes]] = []
    argv = ["check", str(dom), str(prob), "{d}/p.plan", "--json"]
    base = _plan_line(plan)
    if kind == "random-plan":
        steps = draw(st.lists(st.sampled_from(names), max_size=6))
    elif kind == "long-plan":
        steps = draw(st.lists(st.sampled_from(names), min_size=10, max_size=20))
    elif kind == "mutated-plan":
        steps = list(base)
        if steps:
            i = draw(st.integers(0, len(steps) - 1))
            steps[i] = draw(st.sampled_from([*names, "zz", "(open a)", "%%%", "open", "", "x" * 400]))
    else:
        steps = base
    if kind == "property":
        argv += ["--property", draw(property_text(list(task.props)[:6], list(task.agents)))]
    if kind == "mutated-spec":
        argv[2] = "{d}/problem.epddl"
        m = _mutate_epddl(draw, prob.read_text())
        files.append(("problem.epddl", m if isinstance(m, bytes) else m.encode()))
    files.append(("p.plan", "\n".join(steps).encode()))
    return Case("check", tuple(argv), tuple(files), oracle="json", budget=30.0, note=kind)


@lru_cache(maxsize=32)
def _task(dom: Path, prob: Path):
    from planners.lang import load_task

    return load_task(dom, prob)


@st.composite
def property_text(draw, props: list[str], agents: list[str]) -> str:
    head = draw(st.sampled_from(["always", "eventually", "at end", "sometimes", "", "always always"]))
    return f"{head} {draw(formula_text(props, agents))}"


# ----------------------------------------------------------------------------- formulas

@st.composite
def formula_text(draw, props: list[str], agents: list[str], depth: int = 3, junk: bool = True) -> str:
    """Grammar-directed formula text; with ``junk`` a third of them are broken (escapes in quoted names, odd
    tokens, deep nesting, a character spliced in)."""
    props = props or ["p"]
    agents = agents or ["a"]
    if junk and draw(st.integers(0, 2)) == 0:
        kind = draw(st.integers(1, 4))
        if kind < 4:
            return _junk_formula(draw, props, kind)
        text = draw(formula_text(props, agents, depth, junk=False))
        i = draw(st.integers(0, len(text)))
        return text[:i] + draw(st.sampled_from(list("()[]{}~&|!,_\\\"'#") + ["->", "<-", "K_", "C{"])) + text[i:]
    choice = draw(st.integers(3, 12)) if depth > 0 else draw(st.integers(0, 3))
    if choice < 4:
        return draw(st.sampled_from([*props, "T"] if choice == 3 else props))
    return _compound(draw, props, agents, depth, choice)


def _junk_formula(draw, props: list[str], choice: int) -> str:
    if choice == 1:
        return draw(st.sampled_from(["T", "F", "true", "false", "zz", "K_zz p", "", "(", "~", "K{a"]))
    if choice == 2:
        return draw(st.sampled_from(["~" * 3000 + "p", "(" * 2000 + "p" + ")" * 2000, "K_a " * 1500 + "p",
                                     " & ".join(["p"] * 3000)])).replace("p", props[0])
    return "[" + draw(st.sampled_from(["E", "Ann", "zz"])) + "," + draw(st.sampled_from(
            ['"e\\q"', '"\\u12"', '"a\\"b"', '"\\', 'e0', '"e0"', '""', "1"])) + "] " + props[0]


def _compound(draw, props: list[str], agents: list[str], depth: int, choice: int) -> str:
    sub = formula_text(props, agents, depth - 1, junk=False)
    if choice in (4, 5):
        return f"~{draw(sub)}" if choice == 4 else f"({draw(sub)})"
    if choice in (6, 7, 8):
        op = draw(st.sampled_from(["&", "|", "->", "<->"]))
        return f"{draw(sub)} {op} {draw(sub)}"
    if choice in (9, 10):
        a = draw(st.sampled_from(agents))
        return draw(st.sampled_from([f"K_{a} ", f"Kw_{a} ", f"K{{{a}}} ", f"B_{a} "])) + draw(sub)
    if choice == 11:
        group = ",".join(draw(st.lists(st.sampled_from(agents), max_size=3)))
        return draw(st.sampled_from(["C", "E", "D"])) + "{" + group + "} " + draw(sub)
    return f"[!{draw(sub)}] {draw(sub)}"


# ----------------------------------------------------------------------------- models (JSON and DOT)

PROPS, AGENTS = ("p", "q"), ("a", "b")


def _model_dict(draw) -> dict:
    from delkit.io.formats import model_to_dict
    from delkit.testing import kripke_models

    frame = draw(st.sampled_from(["S5", "KD45", "K"]))
    m = draw(kripke_models(PROPS, AGENTS, 4, frame=frame, designated=draw(st.sampled_from(["one", "some"]))))
    return model_to_dict(m)


def _event_dict(draw) -> dict:
    from delkit.io.formats import event_model_to_dict
    from delkit.testing import event_models

    return event_model_to_dict(draw(event_models(PROPS, AGENTS, 3)))


JSON_ODD = [None, True, 0, -1, 1.5, 10 ** 30, float("inf"), float("nan"), "", "T", "true", "x" * 200, [], {},
            [[[[[]]]]], {"a": 1}, ["p", 3], -10 ** 20]


@st.composite
def json_mutation(draw, obj):
    """Edit a JSON tree at one to three random places: drop/add keys, change types, boundary numbers, nest."""
    import copy

    root = copy.deepcopy(obj)

    def places(x, path=()):
        yield path
        if isinstance(x, dict):
            for k, v in x.items():
                yield from places(v, (*path, k))
        elif isinstance(x, list):
            for i, v in enumerate(x):
                yield from places(v, (*path, i))

    for _ in range(draw(st.integers(1, 3))):
        ps = [p for p in places(root) if p]
        if not ps:
            break
        path = draw(st.sampled_from(ps))
        parent = root
        for k in path[:-1]:
            parent = parent[k]
        key = path[-1]
        op = draw(st.sampled_from(["odd", "odd", "delete", "unknown-key", "nest", "dup"]))
        if op == "odd":  # a copy: the shared constants must never be edited by a later mutation
            parent[key] = copy.deepcopy(draw(st.sampled_from(JSON_ODD)))
        elif op == "delete":
            del parent[key]
        elif op == "unknown-key" and isinstance(parent, dict):
            parent[draw(st.sampled_from(["extra", "Worlds", "T", "true", "robots9", "to"]))] = copy.deepcopy(
                draw(st.sampled_from(JSON_ODD)))
        elif op == "nest":
            parent[key] = f"@@NEST{draw(st.sampled_from([5, 200, 20000]))}@@"  # spliced in by _dump
        elif op == "dup" and isinstance(parent, list):
            parent.append(copy.deepcopy(parent[key]))
    return root


def _dump(obj) -> bytes:
    text = json.dumps(obj, allow_nan=True)
    return re.sub(r'"@@NEST(\d+)@@"', lambda m: "[" * int(m.group(1)) + "0" + "]" * int(m.group(1)), text).encode()


@st.composite
def model_cases(draw) -> Case:
    """``model show|dot|contract|check|diff|draw``, ``prove`` on valid, mutated and renamed model files."""
    sub = draw(st.sampled_from(["show", "dot", "contract", "check", "check", "prove", "macro", "dot-in", "diff",
                                "draw"]))
    event = draw(st.integers(0, 3)) == 0 and sub in ("show", "dot", "draw")
    obj = _event_dict(draw) if event else _model_dict(draw)
    mode = draw(st.sampled_from(["valid", "valid", "mutated", "mutated", "renamed", "bytes"]))
    if mode == "mutated":
        obj = draw(json_mutation(obj))
    elif mode == "renamed" and not event:  # propositions named like the constants / odd names
        new = draw(st.sampled_from(["T", "F", "true", "false", "K_a", "p q", "", "~", "a,b", "é"]))
        obj = json.loads(json.dumps(obj).replace('"p"', json.dumps(new)))
    data = draw(text_mutation(json.dumps(obj))) if mode == "bytes" else _dump(obj)
    if sub == "prove":
        f = draw(formula_text(list(PROPS), list(AGENTS)))
        opt = draw(st.sampled_from([[], ["--worlds", draw(st.sampled_from(INTS))],
                                    ["--logic", draw(st.sampled_from(["S5", "KD45", "K", "s5", "", "T"]))]]))
        return Case("prove", ("prove", f, "--json", "--worlds", "2", *opt), oracle="prove", budget=30.0)
    if sub == "check" and draw(st.booleans()):  # [E,e]φ with a (maybe mutated) event model
        ev = _event_dict(draw)
        names = [e["name"] for e in ev["events"]]
        if draw(st.integers(0, 2)) == 0:
            ev = draw(json_mutation(ev))
        inner = draw(formula_text(list(PROPS), list(AGENTS), 2))
        ev_name = draw(st.sampled_from([*names, "zz", '"e0"']))
        f = f"[E,{ev_name}] ({inner})"
        return Case("model check", ("model", "check", "{d}/m.json", f, "--json", "--event", "E={d}/e.json"),
                    (("m.json", data), ("e.json", _dump(ev))), oracle="model-check-event", note=mode)
    if sub == "check":
        f = draw(formula_text(list(PROPS), list(AGENTS)))
        return Case("model check", ("model", "check", "{d}/m.json", f, "--json"), (("m.json", data),),
                    oracle="model-check", note=mode)
    if sub == "macro":
        ev = _dump(draw(json_mutation(_event_dict(draw))) if mode != "valid" else _event_dict(draw))
        return Case("model macro", ("model", "macro", "{d}/e1.json", "{d}/e2.json", "--json", "--worlds",
                                    draw(st.sampled_from(["1", "2", "0", "9", "-1"])), "--logic",
                                    draw(st.sampled_from(["S5", "KD45", "K", "kd45", "XX", ""]))),
                    (("e1.json", data if event else _dump(_event_dict(draw))), ("e2.json", ev)), oracle="json",
                    budget=30.0)
    if sub == "diff":  # the other side: a valid model or a mutated one (rc 1 → the formula is checked)
        other = _dump(_model_dict(draw)) if draw(st.booleans()) else data
        return Case("model diff", ("model", "diff", "{d}/a.json", "{d}/b.json", "--json"),
                    (("a.json", data), ("b.json", other)), oracle="model-diff", note=mode)
    if sub == "draw":
        ext = draw(st.sampled_from(["svg", "png", "tex", "pdf", ""]))
        lay = draw(st.sampled_from([[], ["--layout", "spring", "--layout-seed", draw(st.sampled_from(INTS))],
                                    ["--layout", draw(st.sampled_from(WORDS))]]))
        return Case("model draw", ("model", "draw", "{d}/m.json", "-o", f"{{d}}/out.{ext}", *lay),
                    (("m.json", data),), note=mode, budget=30.0)
    if sub == "dot-in":  # a DOT file written by delkit, then its attributes mutated
        from delkit.io.formats import from_dict, to_dot

        try:
            dot = to_dot(from_dict(obj))
        except Exception:  # noqa: BLE001 - a mutated model may not be writable: use the valid one
            dot = to_dot(from_dict(_model_dict(draw)))
        dot = draw(dot_mutation(dot))
        cmd = draw(st.sampled_from(["show", "contract", "dot"]))
        return Case(f"model {cmd}", ("model", cmd, "{d}/m.dot"), (("m.dot", dot),),
                    oracle="model-roundtrip" if cmd in ("dot", "contract") else None, note="dot")
    return Case(f"model {sub}", ("model", sub, "{d}/m.json", *(["--json"] if sub == "show" else [])),
                (("m.json", data),), oracle="model-roundtrip" if sub in ("dot", "contract") else None, note=mode)


@st.composite
def dot_mutation(draw, dot: str) -> bytes:
    attrs = list(re.finditer(r'(delkit_\w+)="((?:[^"\\]|\\.)*)"', dot))
    if attrs and draw(st.integers(0, 4)):
        m = draw(st.sampled_from(attrs))
        val = json.dumps(draw(st.sampled_from(JSON_ODD + ["p", 5, {"p": "q"}]))).replace('"', '\\"')
        return (dot[:m.start(2)] + val + dot[m.end(2):]).encode()
    return draw(text_mutation(dot))


# ----------------------------------------------------------------------------- puzzles and options

@st.composite
def puzzle_cases(draw) -> Case:
    which = draw(st.sampled_from(["muddy", "sum-product", "drinking", "dining", "cheryl", "russian-cards"]))
    if which == "muddy":
        n, m = draw(st.sampled_from(INTS[3:10] + ["40", "64", "2000"])), draw(st.sampled_from(INTS[3:9]))
        sym = draw(st.sampled_from([[], ["--symbolic"]]))
        return Case("puzzle muddy", ("puzzle", "muddy", "-n", n, "-m", m, "--json", "--timeout", "10", *sym),
                    oracle="json")
    if which == "sum-product":
        return Case("puzzle sum-product", ("puzzle", "sum-product", "--limit",
                                           draw(st.sampled_from(INTS + ["5", "30", "200", "100000", "4294967296"])),
                                           "--json", "--timeout", "15"), oracle="json", budget=40.0)
    if which == "drinking":
        return Case("puzzle drinking", ("puzzle", "drinking", "--wants", draw(st.sampled_from(
            WORDS + ["0", "1", "10", "1" * 16, "1" * 17, "2"])), "--json"), oracle="json")
    if which == "dining":
        args = ("--n", draw(st.sampled_from(INTS[3:12])), "--payer", draw(st.sampled_from(INTS[3:9])),
                "--coins", draw(st.sampled_from(INTS[3:12])))
        return Case("puzzle dining", ("puzzle", "dining", *args, "--json"), oracle="json")
    return Case(f"puzzle {which}", ("puzzle", which, "--json", *draw(st.sampled_from([[], ["--bogus"]]))),
                oracle="json", budget=60.0)


@st.composite
def consistency_cases(draw) -> Case:
    opts = {"--robots": "2", "--epochs": "3", "--width": "6", "--height": "6"}
    opt = draw(st.sampled_from(["--robots", "--epochs", "--width", "--height", "--seed", "--primitives",
                                "--comm-restr", "--algorithm", "--init", "--policy", "--trigger", "--tie-break"]))
    num = opt in ("--robots", "--epochs", "--width", "--height", "--seed", "--primitives", "--comm-restr")
    val = draw(st.sampled_from(INTS if num else WORDS + ["enforce", "all", "entropy", "greedy", "useful"]))
    if opt in ("--epochs",) and val in ("2147483648", "9223372036854775808", "100000000000000000000000000000"):
        opts["--width"] = "3"
    opts[opt] = val
    sub = "table" if draw(st.integers(0, 5)) == 0 else "run"
    if sub == "table":
        for k in ("--robots", "--primitives", "--comm-restr", "--algorithm", "--init"):
            opts.pop(k, None)
        opts.setdefault("--epochs", "2")
    argv = ["consistency", sub, "--json"]
    for k, v in opts.items():
        argv += [k, v]
    # the work grows with epochs × grid: values that ask for years of work are refused up front or capped
    return Case(f"consistency {sub}", tuple(argv), oracle="json", budget=45.0, note=f"{opt} {val!r}")


@st.composite
def map_file(draw) -> bytes:
    w, h = draw(st.integers(1, 12)), draw(st.integers(1, 12))
    rows = ["".join(draw(st.sampled_from(".@.T.")) for _ in range(w)) for _ in range(h)]
    text = f"type octile\nheight {h}\nwidth {w}\nmap\n" + "\n".join(rows) + "\n"
    op = draw(st.sampled_from(["valid", "header", "rows", "bytes", "binary", "huge"]))
    if op == "header":
        text = text.replace(f"height {h}", f"height {draw(st.sampled_from(INTS))}", 1)
    elif op == "rows":
        text = "\n".join(text.splitlines()[:-draw(st.integers(1, 3))])
    elif op == "huge":
        text = f"type octile\nheight {draw(st.sampled_from(['100000', '99999999']))}\nwidth 100000\nmap\n..\n"
    elif op in ("bytes", "binary"):
        return draw(text_mutation(text))
    return text.encode()


@st.composite
def explore_cases(draw) -> Case:
    sub = draw(st.sampled_from(["run", "run", "run", "sweep", "gap"]))
    if sub == "gap":
        return Case("explore gap", ("explore", "gap", "--json", "--instances", draw(st.sampled_from(
            ["1", "2", "0", "-1", "abc"])), "--seed", draw(st.sampled_from(INTS))), oracle="json", budget=40.0)
    if sub == "sweep":
        argv = ["explore", "sweep", "--json", "--no-snapshots", "--out", "{d}/sw",
                "--workers", draw(st.sampled_from(["1", "1", "1", "0", "2147483648"])),
                "--maps", draw(st.sampled_from(["1", "0", "-1", "abc", "2147483648"])),
                "--methods", draw(st.sampled_from(["", ",", "flock", " , ", "zz", "flock,,ideal"])),
                "--robots", draw(st.sampled_from(["2", "", "0", "-3", "2,2", "a", "1"])),
                "--case", draw(st.sampled_from(["1", "3", "", "0", "-1", "1,2,x"]))]
        return Case("explore sweep", tuple(argv), oracle="json", budget=60.0)
    argv = ["explore", "run", "--json", "--t-max", "20", "--robots", "2", "--case", "1"]
    opt = draw(st.sampled_from(["--seed", "--robots", "--case", "--t-max", "--method", "--map", "--map",
                                "--status-model"]))
    files: list[tuple[str, bytes]] = []
    if opt == "--map":
        files.append(("g.map", draw(map_file())))
        argv += ["--map", "{d}/g.map"]
    elif opt == "--status-model":
        argv += ["--status-model", "--robots", draw(st.sampled_from(["2", "3", "4", "5"]))]
    elif opt == "--method":
        argv += ["--method", draw(st.sampled_from(WORDS + ["flock", "ideal"]))]
    else:
        pool = FLOATS if opt == "--t-max" else INTS
        val = draw(st.sampled_from(pool))
        if opt == "--t-max" and val not in ("nan", "-inf", "") and _num(val) > 200:
            val = "200"  # a valid but long mission is not a hang; keep the budget for the bad values
        argv += [opt, val]
    return Case("explore run", tuple(argv), tuple(files), oracle="json", budget=45.0, note=opt)


def _num(v: str) -> float:
    try:
        return float(int(v, 0)) if v.lower().startswith("0x") else float(v)
    except ValueError:
        return 0.0


# ----------------------------------------------------------------------------- arms

ARMS_ODD = ["Infinity", "-Infinity", "NaN", "1e999", "-1", "0", "99", "1.5", "true", "null", '"x"', "[]"]


@st.composite
def arms_cases(draw) -> Case:
    base = arms_plan()
    kind = draw(st.sampled_from(["json", "json", "field", "field", "layout", "bytes", "ik"]))
    if kind == "ik":
        opt = draw(st.sampled_from(["--targets", "--budget-ms", "--seed", "--clock"]))
        pool = {"--targets": ["0", "-1", "1", "abc", "2", "2147483648", "9223372036854775808"],
                "--budget-ms": FLOATS, "--seed": INTS,
                "--clock": WORDS + ["cpu"]}[opt]
        argv = ["arms", "bench-ik", "--json", "--targets", "2", opt, draw(st.sampled_from(pool))]
        return Case("arms bench-ik", tuple(argv), oracle="json", budget=40.0)
    if kind == "bytes":
        data = draw(text_mutation(json.dumps(base)))
    elif kind == "json":
        data = _dump(draw(json_mutation(base)))
    elif kind == "layout":
        key = draw(st.sampled_from(["block_size", "stack_pitch", "base_y", "stack_x", "table_z", "zz"]))
        text = json.dumps({**base, "world": {**base["world"], "layout": {key: 0}}})
        data = text.replace(f'"{key}": 0', f'"{key}": {draw(st.sampled_from(ARMS_ODD))}').encode()
    else:  # one field of one action: robots, stacks, levels, recipients that may not exist
        i = draw(st.integers(0, len(base["actions"]) - 1))
        field = draw(st.sampled_from(["level", "stack", "robot", "to", "block", "args", "action"]))
        val = draw(st.sampled_from(ARMS_ODD + ['"robot9"', '["robot9"]', '"purple"', '["purple", 1, 2, 3]',
                                               '"sense"', '"announce"', '["robot1"]']))
        acts = [dict(a) for a in base["actions"]]
        acts[i][field] = "@@VAL@@"
        data = json.dumps({**base, "actions": acts}).replace('"@@VAL@@"', val).encode()
    cmd = draw(st.sampled_from(["scene", "scene", "run"]))
    if cmd == "scene":
        return Case("arms scene", ("arms", "scene", "{d}/s.xml", "--plan", "{d}/plan.json"),
                    (("plan.json", data),), budget=40.0)
    return Case("arms run", ("arms", "run", "{d}/plan.json", "--json", "--no-video", "--tolerance",
                             draw(st.sampled_from(["0.01", "0.01", "0", "-1", "nan", "inf"]))),
                (("plan.json", data),), oracle="arms", budget=90.0)


@st.composite
def misc_cases(draw) -> Case:
    argv = draw(st.sampled_from([["version"], ["demo", "--only", "zz"], ["demo", "--only", ""], ["nope"],
                                 ["model"], ["plan"], ["check", "x"], ["--help"], ["puzzle", "muddy", "-n"],
                                 ["model", "check", "/nonexistent.json", "p"], ["check", "/", "/", "/"],
                                 ["plan", "/dev/null"], ["model", "show", "/dev/null"]]))
    return Case("misc", tuple(argv))


# ----------------------------------------------------------------------------- EPDDL 2026, convert, smcdel, e-PICO

@lru_cache(maxsize=1)
def epddl2026_rows() -> tuple[tuple[Path, Path, Path | None], ...]:
    """(domain, problem, library) of plank's suite (``expected.csv``), the quick ones only."""
    import csv

    b = _bench()
    if b is None or not (b / "epddl2026" / "expected.csv").exists():
        return ()
    root = b / "epddl2026"
    rows = []
    with open(root / "expected.csv", newline="") as fh:
        for r in csv.DictReader(fh):
            if any(k in r["problem"] for k in ("Selective", "Tiger", "problem_5", "problem_6")):
                continue  # long searches: a valid but slow input is not what this family looks for
            rows.append((root / r["domain"], root / r["problem"], root / r["libraries"] if r["libraries"] else None))
    return tuple(rows)


@st.composite
def epddl2026_cases(draw) -> Case:
    """``delkit plan`` / ``delkit check`` on mutated EPDDL (2026) domains, problems and action-type libraries."""
    rows = epddl2026_rows()
    if not rows:
        return Case("plan epddl2026", ("plan", "/nonexistent/domain.epddl", "/nonexistent/problem.epddl"))
    dom, prob, lib = draw(st.sampled_from(rows))
    which = draw(st.sampled_from(["domain", "problem", "library", "none"] if lib else ["domain", "problem"]))
    texts = {"domain": dom.read_text(), "problem": prob.read_text(), "library": lib.read_text() if lib else ""}
    if which != "none":
        texts[which] = _mutate_epddl(draw, texts[which])
    files = tuple((f"{k}.epddl", v if isinstance(v, bytes) else v.encode()) for k, v in texts.items()
                  if k != "library" or lib)
    libarg = ["--library", "{d}/library.epddl"] if lib else []
    if draw(st.integers(0, 3)) == 0:
        steps = draw(st.lists(st.sampled_from(["zz", "(zz)", "", "%", "x" * 300]), max_size=4))
        return Case("check epddl2026", ("check", "{d}/domain.epddl", "{d}/problem.epddl", "{d}/p.plan", *libarg,
                                        "--json"), (*files, ("p.plan", "\n".join(steps).encode())),
                    oracle="json", note=f"mutated {which} of {prob.parent.parent.name}")
    return Case("plan epddl2026", ("plan", "{d}/domain.epddl", "{d}/problem.epddl", *libarg, *PLAN_OPTS), files,
                oracle="plan", note=f"mutated {which} of {prob.parent.parent.name}")


@st.composite
def convert_cases(draw) -> Case:
    """``delkit convert`` of mutated mA* files to EPDDL (2026) and back to mA*."""
    files_ = mastar_files()
    if not files_:
        return Case("convert", ("convert", "/nonexistent.txt"))
    f = draw(st.sampled_from(files_))
    to = draw(st.sampled_from(["epddl", "epddl", "mastar", "zz", ""]))
    name = draw(st.sampled_from([[], ["--name", "x"], ["--name", ""], ["--name", "../../etc/x"], ["--name", "a/b"]]))
    return Case("convert", ("convert", "{d}/spec.txt", "--to", to, "--out", "{d}/out", *name, "--json"),
                (("spec.txt", draw(token_mutation(f.read_text()))),), oracle="json", note=f"mutated {f.name} → {to}")


SMCDEL_WORDS = ["VARS", "LAW", "OBS", "VALID?", "WHERE?", "TRUE?", "AND", "OR", "XOR", "ONEOF", "Top", "Bot",
                "knows", "whether", "that", "comknow", "[!", "[?!", "]", "(", ")", ":", ",", "~", "->", "<->",
                "Forall", "Exists", "99999999999", "-1", "alice", "zz", "%%"]


@st.composite
def smcdel_cases(draw) -> Case:
    """``delkit smcdel`` on mutated SMCDEL input files (tokens of its language, bytes)."""
    f = draw(st.sampled_from(sorted((SPECS / "smcdel").glob("*.smcdel.txt"))))
    data = draw(token_mutation(f.read_text(), SMCDEL_WORDS, st.sampled_from([3, 300, 5000]).map(lambda n: "(" * n),
                               bytes_one_in=8))
    return Case("smcdel", ("smcdel", "{d}/in.smcdel.txt", "--json"), (("in.smcdel.txt", data),), oracle="json",
                budget=30.0, note=f"mutated {f.name}")


@lru_cache(maxsize=1)
def epico_world() -> dict:
    from planners.epico import generate

    return generate("alpha", 2).layout.to_world()


@st.composite
def epico_cases(draw) -> Case:
    """``delkit epico generate|solve|macros`` with boundary options, odd owners/knowledge and mutated layouts."""
    sub = draw(st.sampled_from(["generate", "solve", "solve", "macros"]))
    if sub == "generate":
        opt = draw(st.sampled_from(["--goal", "--colors", "--seed"]))
        val = draw(st.sampled_from(INTS if opt != "--goal" else WORDS + ["alpha", "delta"]))
        return Case("epico generate", ("epico", "generate", opt, val, "--out", "{d}/g", "--json"), oracle="json")
    if sub == "macros":
        text = (SPECS / "epico" / "listing4.txt").read_text()
        data = draw(_mutate_sexp_or_bytes(text))
        return Case("epico macros", ("epico", "macros", "--colors", draw(st.sampled_from(["1", "2", "0", "7", "x"])),
                                     "--handwritten", "{d}/m.txt", "--json"), (("m.txt", data),), oracle="json",
                    budget=40.0)
    argv = ["epico", "solve", "--goal", "alpha", "--colors", "2", "--timeout", "10", "--json"]
    files: list[tuple[str, bytes]] = []
    kind = draw(st.sampled_from(["world", "world", "owner", "known", "options"]))
    if kind == "world":
        base = epico_world()
        files.append(("world.json", _dump(draw(json_mutation(base)))))
        argv += ["--world", "{d}/world.json"]
    elif kind == "owner":
        argv += ["--owner", draw(st.sampled_from(["b1=robot1", "b1=robot9", "=", "b99=robot1", "x", ""]))]
    elif kind == "known":
        argv += ["--known", draw(st.sampled_from(["robot1:red", "robot1:", "robot9:red", ":", "robot1:purple,red"]))]
    else:
        opt = draw(st.sampled_from(["--goal", "--colors", "--timeout", "--classical"]))
        pool = {"--goal": WORDS + ["beta", "gamma"], "--colors": INTS, "--timeout": FLOATS,
                "--classical": WORDS + ["clingo", "bfs"]}[opt]
        argv += [opt, draw(st.sampled_from(pool))]
    return Case("epico solve", tuple(argv), tuple(files), oracle="json", budget=60.0, note=kind)


@st.composite
def _mutate_sexp_or_bytes(draw, text: str) -> bytes:
    try:
        trees = _sexp_parse(text)
    except Exception:  # noqa: BLE001 - not an s-expression file: byte-level only
        return draw(text_mutation(text))
    out = _mutate_epddl(draw, text) if trees else draw(text_mutation(text))
    return out if isinstance(out, bytes) else out.encode()


# ----------------------------------------------------------------------------------- limits and outputs

HUGE = ["inf", "1e300", "100000000000000000000", "1e0", "5e-1", "0", "0.0", "-0", "nan", "-inf", "-1", "1e-300",
        "2147483648", "9223372036854775808", "+inf", "INF", "1_0"]


@st.composite
def limits_cases(draw) -> Case:
    """Limit and output families: huge and non-finite numbers on every limit option, options given twice and in
    the spellings that go through typer instead of the fast path, empty lists, outputs equal to inputs,
    symbolic-size bombs."""
    kind = draw(st.sampled_from(["timeout", "twice", "empty", "clobber", "bomb"]))
    coin = (str(SPECS / "coin_in_the_box" / "domain.epddl"), str(SPECS / "coin_in_the_box" / "problem.epddl"))
    plan = str(SPECS / "coin_in_the_box" / "problem.plan")
    if kind in ("timeout", "twice"):
        cmd = draw(st.sampled_from(["plan", "check", "prove", "muddy", "sum-product", "epico solve", "epico table",
                                    "explore sweep", "model draw"]))
        val = draw(st.sampled_from(HUGE))
        opt = "--total-timeout" if cmd == "epico table" and draw(st.booleans()) else "--timeout"
        spell = draw(st.sampled_from([[opt, val], [f"{opt}={val}"]]))
        if kind == "twice":
            spell = [*spell, opt, draw(st.sampled_from(HUGE))]
        base = {"plan": ["plan", *coin, "--json"], "check": ["check", *coin, plan, "--json"],
                "prove": ["prove", "K_a p -> p", "--worlds", "2"], "muddy": ["puzzle", "muddy", "-n", "3", "--json"],
                "sum-product": ["puzzle", "sum-product", "--limit", "30", "--json"],
                "epico solve": ["epico", "solve", "--goal", "alpha", "--colors", "1", "--json"],
                "epico table": ["epico", "table", "--colors", "1", "--json"],
                "explore sweep": ["explore", "sweep", "--maps", "1", "--robots", "2", "--methods", "ideal",
                                  "--workers", "1", "--no-snapshots", "--out", "{d}/sweep", "--json"],
                "model draw": ["model", "draw", "{d}/m.json", "-o", "{d}/m.svg", "--max-worlds",
                               draw(st.sampled_from(INTS))]}[cmd]
        files = (("m.json", _dump(_model_dict(draw))),) if cmd == "model draw" else ()
        args = base + (spell if cmd != "model draw" else [])
        oracle = "plan" if cmd == "plan" else ("json" if "--json" in base else None)
        label = cmd if " " in cmd or cmd in ("plan", "check", "prove") else f"puzzle {cmd}"
        return Case(label, tuple(args), files, oracle=oracle, budget=90.0, note=f"limits:{kind}")
    if kind == "empty":
        argv = draw(st.sampled_from([
            ["model", "diff", "{d}/m.json", "{d}/m.json", "--props", draw(st.sampled_from(["", ",", " , "]))],
            ["epico", "table", "--colors", draw(st.sampled_from(["", ",", " "]))],
            ["explore", "sweep", "--methods", "", "--out", "{d}/o"],
            ["explore", "sweep", "--robots", "", "--out", "{d}/o"],
            ["explore", "sweep", "--case", "", "--out", "{d}/o"],
            ["check", *coin, plan, "--property", ""], ["check", *coin, plan, "--properties", "{d}/empty.txt"],
            ["plan", *coin, "--library", ""], ["convert", coin[0], coin[1], "--out", "{d}/o", "--name", ""],
            ["epico", "solve", "--owner", ""], ["epico", "solve", "--known", ""],
            ["model", "check", "{d}/m.json", ""], ["prove", ""]]))
        label = " ".join(argv[:2]) if argv[0] in ("model", "epico", "explore") else argv[0]
        return Case(label, tuple(argv), (("m.json", _dump(_model_dict(draw))), ("empty.txt", b"")), oracle="json"
                    if "--json" in argv else None, budget=60.0, note="limits:empty")
    if kind == "clobber":  # an output named like an input: refused (exit 2), the input unchanged
        files_ = mastar_files()
        which = draw(st.sampled_from(["convert", "convert-name", "contract", "dot", "draw"]))
        if which.startswith("convert") and files_:
            f = draw(st.sampled_from(files_))
            name = ["--name", "spec"] if which == "convert-name" else []
            return Case("convert", ("convert", "{d}/spec.txt", "--to", "mastar", "-o", "{d}", *name),
                        (("spec.txt", f.read_bytes()),), oracle="inputs", note="limits:clobber")
        out = {"contract": "{d}/m.json", "dot": "{d}/m.json", "draw": "{d}/m.json"}.get(which, "{d}/m.json")
        sub = "contract" if which == "convert" else which
        return Case(f"model {sub}", ("model", sub, "{d}/m.json", "-o", out), (("m.json", _dump(_model_dict(draw))),),
                    oracle="inputs", note="limits:clobber")
    bomb = draw(st.sampled_from([
        ["puzzle", "sum-product", "--limit", draw(st.sampled_from(["20000", "100000", "4294967296"])), "--symbolic"],
        ["puzzle", "muddy", "--children", draw(st.sampled_from(["20000", "100000"])), "--muddy", "2", "--symbolic"],
        ["smcdel", "{d}/big.smcdel.txt"], ["model", "draw", "{d}/big.smcdel.txt", "-o", "{d}/b.svg", "--max-worlds",
                                           "100000"],
        ["model", "diff", "{d}/big.smcdel.txt", "{d}/big.smcdel.txt", "--engine", "explicit", "--max-worlds",
         "5000000"],
        ["model", "draw", "{d}/m.json", "-o", "{d}/m.png", "--layout", "kamada-kawai"]]))
    n = draw(st.sampled_from([16, 24, 30, 40]))
    smc = "VARS " + ",".join(str(i) for i in range(1, n + 1)) + "\nLAW Top\nOBS alice: 1\nbob: 2\nWHERE? Top\n"
    label = " ".join(bomb[:2]) if bomb[0] in ("puzzle", "model") else bomb[0]
    return Case(label, tuple(bomb), (("big.smcdel.txt", smc.encode()), ("m.json", _dump(_model_dict(draw)))),
                budget=60.0, note=f"limits:bomb n={n}")


#: command family ↦ strategy; weights = how many of each the big run draws
FAMILIES = {
    "plan": (plan_cases, 20),
    "check": (check_cases, 14),
    "model": (model_cases, 30),
    "puzzle": (puzzle_cases, 8),
    "consistency": (consistency_cases, 7),
    "explore": (explore_cases, 8),
    "arms": (arms_cases, 10),
    "misc": (misc_cases, 3),
    "epddl2026": (epddl2026_cases, 10),
    "convert": (convert_cases, 5),
    "smcdel": (smcdel_cases, 6),
    "epico": (epico_cases, 6),
    "limits": (limits_cases, 12),
}


def register_families(families: dict) -> None:
    """Add command families (``name -> (strategy factory, weight)``) from another module, e.g.
    ``tests/fuzz/fuzzsafety.py`` or ``bench/fuzz_http.py``: ``run_fuzz`` and ``bench/fuzz.py --families`` then
    draw them like their own. A case of such a family may be run by the family's own code
    (``Case(mode="call", argv=("module:function", ...))``: the function gets the case and a scratch directory
    and returns a :class:`fuzzkit.Outcome`)."""
    for name, entry in families.items():
        if name in FAMILIES and FAMILIES[name] is not entry:
            raise ValueError(f"fuzz family {name!r} is registered twice")
        FAMILIES[name] = entry


#: the families of files, processes and limits (tests/fuzz/fuzzsafety.py)
from fuzzsafety import FAMILIES as _SAFETY  # noqa: E402

register_families(_SAFETY)




def run_fuzz(n: int, *, seed: int = 0, families: list[str] | None = None, runner=None, on_outcome=None):
    """Draw ``n`` cases (hypothesis, derandomised by ``seed``, no shrinking) and run each; returns a Tally."""
    from fuzzkit import Runner, Tally
    from hypothesis import HealthCheck, Phase, given, settings
    from hypothesis import seed as hseed

    chosen = families or list(FAMILIES)
    names = [name for name in chosen for _ in range(FAMILIES[name][1])]
    strategy = st.sampled_from(names).flatmap(lambda name: FAMILIES[name][0]())
    tally = Tally()
    own = runner is None
    runner = runner or Runner()

    def body(case):
        if tally.total >= n:
            return
        outcome = runner.run(case)
        tally.add(outcome)
        if on_outcome is not None:
            on_outcome(outcome, tally)

    from hypothesis.errors import FlakyStrategyDefinition

    try:
        rounds = 0
        while tally.total < n and rounds < 50:
            # hypothesis occasionally reports its own replay of a choice sequence as "flaky" when a draw
            # took a different path; the outcomes so far stay counted and generation resumes with a new seed
            test = hseed(seed + 7919 * rounds)(settings(
                max_examples=n - tally.total, database=None, phases=[Phase.generate], deadline=None,
                suppress_health_check=list(HealthCheck))(given(strategy)(body)))
            rounds += 1
            try:
                test()
            except FlakyStrategyDefinition:
                continue
    finally:
        if own:
            runner.close()
    return tally
