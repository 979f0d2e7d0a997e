"""Verification with z3: propositional validity, macro equivalence, DEL reduction, bounded model search.

Four tools, all returning plain data (frozen dataclasses) and never trusting z3 blindly:

1. **Propositional validity / satisfiability** (:func:`valid`, :func:`satisfiable`, :func:`equivalent`,
   :func:`counterexample`) of pre- and postconditions. Exact (z3 is a decision procedure for SAT).
   Defined in :mod:`delkit.logic.propositional` (which :mod:`delkit.models.compose` uses to prune macros) and
   re-exported here.

2. **Macro check** (:func:`check_macro`): a macro (a composed event model E₁;…;Eₙ, see
   :func:`delkit.models.compose.compose`) is compared with the sequence it replaces. Events are matched by name
   (``e1;e2;…``); for every matched event the preconditions must be equivalent, ``⊨ pre_m ↔ pre_s``, and
   every postcondition must agree wherever the event can happen, ``⊨ pre_s → (post_m(p) ↔ post_s(p))``;
   relations and designated events must coincide, and an event of the sequence that the macro leaves out
   must have an unsatisfiable precondition.

3. **Reduction** (:func:`reduce`) of dynamic formulas to static ones by the reduction axioms of DEL with
   factual change (van Ditmarsch, van der Hoek, Kooi 2007/2008; van Benthem, van Eijck, Kooi 2006)::

       [E,e]p        ↔ (pre(e) → post_e(p))
       [E,e]¬φ       ↔ (pre(e) → ¬[E,e]φ)
       [E,e](φ ∧ ψ)  ↔ ([E,e]φ ∧ [E,e]ψ)
       [E,e]K_a φ    ↔ (pre(e) → ⋀_{f : e Q_a f} K_a [E,f]φ)
       [E,e]D_G φ    ↔ (pre(e) → ⋀_{f : e (⋂_{a∈G} Q_a) f} D_G [E,f]φ)

   and for public announcements ``[!ψ]p ↔ (ψ → p)``, ``[!ψ]¬φ ↔ (ψ → ¬[!ψ]φ)``,
   ``[!ψ](φ ∧ χ) ↔ ([!ψ]φ ∧ [!ψ]χ)``, ``[!ψ]K_a φ ↔ (ψ → K_a [!ψ]φ)``. There is no such axiom for C
   (it needs relativised common knowledge), so C under a dynamic operator raises
   :class:`VerificationError`.

4. **Bounded model search** (:func:`find_model`, :func:`prove`): k symbolic worlds with boolean valuation
   variables ``p@w`` and relation variables ``R_a(w,v)`` under the frame constraints of S5 (reflexive,
   symmetric, transitive), KD45 (serial, transitive, euclidean) or K (none). The formula is unfolded over
   the k worlds; ``C_G φ`` uses the transitive closure of ⋃_{a∈G} R_a computed by ⌈log₂ k⌉ squarings,
   which is exact for k worlds; public announcements are encoded directly by relativisation to the worlds
   where the announced formula holds (so C under [!ψ] is supported). A model z3 returns is rebuilt as a
   :class:`~delkit.models.kripke.KripkeModel` and **re-checked by the explicit model checker**; if the two
   disagree a :class:`VerificationError` is raised. A ``Verdict(valid=True)`` from :func:`prove` means "no
   counter-model with at most k worlds"; ``exact`` says whether that is a proof: it is for propositional
   formulas and for single-agent S5 formulas within the small-model bound (:func:`s5_single_agent_bound`);
   otherwise it is a bounded answer.
"""

from __future__ import annotations

import ctypes
import math
from collections.abc import Iterable, Sequence
from dataclasses import dataclass, field

import numpy as np

from delkit.errors import VerificationError
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
    agents_of,
    conj,
    is_propositional,
    show,
    subformulas,
)
from delkit.logic.propositional import _f, counterexample, equivalent, satisfiable, to_z3, valid
from delkit.models.events import EventModel
from delkit.models.kripke import KripkeModel
from delkit.models.relation import Relation
from delkit.resources import check_time

