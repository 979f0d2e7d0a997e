"""Reader for E-PDDL (the 2021 dialect used by e-PICO, seed 004) into a grounded :class:`Task`.

A domain declares typed predicates and action schemas::

    (:action open :act_type ontic            ; ontic (default) | sensing | announcement
      :parameters (?ag - agent)
      :precondition (and ([?ag](has_key ?ag)) (has_key ?ag))
      :effect (opened)                        ; ontic: literals, (when c e), (forall ...);
                                              ; sensing: what is sensed; announcement: what is announced
      :observers (and (forall (diff (?o)(?ag)) (when (looking ?o) (?o))) (?ag))
      :p_observers (...))                     ; partially observant agents

and a problem the agents, objects, the initial state (positive atoms of the actual world — closed world —
and ``([a b c](φ))`` common-knowledge statements) and the goal. Formulas: atoms ``(p x y)``, ``(and …)``,
``(or …)``, ``(not φ)``, ``(imply φ ψ)``, ``([i](φ))`` (belief of i), ``([i j](φ))`` (common knowledge of the
group). ``(forall (?x - t) …)`` and ``(forall (diff (?x)(?y …)) …)`` (x ranges over agents other than
y …) quantify over objects. Grounded atoms are named ``p_x_y`` and actions ``name_x_y`` (as in the mA*
benchmarks), so a domain and its mA* twin give the same plans.
"""

from __future__ import annotations

import itertools
import re
from pathlib import Path

from delkit._records import DataclassFields, Record
from delkit.errors import ParseError, io_reason
from delkit.logic.formula import TOP, C, Formula, Implies, K, Not, Or, Prop, conj
from planners.lang.initial import finitary_s5
from planners.task import ActionSpec, Task, merge_observers

__all__ = ["parse_epddl", "load_epddl", "SExp", "EXTENSION_SECTIONS"]

#: Domain sections that other delkit modules read and this reader skips (a strict reader must accept them):
#: ``(:macro NAME :parameters (...) :steps ((action ?x ...) ...))`` — macro-actions, ``planners.macros``.
EXTENSION_SECTIONS = frozenset({":macro"})


class Atom(Record):
    """A symbol of an s-expression (a frozen record, :mod:`delkit._records`)."""

    __dataclass_fields__ = DataclassFields("text", "line", "col")
    text: str
    line: int
    col: int

    def __init__(self, text: str, line: int, col: int) -> None:
        d = self.__dict__  # item by item: faster than update(**kw) (one per token)
        d["text"], d["line"], d["col"] = text, line, col


class SList(Record):
    """A parenthesised list of s-expressions (a frozen record)."""

    __dataclass_fields__ = DataclassFields("items", "line", "col")
    items: tuple[SExp, ...]
    line: int
    col: int

    def __init__(self, items: tuple[SExp, ...], line: int, col: int) -> None:
        d = self.__dict__
        d["items"], d["line"], d["col"] = items, line, col


SExp = Atom | SList

_TOK = re.compile(r"\s+|;[^\n]*|[()\[\]]|[^\s()\[\];]+")


def read_sexps(text: str, source: str) -> list[SExp]:
    """Parse text into s-expressions; ``[`` and ``]`` are atoms of their own."""
    stack: list[list] = [[]]
    starts: list[tuple[int, int]] = []
    line, lstart = 1, 0
    for m in _TOK.finditer(text):
        s = m.group(0)
        col = m.start() - lstart + 1
        if s[0].isspace() or s[0] == ";":
            pass
        elif s == "(":
            stack.append([])
            starts.append((line, col))
        elif s == ")":
            if len(stack) == 1:
                raise ParseError("unbalanced ')'", source=source, line=line, column=col)
            items = stack.pop()
            ln, cl = starts.pop()
            stack[-1].append(SList(tuple(items), ln, cl))
        else:
            stack[-1].append(Atom(s.lower() if not s.startswith("?") else s.lower(), line, col))
        nl = s.count("\n")
        if nl:
            line += nl
            lstart = m.start() + s.rfind("\n") + 1
    if len(stack) != 1:
        ln, cl = starts[-1]
        raise ParseError("'(' is never closed", source=source, line=ln, column=cl, expected=["')'"])
    return stack[0]


