"""Writing grounded tasks as EPDDL (2026) — domain, problem and the action-type library they need — or as mA*.

**To EPDDL** (tasks with mA*-shaped :class:`~planners.task.ActionSpec` actions, read from mA* or E-PDDL 2021):

* every fluent is a 0-ary predicate, agents are declared in the problem;
* the initial state is written as an explicit model (``:worlds/:relations/:labels/:designated``): exact for
  any frame, no reliance on how each language builds finitary-S5 states;
* each action becomes events plus an action of a generated type of library ``mastar``, mirroring
  ``planners.task.build_event_model``: the real events (one ontic event; 2^m sensing outcomes; announcement
  yes/no), and ``eps`` (the skip event oblivious agents see); observability types Fully (identity),
  Partially (real events confused, ``eps`` apart) and Oblivious (everything → ``eps``);
* mA*'s executability (checked at the pointed world, *not* a precondition of the events: worlds where it
  fails still get updated) is kept exact by splitting every real event e into e⁺ (pre ∧ exe, designated as e
  is) and e⁻ (pre ∧ ¬exe, never designated) related exactly as e is;
* observers: ``(a (if full Fully else-if partial Partially else Oblivious))`` — EPDDL evaluates these on the
  state, mA* at the pointed world; the states of an mA* task are single-pointed, so they agree.

Conditional effects setting one fluent both true and false (mA* lets the later one win where both apply,
EPDDL the positive one) are written as ``(when F (p)) (when (not F) (not (p)))`` with F mA*'s resulting value.
Refused, with the action named: partial observers of an ontic action (not defined in mA*), sensed or
announced formulas with conditions (the event set would depend on the state), and ``D`` in formulas.

**To mA\\*** (the same tasks): the initial state must fit mA*'s finitary S5 — S5 relations, one designated
world, no two worlds with the same valuation; it is written as ``initially`` literals of the pointed world,
common knowledge of the disjunction of the worlds' valuations and, per agent and block of its partition,
common knowledge that the agent knows whether the block's formula holds.
"""

from __future__ import annotations

import itertools
import re
from collections.abc import Iterable

from delkit.errors import PlanningError
from delkit.logic.formula import TOP, And, Bot, C, D, E, Formula, Iff, Implies, K, Kw, Not, Or, Prop, Top, conj, disj
from planners.task import ActionSpec, Task

__all__ = ["to_epddl", "to_mastar", "epddl_formula", "mastar_formula"]

_NAME = re.compile(r"^[A-Za-z][A-Za-z0-9_\-]*$")


def _check_names(task: Task) -> None:
    for kind, names in (("fluent", task.props), ("agent", task.agents), ("action", [a.name for a in task.actions])):
        for n in names:
            if not _NAME.match(n) or n in ("and", "or", "not", "imply", "true", "false", "All", "default"):
                raise PlanningError(f"{task.source}: {kind} name {n!r} is not an EPDDL identifier")


def _group(g: Iterable[str]) -> str:
    g = list(g)
    return g[0] if len(g) == 1 else "(" + " ".join(g) + ")"


def epddl_formula(f: Formula) -> str:  # noqa: C901 - one clause per operator
    """A delkit formula in EPDDL syntax (E_G is [G]: a conjunction of boxes; C is transitive in both)."""
    if isinstance(f, Top):
        return "true"
    if isinstance(f, Bot):
        return "false"
    if isinstance(f, Prop):
        return f"({f.name})"
    if isinstance(f, Not):
        return f"(not {epddl_formula(f.arg)})"
    if isinstance(f, And):
        return "(and " + " ".join(epddl_formula(g) for g in f.args) + ")"
    if isinstance(f, Or):
        return "(or " + " ".join(epddl_formula(g) for g in f.args) + ")"
    if isinstance(f, Implies):
        return f"(imply {epddl_formula(f.left)} {epddl_formula(f.right)})"
    if isinstance(f, Iff):
        a, b = epddl_formula(f.left), epddl_formula(f.right)
        return f"(and (imply {a} {b}) (imply {b} {a}))"
    if isinstance(f, K):
        return f"([{f.agent}] {epddl_formula(f.arg)})"
    if isinstance(f, Kw):
        return f"([Kw. {f.agent}] {epddl_formula(f.arg)})"
    if isinstance(f, E):
        return f"([{_group(f.group)}] {epddl_formula(f.arg)})"
    if isinstance(f, C):
        return f"([C. {_group(f.group)}] {epddl_formula(f.arg)})"
    if isinstance(f, D):
        raise PlanningError("distributed knowledge (D) has no EPDDL syntax")
    raise PlanningError(f"cannot write {type(f).__name__} formulas in EPDDL")


