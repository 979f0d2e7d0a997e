"""Symbolic (BDD) backend: knowledge structures and knowledge transformers (S5), with ``dd.cudd``.

A *knowledge structure* (van Benthem, van Eijck, Gattinger, Su, *Symbolic model checking for Dynamic
Epistemic Logic*, LORI 2015; Gattinger, PhD thesis 2018, Ch. 2) is ``F = (V, θ, O_1 … O_n)``: a
vocabulary V, a state law θ (a BDD over V) and, per agent, the observed variables O_i ⊆ V. The states
are the assignments s ⊆ V satisfying θ; agent i cannot tell s and t apart iff they agree on O_i. A
*scenario* adds a set of actual states (here the BDD ``actual``, so structures are multi-pointed like
:class:`~delkit.models.kripke.KripkeModel`).

Truth sets ``||φ||_F`` are BDDs over V:

* ``||K_i φ||   = ∀(V∖O_i)(θ → ||φ||)``                      (Def. 2.2.2 of the thesis)
* ``||D_G φ||   = ∀(V∖⋃_{i∈G}O_i)(θ → ||φ||)``
* ``||C_G φ||   = gfp X. ⋀_{i∈G} ∀(V∖O_i)(θ → (||φ|| ∧ X))``   (one or more steps, as in the explicit engine)
* ``||[!φ]ψ||   = ||φ||_F → ||ψ||_{F|φ}`` with ``F|φ = (V, θ ∧ ||φ||_F, O)``
* ``||[E,e]ψ||``  through the transformer translation of the (S5) event model E (below).

A *knowledge transformer with factual change* ``X = (V⁺, θ⁺, V₋, θ₋, O⁺)`` has fresh event variables V⁺,
an event law θ⁺ over V ∪ V⁺, changed variables V₋ ⊆ V with post-conditions θ₋(q) over V ∪ V⁺ and
observed event variables O⁺_i ⊆ V⁺. The product ``F × X`` (Gattinger 2018, Def. 2.8.x; SMCDEL's
``Transformer`` update) keeps the old values of V₋ in fresh copies V₋°:

    V^× = V ∪ V⁺ ∪ V₋°
    θ^× = [V₋ ↦ V₋°](θ ∧ ||θ⁺||_F) ∧ ⋀_{q∈V₋} (q ↔ [V₋ ↦ V₋°] ||θ₋(q)||_F)
    O_i^× = [V₋ ↦ V₋°] O_i ∪ O⁺_i

so agent i still observes the *old* values of the variables it observed, exactly as in the explicit
product update ((w,e) R_i (v,f) iff w R_i v and e Q_i f).

Translations: :func:`from_kripke` encodes an S5 Kripke model (vocabulary = its propositions plus, per
agent, binary *label bits* of its partition class, observed by that agent; θ = the disjunction of the
worlds' full assignments), :meth:`KnowledgeStructure.to_kripke` enumerates states back into a model,
:func:`transformer_from_event_model` encodes an S5 event model the same way.
"""

from __future__ import annotations

import itertools
import operator
import time
from collections.abc import Callable, Iterable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from delkit.errors import ModelError, UnknownSymbolError
from delkit.logic.formula import (
    BOT,
    TOP,
    And,
    Announce,
    Bot,
    C,
    D,
    E,
    Formula,
    Iff,
    Implies,
    K,
    Kw,
    Not,
    Or,
    Prop,
    Top,
    Update,
    conj,
    disj,
    parse,
)
from delkit.models.kripke import KripkeModel
from delkit.models.relation import Relation

__all__ = ["KnowledgeStructure", "Transformer", "from_kripke", "transformer_from_event_model", "new_manager",
           "prepare", "declare", "form_of", "puzzle_memory",
           "event_model_from_transformer",
           "muddy_symbolic", "muddy_manager", "SymbolicMuddyResult"]

_FRESH = itertools.count()


def new_manager(*, reordering: bool = False, memory_estimate: int | None = None) -> Any:
    """A fresh ``dd.cudd.BDD`` manager. Dynamic reordering is off by default: variables keep the order in
    which they are declared (the vocabulary order; a transformer's copy q' of a changed variable q is placed
    right below q, since the product's law relates the two), which keeps runs deterministic and, on the
    puzzles, was several times faster than CUDD's sifting (muddy children N = 80, with one quantification
    per child and round: 1.4 s vs 12 s).

    ``memory_estimate`` (bytes; default 80 MiB) is CUDD's estimate of the memory the problem will use, for
    callers that know their problem's size (the puzzles, :func:`puzzle_memory`). It sets two things only,
    since the cache limit and the fast-growth bound are set here afterwards: the threshold past which CUDD
    collects garbage eagerly (90 % of it: a problem that outgrows it runs slower — muddy children N = 100
    with one quantification per child and round: up to 1.6x with 16–40 MiB), and the size of a "death row" (for delayed dereferencing, which dd never
    uses) of 2^⌊log2(estimate / 640)⌋ pointers that CUDD zeroes at creation — page faults that were most
    of a small puzzle (80 MiB: 512 KiB, 128 pages, 0.2–0.3 ms; 2 MiB: 16 KiB). It is no limit.

    The computed table starts at 2^11 entries (32 B each): CUDD doubles it while its hit rate is high and
    the unique table is large enough (up to 4 entries per unique-table slot), so a large problem gets
    the large table it had before, and a small one does not fault in 512 KiB it never fills (dd's
    default is 2^18, the previous setting here 2^14).

    The unique table grows fast (doubling, collecting garbage rarely) only up to 50,000 slots; beyond that
    CUDD collects dead nodes before it grows the table. Dead nodes pile up quickly in the puzzles (every
    round's intermediate conjunctions die), and a table of mostly dead nodes spoils the CPU caches: muddy
    children N = 100 with one quantification per child and round peaked at 496 k nodes in a 178 k-slot
    table, 229 k nodes in 71 k slots with the bound."""
    import dd.cudd

    estimate = _MEMORY_ESTIMATE if memory_estimate is None else int(memory_estimate)
    estimate = min(max(estimate, _MIN_ESTIMATE), _MAX_ESTIMATE)
    mgr = dd.cudd.BDD(memory_estimate=estimate, initial_cache_size=_INITIAL_CACHE)
    mgr.configure(reordering=reordering, loose_up_to=_LOOSE_UP_TO)
    return mgr


