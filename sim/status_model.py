"""The team's statuses as a delkit epistemic state (seed 000, §3.2 and §5.3.1).

A world is the combination of every robot's status σ_i ∈ {exploring, gossiping, task, home}
(proposition ``s<i>_<status>``, one-hot per robot). Robots are the agents ``r0 … r{N-1}``. The model is
updated only by the actions of the paper's library A = {perceive, announce}, both built as one delkit event
model, :func:`tell_event` (the mA* frame of ``delkit.models.events.action``): σ_k := s with one outcome per
status, the observers (robot k's connected group) fully observant, every other robot *oblivious* — it
believes nothing happened. Disconnected robots therefore keep their old belief and it becomes *false*
when σ_k changes (B_j σ_k with σ_k untrue: the paper's Fig. 1, "robot 2 holds a false belief about robot
1's state"; the relations are KD45, no longer S5). Announcing the status *again* to a robot that meets
the group revises that belief (the post-condition sets σ_k to its actual value in every world the new
observer considers, so an outdated belief is replaced, not contradicted — §5.3.1 "belief update is the
process of accepting new information that may contradict initial beliefs").

* :class:`FactoredStatusModel` — the model the simulator runs on (any N): one delkit Kripke model per
  robot k over k's four status propositions. Every event of the library concerns one robot's status, so
  the joint model is the product of these factors and every formula about σ_k (B_i B_j σ_k, eqs. 14, 18)
  is evaluated on factor k; a factor has a handful of worlds instead of the joint model's ≤ 4^N.
* :class:`StatusModel` — the joint model (small N only), kept as the reference the factored one is
  tested against.
* :meth:`announce_local` gives eq. 18: B_i B_j σ_i ∧ B_i B_j B_i σ_i for (i, j) in the group, outsiders'
  beliefs unchanged; :meth:`announce_global` gives eq. 14: K_i σ_i ∧ K_i K_j σ_j ∧ K_i K_j K_k σ_k.

Every update is ``delkit.models.update.product_update`` followed by bisimulation contraction
(``delkit.models.bisimulation``).
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from dataclasses import dataclass

import numpy as np

from delkit.logic.formula import BOT, TOP, Formula, K, Prop, conj
from delkit.models.bisimulation import contract
from delkit.models.events import EventModel, action, sensing
from delkit.models.kripke import KripkeModel
from delkit.models.relation import Relation
from delkit.models.update import product_update

__all__ = ["StatusModel", "FactoredStatusModel", "tell_event", "suspect_event", "status_prop", "agent", "eq14", "eq18",
           "STATUSES", "BUSY"]

STATUSES = ("exploring", "gossiping", "task", "home")
#: ruleset 1 (§5.3.2): a robot not found at its believed state "must be operating according to another status
#: such as gossiping to another robot or completing another task"
BUSY = ("gossiping", "task")


def agent(i: int) -> str:
    return f"r{i}"


def status_prop(i: int, status: str) -> Prop:
    return Prop(f"s{i}_{status}")


def eq14(statuses: Sequence[str], edges: Iterable[tuple[int, int]]) -> Formula:
    """K_i σ_i ∧ ⋀_j K_i K_j σ_j ∧ ⋀_{(j,k) ∈ E} K_i K_j K_k σ_k, for every robot i (eq. 14)."""
    n = len(statuses)
    sig = [status_prop(i, s) for i, s in enumerate(statuses)]
    parts: list[Formula] = []
    for i in range(n):
        parts.append(K(agent(i), sig[i]))
        parts += [K(agent(i), K(agent(j), sig[j])) for j in range(n)]
        parts += [K(agent(i), K(agent(j), K(agent(k), sig[k]))) for j, k in edges]
    return conj(parts)


def eq18(statuses: Sequence[str], group: Sequence[int]) -> Formula:
    """⋀_{(i,j) ∈ E} B_i B_j σ_i ∧ B_i B_j B_i σ_i over the connected group (eq. 18)."""
    parts: list[Formula] = []
    for i in group:
        q = status_prop(i, statuses[i])
        for j in group:
            if i != j:
                parts += [K(agent(i), K(agent(j), q)), K(agent(i), K(agent(j), K(agent(i), q)))]
    return conj(parts)


def tell_event(n: int, k: int, status: str, observers: Iterable[int], name: str = "announce") -> EventModel:
    """announce(x_k) / perceive(σ_k) to ``observers``: σ_k := ``status``; the observers see which outcome
    happened, everyone else is oblivious (see the module docstring)."""
    agents = [agent(a) for a in range(n)]
    outcomes = [(f"to_{s}", TOP, {f"s{k}_{t}": (TOP if t == s else BOT) for t in STATUSES}) for s in STATUSES]
    return action(agents, outcomes, full=[agent(a) for a in sorted(set(observers))],
                  designated=[f"to_{status}"], name=f"r{k}:{name}")


def suspect_event(n: int, k: int, believer: int, statuses: Sequence[str] = BUSY,
                  name: str = "not_found") -> EventModel:
    """Ruleset 1 as a belief revision: robot ``believer`` did not find robot k at its believed state and comes
    to believe σ_k ∈ ``statuses`` (without knowing which). Nothing happens in the world — the designated event
    ``none`` changes nothing — so the new belief may be false (k may still be exploring elsewhere). From
    ``none`` the believer considers the ``to_s`` events; every other robot is oblivious (considers ε, where
    nothing happened for anyone)."""
    agents = [agent(a) for a in range(n)]
    names = tuple([f"to_{s}" for s in statuses] + ["none", "eps"])
    posts = [{f"s{k}_{t}": (TOP if t == s else BOT) for t in STATUSES} for s in statuses] + [{}, {}]
    m = len(statuses)
    none, eps = m, m + 1

    def rel(a: str) -> Relation:
        if a == agent(believer):
            pairs = [(e, f) for e in range(none + 1) for f in range(m)] + [(eps, eps)]
        else:
            pairs = [(e, eps) for e in range(m + 2)]
        return Relation.from_pairs(m + 2, pairs)

    return EventModel(names, tuple(agents), tuple([TOP] * (m + 2)), tuple(posts), {a: rel(a) for a in agents},
                      (none,), f"r{k}:{name}")


@dataclass
class StatusModel:
    """The pointed status model; ``model`` is always contracted."""

    n: int
    model: KripkeModel
    statuses: list[str]

    @classmethod
    def initial(cls, n: int, status: str = "exploring") -> StatusModel:
        """All robots start with a common-knowledge status (all particles at the initial state, §5.1)."""
        props = [f"s{i}_{s}" for i in range(n) for s in STATUSES]
        world = {f"s{i}_{status}" for i in range(n)}
        m = KripkeModel.build([world], {agent(i): [[0]] for i in range(n)}, [0], props=props)
        return cls(n, m, [status] * n)

    @property
    def agents(self) -> list[str]:
        return [agent(i) for i in range(self.n)]

    def _apply(self, ev) -> None:
        self.model = contract(product_update(self.model, ev))

    def change(self, i: int, status: str, group: Iterable[int]) -> None:
        """Robot i's status becomes ``status``; ``group`` (connected to i) observes it, the others do not."""
        self._apply(tell_event(self.n, i, status, set(group) | {i}, "status"))
        self.statuses[i] = status

    def perceive(self, i: int, phi: Formula, group: Iterable[int] = ()) -> None:
        """Robot i (with its connected group) senses whether φ; the others know it may have."""
        full = sorted(set(group) | {i})
        self._apply(sensing(phi, self.agents, full=[agent(k) for k in full],
                            partial=[agent(k) for k in range(self.n) if k not in full]))

    def actual_statuses(self, robots: Iterable[int]) -> Formula:
        return conj([status_prop(k, self.statuses[k]) for k in robots])

    def announce_local(self, group: Sequence[int]) -> None:
        """announce(x_k) of every member k of ``group`` to the group; outsiders are oblivious (eq. 18)."""
        for k in group:
            self._apply(tell_event(self.n, k, self.statuses[k], group, "local_announce"))

    def announce_global(self) -> None:
        """announce(x): every robot's status to everyone (eq. 14)."""
        for k in range(self.n):
            self._apply(tell_event(self.n, k, self.statuses[k], range(self.n), "global_announce"))

    def holds(self, f: Formula) -> bool:
        return bool(self.model.holds(f))

    def knows_status(self, i: int, j: int) -> bool:
        """K_i σ_j for j's actual status."""
        return self.holds(K(agent(i), status_prop(j, self.statuses[j])))



