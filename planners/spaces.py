"""State spaces of a :class:`~planners.task.Task`: the transition function Φ on a chosen backend.

The planner does not implement DEL: it picks a delkit backend and asks it to apply event models.

* :class:`CompactSpace` — the compact bit-set backend (:mod:`delkit.backends.compact`), the default;
* :class:`DelSpace` — the numpy backend: ``delkit.models.update.product_update`` +
  ``delkit.models.bisimulation.contract`` +
  ``delkit.models.bisimulation.canonical_form`` on :class:`~delkit.models.kripke.KripkeModel` (reference semantics,
  ``--engine del``).

Both accept the three kinds of grounded actions of :mod:`planners.task`:

* :class:`ActionSpec` (mA*): executability and observers decided at the pointed world(s), the mA* event
  model built by ``delkit.models.events`` constructors;
* :class:`EventAction`: any event model, chosen by the truth of finitely many conditions in the state;
* :class:`MacroSpec` (seed 004, Definition 4.1): :class:`DelSpace` applies the steps in sequence,
  Φ(j, Φ(i, s)) — the definition; :class:`CompactSpace` applies the *composed* event model E₁;…;Eₙ
  (``delkit.models.compose``) once, the steps' event models chosen by their conditions in the intermediate
  states. The composition theorem (M ⊗ E₁) ⊗ E₂ ≅ M ⊗ (E₁;E₂) makes both equal; the differential tests
  check it along plans.

States are contracted and deduplicated by their canonical key. No vacuous success: a state where some
agent has no accessible world at a designated world (it believes ⊥) is a dead end unless
``allow_inconsistent``.
"""

from __future__ import annotations

from collections.abc import Hashable, Iterator

from delkit._records import DataclassFields
from delkit.backends.compact import CompactEngine, CompactState, PlainEvents, bit_positions, state_of_key
from delkit.errors import PlanningError
from delkit.logic.formula import And, Formula, Top, is_propositional, props_of
from delkit.resources import ALARM_SLACK, check_time
from planners.task import ActionSpec, EventAction, MacroSpec, Task, apply_action, goal_conjuncts, plain_event_model

TYPE_CHECKING = False  # typing.TYPE_CHECKING without importing typing (start-up: delkit._records)
if TYPE_CHECKING:  # numpy: the compact space of a small task never imports it (start-up)
    from typing import Any, Literal

    from delkit.models.events import EventModel
    from delkit.models.kripke import KripkeModel

__all__ = ["CompactSpace", "DelSpace", "make_space"]


class DelSpace:
    """The generic state space on :class:`KripkeModel` via ``delkit`` (reference semantics). A plain class
    compatible with ``@dataclass`` (fields ``task``, ``allow_inconsistent``, ``dead_ends``), written by hand for
    start-up time (:mod:`delkit._records`)."""

    __dataclass_fields__ = DataclassFields("task", ("allow_inconsistent", False), ("dead_ends", 0), frozen=False)
    __match_args__ = ("task", "allow_inconsistent", "dead_ends")
    __hash__ = None  # type: ignore[assignment]  # mutable, compared by its fields

    def __init__(self, task: Task, allow_inconsistent: bool = False, dead_ends: int = 0) -> None:
        self.task = task
        self.allow_inconsistent = allow_inconsistent
        self.dead_ends = dead_ends
        self._conj: tuple[Formula, ...] = goal_conjuncts(self.task.goal)
        self._groups = task_groups(self.task)

    def __repr__(self) -> str:
        return (f"DelSpace(task={self.task!r}, allow_inconsistent={self.allow_inconsistent!r}, "
                f"dead_ends={self.dead_ends!r}, _conj={self._conj!r})")

    def __eq__(self, other: object) -> bool:
        if other.__class__ is self.__class__:
            return ((self.task, self.allow_inconsistent, self.dead_ends, self._conj)
                    == (other.task, other.allow_inconsistent, other.dead_ends, other._conj))  # type: ignore[attr-defined]
        return NotImplemented

    def _key(self, m: KripkeModel) -> tuple[KripkeModel, Hashable]:
        """(state, key): contracted, keyed by its canonical form. With groups whose D matters the state is
        kept as it is (no contraction: D_G is not bisimulation-invariant) and keyed by the canonical form of
        the model extended with one relation ⋂_{a∈G} R_a per group (collective bisimulation)."""
        from delkit.models.bisimulation import canonical_form, contract

        if not self._groups:
            c = contract(m)
            return c, canonical_form(c, generated=False)
        return m, canonical_form(with_group_relations(m, self._groups))

    def initial(self) -> tuple[KripkeModel, Hashable]:
        return self._key(self.task.initial)

    def step(self, model: KripkeModel, name: str) -> KripkeModel | None:
        """Φ(A, M) for the action ``name`` (None if A is not applicable)."""
        return apply_action(self.task, self.task.action(name), model)

    def successors(self, model: KripkeModel) -> Iterator[tuple[str, KripkeModel, Hashable]]:
        for act in self.task.actions:
            check_time(ALARM_SLACK)  # one clock read per action: a single expansion can take seconds
            new = self.step(model, act.name)
            if new is None:
                continue
            if not self.allow_inconsistent and new.inconsistent_agents():
                self.dead_ends += 1
                continue
            yield (act.name, *self._key(new))

    def is_goal(self, model: KripkeModel) -> bool:
        return model.holds(self.task.goal)

    def holds(self, model: KripkeModel, f: Formula) -> bool:
        return model.holds(f)

    def goal_count(self, model: KripkeModel) -> int:
        return sum(0 if model.holds(g) else 1 for g in self._conj)