def puzzle_memory(nodes: float) -> int:
    """A memory estimate for :func:`new_manager` from the number of BDD nodes a problem is expected to
    reach (live and dead, 32 bytes each in CUDD, with room for the unique and computed tables): four times
    the nodes' bytes, at least 2 MiB."""
    return max(_MIN_ESTIMATE, int(128 * nodes))


_INITIAL_CACHE = 1 << 11  # computed-table entries at start; CUDD grows the table while its hit rate is high
_MEMORY_ESTIMATE = 80 * (1 << 20) - 1  # the default: muddy children N = 200 (≈ 60 MiB) clear of eager GC
_MIN_ESTIMATE = 2 * (1 << 20) - 1
_MAX_ESTIMATE = 1 << 30  # dd's default; dd refuses estimates above the machine's memory
_LOOSE_UP_TO = 50_000  # unique-table slots

_PREPARED: list[bool] = []


def prepare() -> None:
    """Load the BDD library and settle the interpreter before a timed region (imports excluded).

    Imports ``dd.cudd`` (with networkx, ~0.1 s: it was inside the CLI's timer) and runs one full garbage
    collection the first time only: until CPython's collector has done a full pass it has no count of the
    long-lived objects, and its first automatic full pass — over every object the imports made, 10–25 ms —
    lands in whatever runs next (SMCDEL's dining cryptographers at n = 40: 35 ms instead of 14 ms)."""
    if _PREPARED:
        return
    import gc

    import dd.cudd  # noqa: F401

    gc.collect()
    _PREPARED.append(True)


def declare(mgr: Any, names: Sequence[str]) -> None:
    """Declare ``names`` (new ones, in this order, after the manager's existing variables).

    CUDD grows its variable arrays by 10 entries per new variable index, copying them each time (quadratic:
    SMCDEL's dining cryptographers at n = 80 declare 3,241 variables, 16–57 ms); declaring the last index
    first creates every subtable in one resize, and the others then take their indices in order, so the
    levels are still the declaration order."""
    new = [v for v in dict.fromkeys(names) if v not in mgr.vars]
    if not new:
        return
    base = len(mgr.vars)
    mgr.add_var(new[-1], base + len(new) - 1)
    add = mgr.add_var
    for j, v in enumerate(new[:-1], base):
        add(v, j)


def _fresh(prefix: str, taken: set[str]) -> str:
    while True:
        name = f"{prefix}{next(_FRESH)}"
        if name not in taken:
            return name


def _and_exists(u: Any, v: Any, qvars: set[str]) -> Any:
    """∃qvars (u ∧ v) in one CUDD pass (``Cudd_bddAndAbstract``)."""
    import dd.cudd

    return dd.cudd.and_exists(u, v, qvars)


def _bits_needed(k: int) -> int:
    return max(0, int(k - 1).bit_length())


def _label_bits(rel: Relation, prefix: str, taken: set[str]) -> tuple[tuple[str, ...], np.ndarray]:
    """Fresh names for the ⌈log2 k⌉ binary digits of a partition's class labels, and the points × bits
    matrix of those digits (``taken`` is extended with the new names)."""
    lab = rel.as_partition().labels
    if lab.size:  # labels need not be 0..k-1 (restricted relations keep theirs): renumber for ⌈log2 k⌉ bits
        lab = np.unique(lab, return_inverse=True)[1].ravel()
    width = _bits_needed(int(lab.max(initial=0)) + 1)
    names = tuple(_fresh(prefix, taken) for _ in range(width))
    taken |= set(names)
    return names, ((lab[:, None] >> np.arange(width)[None, :]) & 1).astype(bool)


@dataclass(frozen=True, eq=False)
class Transformer:
    """A knowledge transformer with factual change ``(V⁺, θ⁺, V₋, θ₋, O⁺)`` and designated events.

    ``law`` θ⁺ and the ``changes`` θ₋(q) are formulas over V ∪ V⁺ (epistemic parts only over V);
    ``designated`` is a propositional formula over V⁺ selecting the actual events.
    """

    vocabulary: tuple[str, ...]
    law: Formula
    changes: Mapping[str, Formula]
    observed: Mapping[str, tuple[str, ...]]
    designated: Formula = TOP


