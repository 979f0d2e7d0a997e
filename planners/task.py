"""Grounded multi-agent epistemic planning tasks (seed 004, Definition 2.1: D = ⟨F, AG, A, φ_ini, φ_goal⟩).

Both spec readers (mA* and E-PDDL) produce a :class:`Task`: the fluents, the agents, the initial pointed
Kripke model, the grounded actions and the goal formula. An :class:`ActionSpec` keeps the mA* description
of an action (type, executability, effects, observers with their conditions); :meth:`Task.event_model`
turns it into the delkit event model that applies in a given state.

Semantics (the mA* frames, as in EFP with its default ``EXE_POINTED__COND_WORLD`` mode):

* executability is checked at the pointed world: M, s ⊨ exe(A);
* observability conditions ``ag observes A if φ`` / ``ag aware_of A if φ`` are evaluated at the pointed
  world; agents that are neither fully nor partially observant are oblivious;
* ontic ``A causes l if φ``: one event whose postcondition sets l where φ holds, *per world*
  (p ↦ (φ ∧ v) ∨ (¬φ ∧ p)); full observers see it, oblivious agents relate it to the skip event ε;
* sensing ``A determines φ``: one event per truth assignment of the sensed formulas, full observers
  distinguish them, partial observers do not, oblivious agents see ε; all are designated (the actual
  one survives);
* announcement ``A announces φ``: events φ (designated) and ¬φ, observers as for sensing. Announcing a
  φ that is false at the pointed world is not executable (truthful announcement).
"""

from __future__ import annotations

import itertools
from collections.abc import Callable, Sequence

from delkit._records import DataclassFields, Factory, Record
from delkit.backends.compact import PlainEvents, PlainModel
from delkit.errors import PlanningError
from delkit.logic.formula import BOT, TOP, Formula, Not, Or, Prop, conj, show

TYPE_CHECKING = False  # typing.TYPE_CHECKING without importing typing (start-up: delkit._records)
if TYPE_CHECKING:  # numpy: imported by the reference semantics only (start-up of small tasks, see _Initial)
    from typing import Any, Literal

    from delkit.models.events import EventModel
    from delkit.models.kripke import KripkeModel

__all__ = ["ActionSpec", "MacroSpec", "EventAction", "Task", "ActionKind", "goal_conjuncts"]

if TYPE_CHECKING:
    ActionKind = Literal["ontic", "sensing", "announcement"]
else:
    ActionKind = str


class ActionSpec(Record):
    """A grounded mA* action.

    ``effects`` (ontic): ``(fluent, value, condition)``; ``sensed`` (sensing/announcement):
    ``(formula, condition)``; ``full``/``partial``: ``(agent, condition)`` observability statements.
    Several statements for one agent are read as a disjunction of their conditions.

    The task's records are frozen and compared, hashed, printed and replaced (``dataclasses.replace``) as
    ``@dataclass(frozen=True)`` records are; they are written by hand for start-up time (:mod:`delkit._records`).
    """

    __dataclass_fields__ = DataclassFields("name", ("kind", "ontic"), ("executable", TOP), ("effects", ()),
                                           ("sensed", ()), ("full", ()), ("partial", ()), ("where", ""))
    name: str
    kind: ActionKind
    executable: Formula
    effects: tuple[tuple[str, bool, Formula], ...]
    sensed: tuple[tuple[Formula, Formula], ...]
    full: tuple[tuple[str, Formula], ...]
    partial: tuple[tuple[str, Formula], ...]
    where: str

    def __init__(self, name: str, kind: ActionKind = "ontic", executable: Formula = TOP,
                 effects: tuple[tuple[str, bool, Formula], ...] = (), sensed: tuple[tuple[Formula, Formula], ...] = (),
                 full: tuple[tuple[str, Formula], ...] = (), partial: tuple[tuple[str, Formula], ...] = (),
                 where: str = "") -> None:
        self.__dict__.update(name=name, kind=kind, executable=executable, effects=effects, sensed=sensed, full=full,
                             partial=partial, where=where)

    def observers(self, model: KripkeModel, agents: tuple[str, ...]) -> tuple[frozenset[str], frozenset[str]]:
        """(fully, partially) observant agents, conditions evaluated at the pointed world(s)."""
        full = {a for a, cond in self.full if model.holds(cond)}
        partial = {a for a, cond in self.partial if model.holds(cond)} - full
        return frozenset(full), frozenset(partial)

    def active_sensed(self, model: KripkeModel) -> tuple[Formula, ...]:
        """Sensed/announced formulas whose condition holds at the pointed world."""
        return tuple(f for f, cond in self.sensed if model.holds(cond))


