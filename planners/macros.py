"""Macro-actions (seed 004, Definition 4.1): declaration, grounding, composition, proof, flattening.

Declaration — delkit's E-PDDL extension, a section of the domain beside the actions::

    (:macro pspb_and_announce
      :parameters (?ag - agent ?c - color)
      :steps ((put_on_shared ?ag ?c) (announce_block_on_barrier ?ag ?c)))

Every step names an action of the domain and its arguments (macro parameters or constants). The plain
E-PDDL reader ignores ``:macro`` sections, so a domain with macros still reads without them ("macros off").
:func:`ground_macros` turns each declaration into one :class:`~planners.task.MacroSpec` per binding of its
parameters whose steps all exist (``NAME_x_y`` like the actions); :func:`with_macros` adds them to a task;
:func:`flatten` maps a plan back to its steps.

Semantics: a macro applied in state s is Φ(A_n, … Φ(A_1, s)) (⊥ if a step is not applicable). Its event
model in s is the composition E_1;…;E_n (``delkit.models.compose``) of the steps' event models, each step's
observers decided in the state the previous steps lead to (:func:`macro_event_model`). :func:`prove_macro`
shows with z3 (``delkit.verify``) that this composed model equals the sequence: the composition pruned of
impossible events passes ``check_macro`` against the sequence, and for every event (e_1,…,e_n) and every
proposition p the reduction axioms give ``⊨ [E_1;…;E_n, e]p ↔ [E_1,e_1]…[E_n,e_n]p`` and
``⊨ ⟨E_1;…;E_n, e⟩⊤ ↔ ⟨E_1,e_1⟩…⟨E_n,e_n⟩⊤`` (modal subformulas left after reduction are abstracted to
fresh atoms: a proof of the abstraction is a proof of the formula). :func:`check_handwritten` compares a
hand-written macro action (Listing 4) with the composition of the steps and reports a counterexample
state reached by a short plan, where applicability or the result differs.
"""

from __future__ import annotations

import itertools
from collections.abc import Sequence
from dataclasses import dataclass, field, replace
from typing import Any

from delkit.errors import ParseError, PlanningError
from delkit.logic.formula import TOP, Formula, Iff, Not, Prop, Update, is_propositional, show
from delkit.models.events import EventModel
from delkit.models.kripke import KripkeModel
from planners.lang.epddl import Atom, SList, _head, _typed_list, read_sexps
from planners.task import ActionSpec, MacroSpec, Task, apply_steps

__all__ = ["MacroDecl", "parse_macros", "ground_macros", "with_macros", "flatten", "macro_event_model",
           "prove_macro", "MacroProof", "check_handwritten", "HandwrittenCheck", "sequence_states"]


@dataclass(frozen=True)
class MacroDecl:
    """A macro declaration: name, typed parameters, steps ``(action, (arg, ...))``."""

    name: str
    params: tuple[tuple[str, str], ...]
    steps: tuple[tuple[str, tuple[str, ...]], ...]
    where: str = ""