@dataclass(frozen=True, eq=False)
class KnowledgeStructure:
    """``F = (V, θ, O)`` plus the BDD ``actual`` of actual states (default: all states).

    Build with :meth:`create` or :func:`from_kripke`. Immutable; operations return new structures that
    share the BDD manager ``bdd``.
    """

    bdd: Any
    vocabulary: tuple[str, ...]
    law: Any
    observed: Mapping[str, tuple[str, ...]]
    actual: Any
    _cache: dict = field(default_factory=dict, repr=False, compare=False)
    _hidden: dict = field(default_factory=dict, repr=False, compare=False)  # agents ↦ V ∖ ⋃O, see _unobserved
    # The truth sets computed on the structure this one was announced from, kept alive (one generation
    # only): the next round's BDDs share most of their nodes, and while those nodes are referenced CUDD
    # keeps its computed-table entries for them instead of garbage-collecting and rebuilding them (muddy
    # children N = 100: 2.2x faster).
    _previous: Any = field(default=None, repr=False, compare=False)
    # Truth sets of propositional formulas do not depend on θ: one cache for all structures derived
    # from this one (announcements, products), which share the manager.
    _props: dict = field(default_factory=dict, repr=False, compare=False)

    # ------------------------------------------------------------------ construction
    @staticmethod
    def create(vocabulary: Iterable[str], law: Formula | str = TOP,
               observed: Mapping[str, Iterable[str]] | None = None, actual: Formula | str | None = None,
               *, bdd: Any = None) -> KnowledgeStructure:
        """Structure from a vocabulary, a propositional state law and observed variables per agent."""
        voc = tuple(dict.fromkeys(vocabulary))
        obs = {a: tuple(v) for a, v in (observed or {}).items()}
        for a, vs in obs.items():
            bad = sorted(set(vs) - set(voc))
            if bad:
                raise UnknownSymbolError(f"agent {a!r} observes {bad}, not in the vocabulary {list(voc)}")
        mgr = bdd if bdd is not None else new_manager()
        if voc:
            declare(mgr, voc)
        bare = KnowledgeStructure(mgr, voc, mgr.true, obs, mgr.true)
        law_node = bare._propositional(law)
        act = law_node if actual is None else law_node & bare._propositional(actual)
        return KnowledgeStructure(mgr, voc, law_node, obs, act, _props=bare._props)

    def _propositional(self, f: Formula | str) -> Any:
        return self.evaluate(parse(f) if isinstance(f, str) else f)

    # ------------------------------------------------------------------ views
    @property
    def agents(self) -> tuple[str, ...]:
        return tuple(self.observed)

    def count_states(self) -> int:
        """Number of states (assignments of V satisfying θ)."""
        return int(self.bdd.count(self.law, nvars=len(self.vocabulary))) if self.vocabulary else \
            int(self.law == self.bdd.true)

    def states(self, node: Any = None) -> list[dict[str, bool]]:
        """All states (or all assignments in ``node`` ∧ θ) as dicts var ↦ bool, in a deterministic order."""
        u = self.law if node is None else node & self.law
        out = [dict(s) for s in self.bdd.pick_iter(u, care_vars=set(self.vocabulary))]
        out.sort(key=lambda s: tuple(s[v] for v in self.vocabulary))
        return out

    def _repr_html_(self) -> str:
        """Inline picture in Jupyter: vocabulary, law, observations/relations and the Kripke model if small."""
        from delkit.drawing.draw import picture

        return picture(self).html()

    def node_size(self) -> int:
        """Number of BDD nodes of the state law."""
        return len(self.law)

    # ------------------------------------------------------------------ truth
    def evaluate(self, formula: Formula | str) -> Any:
        """``||φ||_F``: the BDD of the assignments where φ holds (meaningful on states, i.e. under θ)."""
        cache = self._cache
        hit = cache.get(formula)
        if hit is not None:
            return hit
        kind = type(formula)
        if kind is Not and type(formula.arg) is not Iff:
            return ~self.evaluate(formula.arg)  # negation is free on BDDs (a complemented edge): not cached
        if kind is Kw:  # the per-agent question of epistemic puzzles, asked anew of every announced structure
            lit = self._hidden.get(formula)
            if lit:  # Kw_a x, x hidden from a, decided once per formula (_ev_knows_whether)
                hit = cache[formula] = self._knows_whether_literal(formula.agent, *lit)
                return hit
        return self._compute(formula, kind)

    def _compute(self, formula: Formula | str, kind: type) -> Any:
        """A cache miss of :meth:`evaluate`: the structure-independent cache of propositional truth sets,
        then the rule of the formula's kind."""
        if kind is str:
            return self.evaluate(parse(formula))
        if kind is And:
            flips = self._flip_variables(formula)
            if flips:  # ⋀ ¬Kw_a x_a, each x_a the one variable a does not observe: one pass (_all_flips)
                hit = self._cache[formula] = self._all_flips(flips)
                return hit
        if kind is Prop or kind in _BOOLEAN:
            hit = self._props.get(formula.name if kind is Prop else formula)
            if hit is None:
                hit = _boolean(self, formula)
        else:
            rule = _DISPATCH.get(kind)
            if rule is None:
                raise TypeError(f"cannot evaluate {formula!r}")
            hit = rule(self, formula)
        self._cache[formula] = hit
        return hit

    def holds(self, formula: Formula | str) -> bool:
        """True iff φ holds at every actual state."""
        return (self.actual & ~self.evaluate(formula)) == self.bdd.false

    def truth(self, formula: Formula | str, state: Mapping[str, bool]) -> bool:
        """Truth of φ at one state (a full assignment of the vocabulary)."""
        return self.bdd.let({v: bool(state[v]) for v in self.vocabulary}, self.evaluate(formula)) == self.bdd.true

    def valid(self, formula: Formula | str) -> bool:
        """True iff φ holds at every state of F."""
        return (self.law & ~self.evaluate(formula)) == self.bdd.false

    def _unobserved(self, agents: Iterable[str]) -> frozenset[str]:
        """V ∖ ⋃_{a∈agents} O_a (cached on the vocabulary and observations, shared by announcements)."""
        key = agents if isinstance(agents, tuple) else tuple(agents)
        hidden = self._hidden
        try:
            return hidden[key]
        except KeyError:
            pass
        seen: set[str] = set()
        for a in key:
            if a not in self.observed:
                raise UnknownSymbolError(f"unknown agent {a!r}; the structure has {list(self.observed)}")
            seen.update(self.observed[a])
        out = hidden[key] = frozenset(self.vocabulary).difference(seen)
        return out

    def _box(self, agents: tuple[str, ...], u: Any) -> Any:
        """∀(V ∖ ⋃O)(θ → u)."""
        hidden = self._unobserved(agents)
        if not hidden:
            return ~self.law | u
        # ∀x(¬θ ∨ u) = ¬∃x(θ ∧ ¬u); the cube of x is built once per agent set (dd's and_exists rebuilds
        # it from names on every call, a loop over all variables: SMCDEL's dining cryptographers have 3,241)
        return ~self.bdd.apply("\\E", self._cube(hidden), self.law & ~u)

    def _cube(self, hidden: frozenset[str]) -> Any:
        key = ("__cube", hidden)
        cube = self._hidden.get(key)
        if cube is None:
            cube = self._hidden[key] = self.bdd.cube(hidden)
        return cube

    def _knows_whether(self, agent: str, u: Any) -> Any:
        """``||Kw_a φ|| = ||K_a φ|| ∨ ||K_a ¬φ||`` for ``u = ||φ||``."""
        lit = self._hidden_literal(agent, u)
        if lit:
            return self._knows_whether_literal(agent, *lit)
        hidden = self._unobserved((agent,))
        if not hidden:
            return self.bdd.true
        b, cube, law = self.bdd, self._cube(hidden), self.law
        return ~(b.apply("\\E", cube, law & ~u) & b.apply("\\E", cube, law & u))

    def _hidden_literal(self, agent: str, u: Any) -> tuple:
        """``(node, rest)`` when ``u`` is a literal of a variable x the agent does not observe: x's BDD node and
        the other unobserved variables ``rest`` (None if there are none); ``()`` otherwise."""
        hidden = self._unobserved((agent,))
        x = u.var
        if x is None or x not in hidden:
            return ()
        node = self.bdd.var(x)
        if u != node and u != ~node:
            return ()
        return node, (hidden - {x}) or None

    def _knows_whether_literal(self, agent: str, node: Any, rest: frozenset[str] | None) -> Any:
        """``Kw_a x`` for a variable x hidden from a: ``K_a x ∨ K_a ¬x = ¬(∃H'θ[x:=0] ∧ ∃H'θ[x:=1]) = ¬∀x ∃H'θ``
        with H' = ``rest`` (the other hidden variables): one quantification instead of two and-abstracts and a
        disjunction; ∃H'θ is cached per (agent, x) on this structure."""
        if rest is None:
            base = self.law
        else:
            key = ("__proj", agent, node)
            base = self._cache.get(key)
            if base is None:
                base = self._cache[key] = self.bdd.apply("\\E", self._cube(rest), self.law)
        return ~self.bdd.apply("\\A", node, base)  # the one-variable cube is the variable's node

    def _flip_variables(self, f: And) -> frozenset[str] | None:
        """The variables x_a when ``f`` is ``⋀_a ¬Kw_a x_a`` ("nobody knows") and every x_a is the only variable
        agent a does not observe (V ∖ O_a = {x_a}); None otherwise. Decided once per formula object and kept with
        the observations (shared by announcements)."""
        key = ("__flips", f)
        shared = self._hidden
        try:
            return shared[key]
        except KeyError:
            pass
        found: set[str] | None = set()
        for g in f.args:
            if type(g) is not Not or type(g.arg) is not Kw or type(g.arg.arg) is not Prop:
                found = None
                break
            a, x = g.arg.agent, g.arg.arg.name
            if a not in self.observed or self._unobserved((a,)) != {x}:
                found = None
                break
            found.add(x)
        out = shared[key] = frozenset(found) if found else None
        return out

    def _all_flips(self, flips: frozenset[str]) -> Any:
        """``θ ∧ ⋀_{x∈flips} ∀x θ``: the states that stay states when any one variable of ``flips`` is flipped —
        ``||⋀_a ¬Kw_a x_a||`` on the states when V ∖ O_a = {x_a} (``¬Kw_a x = ∀x θ``: a considers both values
        of x possible).

        One bottom-up pass over θ's diagram instead of one quantification per variable and a conjunction of
        their results: with G(u) = ⋀_{x∈flips} ∀x u and u = (y ? h : l),

            G(u) = y ? (G(h) ∧ l) : (G(l) ∧ h)   if y ∈ flips   (∀y u = h ∧ l, and G(h) ⊆ h)
            G(u) = y ? G(h) : G(l)                otherwise

        (variables u does not depend on give ∀x u = u). G depends on the node only, so the memo is kept for
        all structures announced from this one: each round of an announcement sequence (muddy children)
        visits only the nodes the last announcement made."""
        b = self.bdd
        memo = self._hidden.get(("__flipmemo", flips))
        if memo is None:
            memo = self._hidden[("__flipmemo", flips)] = {int(b.true): (b.true, None), int(b.false): (b.false, None)}
        var = b.var
        stack = [self.law]
        while stack:
            u = stack[-1]
            key = int(u)
            if key in memo:
                stack.pop()
                continue
            lo, hi = u.low, u.high
            if u.negated:
                lo, hi = ~lo, ~hi
            gl, gh = memo.get(int(lo)), memo.get(int(hi))
            if gl is None or gh is None:
                if gl is None:
                    stack.append(lo)
                if gh is None:
                    stack.append(hi)
                continue
            stack.pop()
            y = u.var
            if y in flips:
                r = b.ite(var(y), gh[0] & lo, gl[0] & hi)
            else:
                r = b.ite(var(y), gh[0], gl[0])
            memo[key] = (r, u)  # u kept referenced: its node (and so the key) cannot be reused for another
        return memo[int(self.law)][0]

    def _common(self, group: tuple[str, ...], u: Any) -> Any:
        """gfp X. θ ∧ ⋀_{a∈G} ∀(V∖O_a)(θ → u ∧ X), iterated from X = θ.

        The iterates are kept inside the states (∧ θ): outside θ the boxes are unconstrained and their
        BDDs can grow exponentially (dining cryptographers, 18 agents: 7.4 s without, 0.02 s with)."""
        return _common_fixpoint(self, group, u)

    # ------------------------------------------------------------------ updates
    def announce(self, formula: Formula | str) -> KnowledgeStructure:
        """Public announcement ``F|φ = (V, θ ∧ ||φ||_F, O)``; actual states outside φ drop out."""
        u = self.evaluate(formula)
        return KnowledgeStructure(self.bdd, self.vocabulary, self.law & u, self.observed, self.actual & u,
                                  _hidden=self._hidden, _previous=self._cache, _props=self._props)

    def transform(self, x: Transformer) -> KnowledgeStructure:
        """``F × X`` (module docstring); actual states: old actual ones paired with designated events."""
        new, _ = self._product(x)
        return new

    def _product(self, x: Transformer) -> tuple[KnowledgeStructure, dict[str, str]]:
        b = self.bdd
        clash = sorted(set(x.vocabulary) & set(self.vocabulary))
        if clash:
            raise ModelError(f"transformer variables {clash} are already in the vocabulary; use fresh names")
        missing = [a for a in self.observed if a not in x.observed]
        if missing:
            raise ModelError(f"transformer gives no observed event variables for agent(s) {missing} "
                             "(use an empty tuple for an agent who observes no event variable)")
        unknown = sorted(set(x.changes) - set(self.vocabulary))
        if unknown:
            raise UnknownSymbolError(f"transformer changes {unknown}, not in the vocabulary {list(self.vocabulary)}")
        if x.vocabulary:
            declare(b, x.vocabulary)
        taken = set(b.vars)
        copies = {q: _fresh(f"{q}'", taken) for q in x.changes}
        for q, c in copies.items():  # the old value's copy right below q: the law relates q and q' (q ↔ post(q'))
            b.insert_var(c, b.level_of_var(q) + 1)
        to_copy = {q: b.var(c) for q, c in copies.items()}

        def shift(u: Any) -> Any:
            return b.let(to_copy, u) if to_copy else u

        law = shift(self.law & self.evaluate(x.law))
        for q, post in x.changes.items():
            law = law & b.apply("<=>", b.var(q), shift(self.evaluate(post)))
        actual = shift(self.actual) & self.evaluate(x.designated) & law
        observed = {a: tuple(copies.get(v, v) for v in vs) + tuple(x.observed[a]) for a, vs in self.observed.items()}
        voc = self.vocabulary + tuple(x.vocabulary) + tuple(copies.values())
        return KnowledgeStructure(b, voc, law, observed, actual, _props=self._props), copies

    def _eval_update(self, f: Update) -> Any:
        """||[E,e]ψ|| = ||pre(e)|| → ψ^×[V⁺ := code(e), V₋° := V₋, q := ||post_e(q)||] (simultaneously)."""
        b = self.bdd
        x, codes = transformer_from_event_model(f.model, self)
        new, copies = self._product(x)
        psi = new.evaluate(f.arg)
        event = f.event
        pre = self.evaluate(f.model.pre[event])
        subst: dict[str, Any] = {v: b.true if val else b.false for v, val in codes[event].items()}
        for q, c in copies.items():
            subst[c] = b.var(q)
            subst[q] = self.evaluate(f.model.post[event].get(q, Prop(q)))
        return ~pre | b.let(subst, psi)

    # ------------------------------------------------------------------ toolbox (SMCDEL's optimize, formOf)
    def form_of(self, node: Any = None) -> Formula:
        """A formula over the vocabulary whose truth set is ``node`` (default: the state law), see
        :func:`form_of`; SMCDEL's ``formOf``."""
        return form_of(self.bdd, self.law if node is None else node)

    def generated(self) -> KnowledgeStructure:
        """The substructure generated by the actual states: θ' = the states reachable from them along
        the agents' indistinguishability (least fixpoint of X ∨ ⋁_a (θ ∧ ∃(V∖O_a) X)). Bisimilar to this
        structure at every actual state (a generated submodel)."""
        x = self.actual & self.law
        while True:
            nxt = x
            for a in self.observed:
                hidden = self._unobserved((a,))
                if hidden:
                    nxt = nxt | (self.law & self.bdd.apply("\\E", self._cube(hidden), x))
            if nxt == x:
                break
            x = nxt
        return KnowledgeStructure(self.bdd, self.vocabulary, x, self.observed, self.actual & x)

    def minimise(self, keep: Iterable[str] = ()) -> KnowledgeStructure:
        """SMCDEL's ``optimize``: drop the variables outside ``keep`` that θ determines (θ ⊨ p or θ ⊨ ¬p:
        p is replaced by its constant) or makes equivalent to another variable (θ ⊨ p ↔ q or p ↔ ¬q: p
        is replaced by that literal, and an agent observing p observes q instead — on the states they are
        the same observation). The result has the same states up to the dropped variables and is
        bisimilar to this structure (state by state, through the dropped variables' values)."""
        b = self.bdd
        voc = list(self.vocabulary)
        observed = {a: list(v) for a, v in self.observed.items()}

        def drop(p: str, found: tuple[Any, str | None, bool]) -> None:
            sub = found[0]
            for vs in observed.values():
                if p in vs:
                    vs.remove(p)
                    if sub.var is not None and sub.var not in vs:  # p ↔ ±q: observing p = observing q
                        vs.append(sub.var)

        law, actual = _drop_redundant(b, self.law, self.actual, voc, keep, drop)
        return KnowledgeStructure(b, tuple(voc), law, {a: tuple(v) for a, v in observed.items()}, actual)

    # ------------------------------------------------------------------ translation back
    def to_kripke(self, props: Sequence[str] | None = None) -> KripkeModel:
        """The explicit S5 model: one world per state; i relates states agreeing on O_i.

        ``props`` picks the valuation columns (default: the whole vocabulary; worlds stay one per state).
        """
        states = self.states()
        voc = self.vocabulary
        full = np.array([[s[v] for v in voc] for s in states], dtype=bool).reshape(len(states), len(voc))
        col = {v: j for j, v in enumerate(voc)}
        rels = {}
        for a, obs in self.observed.items():
            cols = full[:, [col[v] for v in obs]]
            _, lab = np.unique(cols, axis=0, return_inverse=True) if cols.shape[1] else (None, np.zeros(len(states)))
            rels[a] = Relation.from_labels(np.asarray(lab).ravel())
        keep = tuple(voc if props is None else props)
        val = full[:, [col[p] for p in keep]]
        actual_states = self.states(self.actual)
        index = {tuple(s[v] for v in voc): i for i, s in enumerate(states)}
        des = tuple(index[tuple(s[v] for v in voc)] for s in actual_states)
        return KripkeModel(keep, self.agents, val, rels, des)