__all__ = [
    "VerificationError", "Verdict", "MacroCheck", "valid", "satisfiable", "equivalent", "counterexample",
    "to_z3", "reduce", "check_macro", "find_model", "prove", "s5_single_agent_bound", "LOGICS",
]

LOGICS = ("S5", "KD45", "K")


# ============================================================================ reduction axioms


def _has_c(f: Formula) -> bool:
    return any(isinstance(g, C) for g in subformulas(f))


def _map_bool(g: Formula, rec) -> Formula | None:
    """g with ``rec`` applied to the children if g is an atom or a Boolean connective, else None."""
    if isinstance(g, (Top, Bot, Prop)):
        return g
    if isinstance(g, Not):
        return Not(rec(g.arg))
    if isinstance(g, (And, Or)):
        return type(g)(rec(a) for a in g.args)
    if isinstance(g, (Implies, Iff)):
        return type(g)(rec(g.left), rec(g.right))
    return None


def _map_static(g: Formula, rec) -> Formula | None:
    """Like :func:`_map_bool`, also rebuilding K, Kw, E, C, D around ``rec`` of the argument."""
    out = _map_bool(g, rec)
    if out is not None:
        return out
    if isinstance(g, (K, Kw)):
        return type(g)(g.agent, rec(g.arg))
    if isinstance(g, (E, C, D)):
        return type(g)(g.group, rec(g.arg))
    return None


def reduce(formula: Formula | str) -> Formula:
    """An equivalent formula without ``[!ψ]`` and ``[E,e]`` (reduction axioms, innermost first).

    Raises :class:`VerificationError` if a common-knowledge operator occurs under a dynamic operator
    (or in the precondition of an event model used under one), for which no reduction axiom exists.
    The result may be exponentially larger than the input (every K_a under [E,e] branches over the
    events e Q_a f); shared subformulas are built once.
    """
    f = _f(formula)
    memo: dict[Formula, Formula] = {}

    def red(g: Formula) -> Formula:
        hit = memo.get(g)
        if hit is not None:
            return hit
        out = _map_static(g, red)
        if out is not None:
            pass
        elif isinstance(g, Announce):
            psi, chi = red(g.announced), red(g.arg)
            out = _announce(psi, chi, show(g))
        elif isinstance(g, Update):
            chi = red(g.arg)
            out = _update(g.model, g.event, chi, red, show(g))
        else:  # pragma: no cover
            raise TypeError(f"not a formula: {g!r}")
        memo[g] = out
        return out

    return red(f)


def _announce(psi: Formula, chi: Formula, where: str) -> Formula:
    """[!ψ]χ for static ψ, χ:  ψ → χ^ψ, where χ^ψ is χ read in the model restricted to ψ."""
    memo: dict[Formula, Formula] = {}

    def box(g: Formula) -> Formula:  # [!ψ]g
        return Implies(psi, after(g))

    def after(g: Formula) -> Formula:  # truth of g at w in M|ψ, for w ⊨ ψ
        hit = memo.get(g)
        if hit is not None:
            return hit
        out = _map_bool(g, after)
        if out is not None:
            pass
        elif isinstance(g, K):
            out = K(g.agent, box(g.arg))
        elif isinstance(g, Kw):
            out = Or((K(g.agent, box(g.arg)), K(g.agent, box(Not(g.arg)))))
        elif isinstance(g, E):
            out = conj(K(a, box(g.arg)) for a in g.group)
        elif isinstance(g, D):
            out = D(g.group, box(g.arg))
        elif isinstance(g, C):
            raise VerificationError(f"{where}: no reduction axiom for common knowledge under a public "
                                    f"announcement (it needs relativised C); use delkit.verify.prove, which "
                                    f"encodes announcements directly, or the explicit model checker")
        else:  # pragma: no cover - static input only
            raise TypeError(f"unexpected {g!r}")
        memo[g] = out
        return out

    return box(chi)


