"""EPDDL (2026), the language of the 2026 planning competition's epistemic track, into a grounded Task.

A run is a domain, a problem and any number of action-type libraries (the built-in type ``basic`` needs
none). The semantics follow the official guideline (Burigana & Fabiano, 2026) and its reference toolkit
``plank`` exactly; the places where they are easy to get wrong:

* ``[i]φ`` box, ``<i>φ`` diamond; for a group ``[G]φ`` is ⋀_{i∈G} [i]φ and ``<G>φ`` is ⋀_{i∈G} <i>φ (every
  agent has *some* successor with φ — not the dual of ``[G]``); ``[Kw. G]φ`` is ⋀ ([i]φ ∨ [i]¬φ) and
  ``<Kw. G>φ`` is ⋀ (<i>φ ∧ <i>¬φ); ``[C. G]φ`` quantifies over the *transitive* (not reflexive) closure of
  ⋃_{i∈G} R_i (delkit's ``C``), ``<C. G>φ`` is its dual.
* a state satisfies φ iff φ holds in every designated world (delkit's ``KripkeModel.holds``).
* action types are event models: events are variables bound in order to the action's events, relations are
  indexed by observability types, designated events are listed. An agent's observability type is decided on
  the whole state before the update: for each (type, condition) of the agent, in type order, the last type
  whose condition the state satisfies wins, and an agent none of whose conditions holds gets the first type
  of the action type (plank's ``calculate_agents_obs_type``). ``if/else-if/else`` chains become conditions
  c1, ¬c1∧c2, ¬c1∧¬c2; ``default T`` gives T to agents with no statement, and to a chain without ``else``.
* an event's effects ``l`` / ``(when φ l)`` / ``(iff φ l)`` give each fluent p' = pos ∨ (p ∧ ¬neg), where pos
  (neg) is the disjunction of the conditions making p true (false).
* an action applies in s iff every designated world satisfies the precondition of some designated event.
* finitary-S5 initial states: worlds are the valuations (facts fixed by ``:facts-init``) satisfying every
  ``[C. All]φ``; designated worlds those satisfying the top-level formulas; i's relation links the worlds
  that agree on every φ of ``[C. All]([Kw. i]φ)``; ``[C. All]([i]φ)`` constrains the worlds as φ does and
  ``[C. All](<Kw. i>φ)`` adds nothing (plank ignores it too). The worlds are found with a BDD, never by
  enumerating all valuations (plank enumerates 2^33 on N-Consecutive-Numbers).
* explicit initial states (``:worlds/:relations/:labels/:designated``) keep the frame they are given: an
  agent with no relation listed has the empty relation (it believes ⊥), as in plank.

Ground action names are ``name_arg1_arg2`` (plank's). Facts (``:fact`` predicates) are static: they are
folded away while grounding and are not fluents of the task.
"""

from __future__ import annotations

import itertools
import time
from collections.abc import Callable, Iterator
from operator import itemgetter
from pathlib import Path

from delkit._lazy import lazy_module
from delkit.backends.compact import PlainEvents
from delkit.errors import ParseError
from delkit.logic.formula import BOT, TOP, And, Bot, C, Formula, Iff, Implies, K, Kw, Not, Or, Prop, Top
from planners.lang.initial import LoadTimeout
from planners.lang.sexpr import Node, Sym, read

TYPE_CHECKING = False  # typing.TYPE_CHECKING without importing typing (start-up: delkit._records)
if TYPE_CHECKING:
    import numpy as np
else:  # only an explicit initial state needs numpy
    np = lazy_module("numpy")

__all__ = ["load_epddl2026", "parse_epddl2026", "LoadTimeout", "find_libraries", "BASIC"]

BASIC = "basic"
REQUIREMENTS = frozenset((
    ":agent-groups :common-knowledge :conditional-effects :del :disjunctive-formulas :disjunctive-goals "
    ":disjunctive-list-formulas :disjunctive-obs-conditions :disjunctive-postconditions :disjunctive-preconditions "
    ":equality :events-conditions :existential-formulas :existential-goals :existential-list-formulas "
    ":existential-obs-conditions :existential-postconditions :existential-preconditions :finitary-S5-theories "
    ":facts :general-formulas :general-frames :general-goals :general-list-formulas :general-obs-conditions "
    ":general-postconditions :general-preconditions :group-modalities :KD45-frames :knowing-whether :lists "
    ":list-comprehensions :modal-formulas :modal-goals :modal-obs-conditions :modal-postconditions "
    ":modal-preconditions :multi-pointed-models :negative-formulas :negative-goals :negative-list-formulas "
    ":negative-obs-conditions :negative-postconditions :negative-preconditions :ontic-actions :pal "
    ":partial-observability :quantified-formulas :quantified-goals :quantified-list-formulas "
    ":quantified-obs-conditions :quantified-postconditions :quantified-preconditions :static-common-knowledge "
    ":typing :universal-formulas :universal-goals :universal-list-formulas :universal-obs-conditions "
    ":universal-postconditions :universal-preconditions").split())   # the guideline's (plank's lexer's) list
_ENTITY, _OBJECT, _AGENT = "entity", "object", "agent"
_NOT_ATOM = frozenset(("and", "or", "not", "imply", "forall", "exists", "=", "/=", "true", "false"))  # heads


# ----------------------------------------------------------------------------- formula smart constructors
def mk_not(f: Formula) -> Formula:
    t = type(f)
    if t is Top:
        return BOT
    if t is Bot:
        return TOP
    if t is Not:
        return f.arg
    return Not(f)


def _contradicts(parts: tuple[Formula, ...]) -> bool:
    negs = {x.arg for x in parts if isinstance(x, Not)}
    return bool(negs) and any(x in negs for x in parts)


def mk_and(parts) -> Formula:
    out: list[Formula] = []
    for p in parts:
        t = type(p)
        if t is Bot:
            return BOT
        if t is Top:
            continue
        if t is And:
            out.extend(p.args)
        else:
            out.append(p)
    return _and_of(out)


def _and_of(out: list[Formula]) -> Formula:
    """The conjunction of ``out`` (no ⊤, ⊥ or And in it): one part as itself, duplicates dropped, x ∧ ¬x ⊥."""
    if len(out) < 2:
        return out[0] if out else TOP
    uniq = tuple(dict.fromkeys(out))
    if _contradicts(uniq):  # x ∧ ¬x
        return BOT
    return uniq[0] if len(uniq) == 1 else And(uniq)


def mk_or(parts) -> Formula:
    out: list[Formula] = []
    for p in parts:
        t = type(p)
        if t is Top:
            return TOP
        if t is Bot:
            continue
        if t is Or:
            out.extend(p.args)
        else:
            out.append(p)
    return _or_of(out)


def _or_of(out: list[Formula]) -> Formula:
    """The disjunction of ``out`` (no ⊤, ⊥ or Or in it), as :func:`_and_of`."""
    if len(out) < 2:
        return out[0] if out else BOT
    uniq = tuple(dict.fromkeys(out))
    if _contradicts(uniq):  # x ∨ ¬x
        return TOP
    return uniq[0] if len(uniq) == 1 else Or(uniq)


# Compiled and/or/forall/exists: mk_and/mk_or over the parts' values, produced lazily (a conjunction is grounded
# per binding): no part is grounded after one that decides the whole (⊥ for and, ⊤ for or).
def _lazy_and(parts: list[Callable]) -> Callable:
    return lambda env: mk_and(part(env) for part in parts)


def _lazy_or(parts: list[Callable]) -> Callable:
    return lambda env: mk_or(part(env) for part in parts)


def _lazy_forall(binder: Callable, body: Callable) -> Callable:
    def forall(env):
        return mk_and(map(body, binder(env)))
    return forall


def _lazy_exists(binder: Callable, body: Callable) -> Callable:
    def exists(env):
        return mk_or(map(body, binder(env)))
    return exists


def atom_name(pred: str, args: tuple[str, ...]) -> str:
    return "_".join((pred, *args)) if args else pred