class CompactSpace:
    """State space of a :class:`Task` on the compact backend (same transitions as :class:`DelSpace`)."""

    def __init__(self, task: Task, *, allow_inconsistent: bool = False) -> None:
        self.task = task
        self.allow_inconsistent = allow_inconsistent
        self.dead_ends = 0
        self.engine = CompactEngine(task.props, task.agents, groups=task_groups(task))
        self._has_groups = bool(self.engine.groups)
        self._sensed_ids: dict[str, tuple[int, ...]] = {}  # action name -> node ids of its sensed formulas
        self.aidx = self.engine.aidx
        self._conj = goal_conjuncts(task.goal)
        self._goal = self.engine.cid(task.goal)
        self._conj_ids = [self.engine.cid(g) for g in self._conj]
        self._acts: list[tuple] = [self._entry(act) for act in task.actions]
        self._index = {act.name: i for i, act in enumerate(task.actions)}
        self._ems: dict[tuple, EventModel] = {}
        # per action whose executability and conditions are all propositional: the event model (or None: not
        # executable) per valuations of the designated worlds restricted to the propositions the conditions
        # mention — they decide it (shared by all states)
        self._select: list[tuple[dict, int] | None] = []
        # per action: the node id of its executability when it is the only condition that is not
        # propositional (B(a, p), say) — the event model is still chosen by the designated valuations, the
        # executability is checked per state; None when it is propositional too
        self._exe_check: list[int | None] = []
        # ... and the node id of its propositional conjuncts (at_x_1, say), decided by the valuations too
        self._exe_prop: list[int | None] = []
        eng = self.engine
        for e in self._acts:
            conds = [] if e[0] == "macro" else [c for c in self._conditions(e) if not isinstance(c, Top)]
            exe = pexe = None
            if e[0] == "spec" and not self._has_groups and not eng.is_propositional(e[2]):
                parts = goal_conjuncts(e[1].executable)
                rest = [g for g in parts if not is_propositional(g)]
                lits = [g for g in parts if is_propositional(g)]
                exe = eng.cid(rest[0] if len(rest) == 1 else And(tuple(rest)))
                if lits:
                    pexe = eng.cid(lits[0] if len(lits) == 1 else And(tuple(lits)))
                conds = [c for c in self._conditions(e)[1:] if not isinstance(c, Top)]
            self._exe_prop.append(pexe)
            if e[0] == "macro" or not all(eng.is_propositional(eng.cid(c)) for c in conds):
                self._select.append(None)
                self._exe_check.append(None)
                continue
            self._exe_check.append(exe)
            support = 0
            for c in conds:
                for p in props_of(c):
                    support |= 1 << eng.pidx[p]
            self._select.append(({}, support))
        self._watch, self._watched, self._always = self._literal_index()
        self._by_point: dict[Any, list] = {}
        # commuting actions (:meth:`_commuting`) and what is known of their transitions: (state key, action
        # name) -> successor key, and successor key -> [(state key, action name)] it was reached by
        self._commute = self._commuting()
        self._pairs: dict[tuple[str, str], bool] = {}
        self._succ: dict[tuple, Hashable] = {}
        self._origin: dict[Hashable, list[tuple[Hashable, str]]] = {}
        self._holds_ids: dict[int, tuple[Formula, int]] = {}

    def _literal_index(self) -> tuple[dict[int, list[tuple[int, int, int]]], int, list[tuple[int, Any]]]:
        """A successor generator: for the actions whose designated events' preconditions are known without
        building an event model (:attr:`EventAction.designated_pre`), the literals they require — a designated
        world must satisfy all literals of some designated event's precondition. An action with one designated
        event requiring a true proposition is filed under one such proposition (the least used so far: the
        lists stay short); the others are tested at every valuation. Returns (proposition -> [(action, pos,
        neg)], the mask of the filed propositions, [(action, ((pos, neg), ...) or None: no test)])."""
        watch: dict[int, list[tuple[int, int, int]]] = {}
        always: list[tuple[int, Any]] = []
        eng = self.engine
        for i, entry in enumerate(self._acts):
            dp = entry[1].designated_pre if entry[0] == "event" else None
            if dp is None:
                always.append((i, None))
                continue
            lits = tuple(map(eng.formula_literals, dp))
            if len(lits) == 1 and lits[0][0]:
                pos, neg = lits[0]
                j = min(bit_positions(pos), key=lambda b: len(watch.get(b, ())))
                watch.setdefault(j, []).append((i, pos, neg))
            else:
                always.append((i, lits))
        watched = 0
        for j in watch:
            watched |= 1 << j
        return watch, watched, always

    def _enabled(self, vals: tuple[int, ...]) -> list[int]:
        """The indices (ascending) of the actions not excluded by the literal index at the designated worlds'
        valuations ``vals``."""
        out = [i for i, lits in self._always
               if lits is None or all(any((v & p) == p and not v & n for p, n in lits) for v in vals)]
        h = vals[0]
        rest = vals[1:]
        m = h & self._watched
        watch = self._watch
        while m:
            low = m & -m
            m ^= low
            for i, pos, neg in watch[low.bit_length() - 1]:
                if (h & pos) == pos and not h & neg and all((v & pos) == pos and not v & neg for v in rest):
                    out.append(i)
        out.sort()
        return out

    def _entry(self, act: ActionSpec | EventAction | MacroSpec) -> tuple:
        """Per action its conditions as node ids: ("spec", act, exe, full, partial, sensed) / ("event", act,
        exe, conds) / ("macro", act, [entries of the steps], [step's conditions all propositional])."""
        cid = self.engine.cid
        if isinstance(act, MacroSpec):
            steps = [self._entry(s) for s in act.steps]
            # per step: are all its conditions propositional (decidable from one valuation)? — fixed per task
            return ("macro", act, steps,
                    [st[0] != "macro" and all(is_propositional(c) for c in self._conditions(st)) for st in steps])
        if isinstance(act, EventAction):
            return ("event", act, cid(act.executable), [cid(c) for c in act.conditions])
        return ("spec", act, cid(act.executable),
                [(self.aidx[a], cid(c)) for a, c in act.full],
                [(self.aidx[a], cid(c)) for a, c in act.partial],
                [cid(c) for _, c in act.sensed] if act.kind != "ontic" else [])

    # ------------------------------------------------------------------ states
    def initial(self) -> tuple[CompactState, Hashable]:
        plain = self.task.plain_initial
        s = self.engine.from_plain(plain) if plain is not None else self.engine.from_kripke(self.task.initial)
        return s, s.key

    def holds(self, s: CompactState, f: Formula) -> bool:
        # the node id by the formula object's identity (a formula's hash walks the whole formula; callers
        # such as the dead-end test ask the same few formula objects for every state)
        hit = self._holds_ids.get(id(f))
        if hit is None or hit[0] is not f:
            hit = self._holds_ids[id(f)] = (f, self.engine.cid(f))  # f is kept alive: its id is not reused
        return self.engine.holds_id(s, hit[1])

    def bits(self, s: CompactState, f: Formula) -> int:
        return self.engine.bits(s, f)

    def is_goal(self, s: CompactState) -> bool:
        return self.engine.holds_id(s, self._goal)

    def goal_count(self, s: CompactState) -> int:
        return sum(0 if self.engine.holds_id(s, g) else 1 for g in self._conj_ids)

    def to_kripke(self, s: CompactState) -> KripkeModel:
        return self.engine.to_kripke(s)

    def inconsistent(self, s: CompactState) -> list[str]:
        """Agents with no accessible world at a designated world (they believe ⊥)."""
        return self.engine.inconsistent(s)

    # ------------------------------------------------------------------ transitions
    def event_model(self, s: CompactState, entry: tuple, check: bool = True) -> EventModel | PlainEvents | None:
        """The event model of a (non-macro) action in ``s``; None if its executability fails in ``s``
        (``check=False``: not tested, the caller does)."""
        kind, act, exe = entry[0], entry[1], entry[2]
        at = self.engine.holds_id
        if check and not at(s, exe):
            return None
        if kind == "event":
            bits = tuple(at(s, c) for c in entry[3])
            return self.task.events_for_bits(act, bits)
        fm, pm, sm = self._observed(s, entry)
        key = (act.name, fm, pm, sm)
        em = self._ems.get(key)
        if em is None:
            ags = self.task.agents
            em = plain_event_model(act, ags, frozenset(ag for i, ag in enumerate(ags) if (fm >> i) & 1),
                                   frozenset(ag for i, ag in enumerate(ags) if (pm >> i) & 1),
                                   tuple(f for j, (f, _) in enumerate(act.sensed) if (sm >> j) & 1))
            self._ems[key] = em
        return em

    def _commuting(self) -> dict[str, tuple[frozenset[str], frozenset[str]]]:
        """The mA* actions whose event model is chosen by propositional conditions and has propositional
        pre- and postconditions — sensings and announcements, and ontic actions — with the fluents their
        event models read (observability conditions, sensed formulas and their conditions, effect conditions
        and values) and write (effect fluents). Two of them commute when neither writes a fluent the other
        reads or writes (:meth:`_commute_pair`; two sensings/announcements always do): each one's event model
        is the same before and after the other, and E_a;E_b ≅ E_b;E_a ((e, f) ↦ (f, e): the composition's
        relations are products, its preconditions pre(e) ∧ pre(f), its postconditions the union), so when
        s·b·a and s·a·b both exist they are bisimilar. Whether a is applicable in s·b is decided in s·b itself
        (its executability and designated preconditions, :meth:`successors`). Empty with group relations."""
        if self._has_groups:
            return {}
        out = {}
        for e in self._acts:
            if e[0] != "spec" or e[1].kind not in ("sensing", "announcement", "ontic"):
                continue
            act = e[1]
            if act.kind != "ontic" and act.effects:
                continue
            forms = [*(c for _, c in act.full), *(c for _, c in act.partial),
                     *(f for f, _ in act.sensed), *(c for _, c in act.sensed),
                     *(c for _, _, c in act.effects), *(v for _, v, _ in act.effects if isinstance(v, Formula))]
            if all(is_propositional(f) for f in forms):
                reads = frozenset().union(*(props_of(f) for f in forms))
                out[act.name] = (reads, frozenset(p for p, _, _ in act.effects))
        return out if len(out) > 1 else {}

    def _commute_pair(self, a: str, b: str) -> bool:
        """Actions a and b of :meth:`_commuting` commute (cached)."""
        hit = self._pairs.get((a, b))
        if hit is None:
            (ra, wa), (rb, wb) = self._commute[a], self._commute[b]
            hit = self._pairs[(a, b)] = not (wa & (rb | wb)) and not (wb & ra)
        return hit

    def _predicted(self, ks: Hashable, name: str) -> Hashable | None:
        """The key of s·a when s was reached from p by a commuting b, and p·a·b is known: s·a = p·b·a ≅
        p·a·b (:meth:`_commuting`); None when not known."""
        succ = self._succ
        for kp, b in self._origin.get(ks, ()):
            if b != name and self._commute_pair(name, b):
                y = succ.get((kp, name))
                if y is not None:
                    z = succ.get((y, b))
                    if z is not None:
                        return z
        return None

    def _observed(self, s: CompactState, entry: tuple) -> tuple[int, int, int]:
        """(full, partial, sensed) of an mA* action in ``s``: the fully and partially observant agents and
        the active sensed/announced formulas, as bit masks (agent index / position in ``act.sensed``)."""
        at = self.engine.holds_id
        _, _, _, full, partial, sensed = entry
        fm = 0
        for a, c in full:
            if at(s, c):
                fm |= 1 << a
        pm = 0
        for a, c in partial:
            if at(s, c):
                pm |= 1 << a
        pm &= ~fm
        sm = 0
        for j, c in enumerate(sensed):
            if at(s, c):
                sm |= 1 << j
        return fm, pm, sm

    def _loop_test(self, s: CompactState, entry: tuple) -> tuple | None:
        """For an mA* sensing or announcement action (no postconditions) applicable in ``s``: (kind, the
        full observers' indices, the node ids of the active sensed/announced formulas), which
        :meth:`_is_loop` reads; None for any other action or when the task has group relations."""
        if entry[0] != "spec" or entry[1].kind not in ("sensing", "announcement") or self._has_groups:
            return None
        act = entry[1]
        ids = self._sensed_ids.get(act.name)
        if ids is None:
            ids = self._sensed_ids[act.name] = tuple(self.engine.cid(f) for f, _ in act.sensed)
        fm, pm, sm = self._observed(s, entry)
        n = len(self.task.agents)
        return (act.kind, tuple(a for a in range(n) if (fm >> a) & 1),
                tuple(c for j, c in enumerate(ids) if (sm >> j) & 1), (fm | pm) == (1 << n) - 1,
                tuple(a for a in range(n) if ((fm | pm) >> a) & 1))

    def _is_loop(self, s: CompactState, test: tuple) -> bool:
        """Whether the action of ``test`` (:meth:`_loop_test`, executable in ``s``) is applicable and leads
        back to ``s``, read from ``s`` without the product. Let X be the worlds reachable from the
        designated ones by the observers' (full and partial) relations: it is a loop when every full
        observer, at every world of X, already knows whether each sensed (announced) formula holds (each
        one's successor set lies inside the world's class of the formula) — and, for an announcement, the
        formulas hold at every designated world (else it is not applicable). Then every pair (w, e) of the
        product that is reached is w with the one real event whose precondition w satisfies, or w with ε
        (the oblivious agents' copy of s), and (w, e) ↦ w is a bounded morphism from the generated part
        of s ⊗ E onto s (back: a full observer's successor v of w satisfies pre(e), a partial observer's
        meets the event of its own truth values, an oblivious one's meets ε): the successor is bisimilar
        to s, the same key."""
        kind, agents, fids, everyone, observers = test
        ev = self.engine.ev
        masks = s.masks
        if kind == "announcement":
            for c in fids:
                b = ev(s, c)
                for p in s.points:
                    if not (b >> p) & 1:
                        return False
        if not agents or not fids:
            return True
        if everyone:  # X is all of s (s is generated by its designated worlds)
            xs: Any = range(len(s.val))
        elif ("X", observers) in s.memo:  # (the other keys of the state's memo are node ids)
            xs = s.memo["X", observers]
        else:
            seen = 0
            for p in s.points:
                seen |= 1 << p
            front = seen
            while front:
                nxt = 0
                for w in bit_positions(front):
                    for a in observers:
                        nxt |= masks[a][w]
                front = nxt & ~seen
                seen |= front
            xs = s.memo["X", observers] = bit_positions(seen)
        for c in fids:
            b = ev(s, c)
            nb = ~b
            for a in agents:
                per = masks[a]
                for w in xs:
                    if per[w] & (nb if (b >> w) & 1 else b):
                        return False
        return True

    def _epistemic_successor(self, s: CompactState, test: tuple) -> CompactState | None:
        """The successor of ``s`` by a sensing or announcement with the :meth:`_loop_test` ``test`` when
        nobody is oblivious of it: ``s`` itself (:meth:`_is_loop`) or its refinement
        (:meth:`CompactEngine.refine_update`) — no product; None if an announced formula is false at a
        designated world (not applicable)."""
        if self._is_loop(s, test):
            return s
        kind, full, fids, _, _ = test
        if kind == "announcement":
            ev = self.engine.ev
            for c in fids:
                b = ev(s, c)
                if any(not (b >> p) & 1 for p in s.points):
                    return None
        return self.engine.refine_update(s, full, fids)

    def event_model_named(self, s: CompactState, name: str) -> EventModel | None:
        """The event model of the (non-macro) action ``name`` in ``s`` as :meth:`step` applies it; None if
        its executability fails in ``s`` (the executor of ``arms.mission`` applies it to its belief state)."""
        return self.event_model(s, self._acts[self._index[name]])

    def _macro_model(self, s: CompactState, entry: tuple) -> EventModel | None:
        """The composed event model E₁;…;Eₙ of a macro in ``s`` (None if a step is not applicable).

        Step i's event model depends on its conditions in the state after steps 1..i-1. When all of step
        i's conditions are propositional and one designated event of the composition so far is possible at
        the (single) pointed world, they are decided by substituting that event's postconditions (no
        intermediate state is built); otherwise on the intermediate state itself.
        """
        from delkit.models.compose import compose

        steps = entry[2]
        models: list[EventModel] = []
        cur: CompactState | None = s
        comp: EventModel | None = None
        for i, st in enumerate(steps):
            if i > 0 and cur is None:
                cur = self.engine.apply(s, comp)  # type: ignore[arg-type]
                if cur is None:
                    return None
            em = self.event_model(cur, st) if cur is not None else None
            if em is None:
                return None
            if isinstance(em, PlainEvents):
                em = em.event_model()  # composed by delkit.models.compose (numpy)
            models.append(em)
            key = ("macro", entry[1].name, tuple(id(m) for m in models))
            nxt = self._ems.get(key)
            if nxt is None:
                nxt = em if comp is None else compose(comp, em, name=f"{comp.name};{em.name}")
                self._ems[key] = nxt  # the parts stay alive in the event-model caches: their ids are stable
            comp = nxt
            if i + 1 < len(steps):
                cur = self._after(s, comp) if entry[3][i + 1] else None
        return comp

    def _after(self, s: CompactState, comp: EventModel) -> CompactState | None:
        """A one-world view of the pointed world after ``comp`` (its valuation post(e) evaluated in s), which
        decides the next step's conditions when they are all propositional; None when ``s`` is multi-pointed
        or not exactly one designated event is possible (the caller then builds the intermediate state)."""
        if len(s.points) != 1:
            return None
        p = s.point
        ev, cid = self.engine.ev, self.engine.cid
        live = [e for e in comp.designated if (ev(s, cid(comp.pre[e])) >> p) & 1]
        if len(live) != 1:
            return None
        post = comp.post[live[0]]
        # the pointed world after the composition so far has the valuation post(e) evaluated at p (in s): a
        # one-world view of it decides propositional conditions
        v = 0
        for j, prop in enumerate(self.task.props):
            f = post.get(prop)
            truth = (s.val[p] >> j) & 1 if f is None else (ev(s, cid(f)) >> p) & 1
            if truth:
                v |= 1 << j
        return _valuation_view(v, len(self.task.agents))

    @staticmethod
    def _conditions(entry: tuple) -> list[Formula]:
        act = entry[1]
        out = [act.executable]
        if entry[0] == "event":
            out += list(act.conditions)
        else:
            out += [c for _, c in act.full] + [c for _, c in act.partial] + [c for _, c in act.sensed]
        return out

    def apply_entry(self, s: CompactState, entry: tuple) -> CompactState | None:
        em = self._macro_model(s, entry) if entry[0] == "macro" else self.event_model(s, entry)
        if em is None:
            return None
        return self.engine.apply(s, em)

    def step(self, s: CompactState, name: str) -> CompactState | None:
        """The successor of ``s`` by the action ``name`` (None if not applicable)."""
        return self.apply_entry(s, self._acts[self._index[name]])

    def _candidates(self, s: CompactState, here: Any) -> list[tuple[str, tuple | None, tuple | None, Any,
                                                                   int | None]]:
        """The actions that may apply in ``s`` as (name, entry, None, None, None) — decided per state — or
        (name, None, compiled event model, loop test, executability) — chosen by the designated worlds'
        valuations ``here`` and not excluded by them (some designated event's propositional precondition
        holds at every designated world); the loop test (:meth:`_loop_test`, decided by ``here`` too) or
        None; the node id of an executability to check per state (``_exe_check``) or None. Computed once per
        ``here`` (cached by :meth:`successors`), so it is not on the per-state path."""
        single = not isinstance(here, frozenset)
        compile_em, may = self.engine.compile, self.engine.may_apply
        out = []
        acts, select = self._acts, self._select
        for i in self._enabled((here,) if single else tuple(sorted(here))):
            entry, sel, exe = acts[i], select[i], self._exe_check[i]
            if sel is None:
                out.append((entry[1].name, entry, None, None, None))
                continue
            pexe = self._exe_prop[i]
            if exe is not None and pexe is not None and not self.engine.holds_id(s, pexe):
                continue  # a propositional conjunct of the executability fails at these valuations
            table, support = sel
            at = here & support if single else frozenset([v & support for v in here])
            comp = table.get(at, _MISSING)
            if comp is _MISSING:
                em = self.event_model(s, entry, check=exe is None)
                comp = table[at] = None if em is None else compile_em(em)
            if comp is not None and may(comp, (here,) if single else here):
                out.append((entry[1].name, None, comp, self._loop_test(s, entry), exe))
        return out

    def successors(self, s: CompactState) -> Iterator[tuple[str, CompactState, Hashable]]:
        val, points = s.val, s.points
        # the candidate actions per valuation(s) of the designated world(s), shared by all states
        here = val[points[0]] if len(points) == 1 else frozenset([val[p] for p in points])
        cands = self._by_point.get(here)
        if cands is None:
            cands = self._by_point[here] = self._candidates(s, here)
        apply = self.engine.apply_compiled
        loop_ok: bool | None = None  # s itself as a successor: is it consistent? (decided on first use)
        commute, ks = self._commute, s.key
        holds = self.engine.holds_id
        done: dict[int, Any] = {}  # id of a compiled event model -> the successor it gave (None: not applicable)
        for name, entry, comp, test, exe in cands:
            check_time(ALARM_SLACK)  # one clock read: a single expansion of a large state can take seconds
            if exe is not None and not holds(s, exe):
                continue
            # (entry is None: the executability was decided by the designated valuations, see _candidates)
            if name in commute and (entry is None or self.engine.holds_id(s, entry[2])):
                z = self._predicted(ks, name)
                if z is not None:  # known by commutation; it was yielded before, so it is consistent
                    yield name, (s if z == ks else state_of_key(z)), z  # type: ignore[arg-type]
                    continue
            # a sensing or announcement that cannot change s (:meth:`_is_loop`) yields s itself: the search
            # sees the same key as the product would give, without the product being built
            if comp is not None:
                # actions whose event models are equal as data share one compiled model (CompactEngine.compile):
                # their successors of s are one state, built once per expansion
                new = done.get(id(comp), _MISSING)
                if new is _MISSING:
                    if test is None:
                        new = apply(s, comp)
                    elif test[3]:
                        new = self._epistemic_successor(s, test)
                    else:
                        new = s if self._is_loop(s, test) else apply(s, comp)
                    done[id(comp)] = new
            elif entry[0] == "spec" and entry[1].kind != "ontic" and not self._has_groups:  # type: ignore[index]
                em = self.event_model(s, entry)  # type: ignore[arg-type]
                if em is None:
                    continue
                t = self._loop_test(s, entry)  # type: ignore[arg-type]
                if t is None:
                    new = self.engine.apply(s, em)
                elif t[3]:
                    new = self._epistemic_successor(s, t)
                else:
                    new = s if self._is_loop(s, t) else self.engine.apply(s, em)
            else:
                new = self.apply_entry(s, entry)  # type: ignore[arg-type]
            if new is None:
                continue
            if new is s:
                if loop_ok is None:
                    loop_ok = self.allow_inconsistent or not self.engine.believes_bottom(s)
                if not loop_ok:
                    self.dead_ends += 1
                    continue
                if name in commute:
                    self._remember(ks, name, ks)
                yield name, s, s.key
                continue
            if not self.allow_inconsistent and self.engine.believes_bottom(new):
                self.dead_ends += 1
                continue
            if name in commute:
                self._remember(ks, name, new.key)
            yield name, new, new.key

    #: at most this many remembered transitions of commuting actions (a bound on the memory they take)
    MEMO_LIMIT = 2_000_000

    def _remember(self, ks: Hashable, name: str, kn: Hashable) -> None:
        if len(self._succ) >= self.MEMO_LIMIT:
            return
        self._succ[(ks, name)] = kn
        if kn != ks:
            org = self._origin.setdefault(kn, [])
            if len(org) < 4:
                org.append((ks, name))