class _Ctx:
    """Shared state while grounding: objects by type, predicate signatures, source for errors."""

    def __init__(self, source: str) -> None:
        self.source = source
        self.objects: dict[str, list[str]] = {}
        self.predicates: dict[str, list[str]] = {}
        self.agents: list[str] = []

    def err(self, msg: str, at: SExp | None, expected: list[str] | None = None) -> ParseError:
        if at is None:
            return ParseError(msg, source=self.source, expected=expected)
        return ParseError(msg, source=self.source, line=at.line, column=at.col, expected=expected)

    def of_type(self, t: str, at: SExp) -> list[str]:
        if t == "agent":
            return list(self.agents)
        if t == "object":
            return sorted({o for v in self.objects.values() for o in v} | set(self.agents))
        if t not in self.objects:
            raise self.err(f"unknown type {t!r}; types are {sorted(set(self.objects) | {'agent'})}", at)
        return self.objects[t]


def _typed_list(items: tuple[SExp, ...], ctx: _Ctx) -> list[tuple[str, str, SExp]]:
    """``?a ?b - t ?c - u`` (or ``a b - t``) → [(name, type, node)]; untyped names are 'object'."""
    out: list[tuple[str, str, SExp]] = []
    pending: list[Atom] = []
    i = 0
    while i < len(items):
        it = items[i]
        if not isinstance(it, Atom):
            raise ctx.err("expected a name in a typed list", it)
        if it.text == "-":
            if i + 1 >= len(items) or not isinstance(items[i + 1], Atom):
                raise ctx.err("expected a type after '-'", it)
            t = items[i + 1].text  # type: ignore[union-attr]
            out.extend((p.text, t, p) for p in pending)
            pending = []
            i += 2
            continue
        pending.append(it)
        i += 1
    out.extend((p.text, "object", p) for p in pending)
    return out


def _head(x: SExp) -> str | None:
    if isinstance(x, SList) and x.items and isinstance(x.items[0], Atom):
        return x.items[0].text
    return None


#: the sections this reader understands; anything else is an error, not ignored (``:macro``: macro actions)
SECTIONS = {"domain": (":requirements", ":types", ":predicates", ":constants", ":action", ":macro"),
            "problem": (":domain", ":requirements", ":agents", ":objects", ":depth", ":init", ":goal")}
ACTION_FIELDS = (":act_type", ":parameters", ":precondition", ":effect", ":observers", ":p_observers")


def _sections(x: SList, ctx: _Ctx, start: int, kind: str = "domain") -> dict[str, SExp]:
    out: dict[str, SExp] = {}
    for it in x.items[start:]:
        h = _head(it)
        if h is None or not h.startswith(":"):
            raise ctx.err("expected a section like (:predicates ...)", it)
        if h not in SECTIONS[kind]:
            raise ctx.err(f"unknown {kind} section {h!r}", it, expected=list(SECTIONS[kind]))
        if h in out and h not in (":action", ":macro"):
            prev = out[h]
            raise ctx.err(f"second {h} section (the first is at line {prev.line}, column {prev.col}); merge them",
                          it)
        out[h] = it
    return out


