"""The plan checker's replay without numpy, for small tasks (start-up of ``delkit check``).

:class:`PlainState` is a pointed Kripke model as plain Python data (valuations as int bit masks over the
task's fluents, per agent the successor tuple of every world, the designated worlds) with the part of
:class:`delkit.models.kripke.KripkeModel`'s interface the checker reads (``check``, ``holds``, ``relation(a)
.successors``, ``world_name``, ``true_props``, ``reachable``, ``inconsistent_agents``). Formulas are
evaluated by the compact backend's evaluator (:meth:`delkit.backends.compact.CompactEngine.ev`, the clauses of
``delkit.logic.semantics``, with distributed knowledge of a group read on the intersection of its members'
relations) on the state as it is; :meth:`PlainState.product` is ``KripkeModel.product`` written with lists:
the same worlds in the same order (the pairs (w, e) with w ⊨ pre(e), sorted by world then event), the same
valuations (postconditions read in the old model), relations ((w,e) R_a (v,f) iff w R_a v and e Q_a f),
designated pairs and world names. Event models are the numpy-free ones the planner uses
(:func:`planners.task.plain_event_model`, an EPDDL reader's :class:`~delkit.backends.compact.PlainEvents`).

The checker (:func:`planners.validate.check_plan`) replays on these while the states stay small enough to
be left uncontracted (its ``_CONTRACT_ABOVE``); anything else — a bigger state, a numpy event model, an
error — raises :class:`NeedNumpy` and the checker replays the plan on the numpy backend from the start, so
the verdicts are the numpy checker's (``tests/planners/test_replay.py`` compares the two on the shared
benchmark instances).
"""

from __future__ import annotations

from delkit.backends.compact import CompactEngine, CompactState, PlainEvents
from delkit.errors import DelkitError
from delkit.logic.formula import Announce, Formula, Update, subformulas

TYPE_CHECKING = False  # typing.TYPE_CHECKING without importing typing (start-up: delkit._records)
if TYPE_CHECKING:
    from planners.task import ActionSpec, EventAction, Task

__all__ = ["NeedNumpy", "PlainState", "initial_state", "event_model", "usable"]


class NeedNumpy(DelkitError):
    """The plain replay cannot go on (a large state, a numpy event model, an error): replay on numpy."""


class _Rows:
    """``relation(a)`` of a :class:`PlainState`: ``successors(w)`` as a tuple of worlds (ascending)."""

    __slots__ = ("rows",)

    def __init__(self, rows: list[tuple[int, ...]]) -> None:
        self.rows = rows

    def successors(self, w: int) -> tuple[int, ...]:
        return self.rows[w]