def parse_macros(domain_text: str, *, source: str = "<domain>") -> list[MacroDecl]:
    """The ``(:macro ...)`` sections of an E-PDDL domain."""
    out: list[MacroDecl] = []
    for top in read_sexps(domain_text, source):
        if _head(top) != "define" or not isinstance(top, SList):
            continue
        for sec in top.items[2:]:
            if _head(sec) != ":macro":
                continue
            assert isinstance(sec, SList)
            where = f"{source}:{sec.line}:{sec.col}"
            if len(sec.items) < 2 or not isinstance(sec.items[1], Atom):
                raise ParseError("expected (:macro NAME :parameters (...) :steps ((action ?x ...) ...))",
                                 source=source, line=sec.line, column=sec.col)
            fields: dict[str, Any] = {}
            items = sec.items[2:]
            for k, v in zip(items[::2], items[1::2], strict=False):
                if not isinstance(k, Atom) or k.text not in (":parameters", ":steps"):
                    raise ParseError(f"unexpected {getattr(k, 'text', '(...)')!r} in a macro; a macro has "
                                     ":parameters and :steps", source=source, line=k.line, column=k.col)
                fields[k.text] = v
            if len(items) % 2 or ":steps" not in fields:
                raise ParseError(f"macro {sec.items[1].text!r} needs ':steps ((action ?x ...) ...)'",
                                 source=source, line=sec.line, column=sec.col)
            params_node = fields.get(":parameters")
            params = tuple((n, t) for n, t, _ in _typed_list(params_node.items, _NoCtx(source))) \
                if isinstance(params_node, SList) else ()
            steps_node = fields[":steps"]
            if not isinstance(steps_node, SList) or not steps_node.items:
                raise ParseError("':steps' must be a non-empty list of (action ?x ...)", source=source,
                                 line=steps_node.line, column=steps_node.col)
            steps = []
            declared = {n for n, _ in params}
            for st in steps_node.items:
                if not isinstance(st, SList) or not st.items or not all(isinstance(a, Atom) for a in st.items):
                    raise ParseError("a macro step is (action arg ...)", source=source, line=st.line,
                                     column=st.col)
                args = tuple(a.text for a in st.items[1:])  # type: ignore[union-attr]
                for a in args:
                    if a.startswith("?") and a not in declared:
                        raise ParseError(f"macro {sec.items[1].text!r}: step uses {a}, which is not one of its "
                                         f"parameters ({', '.join(sorted(declared)) or 'none'})",
                                         source=source, line=st.line, column=st.col)
                steps.append((st.items[0].text, args))  # type: ignore[union-attr]
            out.append(MacroDecl(sec.items[1].text, params, tuple(steps), where))
    return out


class _NoCtx:
    """Just enough of the E-PDDL reader's context for ``_typed_list`` error messages."""

    def __init__(self, source: str) -> None:
        self.source = source

    def err(self, msg: str, at: Any, expected: list[str] | None = None) -> ParseError:
        return ParseError(msg, source=self.source, line=getattr(at, "line", None), column=getattr(at, "col", None))


def _objects(task: Task, problem_text: str) -> dict[str, list[str]]:
    objs: dict[str, list[str]] = {"agent": list(task.agents)}
    for top in read_sexps(problem_text, task.source):
        if _head(top) != "define" or not isinstance(top, SList):
            continue
        for sec in top.items[2:]:
            if _head(sec) == ":objects":
                for n, t, _ in _typed_list(sec.items[1:], _NoCtx(task.source)):  # type: ignore[union-attr]
                    objs.setdefault(t, []).append(n)
    return objs


def ground_macros(task: Task, decls: Sequence[MacroDecl], problem_text: str) -> list[MacroSpec]:
    """One MacroSpec per binding of each declaration's parameters (bindings whose steps do not all exist as
    grounded actions are skipped; a step naming an unknown action is an error)."""
    objs = _objects(task, problem_text)
    names = {a.name: a for a in task.actions if not isinstance(a, MacroSpec)}
    bases = {n.split("_")[0] for n in names}
    out: list[MacroSpec] = []
    for d in decls:
        for act, _ in d.steps:
            if not any(n == act or n.startswith(act + "_") for n in names):
                raise ParseError(f"macro {d.name!r}: step {act!r} is not an action of the domain "
                                 f"(actions start with: {', '.join(sorted(bases))})", source=d.where)
        domains = []
        for p, t in d.params:
            if t not in objs:
                raise ParseError(f"macro {d.name!r}: unknown type {t!r} of {p}", source=d.where)
            domains.append(objs[t])
        for combo in itertools.product(*domains):
            env = dict(zip([p for p, _ in d.params], combo, strict=True))
            steps = []
            for act, args in d.steps:
                g = "_".join([act, *(env.get(a, a) for a in args)])
                if g not in names:
                    break
                steps.append(names[g])
            else:
                out.append(MacroSpec("_".join([d.name, *combo]), tuple(steps), d.where))
    return out