_MISSING = object()


def _valuation_view(v: int, n_agents: int) -> CompactState:
    """A one-world state with valuation ``v`` (for deciding propositional conditions only)."""
    return CompactState((v,), tuple((1,) for _ in range(n_agents)), (0,))


def _group_d_formulas(task: Task) -> list[Formula]:
    """D_G subformulas with |G| ≥ 2 anywhere in the task (goal, executability, effects, observability, the
    declared designated preconditions of event actions). Each distinct formula node is visited once: grounded
    actions share most of their subformulas."""
    from delkit.logic.formula import D, children

    found: list[Formula] = []
    seen: set[int] = set()
    names: dict[type, tuple[str, ...]] = {}

    def formula(f: Formula) -> None:
        stack = [f]
        while stack:
            g = stack.pop()
            if id(g) in seen:
                continue
            seen.add(id(g))
            if isinstance(g, D) and len(g.group) > 1:
                found.append(g)
            stack.extend(children(g))

    def walk(x: Any) -> None:
        if isinstance(x, Formula):
            formula(x)
        elif isinstance(x, EventAction):  # its formulas (the rest are names and the builder)
            walk(x.conditions)
            formula(x.executable)
            walk(x.designated_pre)
        elif isinstance(x, (str, int, float)) or x is None:
            return
        elif isinstance(x, (tuple, list, frozenset, set)):
            for y in x:
                walk(y)
        elif isinstance(x, dict):
            for y in x.values():
                walk(y)
        elif isinstance(x, (ActionSpec, MacroSpec)):  # hand-written records: their fields, without dataclasses
            for y in x._key(x):
                walk(y)
        elif hasattr(type(x), "__dataclass_fields__") and not isinstance(x, type):
            import dataclasses

            fs = names.get(type(x))
            if fs is None:
                fs = names[type(x)] = tuple(fld.name for fld in dataclasses.fields(x))
            for name in fs:
                walk(getattr(x, name))

    walk(task.goal)
    for act in task.actions:
        walk(act)
    return found


