"""Belief structures: the symbolic (BDD) backend beyond S5, for K and KD45 models.

A *belief structure* (Gattinger, PhD thesis 2018, Ch. 3 "symbolic structures for general DEL"; SMCDEL's
``SMCDEL.Symbolic.K``) is ``F = (V, θ, Ω_1 … Ω_n)``: a vocabulary V, a state law θ over V and, per agent,
a relation Ω_i given as one BDD over the doubled vocabulary V ∪ V' (V' = primed copies). The states are
the assignments satisfying θ; state s sees t for agent i iff ``Ω_i(s, t')`` and t is a state. With the
primed copy ``φ'`` of a truth set:

* ``||K_i φ|| = ∀V'(θ' ∧ Ω_i → φ')``                        (belief on KD45 structures)
* ``||D_G φ|| = ∀V'(θ' ∧ ⋀_{i∈G} Ω_i → φ')``
* ``||C_G φ|| = gfp X. θ ∧ ⋀_{i∈G} ||K_i(φ ∧ X)||``          (one or more steps, as in the explicit engine)
* ``||[!φ]ψ|| = ||φ|| → ||ψ||_{F|φ}``, ``F|φ = (V, θ ∧ ||φ||, Ω)``
* ``||[E,e]ψ||``: the product with the event model E as a *transformer* (:meth:`BeliefStructure.transform`):
  fresh event bits X, old values of changed variables V₋ kept in fresh copies V₋°,
  ``θ^× = [V₋↦V₋°](θ ∧ ⋁_e code(e) ∧ pre_e) ∧ ⋀_{q∈V₋} (q ↔ [V₋↦V₋°] ⋁_e code(e) ∧ post_e(q))`` and
  ``Ω_i^× = [V₋↦V₋°, V₋'↦V₋°'] Ω_i ∧ ⋁_{(e,f)∈Q_i} code(e) ∧ code'(f)`` — exactly the explicit product
  update ((w,e) R_i (v,f) iff w R_i v and e Q_i f).

:func:`belief_from_kripke` encodes any Kripke model (worlds with equal valuations get extra bits), and
:meth:`BeliefStructure.to_kripke` enumerates the states back into a model.
"""

from __future__ import annotations

import operator
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

# the common-knowledge fixpoint and the announcement-stack and everybody-knows rules use only ``law``,
# ``evaluate``, ``announce`` and ``_box``, which belief and knowledge structures share: one implementation serves both
from delkit.backends.symbolic import (
    _bits_needed,
    _common_fixpoint,
    _drop_redundant,
    _ev_announce,
    _ev_every,
    _fold_bdds,
    _fresh,
    new_manager,
)
from delkit.errors import ModelError, UnknownSymbolError
from delkit.logic.formula import (
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
    parse,
)
from delkit.models.kripke import KripkeModel
from delkit.models.relation import Relation

__all__ = ["BeliefStructure", "belief_from_kripke"]