def with_macros(task: Task, macros: Sequence[MacroSpec]) -> Task:
    """The task with the macros offered as extra actions (the primitive actions stay)."""
    return replace(task, actions=tuple(task.actions) + tuple(macros), _cache={})


def flatten(plan: Sequence[str], macros: Sequence[MacroSpec]) -> list[str]:
    """A plan with every macro name replaced by its steps' names."""
    by = {m.name: m for m in macros}
    out: list[str] = []
    for name in plan:
        out.extend(by[name].step_names if name in by else (name,))
    return out


# ----------------------------------------------------------------------------- semantics


def sequence_states(task: Task, steps: Sequence[ActionSpec], model: KripkeModel
                    ) -> tuple[list[EventModel], list[KripkeModel]] | None:
    """The steps' event models (observers decided in the intermediate states) and the states M_0..M_n, or
    None if some step is not applicable — :func:`planners.task.apply_steps`, the planner's own reference."""
    return apply_steps(task, steps, model)


def macro_event_model(task: Task, macro: MacroSpec, model: KripkeModel, *, prune: bool = False
                      ) -> EventModel | None:
    """E_1;…;E_n for ``macro`` in state ``model`` (None if a step is not applicable there)."""
    from delkit.models.compose import compose_all

    seq = sequence_states(task, macro.steps, model)
    if seq is None:
        return None
    return compose_all(seq[0], name=macro.name, prune=prune)


@dataclass(frozen=True)
class MacroProof:
    """Outcome of :func:`prove_macro`: ``equal`` iff every obligation was proved valid by z3."""

    macro: str
    equal: bool
    obligations: int
    events: int
    problems: tuple[str, ...] = ()
    bisimilar_on_state: bool | None = None

    def to_json(self) -> dict[str, Any]:
        return {"macro": self.macro, "equal": self.equal, "obligations": self.obligations, "events": self.events,
                "problems": list(self.problems), "bisimilar_on_state": self.bisimilar_on_state}


def _abstract(f: Formula, table: dict[Formula, Prop]) -> Formula:
    """Replace every maximal modal subformula by a fresh atom (sound for validity)."""
    from delkit.logic.formula import And, Implies, Or

    if is_propositional(f):
        return f
    if isinstance(f, Not):
        return Not(_abstract(f.arg, table))
    if isinstance(f, And):
        return And(tuple(_abstract(g, table) for g in f.args))
    if isinstance(f, Or):
        return Or(tuple(_abstract(g, table) for g in f.args))
    if isinstance(f, Implies):
        return Implies(_abstract(f.left, table), _abstract(f.right, table))
    if isinstance(f, Iff):
        return Iff(_abstract(f.left, table), _abstract(f.right, table))
    if f not in table:
        table[f] = Prop(f"§{len(table)}")
    return table[f]


def _valid(f: Formula) -> tuple[bool, str]:
    from delkit.verify import counterexample, reduce

    table: dict[Formula, Prop] = {}
    g = _abstract(reduce(f), table)
    cex = counterexample(g)
    if cex is None:
        return True, ""
    inv = {v.name: show(k) for k, v in table.items()}
    return False, ", ".join(f"{inv.get(p, p)}={'T' if b else 'F'}" for p, b in sorted(cex.items()))