def _fold_bdds(parts: list[Any], op: Any) -> Any:
    if len(parts) <= 2:  # no order to choose (reading a node's level is a Python-level call per node)
        return parts[0] if len(parts) == 1 else op(parts[0], parts[1])
    parts.sort(key=_level, reverse=True)
    out = parts[0]
    for u in parts[1:]:
        out = op(out, u)
    return out


_level = operator.attrgetter("level")


def _is_literal(f: Formula) -> bool:
    return type(f) is Prop or (type(f) is Not and type(f.arg) is Prop)


def _ev_knows(ks: KnowledgeStructure, f: K) -> Any:
    """``||K_a φ||``; a conjunction of literals is split, ``K_a(ℓ1 ∧ … ∧ ℓn) = K_a ℓ1 ∧ … ∧ K_a ℓn``, so that
    the few distinct ``K_a ℓ`` are computed once and shared (Sum and Product's ``⋁_{(x,y)} K_a(x ∧ y)``:
    2352 conjunctions of 14 literals, 28 distinct literals)."""
    arg = f.arg
    if type(arg) is And and len(arg.args) > 1 and all(_is_literal(a) for a in arg.args):
        cache, agent, parts = ks._cache, f.agent, []
        for lit in arg.args:
            key = ("__K", agent, lit)
            u = cache.get(key)
            if u is None:
                u = cache[key] = ks._box((agent,), ks.evaluate(lit))
            parts.append(u)
        return _fold_bdds(parts, operator.and_)
    return ks._box((f.agent,), ks.evaluate(arg))


