"""The team's statuses as a delkit epistemic state (seed 000, §3.2 and §5.3.1).

A world is the combination of every robot's status σ_i ∈ {exploring, gossiping, task, home}
(proposition ``s<i>_<status>``, one-hot per robot; at most 4^N worlds). Robots are the agents ``r0 … r{N-1}``.
The model is updated only by the actions of the paper's library A = {perceive, announce}:

* :meth:`StatusModel.change` — robot i switches status (i: announce(x_i) to its connected group, eq. 17):
  an ontic action with one outcome per possible new status; i and its connected group observe the outcome
  (K_i σ_i), every disconnected robot is *partially* observant: it knows statuses may change while it is out
  of range but not into what (§5.3.1: "each robot may not know when/if the information of the system becomes
  outdated"). Knowledge therefore stays S5 (B = K, as the paper notes) and never becomes false.
* :meth:`StatusModel.perceive` — robot i (and its group) sense a proposition (a task, another robot).
* :meth:`StatusModel.announce_local` — the connected group G announces its members' statuses to each other
  (a private announcement to G; robots outside G are oblivious of it). Afterwards eq. 18 holds:
  B_i B_j σ_i ∧ B_i B_j B_i σ_i for (i, j) ∈ E, and the knowledge of robots outside G is unchanged.
* :meth:`StatusModel.announce_global` — every status is publicly announced (eq. 14): afterwards
  K_i σ_i ∧ K_i K_j σ_j ∧ K_i K_j K_k σ_k for all i, j, k.

Every update is ``delkit.update.product_update`` followed by bisimulation contraction (``delkit.bisim``).
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from dataclasses import dataclass

from delkit.bisim import contract
from delkit.events import action, private_announcement, public_announcement, sensing
from delkit.formula import BOT, TOP, Formula, K, Prop, conj
from delkit.kripke import KripkeModel
from delkit.update import product_update

__all__ = ["StatusModel", "status_prop", "agent", "eq14", "eq18", "STATUSES"]

STATUSES = ("exploring", "gossiping", "task", "home")


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
        group = set(group) | {i}
        outcomes = [(f"to_{s}", TOP, {f"s{i}_{t}": (TOP if t == s else BOT) for t in STATUSES}) for s in STATUSES]
        others = [agent(k) for k in range(self.n) if k not in group]
        ev = action(self.agents, outcomes, full=[agent(k) for k in sorted(group)], partial=others,
                    designated=[f"to_{status}"], name=f"r{i}:status")
        self._apply(ev)
        self.statuses[i] = status

    def perceive(self, i: int, phi: Formula, group: Iterable[int] = ()) -> None:
        """Robot i (with its connected group) senses whether φ; the others know it may have."""
        full = sorted(set(group) | {i})
        self._apply(sensing(phi, self.agents, full=[agent(k) for k in full],
                            partial=[agent(k) for k in range(self.n) if k not in full]))

    def actual_statuses(self, robots: Iterable[int]) -> Formula:
        return conj([status_prop(k, self.statuses[k]) for k in robots])

    def announce_local(self, group: Sequence[int]) -> None:
        """Private announcement of the group's statuses to the group (eq. 18)."""
        self._apply(private_announcement(self.actual_statuses(group), [agent(k) for k in group], self.agents,
                                         name="local_announce"))

    def announce_global(self) -> None:
        """Public announcement of every robot's status (eq. 14)."""
        self._apply(public_announcement(self.actual_statuses(range(self.n)), self.agents, name="global_announce"))

    def holds(self, f: Formula) -> bool:
        return bool(self.model.holds(f))

    def knows_status(self, i: int, j: int) -> bool:
        """K_i σ_j for j's actual status."""
        return self.holds(K(agent(i), status_prop(j, self.statuses[j])))