# ----------------------------------------------------------------------------- specification
def _sections(define: Node, source: str) -> tuple[str, str, list[Node]]:
    """(kind, name, sections) of a ``(define (kind name) ...)`` form."""
    if not isinstance(define, Node) or define.head() != "define" or len(define) < 2 \
            or not isinstance(define[1], Node) or len(define[1]) != 2:
        line = define.line if isinstance(define, Node) else getattr(define, "line", None)
        raise ParseError("expected (define (domain|problem|action-type-library NAME) ...)", source=source,
                         line=line)
    kind, name = define[1][0], define[1][1]
    secs = []
    for s in define[2:]:
        if not isinstance(s, Node) or not s or not isinstance(s[0], Sym) or not s[0].startswith(":"):
            raise ParseError("expected a section (:name ...)", source=source, line=getattr(s, "line", None))
        secs.append(s)
    return str(kind), str(name), secs


def _read_define(path: Path) -> tuple[str, str, list[Node]]:
    try:
        from delkit.paths import read_input

        text = read_input(path, "EPDDL file")
    except (OSError, UnicodeDecodeError) as exc:
        from delkit.errors import io_reason

        raise ParseError(f"cannot read: {io_reason(exc)}", source=str(path)) from None
    forms = read(text, str(path))
    if len(forms) != 1:
        raise ParseError(f"expected one (define ...) form, found {len(forms)}", source=str(path))
    return _sections(forms[0], str(path))


def find_libraries(domain: Path, names: list[str], given: list[Path], have: set[str] | None = None) -> list[Path]:
    """The library files for the declared ``names`` that ``given`` (or the library names ``have``) does not
    provide: ``NAME.epddl`` next to the domain or in a ``libraries/`` folder of one of its ancestors (plank's
    layout)."""
    have = set(have or ())
    for g in given:
        try:
            have.add(_read_define(g)[1])
        except ParseError:
            pass
    out = []
    for n in names:
        if n in have:
            continue
        for d in [domain.parent, *domain.parents]:
            for cand in (d / f"{n}.epddl", d / "libraries" / f"{n}.epddl"):
                if cand.is_file():
                    out.append(cand)
                    break
            else:
                continue
            break
    return out


# ----------------------------------------------------------------------------- grounding context
#: EPDDL term constructs (numeric / aggregate) that delkit refuses by name
_UNSUPPORTED_TERMS = {"count": "numeric terms: counting", "+": "numeric terms", "-": "numeric terms",
                      "*": "numeric terms", "/": "numeric terms", "sum": "numeric terms", "max": "numeric terms",
                      "min": "numeric terms"}