@dataclass(frozen=True, eq=False)
class BeliefStructure:
    """``F = (V, θ, Ω)`` plus the BDD ``actual`` of actual states. ``primes`` maps each variable to its
    primed copy (declared next to it in the manager). Immutable; operations return new structures."""

    bdd: Any
    vocabulary: tuple[str, ...]
    primes: Mapping[str, str]
    law: Any
    relations: Mapping[str, Any]
    actual: Any
    _cache: dict = field(default_factory=dict, repr=False, compare=False)

    # ------------------------------------------------------------------ construction
    @staticmethod
    def create(vocabulary: Iterable[str], law: Formula | str, relations: Mapping[str, Formula | str],
               actual: Formula | str | None = None, *, bdd: Any = None) -> BeliefStructure:
        """Structure from propositional formulas: ``relations[a]`` is over V and the primed names ``p'``
        (e.g. ``"p' <-> p"``: agent a sees exactly the states agreeing on p)."""
        voc = tuple(dict.fromkeys(vocabulary))
        mgr = bdd if bdd is not None else new_manager()
        primes = _declare_pairs(mgr, voc)
        bare = BeliefStructure(mgr, voc, primes, mgr.true, {}, mgr.true)
        rels = {a: bare._relational(r) for a, r in relations.items()}
        law_node = bare._relational(law)
        act = law_node if actual is None else law_node & bare._relational(actual)
        return BeliefStructure(mgr, voc, primes, law_node, rels, act)

    def _relational(self, f: Formula | str) -> Any:
        f = parse(f) if isinstance(f, str) else f
        b = self.bdd
        names = set(self.vocabulary) | set(self.primes.values())
        unknown = sorted(_props(f) - names)
        if unknown:
            raise UnknownSymbolError(f"unknown proposition(s) {unknown}; the vocabulary is {list(self.vocabulary)} "
                                     "(and their primed copies)")
        return _propositional(b, f)

    # ------------------------------------------------------------------ views
    @property
    def agents(self) -> tuple[str, ...]:
        return tuple(self.relations)

    def prime(self, u: Any) -> Any:
        """``u[V ↦ V']``."""
        return self.bdd.let(dict(self.primes), u) if self.primes else u

    def states(self, node: Any = None) -> list[dict[str, bool]]:
        """All states (or those in ``node``) as dicts var ↦ bool, in a deterministic order."""
        u = self.law if node is None else node & self.law
        out = [dict(s) for s in self.bdd.pick_iter(u, care_vars=set(self.vocabulary))]
        out.sort(key=lambda s: tuple(s[v] for v in self.vocabulary))
        return out

    def _repr_html_(self) -> str:
        """Inline picture in Jupyter: vocabulary, law, observations/relations and the Kripke model if small."""
        from delkit.drawing.draw import picture

        return picture(self).html()

    def count_states(self) -> int:
        return len(self.states())

    # ------------------------------------------------------------------ truth
    def evaluate(self, formula: Formula | str) -> Any:
        """``||φ||_F`` as a BDD over V (meaningful on states)."""
        if isinstance(formula, str):
            formula = parse(formula)
        hit = self._cache.get(formula)
        if hit is None:
            rule = _DISPATCH.get(type(formula))
            if rule is None:
                raise TypeError(f"cannot evaluate {formula!r}")
            hit = self._cache[formula] = rule(self, formula)
        return hit

    def holds(self, formula: Formula | str) -> bool:
        """True iff φ holds at every actual state."""
        return (self.actual & ~self.evaluate(formula)) == self.bdd.false

    def valid(self, formula: Formula | str) -> bool:
        """True iff φ holds at every state."""
        return (self.law & ~self.evaluate(formula)) == self.bdd.false

    def truth(self, formula: Formula | str, state: Mapping[str, bool]) -> bool:
        """Truth of φ at one state (a full assignment of the vocabulary)."""
        return self.bdd.let({v: bool(state[v]) for v in self.vocabulary}, self.evaluate(formula)) == self.bdd.true

    def _seen(self, agents: tuple[str, ...]) -> Any:
        """θ' ∧ ⋀ Ω_a: the (primed) states the group considers possible together (cached)."""
        key = ("__seen", agents)
        hit = self._cache.get(key)
        if hit is None:
            for a in agents:
                if a not in self.relations:
                    raise UnknownSymbolError(f"unknown agent {a!r}; the structure has {list(self.relations)}")
            hit = self.prime(self.law)
            for a in agents:
                hit = hit & self.relations[a]
            self._cache[key] = hit
        return hit

    def _box(self, agents: tuple[str, ...], u: Any) -> Any:
        """∀V'(θ' ∧ ⋀Ω → u') = ¬∃V'(θ' ∧ ⋀Ω ∧ ¬u')."""
        import dd.cudd

        return ~dd.cudd.and_exists(self._seen(agents), ~self.prime(u), set(self.primes.values()))

    def _common(self, group: tuple[str, ...], u: Any) -> Any:
        return _common_fixpoint(self, group, u)

    # ------------------------------------------------------------------ updates
    def announce(self, formula: Formula | str) -> BeliefStructure:
        """``F|φ = (V, θ ∧ ||φ||, Ω)``; actual states outside φ drop out."""
        u = self.evaluate(formula)
        return BeliefStructure(self.bdd, self.vocabulary, self.primes, self.law & u, self.relations,
                               self.actual & u)

    def transform(self, events: Any) -> BeliefStructure:
        """The product ``F × E`` with an event model (any relations; see the module docstring)."""
        return self._product(events)[0]

    def _product(self, events: Any) -> tuple[BeliefStructure, list[dict[str, bool]], dict[str, str]]:
        b = self.bdd
        for a in self.agents:
            if a not in events.relations:
                raise ModelError(f"event model {events.name!r} has no relation for agent {a!r}")
        changed = sorted(events.changed_props())
        missing = sorted(set(changed) - set(self.vocabulary))
        if missing:
            raise UnknownSymbolError(f"event model {events.name!r} changes {missing}, not in the vocabulary")
        taken = set(b.vars)
        k = events.n_events
        ev_bits = [_fresh("_ev", taken) for _ in range(_bits_needed(k))]
        taken |= set(ev_bits)
        copies = {q: _fresh(f"{q}°", taken) for q in changed}
        new_vars = ev_bits + list(copies.values())
        new_primes = _declare_pairs(b, new_vars, taken)
        primes = {**self.primes, **new_primes}
        codes = [{v: bool((e >> j) & 1) for j, v in enumerate(ev_bits)} for e in range(k)]
        code = [b.cube(c) if c else b.true for c in codes]
        code_p = [b.cube({new_primes[v]: val for v, val in c.items()}) if c else b.true for c in codes]
        shift = {q: b.var(c) for q, c in copies.items()}
        shift.update({self.primes[q]: b.var(new_primes[c]) for q, c in copies.items()})

        def old(u: Any) -> Any:
            return b.let(shift, u) if shift else u

        pre = [self.evaluate(p) for p in events.pre]
        law = old(self.law & _disjoin(b, (code[e] & pre[e] for e in range(k))))
        for q in changed:
            post = _disjoin(b, (code[e] & self.evaluate(events.post[e].get(q, Prop(q))) for e in range(k)))
            law = law & b.apply("<=>", b.var(q), old(post))
        rels = {}
        for a in self.agents:
            pairs = events.relations[a].pairs()
            q_rel = _disjoin(b, (code[int(e)] & code_p[int(f)] for e, f in pairs))
            rels[a] = old(self.relations[a]) & q_rel
        actual = old(self.actual) & _disjoin(b, (code[e] for e in events.designated)) & law
        voc = self.vocabulary + tuple(new_vars)
        return BeliefStructure(b, voc, primes, law, rels, actual), codes, copies

    def transform_symbolic(self, event_vars: Sequence[str], law: Formula | str,
                           observations: Mapping[str, Formula | str], designated: Formula | str = "true"
                           ) -> BeliefStructure:
        """The product with a *belief transformer* without factual change (SMCDEL's ``SMCDEL.Symbolic.K``
        ``Trf``): fresh event variables X, an event law over V ∪ X whose modal parts speak of V only
        (evaluated in this structure), per agent an observation relation over X ∪ X' (``"x' <-> x"``).

        ``V^× = V ∪ X``, ``θ^× = θ ∧ ||law||``, ``Ω_i^× = Ω_i ∧ obs_i`` and the actual states those of
        ``θ^× ∧ actual ∧ designated`` — the product update with the event model whose events are the
        assignments of X (precondition: the law) and whose relations are the observations."""
        b = self.bdd
        xs = tuple(dict.fromkeys(event_vars))
        clash = sorted(set(xs) & (set(b.vars) | set(self.primes.values())))
        if clash:
            raise ModelError(f"event variables {clash} are not fresh (declared in this manager already)")
        missing = sorted(set(self.agents) - set(observations))
        if missing:
            raise ModelError(f"belief transformer: no observation relation for agent(s) {missing}")
        new_primes = _declare_pairs(b, xs, set(b.vars))
        primes = {**self.primes, **new_primes}
        voc = self.vocabulary + xs
        law_node = self.law & self._mixed(parse(law) if isinstance(law, str) else law, set(xs))
        ext = BeliefStructure(b, tuple(xs), new_primes, b.true, {}, b.true)
        rels = {a: self.relations[a] & ext._relational(observations[a]) for a in self.agents}
        des = ext._relational(designated)
        return BeliefStructure(b, voc, primes, law_node, rels, self.actual & law_node & des)

    def _mixed(self, f: Formula, xs: set[str]) -> Any:
        """BDD of a formula over V ∪ X whose subformulas mentioning X are Boolean combinations."""
        if not (_props(f) & xs):
            return self.evaluate(f)
        if isinstance(f, Prop):
            return self.bdd.var(f.name)
        if isinstance(f, Not):
            return ~self._mixed(f.arg, xs)
        if isinstance(f, And | Or):
            parts = [self._mixed(a, xs) for a in f.args]
            return _fold_bdds(parts, operator.and_ if isinstance(f, And) else operator.or_)
        if isinstance(f, Implies):
            return ~self._mixed(f.left, xs) | self._mixed(f.right, xs)
        if isinstance(f, Iff):
            return self.bdd.apply("<=>", self._mixed(f.left, xs), self._mixed(f.right, xs))
        raise ModelError(f"belief transformer law: a modality may not mention event variables, got {f}")

    def _eval_update(self, f: Update) -> Any:
        b = self.bdd
        new, codes, copies = self._product(f.model)
        psi = new.evaluate(f.arg)
        subst: dict[str, Any] = {v: b.true if val else b.false for v, val in codes[f.event].items()}
        for q, c in copies.items():
            subst[c] = b.var(q)
            subst[q] = self.evaluate(f.model.post[f.event].get(q, Prop(q)))
        return ~self.evaluate(f.model.pre[f.event]) | (b.let(subst, psi) if subst else psi)

    def form_of(self, node: Any = None) -> Formula:
        """A formula whose truth set is ``node`` (default: the state law), :func:`delkit.backends.symbolic.form_of`;
        SMCDEL's ``formOf``."""
        from delkit.backends.symbolic import form_of

        return form_of(self.bdd, self.law if node is None else node)

    # ------------------------------------------------------------------ smaller structures
    def generated(self) -> BeliefStructure:
        """The substructure generated by the actual states: θ' = the states reachable from them along any
        agent's relation (least fixpoint of X ∨ ⋁_a θ ∧ (∃V (X ∧ Ω_a))[V' ↦ V]). Its Kripke model is the
        generated submodel, so it is bisimilar to this structure at every actual state."""
        import dd.cudd

        b = self.bdd
        unprime = {p: b.var(v) for v, p in self.primes.items()}
        voc = set(self.vocabulary)
        step_rel = _disjoin(b, self.relations.values()) & self.prime(self.law)
        x = self.actual & self.law
        while True:
            img = dd.cudd.and_exists(x, step_rel, voc)
            nxt = x | (self.law & b.let(unprime, img))
            if nxt == x:
                break
            x = nxt
        return BeliefStructure(b, self.vocabulary, self.primes, x, self.relations, self.actual & x)

    def minimise(self, keep: Iterable[str] = ()) -> BeliefStructure:
        """SMCDEL's ``optimize`` for belief structures: drop the variables outside ``keep`` that θ determines
        (θ ⊨ p or θ ⊨ ¬p) or makes equivalent to another (θ ⊨ p ↔ q or p ↔ ¬q). p is replaced by its constant
        or literal in θ and the actual states, and p, p' by the same constant or literal (q, q') in every
        Ω_a — on pairs of states (the only pairs the semantics reads: Ω_a is always taken with θ and θ')
        nothing changes. The result has the same states up to the dropped variables, state by state."""
        b = self.bdd
        rels = dict(self.relations)
        voc = list(self.vocabulary)
        primes = dict(self.primes)

        def drop(p: str, found: tuple[Any, str | None, bool]) -> None:
            nonlocal rels
            sub, q, negated = found
            sub_p = sub if q is None else ~b.var(primes[q]) if negated else b.var(primes[q])
            rels = {a: b.let({p: sub, primes[p]: sub_p}, r) for a, r in rels.items()}
            del primes[p]

        law, actual = _drop_redundant(b, self.law, self.actual, voc, keep, drop)
        return BeliefStructure(b, tuple(voc), primes, law, rels, actual)

    # ------------------------------------------------------------------ translation back
    def to_kripke(self, props: Sequence[str] | None = None) -> KripkeModel:
        """The explicit model: one world per state; i relates s to t iff ``Ω_i(s, t')``."""
        b = self.bdd
        states = self.states()
        voc = self.vocabulary
        index = {tuple(s[v] for v in voc): i for i, s in enumerate(states)}
        law_p = self.prime(self.law)
        rels = {}
        for a, omega in self.relations.items():
            pairs = []
            for i, s in enumerate(states):
                succ = b.let({v: s[v] for v in voc}, omega) & law_p
                for t in b.pick_iter(succ, care_vars=set(self.primes[v] for v in voc)):
                    pairs.append((i, index[tuple(t[self.primes[v]] for v in voc)]))
            rels[a] = Relation.from_pairs(len(states), pairs)
        keep = tuple(voc if props is None else props)
        val = np.array([[s[p] for p in keep] for s in states], dtype=bool).reshape(len(states), len(keep))
        des = tuple(index[tuple(s[v] for v in voc)] for s in self.states(self.actual))
        return KripkeModel(keep, self.agents, val, rels, des)