def task_groups(task: Task) -> tuple[tuple[str, ...], ...]:
    """The groups (≥ 2 agents) whose distributed knowledge the task mentions, sorted."""
    return tuple(sorted({tuple(sorted(set(d.group))) for d in _group_d_formulas(task)}))


def with_group_relations(m: KripkeModel, groups: tuple[tuple[str, ...], ...]) -> KripkeModel:
    """``m`` with one extra agent per group, named ``D{a,b}``, whose relation is ⋂_{a∈G} R_a."""
    rels = dict(m.relations)
    names = []
    for g in groups:
        r = m.relations[g[0]]
        for a in g[1:]:
            r = r.intersect(m.relations[a])
        name = "D{" + ",".join(g) + "}"
        rels[name] = r
        names.append(name)
    from delkit.models.kripke import KripkeModel

    return KripkeModel(m.props, tuple(m.agents) + tuple(names), m.valuation, rels, m.designated)


def make_space(task: Task, *, engine: Literal["fast", "compact", "del"] = "fast",
               allow_inconsistent: bool = False) -> Any:
    """The state space for ``task`` on the compact backend (``fast``/``compact``, default) or the numpy one.

    Both deduplicate states by bisimulation. Distributed knowledge of a group of two or more agents is not
    invariant under bisimulation, so for the groups the task mentions both use collective bisimulation
    (the group's intersection relation is refined and kept like an agent's; see ``delkit.backends.compact``).
    """
    if engine == "del":
        return DelSpace(task, allow_inconsistent=allow_inconsistent)
    if engine in ("fast", "compact"):
        return CompactSpace(task, allow_inconsistent=allow_inconsistent)
    raise PlanningError(f"unknown engine {engine!r}; use 'fast' (the compact backend) or 'del'")