class EventAction(Record):
    """A grounded action given as a general event model (EPDDL action types, hand-made event models).

    Its event model may depend on the state only through the truth of ``conditions`` in the state (a formula
    holds in a state when it holds in every designated world — e.g. EPDDL observability conditions, evaluated
    before the update): the planner evaluates them and calls ``build(bits)`` with one bool per condition
    (results are cached per bits). The action is applicable in a state s iff ``executable`` holds in s and
    every designated world of s satisfies the precondition of at least one designated event; the designated
    worlds of the result are the pairs (w, e) of designated w and designated e with w ⊨ pre(e).

    ``designated_pre``, when given, are the preconditions of the designated events of every event model
    ``build`` returns (EPDDL: only the observability relations depend on the conditions): the planner reads
    from them which actions cannot apply at a valuation without building their event models. It is checked
    against each model built (:meth:`Task.event_model_for_bits`).
    """

    __dataclass_fields__ = DataclassFields("name", "build", ("conditions", ()), ("executable", TOP), ("where", ""),
                                           ("kind", "event"), ("designated_pre", None), ("event_labels", None))
    name: str
    build: Callable[[tuple[bool, ...]], EventModel]
    conditions: tuple[Formula, ...]
    executable: Formula
    where: str
    kind: str
    designated_pre: tuple[Formula, ...] | None
    #: the user's name of each event of the event models ``build`` returns (EPDDL: the domain's events with
    #: their arguments, where the event model names the action type's event parameters), for messages
    event_labels: tuple[str, ...] | None

    def __init__(self, name: str, build: Callable[[tuple[bool, ...]], EventModel],
                 conditions: tuple[Formula, ...] = (), executable: Formula = TOP, where: str = "", kind: str = "event",
                 designated_pre: tuple[Formula, ...] | None = None,
                 event_labels: tuple[str, ...] | None = None) -> None:
        self.__dict__.update(name=name, build=build, conditions=conditions, executable=executable, where=where,
                             kind=kind, designated_pre=designated_pre, event_labels=event_labels)


class MacroSpec(Record):
    """A macro-action (seed 004, Definition 4.1): the grounded steps ``A_1; …; A_n`` offered to the planner as
    one action whose transition is Φ(A_n, … Φ(A_1, s)).

    In a state s its event model is the composition E_1;…;E_n (``delkit.models.compose``) of the steps' event
    models, each step's observers decided in the state the previous steps lead to; it is applicable iff
    every step is. ``planners.macros`` builds these from a spec's macro declarations (and proves each
    composition equal to its sequence with z3); plans are flattened back to ``steps``' names.
    """

    __dataclass_fields__ = DataclassFields("name", "steps", ("where", ""), ("kind", "macro"))
    name: str
    steps: tuple[ActionSpec, ...]
    where: str
    kind: str

    def __init__(self, name: str, steps: tuple[ActionSpec, ...], where: str = "", kind: str = "macro") -> None:
        self.__dict__.update(name=name, steps=steps, where=where, kind=kind)

    @property
    def step_names(self) -> tuple[str, ...]:
        return tuple(s.name for s in self.steps)


class _Initial:
    """The ``initial`` field of :class:`Task`: given as a KripkeModel, or as a
    :class:`~delkit.backends.compact.PlainModel`
    (what the readers build for small tasks, without numpy), which is converted to a KripkeModel when
    ``task.initial`` is first read — the compact backend reads ``task.plain_initial`` and never converts."""

    def __set_name__(self, owner: type, name: str) -> None:
        self.slot = "_" + name

    def __get__(self, obj: Any, objtype: Any = None) -> Any:
        if obj is None:
            raise AttributeError(self.slot)  # no class-level value
        v = obj.__dict__[self.slot]
        if isinstance(v, PlainModel):
            v = v.kripke()
        return v

    def __set__(self, obj: Any, value: Any) -> None:
        obj.__dict__[self.slot] = value