class _Grounder:
    def __init__(self, ctx: _Ctx) -> None:
        self.ctx = ctx

    def term(self, a: Atom, env: dict[str, str]) -> str:
        if a.text.startswith("?"):
            if a.text not in env:
                raise self.ctx.err(f"unbound variable {a.text}", a)
            return env[a.text]
        return a.text

    def agent(self, a: SExp, env: dict[str, str]) -> str:
        if not isinstance(a, Atom):
            raise self.ctx.err("expected an agent", a)
        name = self.term(a, env)
        if name not in self.ctx.agents:
            raise self.ctx.err(f"{name!r} is not an agent; agents are {self.ctx.agents}", a)
        return name

    def arity(self, x: SExp, n: int, form: str) -> None:
        """``x`` must be a list of ``n`` items, written like ``form``."""
        if not isinstance(x, SList) or len(x.items) != n:
            raise self.ctx.err(f"expected {form}", x)

    def atom(self, x: SList, env: dict[str, str]) -> str:
        if not isinstance(x, SList) or not x.items or not isinstance(x.items[0], Atom):
            raise self.ctx.err("expected an atom (predicate arg ...)", x)
        name = x.items[0].text  # type: ignore[union-attr]
        if name not in self.ctx.predicates:
            raise self.ctx.err(f"unknown predicate {name!r}; declared: {sorted(self.ctx.predicates)}", x)
        sig = self.ctx.predicates[name]
        args = [self.term(a, env) if isinstance(a, Atom) else None for a in x.items[1:]]
        if len(args) != len(sig) or any(a is None for a in args):
            raise self.ctx.err(f"predicate {name!r} takes {len(sig)} argument(s)", x)
        for i, (arg, typ) in enumerate(zip(args, sig, strict=True), 1):  # the fluent exists only for these
            objects = self.ctx.of_type(typ, x)
            if arg not in objects:
                raise self.ctx.err(f"argument {i} of {name!r} is {arg!r}, which is not an object of type {typ!r} "
                                   f"(objects of that type: {', '.join(objects) or 'none'}); declare it in "
                                   f":objects or fix the name", x)
        return "_".join([name, *args])  # type: ignore[list-item]

    # ------------------------------------------------------------------ quantifiers
    def bindings(self, spec: SExp, env: dict[str, str]) -> list[dict[str, str]]:
        """Variable bindings of a forall: ``(?x - t ...)`` or ``(diff (?x)(?y ...))``."""
        if _head(spec) == "diff":
            assert isinstance(spec, SList)
            if len(spec.items) != 3 or not all(isinstance(p, SList) for p in spec.items[1:]):
                raise self.ctx.err("expected (diff (?x) (?y ...))", spec)
            var_items = spec.items[1].items  # type: ignore[union-attr]
            exc_items = spec.items[2].items  # type: ignore[union-attr]
            excluded = {self.agent(a, env) for a in exc_items}
            out = []
            vars_ = [v.text for v in var_items if isinstance(v, Atom) and v.text != "-"]
            for combo in itertools.product([a for a in self.ctx.agents if a not in excluded], repeat=len(vars_)):
                out.append({**env, **dict(zip(vars_, combo, strict=True))})
            return out
        if not isinstance(spec, SList):
            raise self.ctx.err("expected a parameter list after forall", spec)
        params = _typed_list(spec.items, self.ctx)
        domains = [self.ctx.of_type(t, node) for _, t, node in params]
        return [{**env, **dict(zip([p for p, _, _ in params], combo, strict=True))}
                for combo in itertools.product(*domains)]

    # ------------------------------------------------------------------ formulas
    def formula(self, x: SExp, env: dict[str, str]) -> Formula:  # noqa: C901 - one case per construct
        if isinstance(x, Atom):
            if x.text in ("true", "top"):
                return TOP
            raise self.ctx.err(f"found {x.text!r}", x, expected=["(predicate args)", "(and ...)", "([agent](φ))"])
        if not x.items:
            raise self.ctx.err("empty formula '()'", x)
        first = x.items[0]
        if isinstance(first, Atom) and first.text == "[":
            try:
                close = next(i for i, it in enumerate(x.items) if isinstance(it, Atom) and it.text == "]")
            except StopIteration:
                raise self.ctx.err("'[' without ']'", first) from None
            group = [self.agent(a, env) for a in x.items[1:close]]
            rest = x.items[close + 1:]
            if len(rest) != 1 or not group:
                raise self.ctx.err("expected ([agents](φ)) with one formula", x)
            body = self.formula(rest[0], env)
            if len(group) == 1:
                return K(group[0], body)
            return C(group, body)
        h = _head(x)
        args = x.items[1:]
        if h == "and":
            return conj([self.formula(a, env) for a in args])
        if h == "or":
            return Or(tuple(self.formula(a, env) for a in args))
        if h == "not":
            if len(args) != 1:
                raise self.ctx.err("(not φ) takes one formula", x)
            return Not(self.formula(args[0], env))
        if h in ("imply", "implies"):
            if len(args) != 2:
                raise self.ctx.err("(imply φ ψ) takes two formulas", x)
            return Implies(self.formula(args[0], env), self.formula(args[1], env))
        if h in ("forall", "exists"):
            self.arity(x, 3, f"({h} (?x - type ...) BODY)")
        if h == "forall":
            return conj([self.formula(args[1], b) for b in self.bindings(args[0], env)])
        if h == "exists":
            return Or(tuple(self.formula(args[1], b) for b in self.bindings(args[0], env)))
        if h in self.ctx.predicates:
            return Prop(self.atom(x, env))
        raise self.ctx.err(f"unknown predicate or operator {h!r}", x,
                           expected=["and", "or", "not", "imply", "forall", "[agents]", "a declared predicate"])

    # ------------------------------------------------------------------ effects and observers
    def effects(self, x: SExp, env: dict[str, str], cond: Formula, out: list) -> None:
        """Ontic effects → (fluent, value, condition)."""
        h = _head(x)
        if h == "and":
            for a in x.items[1:]:  # type: ignore[union-attr]
                self.effects(a, env, cond, out)
        elif h == "when":
            self.arity(x, 3, "(when CONDITION EFFECT)")
            c, e = x.items[1:]  # type: ignore[union-attr]
            self.effects(e, env, conj([cond, self.formula(c, env)]), out)
        elif h == "forall":
            self.arity(x, 3, "(forall (?x - type ...) BODY)")
            for b in self.bindings(x.items[1], env):  # type: ignore[union-attr]
                self.effects(x.items[2], b, cond, out)  # type: ignore[union-attr]
        elif h == "not":
            self.arity(x, 2, "(not (predicate arg ...))")
            out.append((self.atom(x.items[1], env), False, cond))  # type: ignore[union-attr, arg-type]
        elif h in self.ctx.predicates:
            out.append((self.atom(x, env), True, cond))  # type: ignore[arg-type]
        elif h is not None and not h.startswith(":") and h not in ("or", "imply", "exists"):
            raise self.ctx.err(f"unknown predicate {h!r} in an effect; declared: {sorted(self.ctx.predicates)}", x)
        else:
            raise self.ctx.err(f"unexpected effect {h!r}", x, expected=["(p ...)", "(not (p ...))", "(when c e)",
                                                                       "(and ...)", "(forall ...)"])

    def sensed(self, x: SExp, env: dict[str, str], cond: Formula, out: list) -> None:
        """Sensing/announcement effects → (formula, condition)."""
        h = _head(x)
        if h == "and":
            for a in x.items[1:]:  # type: ignore[union-attr]
                self.sensed(a, env, cond, out)
        elif h == "when":
            self.arity(x, 3, "(when CONDITION EFFECT)")
            c, e = x.items[1:]  # type: ignore[union-attr]
            self.sensed(e, env, conj([cond, self.formula(c, env)]), out)
        elif h == "forall":
            self.arity(x, 3, "(forall (?x - type ...) BODY)")
            for b in self.bindings(x.items[1], env):  # type: ignore[union-attr]
                self.sensed(x.items[2], b, cond, out)  # type: ignore[union-attr]
        else:
            out.append((self.formula(x, env), cond))

    def observers(self, x: SExp, env: dict[str, str], cond: Formula, out: list) -> None:
        """Observer specs → (agent, condition)."""
        h = _head(x)
        if h == "and":
            for a in x.items[1:]:  # type: ignore[union-attr]
                self.observers(a, env, cond, out)
        elif h == "when":
            self.arity(x, 3, "(when CONDITION EFFECT)")
            c, o = x.items[1:]  # type: ignore[union-attr]
            self.observers(o, env, conj([cond, self.formula(c, env)]), out)
        elif h == "forall":
            self.arity(x, 3, "(forall (?x - type ...) BODY)")
            for b in self.bindings(x.items[1], env):  # type: ignore[union-attr]
                self.observers(x.items[2], b, cond, out)  # type: ignore[union-attr]
        elif isinstance(x, SList):
            for a in x.items:
                out.append((self.agent(a, env), cond))
        else:
            out.append((self.agent(x, env), cond))