def belief_from_kripke(model: KripkeModel, *, bdd: Any = None) -> tuple[BeliefStructure, list[dict[str, bool]]]:
    """Encode any Kripke model; returns the structure and the state of each world.

    Vocabulary: the model's propositions plus ``⌈log2 m⌉`` bits ``_w*`` numbering the worlds that share
    a valuation (m = the largest number of worlds with one valuation); θ = ⋁_w state(w);
    Ω_a = ⋁_{(w,v)∈R_a} state(w) ∧ state(v)'.
    """
    mgr = bdd if bdd is not None else new_manager()
    val = np.asarray(model.valuation, dtype=bool)
    _, inverse, counts = np.unique(val, axis=0, return_inverse=True, return_counts=True)
    inverse = np.asarray(inverse).ravel()
    taken = set(model.props) | set(mgr.vars)
    extra = [_fresh("_w", taken) for _ in range(_bits_needed(int(counts.max(initial=1))))]
    voc = tuple(model.props) + tuple(extra)
    primes = _declare_pairs(mgr, voc)
    seen: dict[int, int] = {}
    states = []
    for w in range(model.n_worlds):
        j = seen.get(int(inverse[w]), 0)
        seen[int(inverse[w])] = j + 1
        st = {p: bool(val[w, i]) for i, p in enumerate(model.props)}
        st.update({x: bool((j >> i) & 1) for i, x in enumerate(extra)})
        states.append(st)
    cubes = [mgr.cube(s) for s in states]
    cubes_p = [mgr.cube({primes[v]: x for v, x in s.items()}) for s in states]
    law = _disjoin(mgr, cubes)
    rels = {a: _disjoin(mgr, (cubes[int(w)] & cubes_p[int(v)] for w, v in model.relations[a].pairs()))
            for a in model.agents}
    actual = _disjoin(mgr, (cubes[w] for w in model.designated))
    return BeliefStructure(mgr, voc, primes, law, rels, actual), states