def _update(model: EventModel, event: int, chi: Formula, red, where: str) -> Formula:
    """[E,e]χ for static χ by the DEL reduction axioms with factual change."""
    pres = [red(p) for p in model.pre]
    for p in pres:
        if _has_c(p):
            raise VerificationError(f"{where}: an event precondition of {model.name!r} uses common "
                                    f"knowledge; [E,e] cannot be reduced then")
    memo: dict[tuple[int, Formula], Formula] = {}

    def box(e: int, g: Formula) -> Formula:  # [E,e]g
        return Implies(pres[e], after(e, g))

    def after(e: int, g: Formula) -> Formula:  # truth of g at (w,e) in M⊗E, for w ⊨ pre(e)
        key = (e, g)
        hit = memo.get(key)
        if hit is not None:
            return hit
        if isinstance(g, Prop):
            out = model.post[e].get(g.name, g)
        elif (b := _map_bool(g, lambda h: after(e, h))) is not None:
            out = b
        elif isinstance(g, K):
            out = _k_after(g.agent, e, g.arg)
        elif isinstance(g, Kw):
            out = Or((_k_after(g.agent, e, g.arg), _k_after(g.agent, e, Not(g.arg))))
        elif isinstance(g, E):
            out = conj(_k_after(a, e, g.arg) for a in g.group)
        elif isinstance(g, D):
            succ = None
            for a in g.group:
                s = set(int(f) for f in model.relation(a).successors(e))
                succ = s if succ is None else succ & s
            out = conj(D(g.group, box(f, g.arg)) for f in sorted(succ or ()))
        elif isinstance(g, C):
            raise VerificationError(f"{where}: no reduction axiom for common knowledge under [E,e]; "
                                    f"use the explicit model checker")
        else:  # pragma: no cover
            raise TypeError(f"unexpected {g!r}")
        memo[key] = out
        return out

    def _k_after(a: str, e: int, g: Formula) -> Formula:
        return conj(K(a, box(int(f), g)) for f in model.relation(a).successors(e))

    return box(event, chi)


# ============================================================================ macros


@dataclass(frozen=True)
class MacroCheck:
    """Result of :func:`check_macro`. ``problems`` names each mismatch (empty iff ``equivalent``);
    ``bounded`` is True if some non-propositional precondition was compared only by bounded search."""

    equivalent: bool
    problems: tuple[str, ...] = ()
    events_compared: int = 0
    bounded: bool = False