class _Ground:
    """Everything needed to ground formulas and lists: types, entities, facts, agents, predicates."""

    def __init__(self, src: dict[int, str], deadline: float | None) -> None:
        self.src = src
        self.deadline = deadline
        self.type_parent: dict[str, str] = {_OBJECT: _ENTITY, _AGENT: _ENTITY}
        self.entities: dict[str, str] = {}  # name -> type
        self.agents: list[str] = []
        self.preds: dict[str, tuple[tuple[str, ...], bool]] = {}  # name -> (param types, is fact)
        self.facts: set[tuple[str, ...]] = set()
        self._by_type: dict[str, list[str]] = {}
        self.where = "<epddl>"
        self.counter = 0
        self.groups: dict[str, tuple[str, ...]] = {}
        self._is_static: dict[Node, bool] = {}
        self._props: dict[str, Prop] = {}
        self._atoms: dict[str, dict[tuple[str, ...], Prop]] = {}
        self._fc: dict[int, tuple] = {}   # compiled formulas, atoms, bindings, list constructs, effects:
        self._ac: dict[int, tuple] = {}   # id(node) -> (node, closure)
        self._bc: dict[tuple, tuple] = {}
        self._ic: dict[int, tuple] = {}
        self._ec: dict[int, tuple] = {}
        self._pc: dict[int, tuple] = {}
        # per action type (by name: unique in a run), event and observability conditions
        self.type_pairs: dict[str, dict[str, list[tuple[int, int]]]] = {}
        self.type_relations: dict[str, dict] = {}
        self.event_params: dict[str, list] = {}
        self.ground_events: dict[tuple, tuple] = {}
        self.type_info: dict[str, tuple] = {}
        self.obs_leaves: dict[tuple, tuple] = {}

    def release(self) -> None:
        """Drop the compiled closures and caches. They refer to this object (reference cycles), so without
        this every load would leave thousands of objects for the cyclic garbage collector, whose passes
        then cost a fifth of a small problem's load; the grounded task refers to none of them."""
        for v in vars(self).values():
            if isinstance(v, dict):
                v.clear()

    def err(self, msg: str, node) -> ParseError:
        return ParseError(msg, source=self.where, line=getattr(node, "line", None))

    def tick(self, every: int = 1023) -> None:
        self.counter += 1
        if self.deadline is not None and (self.counter & every) == 0 and time.monotonic() > self.deadline:
            raise LoadTimeout("time limit reached while grounding the EPDDL task")

    # types ---------------------------------------------------------------
    def is_sub(self, t: str, sup: str) -> bool:
        seen = 0
        while t is not None and seen < 100:
            if t == sup:
                return True
            t = self.type_parent.get(t)
            seen += 1
        return False

    def of_type(self, t: str | tuple[str, ...]) -> list[str]:
        key = t if isinstance(t, str) else "|".join(t)
        got = self._by_type.get(key)
        if got is None:
            ts = (t,) if isinstance(t, str) else t
            for x in ts:
                if x not in self.type_parent and x != _ENTITY:
                    raise ParseError(f"unknown type {x!r}", source=self.where)
            got = [e for e, et in self.entities.items() if any(self.is_sub(et, x) for x in ts)]
            self._by_type[key] = got
        return got

    def typed_list(self, items, default: str = _OBJECT) -> tuple[list[tuple[str, object]], Node | None]:
        """[(name, type)] of ``a b - t c - (either u v)``, and the ``| filter`` if any."""
        out: list[tuple[str, object]] = []
        pending: list[str] = []
        filt = None
        i = 0
        items = list(items)
        while i < len(items):
            x = items[i]
            if x == "|":
                if i + 2 != len(items):
                    raise self.err("a '|' filter must be the last element of a parameter list", x)
                filt = items[i + 1]
                break
            if x == "-":
                if i + 1 >= len(items):
                    raise self.err("'-' without a type", x)
                t = items[i + 1]
                if isinstance(t, Node):
                    if t.head() != "either":
                        raise self.err("expected a type or (either t1 t2 ...)", t)
                    tt: object = tuple(str(y) for y in t[1:])
                else:
                    tt = str(t)
                out += [(p, tt) for p in pending]
                pending = []
                i += 2
                continue
            if not isinstance(x, Sym):
                raise self.err("expected a name in a typed list", x)
            pending.append(str(x))
            i += 1
        out += [(p, default) for p in pending]
        return out, filt

    # compiled nodes -----------------------------------------------------------
    # Every formula, atom, term list, parameter list and list construct is compiled once, on first use, into
    # a closure over the environment (variable -> entity); grounding then only calls closures. A construct
    # that is wrong compiles into a closure raising its error, so an error is still reported only when (and
    # where) the construct is grounded, as when it was interpreted. Caches are keyed by id() of the node and
    # keep the node alive (an id is never reused while its entry exists).
    def _cached(self, cache: dict, key, node, build: Callable[..., Callable], *args) -> Callable:
        got = cache.get(key)
        if got is None:
            got = cache[key] = (node, _deferred(build, *args))
        return got[1]

    def _prop(self, name: str) -> Prop:
        p = self._props.get(name)
        if p is None:
            p = self._props[name] = Prop(name)
        return p

    # terms ---------------------------------------------------------------
    def term(self, x, env: dict[str, str]) -> str:
        if not isinstance(x, Sym):
            head = x.head() if isinstance(x, Node) and x.kind == "(" else None
            if head in _UNSUPPORTED_TERMS:  # name the EPDDL feature instead of a generic "expected a term"
                raise self.err(f"({head} ...) is an EPDDL feature delkit does not support "
                               f"({_UNSUPPORTED_TERMS[head]}); ground it by hand or leave it out", x)
            raise self.err("expected a term (a name or a ?variable)", x)
        if x.startswith("?"):
            try:
                return env[x]
            except KeyError:
                raise self.err(f"unbound variable {x}", x) from None
        return str(x)

    def _terms(self, xs) -> Callable[[dict[str, str]], tuple[str, ...]]:
        """The compiled term list ``xs``: env -> tuple of entities (errors as :meth:`term`, in order)."""
        xs = list(xs)
        if not all(isinstance(x, Sym) for x in xs):
            return lambda env: tuple(self.term(x, env) for x in xs)
        spec = [(x.startswith("?"), str(x)) for x in xs]
        if spec and all(v for v, _ in spec):
            get = itemgetter(*[n for _, n in spec])  # the tuple in one C call (a single value for one variable)
            one = len(spec) == 1

            def all_vars(env):
                try:
                    return (get(env),) if one else get(env)
                except KeyError:
                    return tuple(self.term(x, env) for x in xs)
            return all_vars

        def mixed(env):
            try:
                return tuple([env[n] if v else n for v, n in spec])
            except KeyError:
                return tuple(self.term(x, env) for x in xs)
        return mixed

    def group(self, x, env: dict[str, str]) -> tuple[str, ...]:
        if isinstance(x, Node):
            return tuple(self.agent(y, env) for y in x)
        if x == "All":
            return tuple(self.agents)
        if x in self.groups:
            return self.groups[x]
        return (self.agent(x, env),)

    def agent(self, x, env) -> str:
        a = self.term(x, env)
        if a not in self.agents:
            raise self.err(f"{a!r} is not an agent (agents: {', '.join(self.agents)})", x)
        return a

    # bindings -------------------------------------------------------------
    def bindings(self, params: Node | list, env: dict[str, str], default: str = _OBJECT) -> Iterator[dict[str, str]]:
        """Every extension of ``env`` by the typed variables of ``params`` that passes its ``|`` filter. The
        filter's top-level conjuncts are tested as soon as their variables are bound. The yielded dictionary
        is reused for the next binding: use it before asking for the next one, never keep it."""
        return self._cached(self._bc, (id(params), default), params, self._binder, params, default)(env)

    def _binder(self, params, default: str) -> Callable[[dict[str, str]], Iterator[dict[str, str]]]:
        typed, filt = self.typed_list(params, default)
        names = [v for v, _ in typed]
        types = [t for _, t in typed]
        for v in names:
            if not v.startswith("?"):
                raise self.err(f"expected a ?variable, got {v!r}", params)
        checks: list[list[Callable]] = [[] for _ in names]
        if filt is not None and names:   # without variables the filter is tested once, whole (below)
            conjs = list(filt[1:]) if isinstance(filt, Node) and filt.head() == "and" else [filt]
            for c in conjs:
                used = _vars_in(c)
                idx = max((names.index(u) for u in used if u in names), default=-1)
                checks[max(idx, 0)].append(self._static_test(c))
        n = len(names)
        whole = self._static_test(filt) if filt is not None else None
        deadline = self.deadline

        def run(env: dict[str, str]) -> Iterator[dict[str, str]]:
            doms = [self.of_type(t) for t in types]  # type: ignore[arg-type]
            cur = dict(env)
            if n == 0:
                if whole is None or whole(cur):
                    yield cur
                return
            its: list = [iter(doms[0])] + [None] * (n - 1)
            last = n - 1
            k = 0
            while k >= 0:
                name, tests = names[k], checks[k]
                for val in its[k]:
                    self.counter += 1
                    if deadline is not None and (self.counter & 1023) == 0 and time.monotonic() > deadline:
                        raise LoadTimeout("time limit reached while grounding the EPDDL task")
                    cur[name] = val
                    if tests and not all(t(cur) for t in tests):
                        continue
                    if k == last:
                        yield cur
                    else:
                        k += 1
                        its[k] = iter(doms[k])
                        break
                else:
                    cur.pop(name, None)
                    k -= 1
        return run

    def _static_test(self, f) -> Callable[[dict[str, str]], bool]:
        fn = self.compile(f)

        def test(env) -> bool:
            g = fn(env)
            if g is TOP or g == TOP:
                return True
            if g is BOT or g == BOT:
                return False
            raise self.err("a '|' filter may only use equality and facts (it depends on a fluent)", f)
        return test

    # formulas -------------------------------------------------------------
    def atom(self, node: Node, env) -> Formula:
        return self.atom_of(node)(env)

    def atom_of(self, node) -> Callable[[dict[str, str]], Formula]:
        """The atom ``node`` compiled (a fact gives ⊤/⊥, a fluent its Prop)."""
        got = self._ac.get(id(node))
        return got[1] if got is not None else self._cached(self._ac, id(node), node, self._atom, node)

    def _atom(self, node: Node) -> Callable[[dict[str, str]], Formula]:
        pred = node[0]
        decl = self.preds.get(pred)
        xs = node[1:]
        args = self._terms(xs)
        if decl is None or len(decl[0]) != len(node) - 1:
            def bad(env):
                args(env)  # an unbound variable is reported first
                if decl is None:
                    raise self.err(f"unknown predicate {pred!r}", node)
                raise self.err(f"predicate {pred!r} takes {len(decl[0])} argument(s), got {len(node) - 1}", node)
            return bad
        name = str(pred)
        if decl[1]:
            facts = self.facts
            return lambda env: TOP if (name, *args(env)) in facts else BOT
        cache = self._atoms_of(name)

        def fluent(env) -> Formula:
            a = args(env)
            p = cache.get(a)
            if p is None:
                p = cache[a] = self._prop(atom_name(name, a))
            return p
        if all(type(x) is Sym and x[0] != "?" for x in xs):   # a ground fluent: its Prop now
            ground = fluent({})
            return lambda env: ground
        return fluent

    def _atoms_of(self, pred: str) -> dict[tuple[str, ...], Prop]:
        """arguments -> Prop of the fluent predicate ``pred``, shared by all its occurrences."""
        got = self._atoms.get(pred)
        if got is None:
            got = self._atoms[pred] = {}
        return got

    def formula(self, f, env: dict[str, str]) -> Formula:
        return self.compile(f)(env)

    def compile(self, f) -> Callable[[dict[str, str]], Formula]:
        """The formula ``f`` compiled: env -> ground formula (see "compiled nodes")."""
        got = self._fc.get(id(f))
        if got is not None:
            return got[1]
        if type(f) is Node and f.kind == "(" and f and type(f[0]) is Sym and f[0] not in _NOT_ATOM \
                and f[0][0] != ":":   # an atom, the most frequent node: as _formula would, one call less
            got = self._fc[id(f)] = (f, self.atom_of(f))
            return got[1]
        return self._cached(self._fc, id(f), f, self._formula, f)

    def _formula(self, f) -> Callable[[dict[str, str]], Formula]:  # noqa: C901 - one clause per construct
        if isinstance(f, Sym):
            if f in ("true", "⊤"):
                return lambda env: TOP
            if f in ("false", "⊥"):
                return lambda env: BOT
            raise self.err(f"expected a formula, got {f!r}", f)
        if f.kind != "(" or not f:
            raise self.err("expected a formula in parentheses", f)
        h = f[0]
        if isinstance(h, Node):
            if h.kind not in "[<" or len(f) != 2:
                raise self.err("expected ([modality] formula) or (<modality> formula)", f)
            return self._modal(h, self.compile(f[1]))
        if h in ("and", "or"):
            parts = [self.compile(x) for x in self._static_first(f)]
            return _lazy_and(parts) if h == "and" else _lazy_or(parts)
        if h == "not":
            self._arity(f, 1)
            arg = self.compile(f[1])
            return lambda env: mk_not(arg(env))
        if h == "imply":
            self._arity(f, 2)
            left, right = self.compile(f[1]), self.compile(f[2])

            def imply(env):
                a, b = left(env), right(env)
                if type(a) is Top or type(b) is Bot:   # as a == TOP / b == BOT (only ⊤ equals ⊤)
                    return mk_or([mk_not(a), b])
                if type(a) is Bot or type(b) is Top:
                    return TOP
                return Implies(a, b)
            return imply
        if h in ("forall", "exists"):
            self._arity(f, 2)
            params, body = f[1], self.compile(f[2])
            binder = self._cached(self._bc, (id(params), _OBJECT), params, self._binder, params, _OBJECT)
            return _lazy_forall(binder, body) if h == "forall" else _lazy_exists(binder, body)
        if h in ("=", "/="):
            self._arity(f, 2)
            both = self._terms(f[1:])
            same_is = h == "="

            def eq(env):
                a, b = both(env)
                return TOP if (a == b) == same_is else BOT
            return eq
        if h in ("true", "false"):
            return (lambda env: TOP) if h == "true" else (lambda env: BOT)
        if str(h).startswith(":"):
            raise self.err(f"{h} is a list construct; formulas use and/or/forall/exists (without ':')", f)
        return self.atom_of(f)

    def _static_first(self, f: Node) -> list:
        """The arguments of an and/or, those depending only on facts and equality first (they often decide
        the whole formula, and the others are then never grounded)."""
        args = f[1:]
        static = [self._static(x) for x in args]
        return [x for x, st in zip(args, static, strict=True) if st] + \
            [x for x, st in zip(args, static, strict=True) if not st]

    def _static(self, x) -> bool:
        if not isinstance(x, Node):
            return isinstance(x, Sym) and x in ("true", "false")
        got = self._is_static.get(x)
        if got is None:
            h = x.head()
            if h in ("=", "/="):
                got = True
            elif h in ("and", "or", "not", "imply"):
                got = all(self._static(y) for y in x[1:])
            elif h in ("forall", "exists") and len(x) == 3:
                got = self._static(x[2])
            elif h is not None and h in self.preds:
                got = self.preds[h][1]
            else:
                got = False
            self._is_static[x] = got
        return got

    def _arity(self, f: Node, n: int) -> None:
        if len(f) != n + 1:
            raise self.err(f"({f[0]} ...) takes {n} argument(s), got {len(f) - 1}", f)

    def _modal(self, m: Node, phi: Callable[[dict[str, str]], Formula]) -> Callable[[dict[str, str]], Formula]:
        items = list(m)
        op = None
        if items and items[0] in ("Kw.", "C."):
            op = str(items[0])
            items = items[1:]
        if len(items) != 1:
            def bad(env):
                phi(env)  # the operand's own errors first
                raise self.err("a modality holds one agent, a group (a1 a2 ...) or All", m)
            return bad
        who, box = items[0], m.kind == "["

        def modal(env) -> Formula:
            f = phi(env)
            g = self.group(who, env)
            if op is None:
                if len(g) == 1:   # mk_and of one K (or ¬K) is itself
                    return K(g[0], f) if box else mk_not(K(g[0], mk_not(f)))
                return mk_and(K(a, f) if box else mk_not(K(a, mk_not(f))) for a in g)
            if op == "Kw.":
                if box:
                    return mk_and(Kw(a, f) for a in g)
                return mk_and(mk_and([mk_not(K(a, f)), mk_not(K(a, mk_not(f)))]) for a in g)
            return C(g, f) if box else mk_not(C(g, mk_not(f)))
        return modal

    # effects -------------------------------------------------------------------
    def effects(self, node) -> Callable[[dict[str, str], Formula, dict, dict], None]:
        """The effects ``node`` compiled: (env, condition, pos, neg) -> None, appending to pos[p] (neg[p]) the
        conditions under which fluent p becomes true (false)."""
        got = self._ec.get(id(node))
        return got[1] if got is not None else self._cached(self._ec, id(node), node, self._effect, node)

    def _effect(self, node) -> Callable[[dict[str, str], Formula, dict, dict], None]:
        head = node.head() if isinstance(node, Node) and node.kind == "(" else None
        if head == ":and" or (isinstance(node, Node) and node.kind == "(" and len(node) == 0):
            parts = [self.effects(x) for x in node[1:]]  # `()`: the empty list of effects

            def conj(env, cond, pos, neg) -> None:
                for p in parts:
                    p(env, cond, pos, neg)
            return conj
        if head == ":forall":
            if len(node) != 3:
                raise self.err("(:forall (vars) body) takes a parameter list and one body", node)
            params, body = node[1], self.effects(node[2])

            def forall(env, cond, pos, neg) -> None:
                for e in self.bindings(params, env):
                    body(e, cond, pos, neg)
            return forall
        head = node.head() if isinstance(node, Node) else None
        if head == "when":
            if len(node) != 3:
                raise self.err("(when condition effects)", node)
            test, then = self.compile(node[1]), self.effects(node[2])

            def when(env, cond, pos, neg) -> None:
                c = mk_and([cond, test(env)])
                if type(c) is not Bot:
                    then(env, c, pos, neg)
            return when
        if head == "iff":
            if len(node) != 3:
                raise self.err("(iff condition literal)", node)
            test, lit = self.compile(node[1]), self._literal(node[2])
            inv = node[2][1] if isinstance(node[2], Node) and node[2].head() == "not" else None
            other = self.atom_of(inv if inv is not None else node[2])
            to_pos = inv is not None  # (iff φ (not p)): p is made true when φ is false

            def iff(env, cond, pos, neg) -> None:
                c = test(env)
                lit(env, mk_and([cond, c]), pos, neg)
                p = other(env)
                if type(p) is Prop:
                    (pos if to_pos else neg).setdefault(p.name, []).append(mk_and([cond, mk_not(c)]))
            return iff
        return self._literal(node)

    def posts(self, node) -> Callable[[dict[str, str]], dict[str, Formula]]:
        """The effects ``node`` compiled into env -> {p: p'} (p' = pos ∨ (p ∧ ¬neg), see :func:`_effects`).
        Effects made of literals only (in ``:and`` lists: no ``when``/``iff``/``:forall``, the usual case)
        give ⊤ for a fluent made true and ⊥ for one only made false, without collecting conditions."""
        got = self._pc.get(id(node))
        return got[1] if got is not None else self._cached(self._pc, id(node), node, self._posts, node)

    def _posts(self, node) -> Callable[[dict[str, str]], dict[str, Formula]]:
        lits: list[tuple[Callable, bool, Node]] | None = [] if node is not None else None
        todo = [node] if node is not None else []
        while todo and lits is not None:
            x = todo.pop()
            if isinstance(x, Node) and x.kind == "(" and x.head() == ":and":
                todo.extend(reversed(x[1:]))
            elif isinstance(x, Node) and x.kind == "(" and len(x) == 0:
                continue  # `:effects ()`: no effect (the EPDDL grammar and plank accept the empty list)
            elif (lit := self._literal_atom(x)) is not None:
                lits.append((*lit, x))
            else:   # a conditional effect, a :forall, or an error (reported by the general path, in order)
                lits = None
        if lits is None:
            eff = self.effects(node) if node is not None else None
            return lambda env: _effects(self, eff, env)
        err = self.err

        def post_of(env) -> dict[str, Formula]:
            post: dict[str, Formula] = {}
            negs = []
            for atom, into_pos, x in lits:
                f = atom(env)
                if type(f) is not Prop:
                    raise err("effects may not change a fact", x)
                if into_pos:
                    post[f.name] = TOP
                else:
                    negs.append(f.name)
            for p in negs:
                if p not in post:
                    post[p] = BOT
            return post
        return post_of

    def _literal_atom(self, node) -> tuple[Callable[[dict[str, str]], Formula], bool] | None:
        """(compiled atom, True for p / False for (not p)) of an effect literal; None if ``node`` is none."""
        if isinstance(node, Node) and node.head() == "not" and len(node) == 2:
            return self.atom_of(node[1]), False
        if isinstance(node, Node) and node.head() in self.preds:
            return self.atom_of(node), True
        return None

    def _literal(self, node) -> Callable[[dict[str, str], Formula, dict, dict], None]:
        lit = self._literal_atom(node)
        if lit is None:
            raise self.err("expected an effect: a literal, (when φ effects) or (iff φ literal)", node)
        atom, into_pos = lit

        def literal(env, cond, pos, neg) -> None:
            f = atom(env)
            if type(f) is not Prop:
                raise self.err("effects may not change a fact", node)
            (pos if into_pos else neg).setdefault(f.name, []).append(cond)
        return literal

    # list constructs ----------------------------------------------------------
    def items(self, node, env: dict[str, str], leaf: Callable[[object, dict[str, str]], None]) -> None:
        """Expand ``(:and ...)``/``(:forall (vars | filter) body)`` and call ``leaf`` on each element (with an
        environment that is only valid during the call)."""
        self._cached(self._ic, id(node), node, self._items, node)(env, leaf)

    def _items(self, node) -> Callable[[dict[str, str], Callable], None]:
        if isinstance(node, Node) and node.kind == "(" and node.head() == ":and":
            parts = [self._cached(self._ic, id(x), x, self._items, x) for x in node[1:]]

            def conj(env, leaf) -> None:
                for p in parts:
                    p(env, leaf)
            return conj
        if isinstance(node, Node) and node.kind == "(" and node.head() == ":forall":
            if len(node) != 3:
                raise self.err("(:forall (vars) body) takes a parameter list and one body", node)
            params, body = node[1], self._cached(self._ic, id(node[2]), node[2], self._items, node[2])

            def forall(env, leaf) -> None:
                for e in self.bindings(params, env):
                    body(e, leaf)
            return forall
        return lambda env, leaf: leaf(node, env)