def _ev_knows_whether(ks: KnowledgeStructure, f: Kw) -> Any:
    """``||Kw_a φ||``. Whether ``||φ||`` is a literal of a variable hidden from a is decided once per formula
    with a propositional φ and kept with the observations (shared by all announcements): each further
    round then costs one quantification and no Python-level inspection of the BDD."""
    shared = ks._hidden
    lit = shared.get(f)
    if lit is None:
        lit = ks._hidden_literal(f.agent, ks.evaluate(f.arg))
        if _in_props(f.arg, ks._props):
            shared[f] = lit
    if lit:
        return ks._knows_whether_literal(f.agent, *lit)
    return ks._knows_whether(f.agent, ks.evaluate(f.arg))


def _ev_every(ks: KnowledgeStructure, f: E) -> Any:
    u = ks.evaluate(f.arg)
    out = ks.bdd.true
    for a in f.group:
        out = out & ks._box((a,), u)
    return out


def _drop_redundant(b: Any, law: Any, actual: Any, voc: list[str], keep: Iterable[str],
                    drop: Callable[[str, tuple[Any, str | None, bool]], None]) -> tuple[Any, Any]:
    """SMCDEL's ``optimize`` loop, shared by knowledge and belief structures: until no variable outside ``keep``
    is redundant (:func:`_redundant_variable`), each redundant ``p`` is replaced by its substitute in the law and
    the actual states and removed from ``voc`` (in place), and ``drop(p, found)`` updates the structure's own
    parts (observations, relations). Returns the new (law, actual)."""
    keep_set = set(keep)
    changed = True
    while changed:
        changed = False
        for p in list(voc):
            if p in keep_set:
                continue
            found = _redundant_variable(b, law, p, voc)
            if found is None:
                continue
            sub = found[0]
            law = b.let({p: sub}, law)
            actual = b.let({p: sub}, actual)
            voc.remove(p)
            drop(p, found)
            changed = True
    return law, actual