def check_macro(macro: EventModel, sequence: Sequence[EventModel], *, logic: str = "S5",
                worlds: int = 3) -> MacroCheck:
    """Symbolically check that ``macro`` is the composition of ``sequence`` (E₁;…;Eₙ).

    The reference is ``compose_all(sequence)`` (no pruning). Events are matched by name. For every
    matched event e: ``⊨ pre_m(e) ↔ pre_s(e)`` and ``⊨ pre_s(e) → (post_m(e)(p) ↔ post_s(e)(p))`` for
    every proposition either side assigns; events of the reference missing from the macro need an
    unsatisfiable precondition; relations and designated events must coincide on the common events.
    Propositional conditions are decided by z3; others are reduced (:func:`reduce`) and, if still
    modal, checked by :func:`prove` with ``logic``/``worlds`` (then ``bounded`` is set).
    """
    from delkit.models.compose import compose_all

    ref = compose_all(list(sequence))
    problems: list[str] = []
    bounded = False

    def is_valid(f: Formula) -> tuple[bool, str]:
        nonlocal bounded
        g = reduce(f)
        if is_propositional(g):
            cex = counterexample(g)
            return cex is None, "" if cex is None else f" (e.g. where {_val_text(cex)})"
        bounded = True
        v = prove(g, logic=logic, worlds=worlds)
        return v.valid, "" if v.valid else " (counter-model found)"

    m_idx = {n: i for i, n in enumerate(macro.events)}
    r_idx = {n: i for i, n in enumerate(ref.events)}
    for n in macro.events:
        if n not in r_idx:
            problems.append(f"macro event {n!r} is not an event of the sequence (events: {list(ref.events)})")
    common = [n for n in ref.events if n in m_idx]
    for n in ref.events:
        if n in m_idx:
            continue
        ok, why = is_valid(Not(ref.pre[r_idx[n]]))
        if not ok:
            problems.append(f"event {n!r} of the sequence is missing from the macro but can happen{why}")
    for n in common:
        i, j = m_idx[n], r_idx[n]
        ok, why = is_valid(Iff(macro.pre[i], ref.pre[j]))
        if not ok:
            problems.append(f"event {n!r}: precondition {show(macro.pre[i])} differs from the sequence's "
                            f"{show(ref.pre[j])}{why}")
        for p in sorted(set(macro.post[i]) | set(ref.post[j])):
            pm, pr = macro.post[i].get(p, Prop(p)), ref.post[j].get(p, Prop(p))
            ok, why = is_valid(Implies(ref.pre[j], Iff(pm, pr)))
            if not ok:
                problems.append(f"event {n!r}: postcondition of {p!r} is {show(pm)} in the macro but "
                                f"{show(pr)} in the sequence{why}")
    if set(macro.agents) != set(ref.agents):
        problems.append(f"agents differ: macro {sorted(macro.agents)} vs sequence {sorted(ref.agents)}")
    else:
        for a in ref.agents:
            mm = macro.relation(a).to_matrix()
            rm = ref.relation(a).to_matrix()
            for x in common:
                for y in common:
                    if bool(mm[m_idx[x], m_idx[y]]) != bool(rm[r_idx[x], r_idx[y]]):
                        problems.append(f"relation of {a!r} differs on ({x!r}, {y!r})")
    des_m = {macro.events[d] for d in macro.designated}
    des_r = {ref.events[d] for d in ref.designated}
    # the macro designates nothing the sequence does not, and every designated event of the sequence that it
    # keeps (one it leaves out must be impossible, checked above); the message shows both whole sets
    if des_m - des_r or (des_r & set(common)) - des_m:
        problems.append(f"designated events differ: macro {sorted(des_m)} vs sequence {sorted(des_r)}")
    return MacroCheck(not problems, tuple(problems), len(common), bounded)


def _val_text(v: dict[str, bool]) -> str:
    return ", ".join(f"{p}={'T' if b else 'F'}" for p, b in v.items()) or "any valuation"


# ============================================================================ bounded model search


@dataclass(frozen=True)
class Verdict:
    """Answer of :func:`prove`.

    ``valid`` – no counter-model was found with at most ``worlds`` worlds (a proof if ``exact``);
    ``stats`` – solver time and the small-model bound used for exactness (if any);
    ``counter_model`` – a pointed model (designated world 0) where the formula is false, re-checked by the
    explicit model checker; ``logic`` – S5, KD45 or K; ``exact`` – True when the answer is a proof of
    validity/invalidity (always for invalid; for valid only if the formula is propositional).
    """

    formula: Formula
    valid: bool
    counter_model: KripkeModel | None
    logic: str
    worlds: int
    exact: bool
    stats: dict = field(default_factory=dict, compare=False)

    def to_dict(self) -> dict:
        """A JSON-ready summary (the counter-model in the :mod:`delkit.io.formats` schema)."""
        out = {"formula": show(self.formula), "valid": self.valid, "logic": self.logic, "worlds": self.worlds,
               "exact": self.exact}
        if self.counter_model is not None:
            from delkit.io.formats import model_to_dict

            out["counter_model"] = model_to_dict(self.counter_model)
        return out


def _symbols(f: Formula, props: Iterable[str], agents: Iterable[str]) -> tuple[tuple[str, ...], tuple[str, ...]]:
    ps: set[str] = set(props)
    ags: set[str] = set(agents) | agents_of(f)
    for g in subformulas(f):
        if isinstance(g, Prop):
            ps.add(g.name)
        elif isinstance(g, Update):
            ags |= set(g.model.agents)
            for pre in g.model.pre:
                ps |= {h.name for h in subformulas(pre) if isinstance(h, Prop)}
                ags |= agents_of(pre)
            for post in g.model.post:
                ps |= set(post)
                for v in post.values():
                    ps |= {h.name for h in subformulas(v) if isinstance(h, Prop)}
    return tuple(sorted(ps)), tuple(sorted(ags))