def _vars_in(x) -> set[str]:
    """The ?variables written anywhere in ``x`` (a Sym or a tree)."""
    out: set[str] = set()
    todo = [x]
    while todo:
        y = todo.pop()
        if isinstance(y, Sym):
            if y.startswith("?"):
                out.add(str(y))
        else:
            todo.extend(y)
    return out


def _keyed(sec: Node, g: _Ground) -> dict[str, object]:
    """``:key value`` pairs of an ``(:event ...)``/``(:action ...)`` section after its name."""
    out: dict[str, object] = {}
    for i in range(2, len(sec), 2):
        k = sec[i]
        if not isinstance(k, Sym) or not k.startswith(":"):
            raise g.err(f"expected a :keyword in ({sec[0]} {sec[1]} ...), got {k!r}", sec)
        if i + 1 >= len(sec):
            raise g.err(f"{k} without a value", k)
        out[str(k)] = sec[i + 1]
    return out


# ----------------------------------------------------------------------------- the reader
class _Event:
    """An event declared in a domain (written without ``@dataclass``: start-up time, :mod:`delkit._records`)."""

    __slots__ = ("name", "params", "pre", "effects", "line")

    def __init__(self, name: str, params: Node | list, pre: object, effects: object, line: int) -> None:
        self.name, self.params, self.pre, self.effects, self.line = name, params, pre, effects, line