class Task(Record):
    """A grounded epistemic planning task (``initial``: a KripkeModel, or a PlainModel read as one)."""

    __dataclass_fields__ = DataclassFields("name", "props", "agents", "initial", "actions", "goal",
                                           ("source", "<task>"),
                                           ("_cache", Factory(dict, repr=False, compare=False, hash=False)))
    name: str
    props: tuple[str, ...]
    agents: tuple[str, ...]
    initial: KripkeModel = _Initial()  # type: ignore[assignment]
    actions: tuple[ActionSpec | MacroSpec | EventAction, ...]
    goal: Formula
    source: str
    _cache: dict

    def __init__(self, name: str, props: tuple[str, ...], agents: tuple[str, ...], initial: KripkeModel | PlainModel,
                 actions: tuple[ActionSpec | MacroSpec | EventAction, ...], goal: Formula, source: str = "<task>",
                 _cache: dict | None = None) -> None:
        self.__dict__.update(name=name, props=props, agents=agents, _initial=initial, actions=actions, goal=goal,
                             source=source, _cache={} if _cache is None else _cache)

    @property
    def plain_initial(self) -> PlainModel | None:
        """The initial state as the reader gave it when that was a numpy-free PlainModel, else None."""
        v = self.__dict__["_initial"]
        return v if isinstance(v, PlainModel) else None

    def action(self, name: str) -> ActionSpec:
        """The action called ``name`` (:class:`PlanningError` listing the names if there is none)."""
        idx = self._cache.get("__idx")
        if idx is None:
            idx = {a.name: a for a in self.actions}
            self._cache["__idx"] = idx
        try:
            return idx[name]
        except KeyError:
            close = [n for n in idx if n.startswith(name[:3])][:8]
            raise PlanningError(f"{self.source}: no action named {name!r}"
                                + (f"; similar: {', '.join(close)}" if close else "")) from None

    def executable(self, act: ActionSpec | EventAction, model: KripkeModel) -> bool:
        """M, s ⊨ exe(A) at the pointed world(s)."""
        return model.holds(act.executable)

    def event_model(self, act: ActionSpec | EventAction, model: KripkeModel) -> EventModel:
        """The event model of ``act`` in the state ``model`` (observers decided at the pointed world).

        Event models are cached per (action, full observers, partial observers, active sensed formulas);
        an :class:`EventAction`'s per truth values of its conditions in ``model``.
        """
        if isinstance(act, EventAction):
            return self.event_model_for_bits(act, tuple(model.holds(c) for c in act.conditions))
        if isinstance(act, MacroSpec):
            raise PlanningError(f"{_where(act)}the macro {act.name!r} has no single event model in a state; "
                                f"apply it with planners.task.apply_action (its steps in sequence)")
        full, partial = act.observers(model, self.agents)
        sensed = act.active_sensed(model) if act.kind != "ontic" else ()
        key = (act.name, full, partial, sensed)
        em = self._cache.get(key)
        if em is None:
            em = build_event_model(act, self.agents, full, partial, sensed)
            self._cache[key] = em
        return em


    def event_model_for_bits(self, act: EventAction, bits: tuple[bool, ...]) -> EventModel:
        """``act.build(bits)`` as a delkit EventModel, cached per (action, bits)."""
        em = self.events_for_bits(act, bits)
        return em.event_model() if isinstance(em, PlainEvents) else em

    def events_for_bits(self, act: EventAction, bits: tuple[bool, ...]) -> EventModel | PlainEvents:
        """``act.build(bits)`` as built — an EventModel, or a numpy-free PlainEvents that the compact backend
        uses as it is — checked and cached per (action, bits)."""
        key = ("__event", act.name, bits)
        em = self._cache.get(key)
        if em is None:
            if len(bits) != len(act.conditions):
                raise PlanningError(f"{_where(act)}action {act.name!r} has {len(act.conditions)} condition(s) "
                                    f"{[str(c) for c in act.conditions]}; {len(bits)} truth value(s) were given")
            em = act.build(bits)
            if not isinstance(em, PlainEvents):
                from delkit.models.events import EventModel

                if not isinstance(em, EventModel):
                    raise PlanningError(f"{_where(act)}action {act.name!r} built {type(em).__name__}, not an "
                                        f"EventModel")
            if set(em.agents) != set(self.agents):
                raise PlanningError(f"{_where(act)}the event model of {act.name!r} has agents {list(em.agents)}, "
                                    f"the task {list(self.agents)}")
            if act.designated_pre is not None and tuple(em.pre[d] for d in em.designated) != act.designated_pre:
                raise PlanningError(f"{_where(act)}the event model of {act.name!r} built for conditions {bits} has "
                                    f"designated preconditions {[str(em.pre[d]) for d in em.designated]}, not the "
                                    f"declared designated_pre {[str(f) for f in act.designated_pre]}")
            self._cache[key] = em
        return em