class PlainState:
    """A multi-pointed Kripke model as lists (see the module docstring); ``succ[i]`` are the successor rows of
    the i-th agent of ``engine.agents``."""

    __slots__ = ("engine", "val", "succ", "designated", "names", "_cs", "_checked")

    def __init__(self, engine: CompactEngine, val: list[int], succ: list[list[tuple[int, ...]]],
                 designated: tuple[int, ...], names: tuple[str, ...] | None = None) -> None:
        self.engine = engine
        self.val = val
        self.succ = succ
        self.designated = designated
        self.names = names
        self._cs: CompactState | None = None
        self._checked: dict[Formula, list[bool]] = {}

    @property
    def props(self) -> tuple[str, ...]:
        return self.engine.props

    @property
    def agents(self) -> tuple[str, ...]:
        return self.engine.agents

    @property
    def n_worlds(self) -> int:
        return len(self.val)

    def world_name(self, w: int) -> str:
        return self.names[w] if self.names else f"w{w}"

    def true_props(self, w: int) -> set[str]:
        v = self.val[w]
        return {p for j, p in enumerate(self.engine.props) if (v >> j) & 1}

    def relation(self, agent: str) -> _Rows:
        return _Rows(self.succ[self.engine.aidx[agent]])

    def _state(self) -> CompactState:
        """The state as the compact evaluator reads it (bit masks; each declared group's relation ⋂_{a∈G} R_a
        after the agents')."""
        if self._cs is None:
            masks = [tuple(_mask(r) for r in rows) for rows in self.succ]
            aidx = self.engine.aidx
            for g in self.engine.groups:
                inter = list(masks[aidx[g[0]]])
                for a in g[1:]:
                    inter = [x & y for x, y in zip(inter, masks[aidx[a]], strict=True)]
                masks.append(tuple(inter))
            self._cs = CompactState(tuple(self.val), tuple(masks), self.designated)
        return self._cs

    def check(self, f: Formula) -> list[bool]:
        """Per world: whether ``f`` holds there (memoised)."""
        out = self._checked.get(f)
        if out is None:
            eng = self.engine
            bits = eng.ev(self._state(), eng.cid(f))
            out = [bool((bits >> w) & 1) for w in range(len(self.val))]
            self._checked[f] = out
        return out

    def holds(self, f: Formula) -> bool:
        """``f`` holds in every designated world."""
        vec = self.check(f)
        return all(vec[w] for w in self.designated)

    def reachable(self, sources: list[int], agents: tuple[str, ...]) -> list[bool]:
        """Per world: reachable from ``sources`` in zero or more steps of the agents' relations."""
        mask = [False] * len(self.val)
        todo = list(sources)
        for w in todo:
            mask[w] = True
        rows = [self.succ[self.engine.aidx[a]] for a in agents]
        while todo:
            w = todo.pop()
            for r in rows:
                for v in r[w]:
                    if not mask[v]:
                        mask[v] = True
                        todo.append(v)
        return mask

    def inconsistent_agents(self) -> list[tuple[str, int]]:
        """(agent, designated world) pairs where the agent has no accessible world (it believes ⊥)."""
        return [(a, w) for a, rows in zip(self.engine.agents, self.succ, strict=True) for w in self.designated
                if not rows[w]]

    def product_bytes_bound(self, em: PlainEvents) -> float:
        """An upper bound of :func:`delkit.resources.product_update_bytes` for the numpy replay of this product
        (whatever its relations' representation): the plain replay refuses no more than the numpy one, it leaves
        a product above the budget to it."""
        n, k = len(self.val), 0
        pre = [self.check(p) for p in em.pre]
        degs = [[len(r) for r in rows] for rows in self.succ]
        cand = [0.0] * len(self.succ)
        for e in range(len(em.events)):
            for w in range(n):
                if pre[e][w]:
                    k += 1
                    for i, a in enumerate(self.engine.agents):
                        cand[i] += degs[i][w] * len(em.rows[a][e])
        return k * (8.0 * 4 + len(self.engine.props)) + sum(16.0 * k + 48.0 * c + 16.0 * sum(d)
                                                            for c, d in zip(cand, degs, strict=True))

    def product(self, em: PlainEvents) -> PlainState:
        """M ⊗ E, as ``KripkeModel.product`` builds it (see the module docstring)."""
        if set(em.agents) != set(self.engine.agents) or any(p not in self.engine.pidx for m in em.post for p in m):
            raise NeedNumpy("event model and state do not share the vocabulary")
        n, k = len(self.val), len(em.events)
        pre = [self.check(p) for p in em.pre]
        pairs = [(w, e) for w in range(n) for e in range(k) if pre[e][w]]
        index = {pair: i for i, pair in enumerate(pairs)}
        pidx = self.engine.pidx
        posts = [[(1 << pidx[p], self.check(f)) for p, f in m.items()] for m in em.post]
        val = []
        for w, e in pairs:
            v = self.val[w]
            for bit, vec in posts[e]:
                v = (v | bit) if vec[w] else (v & ~bit)
            val.append(v)
        succ = []
        for a, rows in zip(self.engine.agents, self.succ, strict=True):
            erows = em.rows[a]
            new = []
            for w, e in pairs:
                out = []
                for v in rows[w]:
                    for f in erows[e]:
                        j = index.get((v, f))
                        if j is not None:
                            out.append(j)
                new.append(tuple(out))
            succ.append(new)
        des_w, des_e = set(self.designated), set(em.designated)
        des = tuple(i for i, (w, e) in enumerate(pairs) if w in des_w and e in des_e)
        names = tuple(f"{self.names[w]}.{em.events[e]}" for w, e in pairs) if self.names is not None else None
        return PlainState(self.engine, val, succ, des, names)


def _mask(ws: tuple[int, ...]) -> int:
    m = 0
    for w in ws:
        m |= 1 << w
    return m


def usable(task: Task, formulas: list[Formula], limit: int) -> bool:
    """Whether the plain replay may try ``task``: its initial state came numpy-free from the reader over the
    task's own vocabulary, with at most ``limit`` worlds, and no formula to check (goal, properties,
    executability) has a dynamic operator (those are evaluated on the numpy backend anyway)."""
    m = task.plain_initial
    if m is None or m.n_worlds > limit or m.props != tuple(task.props) or m.agents != tuple(task.agents):
        return False
    fs = [*formulas, task.goal, *(a.executable for a in task.actions if hasattr(a, "executable"))]
    return not any(isinstance(g, (Announce, Update)) for f in fs for g in subformulas(f))


def initial_state(task: Task, groups: tuple[tuple[str, ...], ...]) -> PlainState:
    """The task's initial state (see :func:`usable`) as a :class:`PlainState`."""
    m = task.plain_initial
    assert m is not None
    engine = CompactEngine(task.props, task.agents, groups)
    return PlainState(engine, list(m.vals), [m.rows(a) for a in engine.agents], tuple(m.designated))


def event_model(task: Task, act: ActionSpec | EventAction, model: PlainState) -> PlainEvents:
    """The event model of ``act`` in ``model``, as :meth:`planners.task.Task.event_model` decides it (observers
    and sensed formulas at the designated worlds; an EventAction's conditions), numpy-free."""
    from planners.task import EventAction, plain_event_model

    if isinstance(act, EventAction):
        em = task.events_for_bits(act, tuple(model.holds(c) for c in act.conditions))
        if not isinstance(em, PlainEvents):
            raise NeedNumpy("the action's event model is a numpy one")
        return em
    full, partial = act.observers(model, task.agents)  # type: ignore[arg-type]
    sensed = act.active_sensed(model) if act.kind != "ontic" else ()  # type: ignore[arg-type]
    return plain_event_model(act, task.agents, full, partial, sensed)