class _ActType:
    """An action type of a library."""

    __slots__ = ("name", "events", "obs_types", "relations", "designated", "line", "source")

    def __init__(self, name: str, events: list[str], obs_types: list[str], relations: Node | None,
                 designated: list[str], line: int, source: str) -> None:
        self.name, self.events, self.obs_types, self.relations = name, events, obs_types, relations
        self.designated, self.line, self.source = designated, line, source


_BASIC_TYPE = _ActType(BASIC, ["?e"], ["Fully"], None, ["?e"], 0, "<built-in>")


def parse_epddl2026(domain: Path, problem: Path, libraries: list[Path] = (), *,
                    deadline: float | None = None):
    """Read, type and ground one EPDDL run into a :class:`planners.task.Task`."""
    g = _Ground({}, deadline)
    g.warnings = []  # printed once the whole run has been read without error
    try:
        task = _parse(g, _path(domain), _path(problem), [_path(p) for p in libraries], deadline)
    finally:
        g.release()
    import sys

    for w in g.warnings:
        print(f"delkit: warning: {w}", file=sys.stderr)
    return task


def _parse(g: _Ground, domain: Path, problem: Path, libraries: list[Path], deadline: float | None):
    from planners.task import EventAction, Task

    g.where = str(domain)
    g.tick(0)
    dkind, dname, dsecs = _read_define(domain)
    if dkind != "domain":
        raise ParseError(f"expected (define (domain NAME) ...), found ({dkind} {dname})", source=str(domain))
    pkind, pname, psecs = _read_define(problem)
    if pkind != "problem":
        raise ParseError(f"expected (define (problem NAME) ...), found ({pkind} {pname})", source=str(problem))

    # ---- domain sections
    events: dict[str, _Event] = {}
    actions: list[tuple[str, dict[str, object], int]] = []
    declared_libs: list[str] = []
    for sec in dsecs:
        key = sec[0]
        if key == ":requirements":
            _requirements(g, sec)
            continue
        if key == ":action-type-libraries":
            declared_libs += [str(x) for x in sec[1:]]
        elif key == ":types":
            typed, _ = g.typed_list(sec[1:], _OBJECT)
            declared = {t for t, _ in typed} | set(g.type_parent)
            for t, parent in typed:
                if isinstance(parent, tuple):
                    raise g.err("a type's parent cannot be an (either ...)", sec)
                if parent not in declared:  # accepted (as a type under object), but said
                    g.warnings.append(f"{g.where}:{sec.line}: type {t!r} has the parent type "
                                      f"{parent!r}, which is not declared; it is read as a type under object "
                                      f"(declare it in (:types ...) to silence this)")
                    g.type_parent.setdefault(parent, _OBJECT)  # type: ignore[arg-type]
                    declared.add(parent)
                g.type_parent[t] = parent  # type: ignore[assignment]
        elif key == ":constants":
            typed, _ = g.typed_list(sec[1:], _OBJECT)
            for c, t in typed:
                g.entities[c] = t  # type: ignore[assignment]
        elif key == ":predicates":
            for p in sec[1:]:
                if not isinstance(p, Node) or not p:
                    raise g.err("expected (name ?x - type ...) or (:fact name ...)", p)
                fact = p[0] == ":fact"
                body = list(p[1:]) if fact else list(p)
                if not body or not isinstance(body[0], Sym):   # was an IndexError / the repr of a tree
                    raise g.err("expected (name ?x - type ...) or (:fact name ...)", p)
                typed, _ = g.typed_list(body[1:], _ENTITY)
                g.preds[str(body[0])] = (tuple(str(t) for _, t in typed), fact)
        elif key == ":event":
            kv = _keyed(sec, g)
            events[str(sec[1])] = _Event(str(sec[1]), kv.get(":parameters") or [], kv.get(":precondition"),
                                         kv.get(":effects"), sec.line)
        elif key == ":action":
            actions.append((str(sec[1]), _keyed(sec, g), sec.line))
        else:
            raise g.err(f"unsupported domain section {key} (supported: :requirements, :action-type-libraries, "
                        f":types, :constants, :predicates, :event, :action)", sec)

    # ---- libraries
    act_types: dict[str, _ActType] = {BASIC: _BASIC_TYPE}
    lib_names = []
    given = [(lp, _read_define(lp)) for lp in libraries]  # each file is read once
    found = find_libraries(domain, declared_libs, [], have={d[1] for _, d in given})
    for lp, (lkind, lname, lsecs) in [*given, *((lp, _read_define(lp)) for lp in found)]:
        g.where = str(lp)
        if lkind != "action-type-library":
            raise ParseError(f"expected (define (action-type-library NAME) ...), found ({lkind} {lname})",
                             source=str(lp))
        lib_names.append(lname)
        for sec in lsecs:
            if sec[0] == ":requirements":
                _requirements(g, sec)
                continue
            if sec[0] != ":action-type":
                raise g.err(f"unsupported library section {sec[0]}", sec)
            kv = _keyed(sec, g)
            evs = [str(x) for x in (kv.get(":events") or [])]
            obs = [str(x) for x in (kv.get(":observability-types") or [])]
            des = [str(x) for x in (kv.get(":designated") or [])]
            act_types[str(sec[1])] = _ActType(str(sec[1]), evs, obs, kv.get(":relations"), des, sec.line,
                                              str(lp))  # type: ignore[arg-type]
    missing = [n for n in declared_libs if n != BASIC and n not in lib_names]
    if missing:
        raise ParseError(f"the domain declares action-type librar{'y' if len(missing) == 1 else 'ies'} "
                         f"{', '.join(missing)} but no such file was given (pass --library FILE) or found "
                         f"next to the domain", source=str(domain))

    # ---- problem sections
    g.where = str(problem)
    init = goal = None
    facts_init = None
    group_secs: list[Node] = []
    for sec in psecs:
        key = sec[0]
        if key in (":requirements", ":domain"):
            if key == ":requirements":
                _requirements(g, sec)
            if key == ":domain" and len(sec) != 2:
                raise g.err(f"write the problem's domain as (:domain NAME), e.g. (:domain {dname})", sec)
            if key == ":domain" and str(sec[1]) != dname:
                raise g.err(f"the problem is for domain {sec[1]!r}, the domain file defines {dname!r}", sec)
            continue
        if key == ":agents":
            for a in sec[1:]:
                g.entities[str(a)] = _AGENT
        elif key == ":objects":
            typed, _ = g.typed_list(sec[1:], _OBJECT)
            for o, t in typed:
                unknown = [u for u in (t if isinstance(t, tuple) else (t,)) if u not in g.type_parent]
                if unknown:
                    raise g.err(f"object {o!r} has the type {unknown[0]!r}, which the domain does not declare "
                                f"(its types: {', '.join(sorted(k for k in g.type_parent if k != _ENTITY))}); "
                                f"fix the type or add it to the domain's (:types ...)", sec)
                g.entities[o] = t  # type: ignore[assignment]
        elif key == ":facts-init":
            facts_init = sec
        elif key == ":init":
            init = sec
        elif key == ":goal":
            goal = sec
        elif key == ":agent-groups":
            group_secs.append(sec)
        else:
            raise g.err(f"unsupported problem section {key} (supported: :domain, :requirements, :agents, "
                        f":agent-groups, :objects, :facts-init, :init, :goal)", sec)
    g.agents = [e for e, t in g.entities.items() if g.is_sub(t, _AGENT)]
    for sec in group_secs:
        _agent_groups(g, sec)
    if not g.agents:
        raise g.err("no agents: declare them with (:agents ...) or as constants of type agent", problem)
    if init is None or goal is None:
        raise ParseError("the problem needs an :init and a :goal", source=str(problem))
    if facts_init is not None:
        def fact(node, env):
            if not isinstance(node, Node) or not node or node.head() not in g.preds:
                raise g.err("expected a fact (pred args ...)", node)
            if not g.preds[node[0]][1]:
                raise g.err(f"{node[0]!r} is not declared as a (:fact ...) predicate", node)
            g.facts.add((str(node[0]), *(g.term(x, env) for x in node[1:])))
        for x in facts_init[1:]:
            g.items(x, {}, fact)

    # ---- fluents: every well-typed ground atom of a non-fact predicate
    props: list[str] = []
    for p, (types, is_fact) in g.preds.items():
        if is_fact:
            continue
        for args in itertools.product(*(g.of_type(t) for t in types)):
            props.append(atom_name(p, args))
    agents = tuple(g.agents)

    # ---- initial state and goal
    if len(init) >= 2 and isinstance(init[1], Sym) and init[1] == ":worlds":
        model = _explicit_init(init, g, props, agents)
    else:
        from planners.lang.initial import finitary_s5_epddl

        if len(init) != 2:
            raise g.err("(:init ...) holds one list of finitary-S5 formulas (use (:and ...))", init)
        type1: list[Formula] = []
        type2: list[Formula] = []
        type3: dict[str, list[Formula]] = {a: [] for a in agents}

        def theory(node, env):
            if isinstance(node, Node) and node.kind == "(" and node and isinstance(node[0], Node) \
                    and node[0].kind == "[" and len(node[0]) == 2 and node[0][0] == "C.":
                grp = g.group(node[0][1], env)
                if set(grp) != set(agents):
                    raise g.err("finitary-S5 theories only allow common knowledge of All ([C. All] ...)", node)
                if len(node) != 2:
                    raise g.err("expected ([C. All] formula)", node)
                inner = node[1]
                if isinstance(inner, Node) and inner and isinstance(inner[0], Node) and inner[0].kind in "[<":
                    mod = inner[0]
                    if len(inner) != 2:
                        raise g.err("expected ([C. All] ([modality] formula))", inner)
                    if mod.kind == "[" and len(mod) == 2 and mod[0] == "Kw.":
                        type3[g.agent(mod[1], env)].append(_prop(g, inner[1], env))
                        return
                    if mod.kind == "<" and len(mod) == 2 and mod[0] == "Kw.":
                        g.agent(mod[1], env)
                        _prop(g, inner[1], env)
                        return  # adds no structure (plank ignores it as well)
                    if mod.kind == "[" and len(mod) == 1:
                        g.agent(mod[0], env)
                        type2.append(_prop(g, inner[1], env))
                        return
                    raise g.err("under [C. All] a finitary-S5 theory allows a propositional formula, [i]φ, "
                                "[Kw. i]φ or <Kw. i>φ", inner)
                type2.append(_prop(g, inner, env))
                return
            type1.append(_prop(g, node, env))

        g.items(init[1], {}, theory)
        model = finitary_s5_epddl(props, agents, type1, type2, type3, source=f"{problem}:{init.line}",
                                  deadline=deadline)
    if len(goal) != 2:
        raise g.err("(:goal formula) takes one formula", goal)
    goal_f = g.formula(goal[1], {})

    # ---- actions
    g.where = str(domain)
    ground: list = []
    for aname, kv, line in actions:
        sig = kv.get(":action-type")
        if not isinstance(sig, Node) or not sig:
            raise ParseError(f"action {aname!r} has no :action-type", source=str(domain), line=line)
        tname = str(sig[0])
        at = act_types.get(tname)
        if at is None:
            raise ParseError(f"action {aname!r} uses the unknown action type {tname!r}; pass the library that "
                             f"defines it (--library FILE)", source=str(domain), line=sig.line)
        ev_refs = list(sig[1:])
        if len(ev_refs) != len(at.events):
            raise ParseError(f"action {aname!r}: action type {tname!r} has {len(at.events)} event(s) "
                             f"({' '.join(at.events)}), {len(ev_refs)} given", source=str(domain), line=sig.line)
        params = kv.get(":parameters") or []
        typed, _ = g.typed_list(params)
        pnames = [v for v, _ in typed]
        act = _action_grounder(g, at, ev_refs, events, kv.get(":observability-conditions"), agents, line,
                               EventAction)
        tick = g.tick
        add = ground.append
        for env in g.bindings(params, {}):
            tick(0)
            add(act("_".join([aname, *[env[v] for v in pnames]]), env))
    return Task(name=pname, props=tuple(props), agents=agents, initial=model, actions=tuple(ground),
                goal=goal_f, source=str(problem))