# ----------------------------------------------------------------------------- helpers


def _declare_pairs(mgr: Any, names: Iterable[str], taken: set[str] | None = None) -> dict[str, str]:
    """Declare each name followed by its primed copy (interleaved order); returns name ↦ primed name."""
    taken = set(mgr.vars) if taken is None else taken
    primes = {}
    for v in names:
        p = f"{v}'"
        if p in taken and p not in mgr.vars:
            p = _fresh(f"{v}'", taken)
        taken |= {v, p}
        mgr.declare(v, p)
        primes[v] = p
    return primes


def _disjoin(b: Any, parts: Iterable[Any]) -> Any:
    items = list(parts)
    return _fold_bdds(items, operator.or_) if items else b.false


def _props(f: Formula) -> set[str]:
    from delkit.logic.formula import props_of

    return props_of(f)


def _propositional(b: Any, f: Formula) -> Any:
    """BDD of a propositional formula over declared names."""
    if isinstance(f, Prop):
        return b.var(f.name)
    if isinstance(f, Top):
        return b.true
    if isinstance(f, Bot):
        return b.false
    if isinstance(f, Not):
        return ~_propositional(b, f.arg)
    if isinstance(f, And):
        return _fold_bdds([_propositional(b, a) for a in f.args], operator.and_) if f.args else b.true
    if isinstance(f, Or):
        return _fold_bdds([_propositional(b, a) for a in f.args], operator.or_) if f.args else b.false
    if isinstance(f, Implies):
        return ~_propositional(b, f.left) | _propositional(b, f.right)
    if isinstance(f, Iff):
        return b.apply("<=>", _propositional(b, f.left), _propositional(b, f.right))
    raise ModelError(f"a law or relation must be propositional, got {f}")