def _reduce_updates(f: Formula) -> Formula:
    """Reduce the [E,e] operators (not the announcements, which the encoding handles directly)."""
    if not any(isinstance(g, Update) for g in subformulas(f)):
        return f
    memo: dict[Formula, Formula] = {}

    def go(g: Formula) -> Formula:
        hit = memo.get(g)
        if hit is not None:
            return hit
        if isinstance(g, Update):
            out = reduce(g)
        elif (s := _map_static(g, go)) is not None:
            out = s
        elif isinstance(g, Announce):
            out = Announce(go(g.announced), go(g.arg))
        else:  # pragma: no cover
            raise TypeError(g)
        memo[g] = out
        return out

    return go(f)


class _Encoding:
    """k symbolic worlds: valuation variables, relation variables, frame constraints, formula unfolding."""

    def __init__(self, k: int, props: tuple[str, ...], agents: tuple[str, ...], logic: str) -> None:
        import z3

        self.z3 = z3
        self.k, self.props, self.agents, self.logic = k, props, agents, logic
        self.val = {(p, w): z3.Bool(f"{p}@{w}") for p in props for w in range(k)}
        self.rel = {(a, w, v): z3.Bool(f"R_{a}({w},{v})") for a in agents for w in range(k) for v in range(k)}
        self.constraints: list = []
        self.memo: dict = {}
        self.closures: dict = {}
        self.doms: dict[tuple[Formula, ...], list] = {(): [z3.BoolVal(True)] * k}
        self._frame()

    def _frame(self) -> None:
        z3, k, R = self.z3, self.k, self.rel
        ws = range(k)
        for a in self.agents:
            if self.logic == "S5":
                self.constraints += [R[a, w, w] for w in ws]
                self.constraints += [R[a, w, v] == R[a, v, w] for w in ws for v in ws if w < v]
            if self.logic == "KD45":
                self.constraints += [z3.Or([R[a, w, v] for v in ws]) for w in ws]
                self.constraints += [z3.Implies(z3.And(R[a, w, v], R[a, w, u]), R[a, v, u])
                                     for w in ws for v in ws for u in ws]
            if self.logic in ("S5", "KD45"):
                self.constraints += [z3.Implies(z3.And(R[a, w, v], R[a, v, u]), R[a, w, u])
                                     for w in ws for v in ws for u in ws]

    def closure(self, group: tuple[str, ...], ctx: tuple[Formula, ...]) -> list[list]:
        """T[w][v]: v reachable from w in ≥ 1 steps of ⋃_{a∈G} R_a inside the current domain (exact)."""
        key = (group, ctx)
        hit = self.closures.get(key)
        if hit is not None:
            return hit
        z3, k, dom = self.z3, self.k, self.doms[ctx]
        step = [[z3.And(dom[w], dom[v], z3.Or([self.rel[a, w, v] for a in group])) for v in range(k)]
                for w in range(k)]
        cur = step
        for r in range(max(1, math.ceil(math.log2(k))) if k > 1 else 0):
            nxt = [[z3.Bool(f"T{len(self.closures)}_{r}({w},{v})") for v in range(k)] for w in range(k)]
            for w in range(k):
                check_time()  # the encoding of k = 12 worlds is seconds of Python: the --timeout holds here
                for v in range(k):
                    self.constraints.append(nxt[w][v] == z3.Or(
                        cur[w][v], *[z3.And(cur[w][u], cur[u][v]) for u in range(k)]))
            cur = nxt
        self.closures[key] = cur
        return cur

    def dom_after(self, ctx: tuple[Formula, ...], psi: Formula) -> tuple[Formula, ...]:
        new = (*ctx, psi)
        if new not in self.doms:
            dom = self.doms[ctx]
            self.doms[new] = [self.z3.And(dom[v], self.enc(psi, v, ctx)) for v in range(self.k)]
        return new

    def enc(self, f: Formula, w: int, ctx: tuple[Formula, ...] = ()):  # noqa: C901 - one clause per operator
        key = (f, w, ctx)
        hit = self.memo.get(key)
        if hit is not None:
            return hit
        z3, k = self.z3, self.k
        if isinstance(f, Top):
            out = z3.BoolVal(True)
        elif isinstance(f, Bot):
            out = z3.BoolVal(False)
        elif isinstance(f, Prop):
            out = self.val[f.name, w]
        elif isinstance(f, Not):
            out = z3.Not(self.enc(f.arg, w, ctx))
        elif isinstance(f, And):
            out = z3.And([self.enc(a, w, ctx) for a in f.args]) if f.args else z3.BoolVal(True)
        elif isinstance(f, Or):
            out = z3.Or([self.enc(a, w, ctx) for a in f.args]) if f.args else z3.BoolVal(False)
        elif isinstance(f, Implies):
            out = z3.Implies(self.enc(f.left, w, ctx), self.enc(f.right, w, ctx))
        elif isinstance(f, Iff):
            out = self.enc(f.left, w, ctx) == self.enc(f.right, w, ctx)
        elif isinstance(f, K):
            out = self._box([f.agent], f.arg, w, ctx)
        elif isinstance(f, Kw):
            out = z3.Or(self._box([f.agent], f.arg, w, ctx), self._box([f.agent], Not(f.arg), w, ctx))
        elif isinstance(f, E):
            out = z3.And([self._box([a], f.arg, w, ctx) for a in f.group])
        elif isinstance(f, D):
            out = self._box(list(f.group), f.arg, w, ctx)
        elif isinstance(f, C):
            t = self.closure(tuple(f.group), ctx)
            out = z3.And([z3.Implies(t[w][v], self.enc(f.arg, v, ctx)) for v in range(k)])
        elif isinstance(f, Announce):
            pre = self.enc(f.announced, w, ctx)
            out = z3.Implies(pre, self.enc(f.arg, w, self.dom_after(ctx, f.announced)))
        else:  # Update is reduced beforehand
            raise VerificationError(f"cannot encode {show(f)}")
        self.memo[key] = out
        return out

    def _box(self, group: list[str], arg: Formula, w: int, ctx: tuple[Formula, ...]):
        """⋀_v (dom(v) ∧ ⋀_{a∈G} R_a(w,v)) → arg(v): K_a for one agent, D_G for a group."""
        z3, dom = self.z3, self.doms[ctx]
        return z3.And([z3.Implies(z3.And(dom[v], *[self.rel[a, w, v] for a in group]), self.enc(arg, v, ctx))
                       for v in range(self.k)])

    def model(self, solution) -> KripkeModel:
        z3, k = self.z3, self.k

        def tv(x) -> bool:
            return bool(z3.is_true(solution.eval(x, model_completion=True)))

        val = np.array([[tv(self.val[p, w]) for p in self.props] for w in range(k)], dtype=bool).reshape(k, -1)
        rels = {}
        for a in self.agents:
            r = Relation.from_pairs(k, [(w, v) for w in range(k) for v in range(k) if tv(self.rel[a, w, v])])
            rels[a] = r.as_partition() if self.logic == "S5" else r
        return KripkeModel(self.props, self.agents, val, rels, (0,))