def _define(x: SExp, kind: str, ctx: _Ctx) -> tuple[str, dict[str, SExp], SList]:
    if _head(x) != "define" or not isinstance(x, SList) or len(x.items) < 2 or _head(x.items[1]) != kind:
        raise ctx.err(f"expected (define ({kind} NAME) ...)", x)
    name_node = x.items[1]
    assert isinstance(name_node, SList)
    if len(name_node.items) > 2 or len(name_node.items) == 2 and not isinstance(name_node.items[1], Atom):
        raise ctx.err(f"expected ({kind} NAME) with one plain name", name_node)
    name = name_node.items[1].text if len(name_node.items) > 1 else kind  # type: ignore[union-attr]
    return name, _sections(x, ctx, 2, kind), x


def parse_epddl(domain_text: str, problem_text: str | None = None, *, domain_source: str = "<domain>",
                problem_source: str = "<problem>") -> Task:
    """Ground an E-PDDL domain and problem (they may also be two ``define``s in one text)."""
    dctx = _Ctx(domain_source)
    dx = read_sexps(domain_text, domain_source)
    px: list[SExp]
    if problem_text is None:
        def kind(d: SExp) -> str | None:  # ``(define (domain x) ...)`` → "domain"; ``(define)`` → None
            return _head(d.items[1]) if _head(d) == "define" and len(d.items) > 1 else None  # type: ignore[union-attr]

        dom = [d for d in dx if kind(d) == "domain"]
        prob = [d for d in dx if kind(d) == "problem"]
        if not prob:
            raise ParseError("no (define (problem ...)) given: pass the problem file too", source=domain_source)
        dx, px, problem_source = dom, prob, domain_source
    else:
        px = read_sexps(problem_text, problem_source)
    if len(dx) != 1:
        raise ParseError("expected exactly one (define (domain ...))", source=domain_source)
    if len(px) != 1:
        raise ParseError("expected exactly one (define (problem ...))", source=problem_source)
    dname, dsec, _ = _define(dx[0], "domain", dctx)
    pctx = dctx
    pname, psec, pnode = _define(px[0], "problem", _Ctx(problem_source))
    ctx = dctx
    dom_ref = psec.get(":domain")  # (:domain NAME) must name the domain it is planned with
    if isinstance(dom_ref, SList) and len(dom_ref.items) == 2 and isinstance(dom_ref.items[1], Atom) \
            and dom_ref.items[1].text != dname:
        raise ParseError(f"the problem is for domain {dom_ref.items[1].text!r}, but the domain given is {dname!r}",
                         source=problem_source, line=dom_ref.line, column=dom_ref.col)
    # objects: problem agents/objects and domain constants
    agents_sec = psec.get(":agents")
    if agents_sec is None:
        raise ParseError("the problem has no (:agents ...) section", source=problem_source, line=pnode.line,
                         column=pnode.col)
    ctx.agents = [a.text for a in agents_sec.items[1:] if isinstance(a, Atom)]  # type: ignore[union-attr]
    for sec in (dsec.get(":constants"), psec.get(":objects")):
        if sec is not None:
            for name, t, _ in _typed_list(sec.items[1:], ctx):  # type: ignore[union-attr]
                if t == "agent":
                    if name not in ctx.agents:
                        ctx.agents.append(name)
                else:
                    ctx.objects.setdefault(t, []).append(name)
    preds = dsec.get(":predicates")
    if preds is None:
        raise ctx.err("the domain has no (:predicates ...) section", dx[0])
    props: list[str] = []
    for p in preds.items[1:]:  # type: ignore[union-attr]
        if not isinstance(p, SList) or not p.items or not isinstance(p.items[0], Atom):
            raise ctx.err("expected (predicate ?x - type ...)", p)
        params = _typed_list(p.items[1:], ctx)
        if p.items[0].text in ("true", "false", "top"):  # formulas (and --property) read them as constants
            raise ctx.err(f"predicate name {p.items[0].text!r} clashes with a constant of the formula syntax; "
                          f"rename it", p.items[0])
        ctx.predicates[p.items[0].text] = [t for _, t, _ in params]
        for combo in itertools.product(*[ctx.of_type(t, node) for _, t, node in params]):
            props.append("_".join([p.items[0].text, *combo]))
    g = _Grounder(ctx)
    actions: list[ActionSpec] = []
    for sec in dx[0].items[2:]:  # type: ignore[union-attr]
        if _head(sec) == ":action":
            actions.extend(_ground_action(sec, g, ctx))  # type: ignore[arg-type]
    # problem
    ctx.source = problem_source
    pctx.source = problem_source
    pointed: dict[str, bool] = dict.fromkeys(props, False)
    common: list[tuple[Formula, str]] = []
    others: list[tuple[Formula, str]] = []
    init = psec.get(":init")
    stated: dict[str, tuple[bool, SExp]] = {}  # fluent ↦ (value, statement) of the actual world's literals
    for it in (init.items[1:] if init is not None else ()):  # type: ignore[union-attr]
        where = f"{problem_source}:{it.line}:{it.col}"
        f = g.formula(it, {})
        lit = (f.name, True) if isinstance(f, Prop) else (
            (f.arg.name, False) if isinstance(f, Not) and isinstance(f.arg, Prop) else None)
        if lit is not None and lit[0] in stated and stated[lit[0]][0] != lit[1]:
            first = stated[lit[0]][1]
            raise ctx.err(f":init says both {lit[0]} and not {lit[0]} (the other statement is at line "
                          f"{first.line}, column {first.col}); the initial state is contradictory", it)
        if lit is not None:
            stated[lit[0]] = (lit[1], it)
        if isinstance(f, Prop):
            pointed[f.name] = True
        elif isinstance(f, Not) and isinstance(f.arg, Prop):
            pointed[f.arg.name] = False
        elif isinstance(f, C):
            common.append((f.arg, where))
        else:
            others.append((f, where))
    goal = psec.get(":goal")
    if goal is None or len(goal.items) != 2:  # type: ignore[union-attr]
        raise ctx.err("the problem needs one (:goal φ)", pnode)
    goal_f = g.formula(goal.items[1], {})  # type: ignore[union-attr]
    model = finitary_s5(props, ctx.agents, pointed, common, others, source=problem_source)
    return Task(f"{dname}/{pname}", tuple(props), tuple(ctx.agents), model, tuple(actions), goal_f,
                f"{domain_source} {problem_source}")