def _group_members(g: _Ground, node) -> list[str]:
    members: list[str] = []

    def member(n, env) -> None:
        if isinstance(n, Node) and n.kind == "(" and n.head() not in (":and", ":forall"):
            for y in n:
                g.items(y, env, member)
            return
        members.append(g.agent(n, env))
    g.items(node, {}, member)
    return members


def _requirements(g: _Ground, sec: Node) -> None:
    """Requirement names are checked (an unknown one is a typo or a construct plank does not know); what
    they imply is not enforced — plank only warns when a construct's requirement is missing."""
    for r in sec[1:]:
        if not isinstance(r, Sym) or r not in REQUIREMENTS:
            raise g.err(f"unknown requirement {r!r} (EPDDL requirements: {', '.join(sorted(REQUIREMENTS))})", r)


def _agent_groups(g: _Ground, sec: Node) -> None:
    """``(:agent-groups (Name [- type] (a1 a2 ...)) ...)``: named groups usable in modalities."""
    for item in sec[1:]:
        if not isinstance(item, Node) or len(item) not in (2, 4) or not isinstance(item[0], Sym):
            raise g.err("expected (GroupName [- type] (agent ...))", item)
        members = _group_members(g, item[-1])
        if not members:
            raise g.err(f"agent group {item[0]} is empty", item)
        g.groups[str(item[0])] = tuple(dict.fromkeys(members))


def _prop(g: _Ground, node, env) -> Formula:
    f = g.formula(node, env)
    if not _is_propositional(f):
        raise g.err("a finitary-S5 theory allows only propositional formulas here", node)
    return f


def _is_propositional(f: Formula) -> bool:
    """``delkit.logic.formula.is_propositional`` without collecting the subformulas (one walk, stops at the first
    modal or dynamic operator)."""
    todo = [f]
    while todo:
        x = todo.pop()
        t = type(x)
        if t is Prop or t is Top or t is Bot:
            continue
        if t is Not:
            todo.append(x.arg)
        elif t is And or t is Or:
            todo.extend(x.args)
        elif t is Implies or t is Iff:
            todo.append(x.left)
            todo.append(x.right)
        else:
            return False
    return True