def _dense(rel: Relation, n: int) -> np.ndarray:
    """A relation on a factor's handful of worlds as a dense boolean matrix (no scipy round trip)."""
    if rel.is_partition:
        return rel.labels[:, None] == rel.labels[None, :]
    out = np.zeros((n, n), dtype=bool)
    for w in range(n):
        out[w, rel.successors(w)] = True
    return out


class FactoredStatusModel:
    """The team's status model as N delkit models, factor k over robot k's status (see module docstring).

    :meth:`tell` applies the announce/perceive event to factor k; :meth:`believed` gives the table
    ``B[i, j, k]`` = index into :data:`STATUSES` of the status robot i believes robot j believes robot k has
    (B_i B_j σ_k; i = j gives B_i σ_k), −1 when that belief is not a single status. It is read off the
    accessibility relations of the delkit models; :meth:`holds` model-checks a formula about σ_k on factor k.
    """

    def __init__(self, n: int, status: str = "exploring") -> None:
        self.n = n
        self.agents = [agent(i) for i in range(n)]
        self.statuses = [status] * n
        self.factors = [self._single(k, status) for k in range(n)]
        self.updates = 0
        self._table = np.full((n, n, n), STATUSES.index(status), dtype=np.int8)
        self._considers = np.zeros((n, n, len(STATUSES)), dtype=bool)  # [i, k, s]: i considers σ_k = s possible
        self._considers[:, :, STATUSES.index(status)] = True

    def tell(self, k: int, status: str, observers: Iterable[int], name: str = "announce") -> None:
        """announce(x_k)/perceive(σ_k) to ``observers`` (robot k's connected group, k included).

        Told to everyone, the contracted product is the one-world model where σ_k = ``status`` (every world
        of the product has that valuation and every agent sees the same outcome, so all worlds are bisimilar);
        that model is built directly (the property test checks it against the product update)."""
        observers = set(observers)
        if observers >= set(range(self.n)):
            self.factors[k] = self._single(k, status)
        else:
            ev = tell_event(self.n, k, status, observers, name)
            self.factors[k] = contract(product_update(self.factors[k], ev))
        self.statuses[k] = status
        self._refresh(k)

    def suspect(self, i: int, k: int, statuses: Sequence[str] = BUSY) -> None:
        """Robot i revises its belief about σ_k to "one of ``statuses``" (:func:`suspect_event`)."""
        self.factors[k] = contract(product_update(self.factors[k], suspect_event(self.n, k, i, statuses)))
        self._refresh(k)

    def _refresh(self, k: int) -> None:
        self.updates += 1
        self._table[:, :, k], self._considers[:, k, :] = self._beliefs_about(k)

    def _single(self, k: int, status: str) -> KripkeModel:
        return KripkeModel.build([{f"s{k}_{status}"}], {a: [[0]] for a in self.agents}, [0],
                                 props=[f"s{k}_{s}" for s in STATUSES])

    def _beliefs_about(self, k: int) -> tuple[np.ndarray, np.ndarray]:
        m = self.factors[k]
        rel = np.stack([_dense(m.relation(a), m.n_worlds) for a in self.agents]).astype(np.int32)  # N × W × W
        first = rel[:, m.designated[0], :]  # worlds robot i considers
        second = np.einsum("iw,jwv->ijv", first, rel) > 0  # worlds i thinks j considers
        second[np.arange(self.n), np.arange(self.n)] = first > 0
        cols = [m.prop_index(f"s{k}_{s}") for s in STATUSES]
        val = m.valuation[:, cols].astype(np.int32)  # W × 4, columns in STATUSES order
        have = (second.astype(np.int32) @ val) > 0  # N × N × 4: statuses present
        out = np.argmax(have, axis=2).astype(np.int8)
        out[have.sum(axis=2) != 1] = -1
        return out, have[np.arange(self.n), np.arange(self.n)]

    def believed(self) -> np.ndarray:
        """``B[i, j, k]`` (see class docstring); a view, do not modify."""
        return self._table

    def own_status(self, i: int) -> str:
        """σ_i as robot i knows it (K_i σ_i: every status change of i is an event i observes)."""
        return STATUSES[int(self._table[i, i, i])]

    def considers(self, i: int, k: int) -> frozenset[str]:
        """The statuses robot i considers possible for robot k (B_i σ_k is their disjunction)."""
        return frozenset(s for s, c in zip(STATUSES, self._considers[i, k], strict=True) if c)

    def believes_busy(self, i: int, k: int) -> bool:
        """B_i (σ_k ∈ BUSY) without B_i knowing which: the belief ruleset 1 leaves (robot k is excluded from
        i's planning until i hears k's status again)."""
        c = self._considers[i, k]
        busy = [STATUSES.index(s) for s in BUSY]
        return bool(c[busy].all() and c.sum() == len(busy))

    def holds(self, k: int, f: Formula) -> bool:
        return bool(self.factors[k].holds(f))

    def false_beliefs(self) -> int:
        """Number of (i, k) with B_i σ_k false: robot i does not consider robot k's actual status possible
        (a single wrong status, or ruleset 1's "busy" when k is not)."""
        actual = np.array([STATUSES.index(s) for s in self.statuses])
        return int((~self._considers[:, np.arange(self.n), actual]).sum())

    def check_eq14(self, edges: Iterable[tuple[int, int]]) -> bool:
        """Eq. 14 after a global announcement, factor by factor (each conjunct is about one σ_k)."""
        edges = list(edges)
        for k in range(self.n):
            q = status_prop(k, self.statuses[k])
            parts = [K(agent(k), q)] + [K(agent(i), K(agent(k), q)) for i in range(self.n)]
            parts += [K(agent(i), K(agent(j), K(agent(k), q))) for i in range(self.n) for j, kk in edges if kk == k]
            if not self.holds(k, conj(parts)):
                return False
        return True

    def check_eq18(self, group: Sequence[int]) -> bool:
        """Eq. 18 after a local announcement to ``group``: B_i B_j σ_i ∧ B_i B_j B_i σ_i for i ≠ j in it."""
        for i in group:
            q = status_prop(i, self.statuses[i])
            parts = [f for j in group if j != i
                     for f in (K(agent(i), K(agent(j), q)), K(agent(i), K(agent(j), K(agent(i), q))))]
            if parts and not self.holds(i, conj(parts)):
                return False
        return True

    def n_worlds(self) -> list[int]:
        return [f.n_worlds for f in self.factors]