def _ground_action(sec: SList, g: _Grounder, ctx: _Ctx) -> list[ActionSpec]:
    if len(sec.items) < 2 or not isinstance(sec.items[1], Atom):
        raise ctx.err("expected (:action NAME ...)", sec)
    name = sec.items[1].text
    fields: dict[str, SExp] = {}
    items = sec.items[2:]
    i = 0
    while i < len(items):
        k = items[i]
        if not isinstance(k, Atom) or not k.text.startswith(":") or i + 1 >= len(items):
            raise ctx.err("expected ':keyword value' in the action", k, expected=list(ACTION_FIELDS))
        if k.text not in ACTION_FIELDS:  # a misspelt :precondition would silently drop the precondition
            raise ctx.err(f"unknown keyword {k.text!r} in action {name!r}", k, expected=list(ACTION_FIELDS))
        if k.text in fields:
            raise ctx.err(f"{k.text} given twice in action {name!r}", k)
        fields[k.text] = items[i + 1]
        i += 2
    kind_node = fields.get(":act_type")
    if kind_node is not None and not isinstance(kind_node, Atom):
        raise ctx.err(f"write ':act_type ontic|sensing|announcement' without parentheses in action {name!r}",
                      kind_node, expected=["ontic", "sensing", "announcement"])
    kind = kind_node.text if isinstance(kind_node, Atom) else "ontic"
    kinds = {"ontic": "ontic", "sensing": "sensing", "announcement": "announcement"}
    if kind not in kinds:
        raise ctx.err(f"unknown :act_type {kind!r}", kind_node, expected=list(kinds))
    params_node = fields.get(":parameters")
    params = _typed_list(params_node.items, ctx) if isinstance(params_node, SList) else []
    domains = [ctx.of_type(t, node) for _, t, node in params]
    out = []
    for combo in itertools.product(*domains):
        env = dict(zip([p for p, _, _ in params], combo, strict=True))
        gname = "_".join([name, *combo])
        where = f"{ctx.source}:{sec.line}:{sec.col}"
        pre = g.formula(fields[":precondition"], env) if ":precondition" in fields else TOP
        effects: list = []
        sensed: list = []
        if ":effect" in fields:
            if kind == "ontic":
                g.effects(fields[":effect"], env, TOP, effects)
            else:
                g.sensed(fields[":effect"], env, TOP, sensed)
        full: list = []
        partial: list = []
        if ":observers" in fields:
            g.observers(fields[":observers"], env, TOP, full)
        if ":p_observers" in fields:
            g.observers(fields[":p_observers"], env, TOP, partial)
        out.append(ActionSpec(gname, kinds[kind], pre, tuple(effects), tuple(sensed),  # type: ignore[arg-type]
                              tuple(merge_observers(full)), tuple(merge_observers(partial)), where))
    return out


def load_epddl(domain: str | Path, problem: str | Path | None = None) -> Task:
    """Read an E-PDDL domain file and problem file (or one file holding both)."""
    def read(p: str | Path) -> str:
        try:
            from delkit.paths import read_input

            return read_input(p, "E-PDDL file")
        except (OSError, UnicodeDecodeError) as exc:
            raise ParseError(f"cannot read the E-PDDL file: {io_reason(exc)}", source=str(p)) from None

    return parse_epddl(read(domain), read(problem) if problem is not None else None, domain_source=str(domain),
                       problem_source=str(problem) if problem is not None else str(domain))