def _explicit_init(init: Node, g: _Ground, props: list[str], agents: tuple[str, ...]):
    from delkit.models.kripke import KripkeModel
    from delkit.models.relation import Relation

    kv: dict[str, object] = {}
    i = 1
    while i < len(init):
        k = init[i]
        if not isinstance(k, Sym) or k not in (":worlds", ":relations", ":labels", ":designated"):
            raise g.err("expected :worlds, :relations, :labels or :designated", k if isinstance(k, Sym) else init)
        if i + 1 >= len(init):
            raise g.err(f"{k} without a value", k)
        kv[str(k)] = init[i + 1]
        i += 2
    for k in (":worlds", ":relations", ":labels", ":designated"):
        if k not in kv:
            raise g.err(f"an explicit initial state needs {k}", init)
    worlds = [str(w) for w in kv[":worlds"]]  # type: ignore[union-attr]
    widx = {w: j for j, w in enumerate(worlds)}
    for w in worlds:
        g.entities[w] = "world"
    g.type_parent.setdefault("world", _ENTITY)
    g._by_type.clear()

    def world(x, env) -> int:
        w = g.term(x, env)
        if w not in widx:
            raise g.err(f"unknown world {w!r}", x)
        return widx[w]

    pairs: dict[str, list[tuple[int, int]]] = {a: [] for a in agents}
    rel = kv[":relations"]
    for j in range(0, len(rel), 2):  # type: ignore[arg-type]
        a = g.agent(rel[j], {})  # type: ignore[index]
        if j + 1 >= len(rel):  # type: ignore[arg-type]
            raise g.err(f"no relation after agent {a}", rel)

        def pair(node, env, a=a):
            if not isinstance(node, Node) or len(node) != 2:
                raise g.err("expected a pair of worlds (w v)", node)
            pairs[a].append((world(node[0], env), world(node[1], env)))
        g.items(rel[j + 1], {}, pair)  # type: ignore[index]
    pidx = {p: j for j, p in enumerate(props)}
    val = np.zeros((len(worlds), len(props)), dtype=bool)
    lab = kv[":labels"]
    for j in range(0, len(lab), 2):  # type: ignore[arg-type]
        w = world(lab[j], {})  # type: ignore[index]

        def true_atom(node, env, w=w):
            f = g.atom(node, env) if isinstance(node, Node) and node.head() in g.preds else None
            if not isinstance(f, Prop):
                raise g.err("a label lists the fluents true in the world", node)
            val[w, pidx[f.name]] = True
        g.items(lab[j + 1], {}, true_atom)  # type: ignore[index]
    des = [world(x, {}) for x in kv[":designated"]]  # type: ignore[union-attr]
    if not des:
        raise g.err("no designated world", init)
    rels = {a: Relation.from_pairs(len(worlds), pairs[a]) for a in agents}
    return KripkeModel(tuple(props), agents, val, rels, tuple(des), names=tuple(worlds))


def _effects(g: _Ground, eff: Callable | None, env) -> dict[str, Formula]:
    """p ↦ p' of an event's compiled effects ``eff`` (p' = pos ∨ (p ∧ ¬neg))."""
    pos: dict[str, list[Formula]] = {}
    neg: dict[str, list[Formula]] = {}
    if eff is not None:
        eff(env, TOP, pos, neg)
    post: dict[str, Formula] = {}
    for p, cs in pos.items():   # fluents made true first, then those only made false (as dict.fromkeys)
        if len(cs) == 1 and type(cs[0]) is Top:   # an unconditional p: ⊤ ∨ … = ⊤
            post[p] = TOP
        else:
            post[p] = mk_or([mk_or(cs), mk_and([g._prop(p), mk_not(mk_or(neg.get(p, [])))])])
    for p, cs in neg.items():
        if p in post:
            continue
        if len(cs) == 1 and type(cs[0]) is Top:   # an unconditional ¬p (and no p): ⊥ ∨ (p ∧ ¬⊤) = ⊥
            post[p] = BOT
        else:
            post[p] = mk_or([BOT, mk_and([g._prop(p), mk_not(mk_or(cs))])])
    return post


def _deferred(build: Callable[..., Callable], *args) -> Callable:
    """``build(*args)``, or, if building raises a ParseError, a function raising it when called: an error of
    a construct is reported only when (and if) the construct is grounded."""
    try:
        return build(*args)
    except ParseError as exc:
        def fail(*_args, exc=exc):
            raise exc
        return fail


def _event_grounder(g: _Ground, ref, events: dict[str, _Event]) -> Callable[[dict[str, str]], tuple]:
    """The event reference ``ref`` of an action compiled: env -> (name, pre, post); an event with the same
    arguments (in this or another action) is grounded once."""
    if isinstance(ref, Sym):
        name, args = str(ref), []
    elif isinstance(ref, Node) and ref and isinstance(ref[0], Sym):
        name, args = str(ref[0]), list(ref[1:])
    else:
        raise g.err("expected an event (name args ...)", ref)
    ev = events.get(name)
    if ev is None:
        raise g.err(f"unknown event {name!r}", ref)
    typed = g.event_params.get(name)
    if typed is None:
        typed = g.event_params[name] = g.typed_list(ev.params)[0]
    if len(typed) != len(args):
        raise g.err(f"event {name!r} takes {len(typed)} argument(s), got {len(args)}", ref)
    terms = g._terms(args)
    names = [v for v, _ in typed]
    cache = g.ground_events
    pre_of = g.compile(ev.pre) if ev.pre is not None else None
    post_of = g.posts(ev.effects)

    def ground(env) -> tuple:
        vals = terms(env)
        key = (name, vals)
        got = cache.get(key)
        if got is None:
            eenv = dict(zip(names, vals, strict=True))
            pre = pre_of(eenv) if pre_of is not None else TOP
            got = cache[key] = (atom_name(name, vals), pre, post_of(eenv))
        return got
    return ground


def _type_relations(g: _Ground, at: _ActType) -> dict[str, list[tuple[int, int]]]:
    """obs type -> event index pairs of an action type (ground once per type and load)."""
    got = g.type_pairs.get(at.name)
    if got is not None:
        return got
    if at.relations is None:  # basic
        got = g.type_pairs[at.name] = {"Fully": [(0, 0)]}
        return got
    eidx = {e: j for j, e in enumerate(at.events)}
    saved = (dict(g.entities), g.where, g._by_type)   # the domains of types stay valid once restored
    g.where = at.source
    for e in at.events:
        g.entities[e] = "event"
    g.type_parent.setdefault("event", _ENTITY)
    g._by_type = {}
    got = {t: [] for t in at.obs_types}
    rel = at.relations
    for j in range(0, len(rel), 2):
        t = str(rel[j])
        if t not in got:
            raise g.err(f"relation for {t!r}, which is not an observability type of {at.name!r}", rel[j])

        def pair(node, env, t=t):
            if not isinstance(node, Node) or len(node) != 2:
                raise g.err("expected a pair of events (?e ?f)", node)
            a, b = g.term(node[0], env), g.term(node[1], env)
            if a not in eidx or b not in eidx:
                raise g.err(f"({a} {b}): not events of {at.name!r}", node)
            got[t].append((eidx[a], eidx[b]))
        g.items(rel[j + 1], {e: e for e in at.events}, pair)
    g.entities, g.where, g._by_type = saved
    g.type_pairs[at.name] = got
    return got


def _obs_spec_of(g: _Ground, node, env, at: _ActType, agents) -> dict[str, list[tuple[int, Formula]]]:
    """agent -> [(obs type index, condition)] (plank's per-agent map, first statement per type wins). One walk
    over the list constructs collects the statements (and the ``default``, whose type is checked there);
    each statement is then applied by its handler, compiled once per statement node (:func:`_obs_leaf`)."""
    if node is None:
        return {a: [(0, TOP)] for a in agents}
    default: list[int] = []
    found: list[tuple[object, dict[str, str]]] = []

    def collect(n, env) -> None:
        if isinstance(n, Node) and n.head() == "default" and len(n) > 1:
            default.append(_obs_type(g, n[1], at))
        found.append((n, dict(env)))   # the environment is only valid during the call
    g.items(node, env, collect)
    spec: dict[str, dict[int, Formula]] = {a: {} for a in agents}
    cache = g.obs_leaves
    for n, e in found:
        got = cache.get((id(n), at.name))
        if got is None:
            got = cache[(id(n), at.name)] = (n, _deferred(_obs_leaf, g, n, at))
        got[1](e, spec, default)
    for a in agents:
        if not spec[a]:
            if not default:
                raise g.err(f"no observability condition for agent {a} and no (default Type)", node)
            spec[a][default[0]] = TOP
    return {a: sorted(spec[a].items()) for a in agents}