def _redundant_variable(b: Any, law: Any, p: str, voc: Sequence[str]) -> tuple[Any, str | None, bool] | None:
    """Whether the state law makes ``p`` redundant (SMCDEL's ``optimize``): (its substitute, None, False) when
    the law determines it (``b.true`` / ``b.false``), (±q, q, negated) when the law makes it equivalent to
    another variable q of ``voc`` (or to its negation), None otherwise."""
    x = b.var(p)
    if (law & ~x) == b.false:
        return b.true, None, False
    if (law & x) == b.false:
        return b.false, None, False
    for q in voc:
        if q == p:
            continue
        y = b.var(q)
        if (law & b.apply("xor", x, y)) == b.false:
            return y, q, False
        if (law & ~b.apply("xor", x, y)) == b.false:
            return ~y, q, True
    return None


def _common_fixpoint(st: Any, group: tuple[str, ...], u: Any) -> Any:
    """gfp X. law ∧ ⋀_{a∈G} □_a(u ∧ X), iterated from X = law — for any structure with ``law`` and ``_box``
    (knowledge structures here, belief structures in ``delkit.backends.symbolic_belief``)."""
    x = st.law
    while True:
        target = u & x
        nxt = st.law
        for a in group:
            nxt = nxt & st._box((a,), target)
        if nxt == x:
            return x
        x = nxt


def _ev_announce(ks: KnowledgeStructure, f: Announce) -> Any:
    """``||[!φ1]…[!φk]ψ||`` for a stack of announcements, iteratively (SMCDEL's drinking-logicians formula
    nests hundreds): ``¬||φ1|| ∨ (¬||φ2||_{F|φ1} ∨ (… ∨ ||ψ||_{F|φ1…φk}))``."""
    pres = []
    cur: Any = f
    while isinstance(cur, Announce):
        pres.append(ks.evaluate(cur.announced))
        ks = ks.announce(cur.announced)
        cur = cur.arg
    out = ks.evaluate(cur)
    for pre in reversed(pres):
        out = ~pre | out
    return out


_BOOLEAN = frozenset((Top, Bot, Not, And, Or, Implies, Iff))


def _xor_leaves(f: Not) -> list[Formula]:
    """The operands of a nest of exclusive ors ``¬(a ↔ b)`` (an n-ary XOR written with binary ones)."""
    leaves, stack = [], [f.arg.right, f.arg.left]
    while stack:
        g = stack.pop()
        if type(g) is Not and type(g.arg) is Iff:
            stack += (g.arg.right, g.arg.left)
        else:
            leaves.append(g)
    return leaves


def _boolean(ks: KnowledgeStructure, root: Formula) -> Any:
    """``||φ||`` for a formula whose top is a proposition or a Boolean connective, in one iterative pass
    over its Boolean skeleton (the evaluator's per-node dispatch, cache probes and fold set-up cost several
    microseconds of Python per node: most of a small puzzle).

    Shared subformulas are computed once (memo by identity); modal subformulas go through
    :meth:`KnowledgeStructure.evaluate` (cached per structure); propositional subformulas are looked up in
    and stored into the manager-wide propositional cache (their truth sets do not depend on θ; negations
    are not stored, ``~u`` is free). n-ary ∧/∨ fold deepest top variable first, nested ⊕ are flattened
    (XOR is associative and commutative) and folded the same way."""
    props, b, ev = ks._props, ks.bdd, ks.evaluate
    if type(root) is Prop:
        return _var(ks, root.name)
    memo: dict[int, tuple[Any, bool]] = {}  # id ↦ (truth set, propositional)
    stack = [root]
    while stack:
        f = stack[-1]
        kind = type(f)
        if kind is Not:
            kids = _xor_leaves(f) if type(f.arg) is Iff else (f.arg,)
        elif kind is And or kind is Or:
            kids = f.args
        elif kind is Implies or kind is Iff:
            kids = (f.left, f.right)
        else:  # ⊤, ⊥
            kids = ()
        parts, plain, todo = [], True, False
        for c in kids:
            kc = type(c)
            negate = False
            if kc is Not and type(c.arg) is not Iff:
                c, kc, negate = c.arg, type(c.arg), True
            if kc is Prop:
                u = props.get(c.name)
                if u is None:
                    u = _var(ks, c.name)
            elif kc not in _BOOLEAN:  # a modal subformula
                u, plain = ev(c), False
            else:
                hit = memo.get(id(c))
                if hit is None:
                    u = props.get(c) if kc is not Not else None
                    if u is None:
                        stack.append(c)
                        todo = True
                        continue
                else:
                    u, ok = hit
                    plain = plain and ok
            parts.append(~u if negate else u)
        if todo:
            continue
        stack.pop()
        if kind is Not:
            if len(parts) == 1:
                u = ~parts[0]
            else:
                parts.sort(key=_level, reverse=True)
                u = parts[0]
                for v in parts[1:]:
                    u = b.apply("xor", u, v)
        elif kind is And:
            u = _fold_bdds(parts, operator.and_) if parts else b.true
        elif kind is Or:
            u = _fold_bdds(parts, operator.or_) if parts else b.false
        elif kind is Implies:
            u = ~parts[0] | parts[1]
        elif kind is Iff:
            u = b.apply("<=>", parts[0], parts[1])
        else:
            u = b.true if kind is Top else b.false
        memo[id(f)] = (u, plain)
        if plain and kind is not Not:
            props[f] = u  # propositional: the same BDD in every structure on this manager
    return memo[id(root)][0]