def _type_name(kind: str, outcomes: int, exe: bool) -> str:
    return f"mastar-{kind}-{outcomes}" + ("-exe" if exe else "")


def _library_type(kind: str, outcomes: int, exe: bool) -> str:
    """An action type: real events r1..rk (split into ±), eps; Fully / Partially / Oblivious."""
    reals = [f"?r{i}" for i in range(1, outcomes + 1)]
    if exe:
        evs = [x for r in reals for x in (r + "p", r + "m")]
        group = {x: r for r in reals for x in (r + "p", r + "m")}
    else:
        evs = list(reals)
        group = {r: r for r in reals}
    des = [e for e in evs if (not exe or e.endswith("p")) and (kind != "announcement" or group[e] == "?r1")]
    full = " ".join(f"({a} {b})" for a in evs for b in evs if group[a] == group[b]) + " (?eps ?eps)"
    part = " ".join(f"({a} {b})" for a in evs for b in evs) + " (?eps ?eps)"
    obl = " ".join(f"({a} ?eps)" for a in [*evs, "?eps"])
    return (f"    (:action-type {_type_name(kind, outcomes, exe)}\n"
            f"        :events ({' '.join(evs)} ?eps)\n"
            f"        :observability-types (Fully Partially Oblivious)\n"
            f"        :relations (Fully (:and {full})\n"
            f"                    Partially (:and {part})\n"
            f"                    Oblivious (:and {obl}))\n"
            f"        :designated ({' '.join(des)}))\n")


def _outcomes(act: ActionSpec) -> list[tuple[Formula, list[tuple[str, bool, Formula]]]]:
    """(precondition, effects) of the real events of an mA* action, as ``build_event_model`` makes them."""
    if act.kind == "ontic":
        if act.partial:
            raise PlanningError(f"{act.where}: {act.name}: partial observers of an ontic action do not fit")
        seen: dict[str, set[bool]] = {}
        for p, v, _c in act.effects:
            seen.setdefault(p, set()).add(v)
        effects = []
        for p, vs in seen.items():
            mine = [(q, v, c) for q, v, c in act.effects if q == p]
            if len(vs) == 1:
                effects += mine
                continue
            # both values under conditions: mA* folds them in order (the later wins where both apply);
            # write the resulting p' = F exactly as (when F p) (when ¬F ¬p)
            new: Formula = Prop(p)
            for _q, v, c in mine:
                keep = conj([Not(c), new])
                new = Or((c, keep)) if v else keep
            effects += [(p, True, new), (p, False, Not(new))]
        return [(TOP, effects)]
    if any(c != TOP for _f, c in act.sensed):
        raise PlanningError(f"{act.where}: {act.name}: sensed/announced formulas with conditions do not fit an "
                            f"EPDDL action type (the set of events would depend on the state)")
    sensed = [f for f, _c in act.sensed]
    if act.kind == "announcement":
        phi = conj(sensed) if sensed else TOP
        return [(phi, []), (Not(phi), [])]
    if not sensed:
        return [(TOP, [])]
    return [(conj([f if b else Not(f) for f, b in zip(sensed, bits, strict=True)]), [])
            for bits in itertools.product((True, False), repeat=len(sensed))]


def _effects_text(effects: list[tuple[str, bool, Formula]]) -> str:
    items = []
    for p, v, c in effects:
        lit = f"({p})" if v else f"(not ({p}))"
        items.append(lit if c == TOP else f"(when {epddl_formula(c)} {lit})")
    return "(:and " + " ".join(items) + ")"


def _obs_text(act: ActionSpec, agents: tuple[str, ...]) -> str:
    full = {a: c for a, c in act.full}
    part = {a: c for a, c in act.partial}
    items = []
    for a in agents:
        if a not in full and a not in part:
            continue
        if full.get(a) == TOP:
            items.append(f"({a} Fully)")
            continue
        chain = []
        if a in full:
            chain.append(f"if {epddl_formula(full[a])} Fully")
        if a in part:
            chain.append(f"{'else-if' if chain else 'if'} {epddl_formula(part[a])} Partially")
        items.append(f"({a} ({' '.join(chain)} else Oblivious))")
    items.append("(default Oblivious)")
    return "(:and " + " ".join(items) + ")"