def _obs_type(g: _Ground, x, at: _ActType) -> int:
    try:
        return at.obs_types.index(str(x))
    except ValueError:
        raise g.err(f"{x!r} is not an observability type of {at.name!r} ({', '.join(at.obs_types)})", x) from None


def _obs_type_or_error(g: _Ground, x, at: _ActType) -> int | ParseError:
    try:
        return _obs_type(g, x, at)
    except ParseError as exc:
        return exc


def _obs_leaf(g: _Ground, n, at: _ActType) -> Callable[[dict[str, str], dict, list[int]], None]:
    """One observability statement ``(agent Type)`` / ``(agent (if φ T else-if φ T ... else T))`` compiled:
    (env, spec, default) -> None. Errors of the statement are raised when it is applied, in the order the
    statement is read (agent, then each condition before its type, ...)."""
    if not isinstance(n, Node) or len(n) != 2:
        raise g.err("expected (agent Type), (agent (if ...)) or (default Type)", n)
    if n[0] == "default":
        return lambda env, spec, default: None
    who, body = n[0], n[1]
    names = at.obs_types

    def assign(spec: dict, a: str, t: int, c: Formula, where) -> None:
        got = spec[a]
        if t not in got:
            got[t] = c
        elif got[t] != c:
            raise g.err(f"agent {a}: observability type {names[t]} given twice with different conditions", where)

    if isinstance(body, Sym):
        t = _obs_type_or_error(g, body, at)

        def fixed(env, spec, default) -> None:
            a = g.agent(who, env)
            if type(t) is not int:
                raise t
            assign(spec, a, t, TOP, n)
        return fixed
    bad = None
    if not (isinstance(body, Node) and body.head() == "if"):
        bad = g.err("expected an observability type or (if φ T else-if φ T ... else T)", body)
    elif len(body) < 3:
        bad = g.err("(if φ T else-if φ T ... else T)", body)
    steps: list[tuple[Callable | None, int | ParseError]] = []   # (condition or None for else, type)
    has_else = False
    k = 0
    while bad is None and k < len(body):
        w = body[k]
        if w in ("if", "else-if") and k + 2 < len(body) and (w == "if") == (k == 0):
            steps.append((g.compile(body[k + 1]), _obs_type_or_error(g, body[k + 2], at)))
            k += 3
        elif w == "else" and k > 0 and k + 2 == len(body):
            steps.append((None, _obs_type_or_error(g, body[k + 1], at)))
            has_else = True
            k += 2
        else:
            steps.append((None, g.err(f"unexpected {w!r} in (if φ T else-if φ T ... else T)", body)))
            break

    def chain(env, spec, default) -> None:
        a = g.agent(who, env)
        if bad is not None:
            raise bad
        prev: list[Formula] = []
        for cond, t in steps:
            if cond is not None:
                c = cond(env)
                if type(t) is not int:
                    raise t
                assign(spec, a, t, mk_and([*(mk_not(p) for p in prev), c]), body)
                prev.append(c)
            else:
                if type(t) is not int:
                    raise t
                assign(spec, a, t, mk_and(mk_not(p) for p in prev), body)
        if not has_else and default:
            assign(spec, a, default[0], mk_and(mk_not(p) for p in prev), body)
    return chain


def _relation(n: int, pairs: list[tuple[int, int]]) -> list[tuple[int, ...]]:
    """A relation on n events as successor rows (ascending; :class:`~delkit.backends.compact.PlainEvents` turns an
    equivalence into a partition when a delkit EventModel is needed)."""
    succ: list[set[int]] = [set() for _ in range(n)]
    for a, b in pairs:
        succ[a].add(b)
    return [tuple(sorted(x)) for x in succ]


def _action_grounder(g: _Ground, at: _ActType, ev_refs, events, obs_node, agents, line, EventAction):
    """An action schema compiled: (ground name, env) -> EventAction. Per binding, in this order: its events
    (each grounded once per arguments), the action type's relations (once per type), the observability
    conditions (once per values of the variables they mention) — so errors come in the order of the
    constructs."""
    refs = [_deferred(_event_grounder, g, r, events) for r in ev_refs]
    obs_vars = sorted(_vars_in(obs_node)) if obs_node is not None else []
    obs_cache: dict[tuple, tuple] = {}   # values of obs_vars -> (conditions, agent -> [(relation, condition)])
    where = f"{g.where}:{line}"
    tname = at.name

    def ground(name: str, env: dict[str, str]) -> EventAction:
        evs = [r(env) for r in refs]
        rels = _type_relations(g, at)
        key = tuple([env.get(v) for v in obs_vars])
        got = obs_cache.get(key)
        if got is None:
            got = obs_cache[key] = _obs_plan(_obs_spec_of(g, obs_node, env, at, agents), agents)
        conds, plan = got
        info = g.type_info.get(tname)
        if info is None:
            slots = tuple(e.lstrip("?") for e in at.events)
            bad = [d for d in at.designated if d not in at.events]
            if bad:
                raise ParseError(f"action type {tname!r}: designated {' '.join(bad)} not among its events "
                                 f"({' '.join(at.events)})", source=at.source, line=at.line)
            des = tuple(at.events.index(d) for d in at.designated)
            type_rel = g.type_relations.get(tname)
            if type_rel is None:
                type_rel = g.type_relations[tname] = {t: _relation(len(slots), rels.get(t, []))
                                                      for t in at.obs_types}
            info = g.type_info[tname] = (slots, des, [type_rel[t] for t in at.obs_types])
        slots, des, by_type = info
        pre = tuple([e[1] for e in evs])
        post = tuple([e[2] for e in evs])

        def build(bits: tuple[bool, ...]) -> PlainEvents:
            relations = {}
            for a in agents:
                t = 0
                for tt, ci in plan[a]:
                    if ci is None or bits[ci]:
                        t = tt
                relations[a] = by_type[t]
            return PlainEvents(slots, agents, pre, post, relations, des, name)

        return EventAction(name=name, build=build, conditions=conds, where=where, kind=tname,
                           designated_pre=tuple([pre[d] for d in des]),
                           event_labels=tuple([f"{e[0]} (the action type's ?{slot})"
                                               for e, slot in zip(evs, slots, strict=True)]))
    return ground


def _obs_plan(obs: dict[str, list[tuple[int, Formula]]], agents) -> tuple[tuple[Formula, ...], dict]:
    """(conditions, agent -> [(obs type index, index of its condition or None for ⊤)]) of an observability
    spec: each distinct condition once, in order of first use; a ⊥ condition never applies."""
    conds: list[Formula] = []
    cidx: dict[Formula, int] = {}
    plan: dict[str, list[tuple[int, int | None]]] = {}
    for a in agents:
        plan[a] = []
        for t, c in obs[a]:
            if c == TOP:
                plan[a].append((t, None))
            elif c != BOT:
                if c not in cidx:
                    cidx[c] = len(conds)
                    conds.append(c)
                plan[a].append((t, cidx[c]))
    return tuple(conds), plan


def load_epddl2026(domain: str | Path, problem: str | Path, libraries: list[str | Path] = (), *,
                   deadline: float | None = None):
    """Read an EPDDL (2026) run; ``deadline`` is a ``time.monotonic()`` instant (:class:`LoadTimeout`)."""
    given = (domain, problem, *libraries)
    paths = [_path(p) for p in given]
    for raw, p in zip(given, paths, strict=True):
        if not p.exists():
            raise ParseError("no such file", source=str(raw))
    return parse_epddl2026(paths[0], paths[1], paths[2:], deadline=deadline)


def _path(p: str | Path) -> Path:
    return p if isinstance(p, Path) else Path(p)   # a Path re-made from a Path re-parses every part