def _var(ks: KnowledgeStructure, name: str) -> Any:
    """The BDD variable ``name``, kept in the propositional cache by name (a str hashes in C; fresh Prop
    objects would hash in Python)."""
    b = ks.bdd
    if name not in b.vars:
        raise UnknownSymbolError(f"unknown proposition {name!r}; the vocabulary is {list(ks.vocabulary)}")
    u = ks._props[name] = b.var(name)
    return u


def _in_props(f: Formula, props: dict) -> bool:
    """Whether the truth set of ``f`` is in the propositional cache (negations are looked up by argument,
    propositions by name)."""
    while type(f) is Not and type(f.arg) is not Iff:
        f = f.arg
    return (f.name in props) if type(f) is Prop else (f in props)


_DISPATCH: dict[type, Any] = {  # modal kinds; propositions and Boolean connectives: _boolean
    K: lambda ks, f: _ev_knows(ks, f),
    Kw: _ev_knows_whether,
    E: _ev_every,
    D: lambda ks, f: ks._box(f.group, ks.evaluate(f.arg)),
    C: lambda ks, f: ks._common(f.group, ks.evaluate(f.arg)),
    Announce: _ev_announce,
    Update: lambda ks, f: ks._eval_update(f),
}


def form_of(bdd: Any, node: Any) -> Formula:
    """A formula whose truth set is the BDD ``node`` (SMCDEL's ``formOf``), read off the diagram top-down
    with the usual simplifications: a node ``x ? h : l`` becomes ``x`` / ``¬x`` for constant children,
    ``x ∨ l``, ``¬x ∨ h``, ``x ∧ h``, ``¬x ∧ l`` when one child is constant, ``x ↔ h`` when ``l = ¬h``, and
    ``(x ∧ h) ∨ (¬x ∧ l)`` otherwise; shared sub-diagrams give shared (identical) subformulas. The size is
    the diagram's when printed as a DAG, not minimal as a DNF would be."""
    memo: dict[Any, Formula] = {}
    true, false = bdd.true, bdd.false

    def rec(u: Any) -> Formula:
        if u == true:
            return TOP
        if u == false:
            return BOT
        hit = memo.get(u)
        if hit is not None:
            return hit
        v = u.var
        lo, hi = bdd.let({v: False}, u), bdd.let({v: True}, u)
        x = Prop(v)
        if hi == true and lo == false:
            out: Formula = x
        elif hi == false and lo == true:
            out = Not(x)
        elif hi == true:
            out = disj([x, rec(lo)])
        elif lo == true:
            out = disj([Not(x), rec(hi)])
        elif hi == false:
            out = conj([Not(x), rec(lo)])
        elif lo == false:
            out = conj([x, rec(hi)])
        elif lo == ~hi:
            out = Iff(x, rec(hi))
        else:
            out = disj([conj([x, rec(hi)]), conj([Not(x), rec(lo)])])
        memo[u] = out
        return out

    return rec(node)


def from_kripke(model: KripkeModel, *, bdd: Any = None) -> tuple[KnowledgeStructure, list[dict[str, bool]]]:
    """Encode an S5 Kripke model; returns the structure and the state of each world.

    Vocabulary: the model's propositions and, per agent a, ``⌈log2 k_a⌉`` label bits ``_a<name>_<j>`` of
    its partition class, observed by a. θ = ⋁_w (valuation(w) ∧ labels(w)). Worlds with equal valuation
    and equal classes for every agent map to one state (they are bisimilar).
    """
    for a, r in model.relations.items():
        if not r.is_partition and r.as_partition().labels is None:
            raise ModelError(f"from_kripke needs an S5 model; the relation of agent {a!r} is not an equivalence "
                             "(knowledge structures are S5)")
    mgr = bdd if bdd is not None else new_manager()
    taken = set(model.props) | set(mgr.vars)
    columns = [model.valuation]
    voc = list(model.props)
    observed: dict[str, tuple[str, ...]] = {}
    for a in model.agents:
        names, bits = _label_bits(model.relations[a], f"_{a}", taken)
        voc += names
        observed[a] = names
        columns.append(bits)
    full = np.concatenate(columns, axis=1)
    declare(mgr, voc)
    states = [dict(zip(voc, (bool(x) for x in row), strict=True)) for row in full]
    cubes = [mgr.cube(s) for s in states]
    law = mgr.false
    for c in cubes:
        law = law | c
    actual = mgr.false
    for w in model.designated:
        actual = actual | cubes[w]
    return KnowledgeStructure(mgr, tuple(voc), law, observed, actual), states


def transformer_from_event_model(events, structure: KnowledgeStructure) \
        -> tuple[Transformer, list[dict[str, bool]]]:
    """Encode an S5 event model as a transformer with fresh variables; returns it and each event's code.

    V⁺: ``⌈log2 k⌉`` event bits plus per-agent label bits (observed by that agent);
    θ⁺ = ⋁_e (code(e) ∧ labels(e) ∧ pre(e)); θ₋(q) = ⋁_e (code(e) ∧ post_e(q)) for every q some event
    changes; designated = ⋁_{e designated} code(e).
    """
    for a in structure.agents:
        if a not in events.relations:
            raise ModelError(f"event model {events.name!r} has no relation for agent {a!r}")
        r = events.relations[a]
        if not r.is_partition and r.as_partition().labels is None:
            raise ModelError(f"event model {events.name!r}: the relation of {a!r} is not an equivalence; "
                             "knowledge transformers encode S5 event models only")
    taken = set(structure.bdd.vars)
    k = events.n_events
    ev_bits = tuple(_fresh("_ev", taken) for _ in range(_bits_needed(k)))
    taken |= set(ev_bits)
    codes: list[dict[str, bool]] = [{v: bool((e >> j) & 1) for j, v in enumerate(ev_bits)} for e in range(k)]
    observed: dict[str, tuple[str, ...]] = {}
    vocab = list(ev_bits)
    for a in structure.agents:
        names, bits = _label_bits(events.relations[a], f"_ev{a}", taken)
        vocab += names
        observed[a] = names
        for e in range(k):
            codes[e].update(zip(names, (bool(x) for x in bits[e]), strict=True))
    code_f = [conj(Prop(v) if val else Not(Prop(v)) for v, val in c.items()) for c in codes]
    law = disj(conj([code_f[e], events.pre[e]]) for e in range(k))
    changed = sorted(events.changed_props() & set(structure.vocabulary))
    missing = sorted(events.changed_props() - set(structure.vocabulary))
    if missing:
        raise UnknownSymbolError(f"event model {events.name!r} changes {missing}, not in the vocabulary")
    changes = {q: disj(conj([code_f[e], events.post[e].get(q, Prop(q))]) for e in range(k)) for q in changed}
    designated = disj(code_f[e] for e in events.designated)
    return Transformer(tuple(vocab), law, changes, observed, designated), codes