def find_model(formula: Formula | str, *, logic: str = "S5", worlds: int = 4, props: Iterable[str] = (),
               agents: Iterable[str] = (), min_worlds: int = 1) -> KripkeModel | None:
    """A model of the given frame class with at most ``worlds`` worlds whose world 0 satisfies ``formula``.

    Tries 1, 2, …, ``worlds`` worlds (so the model returned is one of the smallest), and returns None if
    there is none that small. The model is re-checked by the explicit model checker (and the frame
    class by :meth:`KripkeModel.frame_violations`); :class:`VerificationError` if either disagrees.
    [E,e] operators are reduced first (:func:`reduce`); announcements are encoded directly.
    """
    import z3

    f = _f(formula)
    logic = logic.upper()
    if logic not in LOGICS:
        raise VerificationError(f"unknown logic {logic!r}; use one of {', '.join(LOGICS)}")
    if worlds < 1:
        raise VerificationError(f"need at least 1 world for the model search, got {worlds}")
    ps, ags = _symbols(f, props, agents)
    g = _reduce_updates(f)
    for k in range(max(1, min_worlds), worlds + 1):
        enc = _Encoding(k, ps, ags, logic)
        try:
            goal = enc.enc(g, 0)
            s = z3.Solver()
            s.add(*enc.constraints)
            s.add(goal)
            from delkit.resources import remaining, time_limit

            check_time()
            left = remaining()  # z3 runs in C: the alarm cannot interrupt it, its own timeout can
            if left is not None:
                s.set("timeout", max(1, int(left * 1000)))
            res = s.check()
            if res == z3.unknown and left is not None and remaining() <= 0.05:
                raise time_limit()
        except (RecursionError, ctypes.ArgumentError) as exc:
            # z3's Python API converts terms recursively: its ctypes calls report Python's recursion limit as
            # an ArgumentError wrapping the RecursionError
            if isinstance(exc, ctypes.ArgumentError) and "RecursionError" not in str(exc):
                raise
            raise VerificationError(f"{show(f)[:80]}...: nested too deeply for z3 (more than a few hundred "
                                    f"operators inside each other); split the formula or flatten chains "
                                    f"with E{{...}} / C{{...}}") from None
        if res == z3.unknown:  # pragma: no cover - propositional + finite domains: z3 decides
            raise VerificationError(f"z3 returned unknown for {show(f)} with {k} worlds: {s.reason_unknown()}")
        if res == z3.sat:
            m = enc.model(s.model())
            bad = m.frame_violations(logic)
            if bad:
                raise VerificationError(f"internal error: z3 model is not {logic} ({'; '.join(bad)}) for "
                                        f"{show(f)}; please report")
            if not bool(m.check(f)[0]):
                raise VerificationError(f"internal error: the explicit checker rejects the z3 model of "
                                        f"{show(f)} ({m.summary()}); please report")
            return m
    return None