def to_epddl(task: Task, name: str | None = None) -> tuple[str, str, str]:
    """(domain, problem, library) texts of ``task`` (see the module docstring)."""
    _check_names(task)
    name = re.sub(r"[^A-Za-z0-9_\-]", "-", name or task.name) or "task"
    if not name[0].isalpha():
        name = "t-" + name
    for a in task.actions:
        if not isinstance(a, ActionSpec):
            raise PlanningError(f"{task.source}: action {a.name!r} is not an mA*-shaped action; only tasks read "
                                f"from mA* or E-PDDL (2021) can be written as EPDDL")
    types: dict[str, str] = {}
    events, acts = [], []
    for act in task.actions:
        outs = _outcomes(act)
        exe = act.executable != TOP
        tname = _type_name(act.kind, len(outs), exe)
        types.setdefault(tname, _library_type(act.kind, len(outs), exe))
        refs = []
        for i, (pre, eff) in enumerate(outs, 1):
            variants = [(pre, "p"), (conj([pre, Not(act.executable)]), "m")] if exe else [(pre, "")]
            for j, (pf, suffix) in enumerate(variants):
                p = conj([pf, act.executable]) if exe and j == 0 else pf
                ev = f"ev-{act.name}-{i}{suffix}"
                events.append(f"    (:event {ev}\n        :precondition {epddl_formula(p)}"
                              + (f"\n        :effects {_effects_text(eff)}" if eff else "") + ")\n")
                refs.append(f"({ev})")
        refs.append("(eps)")
        acts.append(f"    (:action {act.name}\n        :action-type ({tname} {' '.join(refs)})\n"
                    f"        :observability-conditions {_obs_text(act, task.agents)})\n")
    library = ("(define (action-type-library mastar)\n"
               "    (:requirements :partial-observability :multi-pointed-models)\n"
               + "".join(types[t] for t in sorted(types)) + ")\n")
    domain = (f"(define (domain {name})\n"
              f"    (:requirements :partial-observability :ontic-actions :conditional-effects :modal-preconditions)\n"
              f"    (:action-type-libraries mastar)\n"
              f"    (:predicates {' '.join(f'({p})' for p in task.props)})\n"
              f"    (:event eps)\n" + "".join(events) + "".join(acts) + ")\n")
    m = task.initial
    wn = [f"w{i}" for i in range(m.n_worlds)]
    rel = []
    for a in task.agents:
        pairs = m.relations[a].pairs()
        rel.append(f"{a} (:and {' '.join(f'({wn[int(x)]} {wn[int(y)]})' for x, y in pairs)})")
    labels = []
    for w in range(m.n_worlds):
        labels.append(f"{wn[w]} (:and {' '.join(f'({p})' for p in sorted(m.true_props(w)))})")
    problem = (f"(define (problem {name}-problem)\n    (:domain {name})\n"
               f"    (:requirements :modal-goals)\n"
               f"    (:agents {' '.join(task.agents)})\n"
               f"    (:init\n        :worlds ({' '.join(wn)})\n"
               f"        :relations ({' '.join(rel)})\n"
               f"        :labels ({' '.join(labels)})\n"
               f"        :designated ({' '.join(wn[d] for d in m.designated)}))\n"
               f"    (:goal {epddl_formula(task.goal)}))\n")
    return domain, problem, library