def has_event_actions(task: Task) -> bool:
    """Whether ``task`` has :class:`EventAction` s (as the tasks read from EPDDL (2026) files do): the planner
    and the plan checker then use EPDDL's semantics (no agent-believes-⊥ pruning)."""
    return any(isinstance(a, EventAction) for a in task.actions)


def uncovered_worlds(em: EventModel | PlainEvents, model: KripkeModel) -> list[int]:
    """The designated worlds of ``model`` where no designated event of ``em`` has its precondition true (``model``
    anything with ``designated`` and a per-world ``check``: also the checker's numpy-free states)."""
    checks = [model.check(em.pre[e]) for e in em.designated]
    return [int(w) for w in model.designated if not any(c[int(w)] for c in checks)]


def applicable(em: EventModel, model: KripkeModel) -> bool:
    """Every designated world of ``model`` satisfies the precondition of some designated event of ``em``."""
    return not uncovered_worlds(em, model)


def apply_steps(task: Task, steps: Sequence[ActionSpec | EventAction], model: KripkeModel
                ) -> tuple[list[EventModel], list[KripkeModel]] | None:
    """The reference transitions of ``steps`` applied in sequence from ``model``: the event models used (each
    decided in its own intermediate state) and the states M_0..M_n, or None as soon as a step is not
    applicable (its executability fails, some designated world has no designated event, or nothing designated
    survives). Macros' proofs and :func:`apply_action` share this one definition."""
    from delkit.models.update import product_update

    ems: list[EventModel] = []
    states = [model]
    for act in steps:
        m = states[-1]
        if not m.holds(act.executable):
            return None
        em = task.event_model(act, m)
        if not applicable(em, m):
            return None
        new = product_update(m, em)
        if not new.designated:
            return None
        ems.append(em)
        states.append(new)
    return ems, states


def apply_action(task: Task, act: ActionSpec | MacroSpec | EventAction, model: KripkeModel) -> KripkeModel | None:
    """The reference transition Φ(A, M) with delkit's product update (no contraction), or None when A is not
    applicable (see :func:`apply_steps`); a macro applies its steps in sequence (Definition 4.1: Φ(j, Φ(i, s)))."""
    seq = apply_steps(task, act.steps if isinstance(act, MacroSpec) else (act,), model)
    return None if seq is None else seq[1][-1]


def build_event_model(act: ActionSpec, agents: tuple[str, ...], full: frozenset[str], partial: frozenset[str],
                      sensed: tuple[Formula, ...]) -> EventModel:
    """The mA* event model of one action for given observer sets (see the module docstring), built by the
    ``delkit.models.events`` constructors (the reference; :func:`plain_event_model` is the same model without numpy)."""
    from delkit.models.events import action, ontic

    kind, outcomes, full_l, part_l, designated = _mastar_frame(act, agents, full, partial, sensed)
    if kind == "ontic":
        return ontic([(p, v, c) for p, v, c in act.effects], agents, full=full_l, name=act.name)
    return action(agents, outcomes, full=full_l, partial=part_l, designated=designated, name=act.name)


