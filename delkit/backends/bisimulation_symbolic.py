"""Distinguishing formulas on BDDs: symbolic partition refinement for knowledge and belief structures.

:func:`symbolic_diff` compares two structures (:class:`~delkit.backends.symbolic.KnowledgeStructure`,
:class:`~delkit.backends.symbolic_belief.BeliefStructure`, in any combination) without enumerating their states:

1. **Disjoint union as one belief structure** in a fresh BDD manager. Every variable v of structure A
   becomes ``A.v``, of B ``B.v``; a variable ``⋄side`` says which structure a state belongs to, and each
   compared proposition p is a variable constrained by the law to ``side ? B.p : A.p``. Agent a's relation
   is A's relation on A-states and B's on B-states (for knowledge structures: agreement on the observed
   variables; for belief structures: Ω_a), so truth in the union is truth in A or in B.
2. **Bisimilarity as a BDD over pairs of states** ``Z(s, t)`` (four copies of the union's variables: s, s',
   t, t'), the greatest fixpoint of
   ``Z_0 = θ(s) ∧ θ(t) ∧ ⋀_p (p(s) ↔ p(t))`` and
   ``Z_{k+1} = Z_k ∧ ⋀_a [∀s'(R_a(s,s') → ∃t'(R_a(t,t') ∧ Z_k(s',t'))) ∧ ∀t'(R_a(t,t') → ∃s'(R_a(s,s') ∧ Z_k(s',t')))]``
   — partition refinement with the partition kept as its equivalence relation. Every round's Z_k is kept.
3. **Formulas** as in :mod:`delkit.models.bisimulation`, with the sets of successors as BDDs: two states split in
   round 0 differ on a proposition; split in round k by agent a, one has a successor x' that is not
   Z_{k-1}-related to any successor of the other (a BDD query, one state picked from it), and χ is a
   conjunction of formulas for x' against successors picked one at a time, each removing from the
   remaining set (a BDD) every successor where it is false. Truth sets are computed by the union's
   own evaluator, so the formula is checked as it is built.

Bisimilar multi-pointed structures: every actual state of each is Z-related to an actual state of the
other. The bisimulation is returned as pairs of state names (``{1,3}``: the true variables), limited to
``max_pairs`` pairs (the BDD may stand for exponentially many).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

from delkit.errors import ModelError
from delkit.logic.formula import Formula, Not, Prop, conj, disj
from delkit.models.bisimulation import Diff, formula_size, split_formula

__all__ = ["symbolic_diff", "SymbolicUnion"]

SIDE = "⋄side"


@dataclass
class SymbolicUnion:
    """The disjoint union of two structures as one belief structure, plus the refinement rounds."""

    union: Any               # BeliefStructure over W
    words: tuple[str, ...]   # W
    second: dict[str, str]   # W → W2 (t), W' → W2' (t')
    rounds: list[Any]        # Z_0, Z_1, ..., Z_final over W ∪ W2
    props: tuple[str, ...]
    a_vars: tuple[str, ...]
    b_vars: tuple[str, ...]
    a_names: tuple[str, ...]
    b_names: tuple[str, ...]

    @property
    def bdd(self) -> Any:
        return self.union.bdd


def _relation(mgr: Any, obj: Any, a: str, rename: dict[str, str], primes: dict[str, str]) -> Any:
    """Agent a's relation of ``obj`` over (renamed V, renamed V'), as a BDD in ``mgr``."""
    if hasattr(obj, "observed"):
        rel = mgr.true
        for v in obj.observed[a]:
            rel &= mgr.apply("<=>", mgr.var(rename[v]), mgr.var(primes[rename[v]]))
        return rel
    # belief structure: copy Ω_a by variable names into mgr, then rename V ↦ side-V, V' ↦ side-V'
    src_names = {**{v: rename[v] for v in obj.vocabulary},
                 **{obj.primes[v]: primes[rename[v]] for v in obj.vocabulary}}
    return _transfer(obj.bdd, obj.relations[a], mgr, src_names)


def _transfer(src: Any, u: Any, mgr: Any, names: dict[str, str]) -> Any:
    """Copy u from manager ``src`` into ``mgr`` renaming its variables by ``names``."""
    import dd.cudd

    tmp = dd.cudd.BDD()
    support = src.support(u)
    if support:
        tmp.declare(*sorted(support))
    v = src.copy(u, tmp)
    # rename inside tmp to fresh-free names, then copy into mgr
    tmp.declare(*[names[x] for x in sorted(support) if names[x] not in tmp.vars])
    v = tmp.let({x: tmp.var(names[x]) for x in support}, v) if support else v
    return tmp.copy(v, mgr)


def build_union(a: Any, b: Any, props: Sequence[str] | None = None) -> SymbolicUnion:
    from delkit.backends.symbolic import new_manager
    from delkit.backends.symbolic_belief import BeliefStructure

    if set(a.agents) != set(b.agents):
        raise ModelError(f"the structures have different agents ({sorted(a.agents)} vs {sorted(b.agents)}); "
                         "bisimulation compares structures over the same agents")
    if props is None:
        if set(a.vocabulary) != set(b.vocabulary):
            raise ModelError(f"the structures have different vocabularies ({list(a.vocabulary)} vs "
                             f"{list(b.vocabulary)}); compare them on common ones with props=[...] (CLI: --props)")
        props = tuple(a.vocabulary)
    for which, obj in (("A", a), ("B", b)):
        missing = sorted(set(props) - set(obj.vocabulary))
        if missing:
            raise ModelError(f"structure {which} has no variable(s) {missing} (it has {list(obj.vocabulary)})")
    props = tuple(props)
    ra = {v: f"A.{v}" for v in a.vocabulary}
    rb = {v: f"B.{v}" for v in b.vocabulary}
    # variable order: each compared proposition next to its two copies (p ↔ A.p is then a small BDD; with
    # all A-copies after all propositions the law would be exponential), then the other variables
    words = (SIDE, *(w for p in props for w in (p, ra[p], rb[p])),
             *(ra[v] for v in a.vocabulary if v not in props), *(rb[v] for v in b.vocabulary if v not in props))
    mgr = new_manager()
    primes, second = {}, {}
    for w in words:  # interleaved: w, w', w2, w2'
        p, w2, p2 = f"{w}'", f"{w}²", f"{w}²'"
        mgr.declare(w, p, w2, p2)
        primes[w] = p
        second[w], second[p] = w2, p2
    side = mgr.var(SIDE)

    def law_of(obj: Any, rename: dict[str, str], others: dict[str, str], on: Any) -> Any:
        law = _transfer(obj.bdd, obj.law, mgr, rename)
        for v in others.values():
            law &= ~mgr.var(v)
        for p in props:
            law &= mgr.apply("<=>", mgr.var(p), mgr.var(rename[p]))
        return on & law

    law = law_of(a, ra, rb, ~side) | law_of(b, rb, ra, side)
    side_p = mgr.var(primes[SIDE])
    rels = {}
    for ag in a.agents:
        rel_a = _relation(mgr, a, ag, ra, primes)
        rel_b = _relation(mgr, b, ag, rb, primes)
        rels[ag] = (~side & ~side_p & rel_a) | (side & side_p & rel_b)
    actual = (~side & _transfer(a.bdd, a.actual, mgr, ra)) | (side & _transfer(b.bdd, b.actual, mgr, rb))
    union = BeliefStructure(mgr, words, primes, law, rels, actual & law)
    rounds = _refine(union, words, primes, second, props)
    return SymbolicUnion(union, words, second, rounds, props, tuple(a.vocabulary), tuple(b.vocabulary),
                         tuple(ra.values()), tuple(rb.values()))


def _refine(u: Any, words: tuple[str, ...], primes: dict[str, str], second: dict[str, str],
            props: tuple[str, ...]) -> list[Any]:
    import dd.cudd

    mgr = u.bdd
    w_p = set(primes.values())
    w2_p = {second[primes[w]] for w in words}
    law_t = mgr.let({w: mgr.var(second[w]) for w in words}, u.law)
    z = u.law & law_t
    for p in props:
        z &= mgr.apply("<=>", mgr.var(p), mgr.var(second[p]))
    # R_a(s,s') ∧ θ(s') and its copy R_a(t,t') ∧ θ(t')
    law_p = u.prime(u.law)
    rel_s = {a: r & law_p for a, r in u.relations.items()}
    rel_t = {a: mgr.let({**{w: mgr.var(second[w]) for w in words},
                         **{primes[w]: mgr.var(second[primes[w]]) for w in words}}, r) for a, r in rel_s.items()}
    to_succ = {**{w: mgr.var(primes[w]) for w in words}, **{second[w]: mgr.var(second[primes[w]]) for w in words}}
    rounds = [z]
    while True:
        z_succ = mgr.let(to_succ, z)  # Z(s', t')
        new = z
        for a in u.relations:
            some_t = dd.cudd.and_exists(rel_t[a], z_succ, w2_p)      # ∃t'(R(t,t') ∧ Z(s',t'))
            zig = ~dd.cudd.and_exists(rel_s[a], ~some_t, w_p)         # ∀s'(R(s,s') → ...)
            some_s = dd.cudd.and_exists(rel_s[a], z_succ, w_p)       # ∃s'(R(s,s') ∧ Z(s',t'))
            zag = ~dd.cudd.and_exists(rel_t[a], ~some_s, w2_p)        # ∀t'(R(t,t') → ...)
            new = new & zig & zag
        if new == z:
            return rounds
        rounds.append(new)
        z = new


class _Explainer:
    def __init__(self, su: SymbolicUnion) -> None:
        self.su = su
        self.memo: dict[tuple, tuple[Formula, Any]] = {}

    def _key(self, s: dict[str, bool]) -> tuple:
        return tuple(bool(s[w]) for w in self.su.words)

    def cube(self, s: dict[str, bool]) -> Any:
        return self.su.bdd.cube({w: bool(s[w]) for w in self.su.words})

    def related(self, z: Any, x: dict[str, bool], y: dict[str, bool]) -> bool:
        b = self.su.bdd
        sub = {w: bool(x[w]) for w in self.su.words}
        sub.update({self.su.second[w]: bool(y[w]) for w in self.su.words})
        return b.let(sub, z) == b.true

    def successors(self, a: str, x: dict[str, bool]) -> Any:
        """R_a(x) ∧ θ as a BDD over W."""
        u, b = self.su.union, self.su.bdd
        succ = b.let({w: bool(x[w]) for w in self.su.words}, u.relations[a]) & u.prime(u.law)
        return b.let({u.primes[w]: b.var(w) for w in self.su.words}, succ)

    def pick(self, node: Any) -> dict[str, bool]:
        return dict(self.su.bdd.pick(node, care_vars=set(self.su.words)))

    def formula(self, x: dict[str, bool], y: dict[str, bool]) -> tuple[Formula, Any]:
        key = (self._key(x), self._key(y))
        hit = self.memo.get(key)
        if hit is not None:
            return hit
        k = next((i for i, z in enumerate(self.su.rounds) if not self.related(z, x, y)), None)
        if k is None:
            raise ValueError("the states are bisimilar")
        if k == 0:
            p = next(p for p in self.su.props if x[p] != y[p])
            f: Formula = Prop(p) if x[p] else Not(Prop(p))
        else:
            f = self._modal(x, y, k)
        hit = (f, self.su.union.evaluate(f))
        self.memo[key] = hit
        return hit

    def _unmatched(self, z: Any, src: Any, other: Any) -> Any:
        """States of ``src`` (over W) not z-related to any state of ``other`` (over W)."""
        import dd.cudd

        b, su = self.su.bdd, self.su
        other_t = b.let({w: b.var(su.second[w]) for w in su.words}, other)
        matched = dd.cudd.and_exists(z, other_t, {su.second[w] for w in su.words})
        return src & ~matched

    def _cover(self, keep: dict[str, bool], avoid: Any) -> Formula:
        """A conjunction true at ``keep`` and false at every state of ``avoid``."""
        b = self.su.bdd
        parts = []
        left = avoid
        while left != b.false:
            f, truth = self.formula(keep, self.pick(left))
            parts.append(f)
            left = left & truth
        return conj(parts)

    def _modal(self, x: dict[str, bool], y: dict[str, bool], k: int) -> Formula:
        prev = self.su.rounds[k - 1]
        best: Formula | None = None
        for a in sorted(self.su.union.relations):
            sx, sy = self.successors(a, x), self.successors(a, y)
            for diamond, src, other in ((True, sx, sy), (False, sy, sx)):
                cand = self._unmatched(prev, src, other) if diamond else self._unmatched_rev(prev, src, other)
                if cand == self.su.bdd.false:
                    continue
                chi = self._cover(self.pick(cand), other)
                f = split_formula(a, chi, diamond)
                if best is None or formula_size(f) < formula_size(best):
                    best = f
        if best is None:
            raise AssertionError(f"no agent splits the states in round {k}")
        return best

    def _unmatched_rev(self, z: Any, src: Any, other: Any) -> Any:
        """States of ``src`` (y's successors) to which no state of ``other`` (x's successors) is z-related."""
        import dd.cudd

        b, su = self.su.bdd, self.su
        src_t = b.let({w: b.var(su.second[w]) for w in su.words}, src)
        matched_t = dd.cudd.and_exists(z, other, set(su.words))  # t with some s ∈ other, Z(s, t)
        unmatched_t = src_t & ~matched_t
        return b.let({su.second[w]: b.var(w) for w in su.words}, unmatched_t)


def _name(su: SymbolicUnion, s: dict[str, bool]) -> str:
    side_vars, plain = (su.b_names, su.b_vars) if s[SIDE] else (su.a_names, su.a_vars)
    return "{" + ",".join(v for v, n in zip(plain, side_vars, strict=True) if s[n]) + "}"


def symbolic_diff(a: Any, b: Any, *, props: Sequence[str] | None = None, max_pairs: int = 1000) -> Diff:
    """Like :func:`delkit.models.bisimulation.diff`, on BDDs: structures A and B (their actual states designated).

    ``Diff.relation`` holds indices into ``Diff.names`` (state names such as ``{1,3}``) of at most
    ``max_pairs`` pairs of the largest bisimulation between the parts generated by the actual states.
    """
    su = build_union(a, b, props)
    bdd, u = su.bdd, su.union
    z = su.rounds[-1]
    side = bdd.var(SIDE)
    da, db = u.actual & ~side, u.actual & side
    if da == bdd.false or db == bdd.false:
        raise ModelError("both structures need actual states to be compared")
    ex = _Explainer(su)
    w2 = {su.second[w] for w in su.words}
    missing_b = ex._unmatched_rev(z, db, da)  # actual states of B matched by no actual state of A
    missing_a = ex._unmatched(z, da, db)
    if missing_b == bdd.false and missing_a == bdd.false:
        reach = _reachable(u, u.actual)
        reach_t = bdd.let({w: bdd.var(su.second[w]) for w in su.words}, reach & side)
        pairs_bdd = z & reach & ~side & reach_t
        names_a: list[str] = []
        names_b: list[str] = []
        pairs = []
        for assignment in bdd.pick_iter(pairs_bdd, care_vars=set(su.words) | w2):
            s = {w: assignment[w] for w in su.words}
            t = {w: assignment[su.second[w]] for w in su.words}
            names_a.append(_name(su, s))
            names_b.append(_name(su, t))
            pairs.append((len(names_a) - 1, len(names_b) - 1))
            if len(pairs) >= max_pairs:
                break
        return Diff(True, relation=tuple(pairs), names=(tuple(names_a), tuple(names_b)),
                    explanation=_explain(a, b, None, "A"))
    if missing_b != bdd.false:
        e = ex.pick(missing_b)
        f = _cover_designated(ex, da, e)
        return Diff(False, formula=f, true_in="A", fails_at=0, names=((), (_name(su, e),)),
                    explanation=_explain(a, b, f, "A"))
    d = ex.pick(missing_a)
    f = _cover_designated(ex, db, d)
    return Diff(False, formula=f, true_in="B", fails_at=0, names=((_name(su, d),), ()),
                explanation=_explain(a, b, f, "B"))


def _explain(a: Any, b: Any, f: Formula | None, true_in: str) -> tuple[tuple[str, str], ...]:
    """The sets of states behind a diff as readable formulas over each structure's own vocabulary
    (:func:`delkit.backends.symbolic.form_of`): the actual states of A and B and, when told apart, the states of each
    where the distinguishing formula holds / the actual states where it fails."""
    from delkit.backends.symbolic import form_of
    from delkit.logic.formula import show

    lines = [("actual states of A", show(form_of(a.bdd, a.actual))),
             ("actual states of B", show(form_of(b.bdd, b.actual)))]
    if f is not None:
        yes, no = (a, b) if true_in == "A" else (b, a)
        other = "B" if true_in == "A" else "A"
        lines.append((f"states of {true_in} where the formula holds",
                      show(form_of(yes.bdd, yes.law & yes.evaluate(f)))))
        lines.append((f"actual states of {other} where it fails",
                      show(form_of(no.bdd, no.actual & ~no.evaluate(f)))))
    return tuple(lines)


def _cover_designated(ex: _Explainer, keep: Any, avoid: dict[str, bool]) -> Formula:
    """A disjunction true at every state of ``keep`` and false at ``avoid``."""
    b = ex.su.bdd
    parts = []
    left = keep
    while left != b.false:
        f, truth = ex.formula(ex.pick(left), avoid)
        parts.append(f)
        left = left & ~truth
    return disj(parts)


def _reachable(u: Any, start: Any) -> Any:
    """States reachable from ``start`` along any agent's relation (least fixpoint)."""
    import dd.cudd

    b = u.bdd
    reach = start
    any_rel = b.false
    for r in u.relations.values():
        any_rel |= r
    any_rel &= u.prime(u.law)
    back = {u.primes[w]: b.var(w) for w in u.vocabulary}
    while True:
        step = dd.cudd.and_exists(reach, any_rel, set(u.vocabulary))
        new = reach | b.let(back, step)
        if new == reach:
            return reach
        reach = new