# ----------------------------------------------------------------------------- mA*
def mastar_formula(f: Formula) -> str:  # noqa: C901 - one clause per operator
    """A delkit formula in mA* syntax (``B(a, φ)``, ``C([a,b], φ)``; ``,`` is ∧, ``|`` is ∨, ``-`` is ¬)."""
    if isinstance(f, (Top, Bot)):
        raise PlanningError("mA* has no constant true/false formulas")
    if isinstance(f, Prop):
        return f.name
    if isinstance(f, Not):
        return f"-({mastar_formula(f.arg)})" if not isinstance(f.arg, Prop) else f"-{f.arg.name}"
    if isinstance(f, And):
        return "(" + ", ".join(mastar_formula(g) for g in f.args) + ")"
    if isinstance(f, Or):
        return "(" + " | ".join(mastar_formula(g) for g in f.args) + ")"
    if isinstance(f, Implies):
        return mastar_formula(Or((Not(f.left), f.right)))
    if isinstance(f, Iff):
        return mastar_formula(Or((And((f.left, f.right)), And((Not(f.left), Not(f.right))))))
    if isinstance(f, K):
        return f"B({f.agent}, {mastar_formula(f.arg)})"
    if isinstance(f, Kw):
        return f"(B({f.agent}, {mastar_formula(f.arg)}) | B({f.agent}, {mastar_formula(Not(f.arg))}))"
    if isinstance(f, E):
        return f"E([{','.join(f.group)}], {mastar_formula(f.arg)})"
    if isinstance(f, C):
        return f"C([{','.join(f.group)}], {mastar_formula(f.arg)})"
    raise PlanningError(f"cannot write {type(f).__name__} formulas in mA*")


def _world_formula(props: tuple[str, ...], row) -> Formula:
    return conj([Prop(p) if v else Not(Prop(p)) for p, v in zip(props, row, strict=True)])


def to_mastar(task: Task) -> str:
    """The task as one mA* file (see the module docstring); :class:`PlanningError` if it does not fit."""
    _check_names(task)
    m = task.initial
    if len(m.designated) != 1:
        raise PlanningError(f"{task.source}: the initial state has {len(m.designated)} designated worlds; mA* "
                            f"describes single-pointed states")
    if not m.is_s5():
        raise PlanningError(f"{task.source}: the initial state is not S5; mA* initial states are finitary S5")
    rows = [tuple(bool(x) for x in r) for r in m.valuation.tolist()]
    if len(set(rows)) != len(rows):
        raise PlanningError(f"{task.source}: two initial worlds have the same valuation; mA*'s finitary S5 "
                            f"cannot tell them apart")
    out = [f"% written by delkit convert from {task.source}",
           "fluent " + ", ".join(task.props) + ";",
           "action " + ", ".join(a.name for a in task.actions) + ";",
           "agent " + ", ".join(task.agents) + ";", ""]
    for act in task.actions:
        if not isinstance(act, ActionSpec):
            raise PlanningError(f"{task.source}: action {act.name!r} is a general event model; only mA*-shaped "
                                f"actions can be written as mA*")
        if act.executable != TOP:
            out.append(f"executable {act.name} if {mastar_formula(act.executable)};")
        for p, v, c in act.effects:
            out.append(f"{act.name} causes {'' if v else '-'}{p}" + ("" if c == TOP else f" if {mastar_formula(c)}")
                       + ";")
        verb = {"sensing": "determines", "announcement": "announces"}.get(act.kind)
        for f, c in act.sensed:
            out.append(f"{act.name} {verb} {mastar_formula(f)}" + ("" if c == TOP else f" if {mastar_formula(c)}")
                       + ";")
        for a, c in act.full:
            out.append(f"{a} observes {act.name}" + ("" if c == TOP else f" if {mastar_formula(c)}") + ";")
        for a, c in act.partial:
            out.append(f"{a} aware_of {act.name}" + ("" if c == TOP else f" if {mastar_formula(c)}") + ";")
        out.append("")
    point = rows[m.designated[0]]
    out.append("initially " + ", ".join(p if v else f"-{p}" for p, v in zip(task.props, point, strict=True)) + ";")
    everyone = f"[{','.join(task.agents)}]"
    out.append(f"initially C({everyone}, {mastar_formula(disj([_world_formula(task.props, r) for r in rows]))});")
    for a in task.agents:
        lab = m.relations[a].labels
        if lab is None:
            lab = m.relations[a].as_partition().labels
        blocks = sorted(set(int(x) for x in lab))
        if len(blocks) < 2:
            continue
        for b in blocks:
            phi = disj([_world_formula(task.props, rows[w]) for w in range(len(rows)) if int(lab[w]) == b])
            out.append(f"initially C({everyone}, B({a}, {mastar_formula(phi)}) | B({a}, {mastar_formula(Not(phi))}));")
    g = task.goal
    for part in (g.args if isinstance(g, And) else (g,)):
        out.append(f"goal {mastar_formula(part)};")
    return "\n".join(out) + "\n"