def prove_macro(task: Task, macro: MacroSpec, model: KripkeModel | None = None, *,
                composed: EventModel | None = None) -> MacroProof:
    """Prove with z3 that the composed event model of ``macro`` in ``model`` (default: the initial state; the
    macro must be applicable there) equals the sequence of its steps. ``composed`` checks a given event
    model (events named ``e1;e2;…`` like the composition's) instead of building it."""
    from delkit.models.bisimulation import bisimilar
    from delkit.models.compose import compose_all
    from delkit.models.update import product_update
    from delkit.verify import check_macro

    model = task.initial if model is None else model
    seq = sequence_states(task, macro.steps, model)
    if seq is None:
        raise PlanningError(f"macro {macro.name}: not applicable in the given state; pass a state where it is")
    ems, states = seq
    problems: list[str] = []
    if composed is None:
        composed = compose_all(ems, name=macro.name)
        pruned = compose_all(ems, name=macro.name, prune=all(is_propositional(p) for e in ems for p in e.pre))
    else:
        pruned = composed
    mc = check_macro(pruned, ems)
    problems.extend(mc.problems)
    obligations = mc.events_compared
    props = sorted({p for e in ems for post in e.post for p in post} | set(task.props))
    for k, name in enumerate(composed.events):
        parts = name.split(";")
        idx = [ems[i].events.index(parts[i]) for i in range(len(ems))]

        def nested(arg: Formula, idx: list[int] = idx) -> Formula:
            out = arg
            for i in reversed(range(len(ems))):
                out = Update(ems[i], idx[i], out, ems[i].name)
            return out

        pairs = [(Not(Update(composed, k, Not(TOP), macro.name)), Not(nested(Not(TOP))), "⟨E⟩⊤")]
        pairs += [(Update(composed, k, Prop(p), macro.name), nested(Prop(p)), p) for p in props
                  if any(p in e.post[i] for e, i in zip(ems, idx, strict=True))]
        for left, right, what in pairs:
            obligations += 1
            ok, cex = _valid(Iff(left, right))
            if not ok:
                problems.append(f"event {name}: {what} differs (e.g. where {cex})")
    direct = product_update(model, composed)
    return MacroProof(macro.name, not problems, obligations, composed.n_events, tuple(problems),
                      bisimilar(direct, states[-1]) if direct.designated else False)


# ----------------------------------------------------------------------------- hand-written macros


@dataclass(frozen=True)
class HandwrittenCheck:
    """Outcome of :func:`check_handwritten`: ``consistent`` iff no difference was found; otherwise the
    counterexample: the plan prefix reaching the state, the grounded actions compared, what differs."""

    consistent: bool
    states_checked: int
    counterexample: dict[str, Any] = field(default_factory=dict)
    symbolic: tuple[str, ...] = ()

    def to_json(self) -> dict[str, Any]:
        return {"consistent": self.consistent, "states_checked": self.states_checked,
                "counterexample": self.counterexample, "symbolic": list(self.symbolic)}


def ground_handwritten(domain_text: str, problem_text: str, action_text: str,
                       source: str = "<macro>") -> tuple[Task, list[ActionSpec]]:
    """Ground a hand-written action (an ``(:action ...)`` form) in the domain: (task, its groundings);
    ``source`` names the file it came from in the errors."""
    from planners.lang.epddl import parse_epddl

    forms = [x for x in read_sexps(action_text, source) if _head(x) == ":action"]
    if len(forms) != 1:
        raise ParseError(f"expected exactly one (:action NAME ...) form, found {len(forms)}; write the macro as "
                         f"one (:action ...)", source=source)
    name = forms[0].items[1].text  # type: ignore[union-attr]
    body = "\n".join(ln for ln in action_text.splitlines() if not ln.lstrip().startswith(";"))
    end = domain_text.rstrip().rfind(")")
    task = parse_epddl(domain_text[:end] + "\n" + body + "\n)", problem_text)
    mine = [a for a in task.actions if isinstance(a, ActionSpec) and a.name.startswith(name + "_")]
    return task, mine