# ----------------------------------------------------------------------------- muddy children, symbolically


@dataclass(frozen=True)
class SymbolicMuddyResult:
    """As :class:`delkit.puzzles.muddy.MuddyResult`; ``law_nodes`` is the peak BDD size of the state law,
    ``seconds`` the CPU time (``time.process_time``) of building the structure and running the whole
    protocol (imports excluded), ``wall_seconds`` the same region on the wall clock."""

    children: int
    muddy: int
    nobody_knows_rounds: int
    muddy_know_round: int
    clean_know_round: int | None
    law_nodes: int
    seconds: float
    wall_seconds: float = 0.0

    def as_dict(self) -> dict:
        return {"puzzle": "muddy", "engine": "symbolic", "children": self.children, "muddy": self.muddy,
                "nobody_knows_rounds": self.nobody_knows_rounds, "muddy_know_round": self.muddy_know_round,
                "clean_know_round": self.clean_know_round, "law_nodes": self.law_nodes, "seconds": self.seconds,
                "wall_seconds": self.wall_seconds}


def muddy_manager(children: int) -> Any:
    """The BDD manager :func:`muddy_symbolic` creates (inside its clock) unless given one: sized to the puzzle;
    with "nobody knows" in one pass (:meth:`KnowledgeStructure._all_flips`) peak nodes grow ~N^2/2 (all
    muddy, N = 100: 6.1 k, N = 200: 20 k)."""
    return new_manager(memory_estimate=puzzle_memory(2 * children ** 2))


def muddy_symbolic(children: int, muddy: int, *, max_rounds: int | None = None, bdd: Any = None) \
        -> SymbolicMuddyResult:
    """Muddy children on a knowledge structure: V = {m_i}, θ = ⊤, O_i = V ∖ {m_i}; same protocol as
    :func:`delkit.puzzles.muddy.solve_muddy` (father's ⋁ m_i, then rounds of truthful ±Kw_i m_i).

    ``bdd``: a fresh manager made before the call (:func:`muddy_manager`), so that its creation is outside
    the timed region; by default the manager is created inside it."""
    if children < 1 or not 1 <= muddy <= children:
        raise ModelError(f"muddy children: need 1 <= muddy <= children, got children={children}, muddy={muddy}")
    from delkit.puzzles.muddy import at_least_one, run_rounds

    prepare()  # imports and the interpreter's first full garbage collection before the clock starts

    t0, w0 = time.process_time(), time.perf_counter()
    props = [f"m{i}" for i in range(children)]
    agents = [f"c{i}" for i in range(children)]
    actual = conj(Prop(p) if i < muddy else Not(Prop(p)) for i, p in enumerate(props))
    mgr = muddy_manager(children) if bdd is None else bdd
    f = KnowledgeStructure.create(props, TOP, {a: [q for q in props if q != p] for a, p in zip(agents, props,
                                                                                                strict=True)},
                                  actual=actual, bdd=mgr)
    f, nobody, muddy_round, clean_round, sizes = run_rounds(f.announce(at_least_one(children)), children, muddy,
                                                        max_rounds=max_rounds, size=KnowledgeStructure.node_size)
    return SymbolicMuddyResult(children, muddy, nobody, muddy_round, clean_round, max([f.node_size(), *sizes]),
                               time.process_time() - t0, time.perf_counter() - w0)


def event_model_from_transformer(x: Transformer, structure: KnowledgeStructure, *, name: str = "E"):
    """Translate a knowledge transformer with propositional law and post-conditions back into an event
    model (SMCDEL translates both ways): one event per assignment of the event variables V⁺ whose
    precondition ``θ⁺[V⁺ := assignment]`` holds at some state of ``structure``; post-conditions
    ``θ₋(q)[V⁺ := assignment]``; agent a cannot tell two events apart iff they agree on O⁺_a; designated:
    the events satisfying ``designated``. ``product_update(M, E')`` is then bisimilar to ``M × X``.
    """
    from delkit.logic.formula import is_propositional, substitute
    from delkit.models.events import EventModel

    for f in (x.law, x.designated, *x.changes.values()):
        if not is_propositional(f):
            raise ModelError("event_model_from_transformer needs a propositional event law and post-conditions, "
                             f"got {f}")
    events, pres, posts, codes, designated = [], [], [], [], []
    for bits in itertools.product((False, True), repeat=len(x.vocabulary)):
        sub = {v: TOP if b else BOT for v, b in zip(x.vocabulary, bits, strict=True)}
        pre = substitute(x.law, sub)
        is_designated = _closed_truth(substitute(x.designated, sub))
        if not is_designated and (structure.law & structure._propositional(pre)) == structure.bdd.false:
            continue  # no state can host this event
        code = dict(zip(x.vocabulary, bits, strict=True))
        if is_designated:
            designated.append(len(events))
        events.append("e" + "".join("1" if b else "0" for b in bits))
        pres.append(pre)
        posts.append({q: substitute(f, sub) for q, f in x.changes.items()})
        codes.append(code)
    rels = {}
    for a, obs in x.observed.items():
        labels = [tuple(c[v] for v in obs) for c in codes]
        index = {lab: i for i, lab in enumerate(dict.fromkeys(labels))}
        rels[a] = Relation.from_labels(np.array([index[lab] for lab in labels], dtype=np.int64))
    return EventModel(tuple(events), tuple(x.observed), tuple(pres), tuple(posts), rels, tuple(designated), name)


def _closed_truth(f: Formula) -> bool:
    """Truth of a formula without propositions (only ⊤, ⊥ and connectives)."""
    if isinstance(f, Top):
        return True
    if isinstance(f, Bot):
        return False
    if isinstance(f, Not):
        return not _closed_truth(f.arg)
    if isinstance(f, And):
        return all(_closed_truth(a) for a in f.args)
    if isinstance(f, Or):
        return any(_closed_truth(a) for a in f.args)
    if isinstance(f, Implies):
        return (not _closed_truth(f.left)) or _closed_truth(f.right)
    if isinstance(f, Iff):
        return _closed_truth(f.left) == _closed_truth(f.right)
    raise ModelError(f"designated events must be given over the event variables only, got {f}")