def s5_single_agent_bound(formula: Formula | str) -> int | None:
    """Small-model bound for single-agent S5: 1 + the number of distinct modal subformulas (Kw counted
    twice), or None if the formula has more than one agent or a dynamic operator.

    Why it suffices (the filtration argument of Ladner 1977 / Fagin et al., *Reasoning about Knowledge*
    §3.6): an S5 model for one agent is, from the actual world, one cluster; every ¬K_a ψ true there
    needs one witness world and every other modal subformula keeps its truth value in any sub-cluster
    that keeps the witnesses. With one agent, E, C and D of {a} all coincide with K_a on S5 frames.
    """
    f = _f(formula)
    if len(agents_of(f)) > 1:
        return None
    count = 0
    for g in subformulas(f):
        if isinstance(g, (Announce, Update)):
            return None
        if isinstance(g, Kw):
            count += 2
        elif isinstance(g, (K, E, C, D)):
            count += 1
    return count + 1


def prove(formula: Formula | str, *, logic: str = "S5", worlds: int = 4, props: Iterable[str] = (),
          agents: Iterable[str] = ()) -> Verdict:
    """Is ``formula`` valid on the frames of ``logic``? Searches a counter-model of at most ``worlds``
    worlds (a model of ¬φ at world 0, re-checked explicitly).

    The answer is exact (``Verdict.exact``) when a counter-model is found, for propositional formulas
    (one world suffices: a counter-valuation), and for single-agent S5 formulas when ``worlds`` reaches
    :func:`s5_single_agent_bound`; otherwise "valid" means "no counter-model with ≤ ``worlds`` worlds".
    """
    import time

    f = _f(formula)
    prop = is_propositional(f)
    k = 1 if prop else worlds
    t0 = time.perf_counter()
    m = find_model(Not(f), logic=logic, worlds=k, props=props, agents=agents)
    seconds = time.perf_counter() - t0
    bound = s5_single_agent_bound(f) if logic.upper() == "S5" and not set(agents) - agents_of(f) else None
    exact = prop or m is not None or (bound is not None and bound <= k)
    return Verdict(f, m is None, m, logic.upper(), k, exact=exact,
                   stats={"seconds": round(seconds, 4), "small_model_bound": bound})