def check_handwritten(task: Task, hand: Sequence[ActionSpec], macros: Sequence[MacroSpec], *,
                      depth: int = 3, max_states: int = 400) -> HandwrittenCheck:
    """Compare hand-written macro actions with composed macros on the states reachable within ``depth``
    steps: for each state s, each macro m and each grounding h of the hand-written action whose name
    extends m's arguments, h must be applicable iff m is, and then M ⊗ E_h ≅ M ⊗ (E_1;…;E_n). Returns the
    first difference (with a plan that reaches the state) and the symbolic differences (``check_macro``)."""
    from delkit.models.bisimulation import bisimilar, contract
    from delkit.models.compose import compose_all
    from delkit.models.update import product_update
    from delkit.verify import check_macro

    prims = [a for a in task.actions if isinstance(a, ActionSpec) and a not in hand]
    frontier: list[tuple[tuple[str, ...], KripkeModel]] = [((), task.initial)]
    seen = 0
    symbolic: list[str] = []
    for _ in range(depth + 1):
        nxt: list[tuple[tuple[str, ...], KripkeModel]] = []
        for prefix, m in frontier:
            seen += 1
            for mac in macros:
                margs = mac.name.split("_")
                for h in hand:
                    if not _extends(h.name, margs):
                        continue
                    seq = sequence_states(task, mac.steps, m)
                    h_ok = task.executable(h, m)
                    h_res = product_update(m, task.event_model(h, m)) if h_ok else None
                    if h_res is not None and not h_res.designated:
                        h_res = None
                    if (seq is None) != (h_res is None):
                        return HandwrittenCheck(False, seen, {
                            "plan": list(prefix), "handwritten": h.name, "macro": mac.name,
                            "difference": (f"{h.name} is {'' if h_res is not None else 'not '}applicable but the "
                                           f"sequence {'; '.join(mac.step_names)} is "
                                           f"{'not ' if seq is None else ''}applicable"),
                            "handwritten_precondition": show(h.executable)}, tuple(symbolic))
                    if seq is not None and h_res is not None:
                        if not symbolic:
                            em = task.event_model(h, m)
                            ref = compose_all(seq[0])
                            if em.n_events == 1:
                                em = _rename_single(em, ref)
                            symbolic = list(check_macro(em, seq[0]).problems)
                        if not bisimilar(contract(h_res), contract(seq[1][-1])):
                            return HandwrittenCheck(False, seen, {
                                "plan": list(prefix), "handwritten": h.name, "macro": mac.name,
                                "difference": _diff(task, h_res, seq[1][-1])}, tuple(symbolic))
            if seen >= max_states:
                break
            for a in prims:
                r = sequence_states(task, (a,), m)
                if r is not None and not r[1][-1].inconsistent_agents():
                    nxt.append(((*prefix, a.name), contract(r[1][-1])))
        frontier = nxt
    return HandwrittenCheck(True, seen, {}, tuple(symbolic))


def _extends(hname: str, margs: list[str]) -> bool:
    """Listing 4's parameters are (?ag ?ag2 ?c ?c2) and the macro's (?ag ?c): does the grounded hand-written
    action bind ?ag and ?c as the grounded macro does?"""
    hargs = hname.split("_")[-4:]
    return hargs[0] == margs[-2] and hargs[2] == margs[-1]


def _rename_single(em: EventModel, ref: EventModel) -> EventModel:
    """A one-event model renamed to the reference's designated event (so check_macro matches them)."""
    d = ref.events[ref.designated[0]]
    return EventModel((d,), em.agents, em.pre, em.post, em.relations, em.designated, em.name)


def _diff(task: Task, a: KripkeModel, b: KripkeModel) -> str:
    """A formula of the task's language (goal atoms under beliefs) true in one result, false in the other."""
    from delkit.logic.formula import K

    cands: list[Formula] = [Prop(p) for p in task.props]
    cands += [K(ag, Prop(p)) for ag in task.agents for p in task.props]
    cands += [K(ag, Not(Prop(p))) for ag in task.agents for p in task.props]
    for f in cands:
        if a.holds(f) != b.holds(f):
            return (f"after the hand-written macro {show(f)} is {a.holds(f)}, after the sequence it is "
                    f"{b.holds(f)}")
    return "the results are not bisimilar"