def plain_event_model(act: ActionSpec, agents: tuple[str, ...], full: frozenset[str], partial: frozenset[str],
                      sensed: tuple[Formula, ...]) -> PlainEvents:
    """:func:`build_event_model` as plain data for the compact backend: the frame of ``delkit.models.events.action``
    (full observers: identity; partial: the real events in one class, ε alone; oblivious: every event to ε,
    which exists iff someone is oblivious) and ``ontic``'s postconditions p ↦ (c ∧ v) ∨ (¬c ∧ old)."""
    kind, outcomes, full_l, part_l, designated = _mastar_frame(act, agents, full, partial, sensed)
    if kind == "ontic":
        post: dict[str, Formula] = {}
        for p, v, c in act.effects:
            value = TOP if v is True else BOT if v is False else v
            post[p] = Or((conj([c, value]), conj([Not(c), post.get(p, Prop(p))])))
        outcomes = [("e", TOP, post)]
        full_l, part_l, designated = full_l + part_l, [], None
    k = len(outcomes)
    oblivious = [a for a in agents if a not in full_l and a not in part_l]
    names = [o[0] for o in outcomes] + (["eps"] if oblivious else [])
    pres = [o[1] for o in outcomes] + ([TOP] if oblivious else [])
    posts = [o[2] for o in outcomes] + ([{}] if oblivious else [])
    n = len(names)
    real, eps = tuple(range(k)), (k,)
    rows: dict[str, list[tuple[int, ...]]] = {}
    for a in agents:
        if a in full_l:
            rows[a] = [(e,) for e in range(n)]
        elif a in part_l:
            rows[a] = [real] * k + ([eps] if oblivious else [])
        else:
            rows[a] = [eps] * n
    des = [names.index(d) for d in designated] if designated is not None else list(range(k))
    return PlainEvents(names, agents, pres, posts, rows, des, act.name)


def _mastar_frame(act: ActionSpec, agents: tuple[str, ...], full: frozenset[str], partial: frozenset[str],
                  sensed: tuple[Formula, ...]) -> tuple[str, list, list[str], list[str], list[str] | None]:
    """(kind, real events (name, pre, post), full observers, partial observers, designated event names or
    None: all) of an mA* action — the part of its event model both builders share."""
    full_l = [a for a in agents if a in full]
    part_l = [a for a in agents if a in partial]
    if act.kind == "ontic":
        if part_l:
            raise PlanningError(f"{_where(act)}agent(s) {part_l} partially observe the ontic action {act.name!r}; "
                                f"partial observability is not defined for ontic actions in mA* (make them "
                                f"fully observant or oblivious)")
        return "ontic", [], full_l, part_l, None
    if act.kind == "sensing":
        if not sensed:
            return "sensing", [("e", TOP, {})], full_l, part_l, None
        outcomes = []
        for bits in itertools.product((True, False), repeat=len(sensed)):
            pre = conj([f if b else Not(f) for f, b in zip(sensed, bits, strict=True)])
            label = "".join("1" if b else "0" for b in bits)
            outcomes.append((f"s{label}", pre, {}))
        return "sensing", outcomes, full_l, part_l, None
    if act.kind == "announcement":
        phi = conj(list(sensed)) if sensed else TOP
        return "announcement", [("yes", phi, {}), ("no", Not(phi), {})], full_l, part_l, ["yes"]
    raise PlanningError(f"{_where(act)}unknown action type {act.kind!r}")


def describe(act: ActionSpec) -> str:
    """One-line human description of an action (used by the checker's messages)."""
    parts = [f"{act.name} ({act.kind})", f"executable if {show(act.executable)}"]
    if act.effects:
        parts.append("effects " + ", ".join(("" if v else "¬") + p + ("" if c == TOP else f" if {show(c)}")
                                             for p, v, c in act.effects))
    if act.sensed:
        parts.append(("senses " if act.kind == "sensing" else "announces ")
                     + ", ".join(show(f) for f, _ in act.sensed))
    return "; ".join(parts)


def goal_conjuncts(goal: Formula) -> tuple[Formula, ...]:
    """Top-level conjuncts of a goal (nested conjunctions flattened)."""
    from delkit.logic.formula import And

    if isinstance(goal, And):
        out: list[Formula] = []
        for g in goal.args:
            out.extend(goal_conjuncts(g))
        return tuple(out)
    return (goal,)


def merge_observers(obs: list[tuple[str, Formula]]) -> list[tuple[str, Formula]]:
    """One (agent, condition) per agent: several statements are a disjunction of their conditions."""
    by: dict[str, list[Formula]] = {}
    for ag, cond in obs:
        by.setdefault(ag, []).append(cond)
    return [(ag, cs[0] if len(cs) == 1 else (TOP if TOP in cs else Or(tuple(cs)))) for ag, cs in by.items()]


def literal(p: str, value: bool) -> Formula:
    return Prop(p) if value else Not(Prop(p))


def _where(act: ActionSpec | EventAction | MacroSpec) -> str:
    """``"FILE:LINE: "`` of an action for an error message, or nothing for an action made in Python."""
    return f"{act.where}: " if act.where else ""