def _ev_prop(bs: BeliefStructure, f: Prop) -> Any:
    if f.name not in bs.vocabulary:
        raise UnknownSymbolError(f"unknown proposition {f.name!r}; the vocabulary is {list(bs.vocabulary)}")
    return bs.bdd.var(f.name)


def _ev_fold(op: Any, unit: str) -> Any:
    def rule(bs: BeliefStructure, f: Any) -> Any:
        if not f.args:
            return getattr(bs.bdd, unit)
        return _fold_bdds([bs.evaluate(a) for a in f.args], op)
    return rule


_DISPATCH: dict[type, Any] = {
    Prop: _ev_prop,
    Top: lambda bs, f: bs.bdd.true,
    Bot: lambda bs, f: bs.bdd.false,
    Not: lambda bs, f: ~bs.evaluate(f.arg),
    And: _ev_fold(operator.and_, "true"),
    Or: _ev_fold(operator.or_, "false"),
    Implies: lambda bs, f: ~bs.evaluate(f.left) | bs.evaluate(f.right),
    Iff: lambda bs, f: bs.bdd.apply("<=>", bs.evaluate(f.left), bs.evaluate(f.right)),
    K: lambda bs, f: bs._box((f.agent,), bs.evaluate(f.arg)),
    Kw: lambda bs, f: bs._box((f.agent,), bs.evaluate(f.arg)) | bs._box((f.agent,), ~bs.evaluate(f.arg)),
    E: _ev_every,
    D: lambda bs, f: bs._box(f.group, bs.evaluate(f.arg)),
    C: lambda bs, f: bs._common(f.group, bs.evaluate(f.arg)),
    Announce: _ev_announce,
    Update: lambda bs, f: bs._eval_update(f),
}
