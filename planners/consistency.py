r"""Multi-robot action consistency with inconsistent beliefs: VERIFYAC and ENFORCEAC (seed 002).

Kundu, Rafaeli, Indelman — *Multi-Robot Communication-Aware Cooperative Belief Space Planning with
Inconsistent Beliefs: An Action-Consistent Approach*.

Robots that have not shared all their observations hold different beliefs (eq. 5)

.. math::  b_k^r = \mathbb P(x_k \mid {}^c\mathcal H_k^{r,r'},\ \Delta\mathcal H_k^{r',r}),\qquad
           b_k^{r'} = \mathbb P(x_k \mid {}^c\mathcal H_k^{r,r'},\ \Delta\mathcal H_k^{r,r'})      \tag{10}

where :math:`{}^c\mathcal H` is the common history and :math:`\Delta\mathcal H^{r',r}` the observations of
*r* that *r'* lacks.  Each robot picks :math:`a^\star = \arg\max_a J(b,a)` (eq. 3).  The two robots are
*action consistent* (Def. 3.1) when they pick the same joint action although :math:`b^r \neq b^{r'}`.

**VERIFYAC** (§III-C), from the perspective of robot *r*:

1. :math:`\bar a = \arg\max_a J(b_k^r, a)` — its own choice;
2. for every realisation :math:`\tilde z^{r'} \in \Delta\mathcal Z_k^{r,r'}` of the other robot's missing
   observations (eq. 12), the belief :math:`b^{r'|r}(\tilde z^{r'}) = \mathbb P(x\mid{}^c\mathcal H,
   \tilde z^{r'})` (eq. 14) must also select :math:`\bar a`, i.e. :math:`\mathrm{con}_{\bar a}(\Delta
   \mathcal Z^{r,r'})`;
3. for every realisation :math:`\tilde z^{r} \in \Delta\mathcal Z_k^{r',r}` of its *own* unshared
   observations (eq. 13), the belief :math:`b^{r|r'|r}(\tilde z^{r})` (eq. 15) — what *r'* imagines *r*
   believes — must select :math:`\bar a`, i.e. :math:`\mathrm{con}_{\bar a}(\Delta\mathcal Z^{r',r})`.

If 1–3 hold, both robots select :math:`\bar a` (Theorem 3.3): *r'*'s actual belief is one of the beliefs
of step 2.  The verdict is symmetric: *r'* runs the same test on the same two sets, so both robots know
whether they agree.

**ENFORCEAC** (§III-D) self-triggers communications (COMMs) while (16) holds.  Robot *r* sends one of
its unshared observations to *r'* when

* (T1) step 3 is not consistent in favour of :math:`\bar a` — *r'* will find realisations of *r* that
  disagree; or
* (T2) step 2 is consistent in favour of some :math:`a' \neq \bar a` — *r'* surely picks *a'*.

When step 2 is not consistent in favour of :math:`\bar a`, *r* *expects* a COMM from *r'* (which sees
the same sets with the roles swapped and fires T1).  After each round of COMMs the common history grows
and VERIFYAC is run again; every COMM moves one observation into the common history, so ENFORCEAC ends
after at most :math:`|\Delta\mathcal H^{r,r'}| + |\Delta\mathcal H^{r',r}| \le 2p` COMMs (Theorem 3.4).

**N robots** (the paper's future work): every pair (r, r') runs the test above on its own common history
:math:`H^r \cap H^{r'}`; rounds of COMMs continue until every pair agrees.  If *r* agrees with every other
robot, every robot selects *r*'s action, so the team is action consistent.  We assume the *index* of who
holds which observation (not the values) is known to all, as it is for two robots.

Conventions
-----------
* A *slot* is one robot's observation at one time step; slots are integers indexing a :class:`Ledger`.
  Its observation space is discrete with ``model.sizes(slots)`` values ``0..size-1``.
* A *belief batch* is whatever the model uses, with a leading batch axis; a single belief is a batch of 1.
* Selection: :func:`select_actions` picks the lowest action index among the :math:`\varepsilon`-maximisers
  of *J* (``atol``), so ties are broken the same way by every robot and the most preferred action
  (Def. 3.2, :math:`a^\star \succcurlyeq a\ \forall a`) is unique.
* Exact reduction: slots that the model reports as not ``relevant`` (their value cannot change any
  selection, e.g. a cell that no candidate action observes) are left out of the enumeration; every
  realisation of them yields the same selection, so the verdicts of Theorems 3.3/3.4 are unchanged.
* Vectorised: all realisations of a step are evaluated by one ``model.update`` + ``model.objective`` call.

Usage
-----
>>> import numpy as np
>>> from planners.consistency import DiscreteBeliefModel, Ledger, enforce_ac, expected_reward
>>> # two hidden states, two robots each observed one noisy binary slot; 3 candidate joint actions
>>> lik = np.array([[0.8, 0.3], [0.2, 0.7]])          # P(z | x): rows z, columns x
>>> model = DiscreteBeliefModel(prior=np.array([0.5, 0.5]), likelihoods=(lik, lik),
...                             objective=expected_reward(np.array([[1.0, 0.0, 0.45], [0.0, 1.0, 0.45]])))
>>> ledger = Ledger(owner=np.array([0, 1]), step=np.array([1, 1]), value=np.array([0, 1]))
>>> known = np.array([[True, False], [False, True]])   # robot 0 knows slot 0, robot 1 knows slot 1
>>> result = enforce_ac(model, ledger, known)
>>> result.agreed, len(result.comms) <= 2, len(set(result.actions)) == 1
(True, True, True)
"""

from __future__ import annotations

import itertools
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import Any, Literal, Protocol

import numpy as np
from scipy.special import entr

from delkit.errors import PlanningError

__all__ = [
    "BeliefModel",
    "Communication",
    "DiscreteBeliefModel",
    "EnforceResult",
    "Ledger",
    "SendPolicy",
    "TriggerRule",
    "Verification",
    "enforce_ac",
    "expected_reward",
    "information_gain",
    "own_actions",
    "realisations",
    "select_actions",
    "verify_ac",
    "verify_pair",
]

SendPolicy = Literal["greedy", "oldest", "all"]
DEFAULT_ATOL = 1e-9
DEFAULT_MAX_REALISATIONS = 1 << 16
_NO_RANK = np.iinfo(np.int64).max


class BeliefModel(Protocol):
    """What VERIFYAC/ENFORCEAC need from a belief type (generic over the state representation).

    * ``prior`` — the belief :math:`b_0` as a batch of one;
    * ``sizes(slots)`` — :math:`|\\mathcal Z_j|` for each slot (discrete observation spaces);
    * ``update(beliefs, slots, values)`` — Bayes' rule :math:`b(x)\\prod_j \\mathbb P(z_j\\mid x)/\\eta`
      for a batch: ``values`` has shape ``(n, len(slots))`` and ``beliefs`` a batch of 1 or *n*;
    * ``objective(beliefs)`` — :math:`J(b, a)` (eq. 2) for every candidate joint action, shape ``(n, m)``;
    * ``relevant(slots)`` — boolean mask of slots whose value can change a selection (``True`` is safe);
    * optionally ``tie_ranks`` — an ``(m,)`` int array, common to all robots, that breaks ties in *J*
      (see :func:`select_actions`); without it the lowest action index wins.
    """

    prior: Any

    def sizes(self, slots: np.ndarray) -> np.ndarray: ...

    def update(self, beliefs: Any, slots: np.ndarray, values: np.ndarray) -> Any: ...

    def objective(self, beliefs: Any) -> np.ndarray: ...

    def relevant(self, slots: np.ndarray) -> np.ndarray: ...


# ----------------------------------------------------------------------------------------------- helpers


def select_actions(values: np.ndarray, atol: float = DEFAULT_ATOL, ranks: np.ndarray | None = None) -> np.ndarray:
    """Deterministic :math:`\\arg\\max_a J(b,a)` (eq. 3) per row.

    Among the :math:`\\varepsilon`-maximisers :math:`\\{a: J(b,a) \\ge \\max_{a'} J(b,a') - \\varepsilon\\}` the
    action with the smallest ``ranks[a]`` wins (default: the lowest index).  The ranks must be common to
    all robots (e.g. drawn from a seed and the time step).  ``values`` is ``(n, m)``; returns ``(n,)``."""
    values = np.asarray(values, dtype=float)
    if values.ndim != 2 or values.shape[1] == 0:
        raise PlanningError(f"objective must return an (n, m) array with m >= 1 candidate actions, "
                            f"got shape {values.shape}")
    best = values.max(axis=1, keepdims=True)
    ties = values >= best - atol
    if ranks is None:
        return np.argmax(ties, axis=1)
    return np.argmin(np.where(ties, np.asarray(ranks)[None, :], _NO_RANK), axis=1)


def realisations(sizes: Sequence[int] | np.ndarray,
                 max_realisations: int = DEFAULT_MAX_REALISATIONS) -> np.ndarray:
    """All joint realisations of independent discrete slots, :math:`\\mathcal Z_{1}\\times\\dots\\times
    \\mathcal Z_{p}` (eqs. 12–13), as an int array ``(∏ sizes, len(sizes))`` in C (row-major) order, so
    that ``np.ravel_multi_index(z, sizes)`` is the row of realisation *z*."""
    sizes = tuple(int(s) for s in sizes)
    if not sizes:
        return np.zeros((1, 0), dtype=np.int64)
    if min(sizes) < 1:
        raise PlanningError(f"observation spaces must be non-empty, got sizes {sizes}")
    total = int(np.prod(sizes, dtype=object))
    if total > max_realisations:
        raise PlanningError(
            f"{total} joint observation realisations over {len(sizes)} unshared slots exceed the limit "
            f"{max_realisations}; communicate more often or raise max_realisations")
    return np.indices(sizes).reshape(len(sizes), -1).T.astype(np.int64)


# ----------------------------------------------------------------------------------------------- data


@dataclass(frozen=True, eq=False)
class Ledger:
    """Every observation taken so far: slot *j* was captured by robot ``owner[j]`` at time ``step[j]``
    and has the value ``value[j]``.  Robots may only read the values of slots they know."""

    owner: np.ndarray
    step: np.ndarray
    value: np.ndarray

    def __post_init__(self) -> None:
        for name in ("owner", "step", "value"):
            object.__setattr__(self, name, np.asarray(getattr(self, name), dtype=np.int64).reshape(-1))
        if not (len(self.owner) == len(self.step) == len(self.value)):
            raise PlanningError("ledger arrays owner/step/value must have the same length")

    def __len__(self) -> int:
        return len(self.owner)

    def order(self, slots: np.ndarray) -> np.ndarray:
        """``slots`` sorted oldest first (by step, then owner, then id)."""
        slots = np.asarray(slots, dtype=np.int64)
        return slots[np.lexsort((slots, self.owner[slots], self.step[slots]))]


@dataclass(frozen=True)
class Communication:
    """One one-way COMM: ``sender`` sends the observation ``slot`` (captured by ``owner`` at ``step``) to
    ``receiver`` in negotiation ``round``; ``delivered`` is False when the channel was down."""

    sender: int
    receiver: int
    slot: int
    owner: int
    step: int
    round: int
    trigger: str
    delivered: bool = True


@dataclass(frozen=True, eq=False)
class Verification:
    """Result of VERIFYAC for robot ``robot`` against ``other``.

    ``action`` is :math:`\\bar a` (step 1); ``step2_consistent`` is :math:`\\mathrm{con}_{\\bar a}(\\Delta
    \\mathcal Z^{r,r'})`, ``step3_consistent`` is :math:`\\mathrm{con}_{\\bar a}(\\Delta\\mathcal Z^{r',r})`;
    ``step2_favours`` is *a'* when all of step 2 selects one action *a'* (else ``None``).  ``send`` lists the
    triggers (``"T1"``, ``"T2"``) that make *r* send to *r'*; ``expect`` is True when *r* expects a COMM
    from *r'* (step 2 inconsistent).  The realisation matrices and per-realisation selections are kept for
    diagnosis and for choosing what to send."""

    robot: int
    other: int
    action: int
    step2_consistent: bool
    step3_consistent: bool
    step2_favours: int | None
    own_slots: np.ndarray
    other_slots: np.ndarray
    step2_realisations: np.ndarray
    step3_realisations: np.ndarray
    step2_actions: np.ndarray
    step3_actions: np.ndarray
    own_row: int
    send: tuple[str, ...] = ()
    expect: bool = False

    @property
    def agreed(self) -> bool:
        """Steps 1–3 select the same action: :math:`\\mathrm{con}_{\\bar a}(\\Delta\\mathcal Z_k)` (eq. 11)."""
        return self.step2_consistent and self.step3_consistent

    @property
    def failed_steps(self) -> tuple[int, ...]:
        return tuple(s for s, ok in ((2, self.step2_consistent), (3, self.step3_consistent)) if not ok)

    @property
    def reason(self) -> str:
        """Human-readable verdict."""
        if self.agreed:
            return (f"robot {self.robot} and robot {self.other} agree on action {self.action}: all "
                    f"{len(self.step2_actions)} + {len(self.step3_actions)} realisations select it")
        parts = []
        if not self.step2_consistent:
            bad = int(np.sum(self.step2_actions != self.action))
            parts.append(f"step 2: {bad}/{len(self.step2_actions)} realisations of robot {self.other}'s "
                         f"missing observations select another action")
        if not self.step3_consistent:
            bad = int(np.sum(self.step3_actions != self.action))
            parts.append(f"step 3: {bad}/{len(self.step3_actions)} realisations of robot {self.robot}'s "
                         f"own unshared observations select another action")
        return f"robot {self.robot} (action {self.action}) vs robot {self.other}: " + "; ".join(parts)


@dataclass(frozen=True, eq=False)
class EnforceResult:
    """Outcome of ENFORCEAC for one planning session.

    ``actions[r]`` is the joint action robot *r* selects from its own (final) history; ``agreed`` is True
    when every pair verified (then all ``actions`` are equal, Theorem 3.3); ``comms`` lists the delivered
    COMMs, ``failed`` the COMMs that a down channel dropped; ``known`` is the updated knowledge matrix."""

    actions: tuple[int, ...]
    agreed: bool
    comms: tuple[Communication, ...]
    failed: tuple[Communication, ...]
    rounds: int
    known: np.ndarray
    verifications: tuple[Verification, ...] = field(default=())

    @property
    def messages(self) -> int:
        """One-way messages: delivered COMMs grouped by (round, sender, receiver) — a robot that sends
        several observations to the same partner in one round sends one message."""
        return len({(c.round, c.sender, c.receiver) for c in self.comms})

    @property
    def action(self) -> int | None:
        """The common joint action, or ``None`` when the robots disagree."""
        return self.actions[0] if len(set(self.actions)) == 1 else None


# ----------------------------------------------------------------------------------------------- VERIFYAC


def _relevant(model: BeliefModel, slots: np.ndarray) -> np.ndarray:
    if len(slots) == 0:
        return slots
    mask = np.asarray(model.relevant(slots), dtype=bool)
    return slots[mask]


def _select_all(model: BeliefModel, common: Any, slots: np.ndarray, rows: np.ndarray, atol: float) -> np.ndarray:
    beliefs = model.update(common, slots, rows)
    return select_actions(model.objective(beliefs), atol, getattr(model, "tie_ranks", None))


def verify_ac(model: BeliefModel, common: Any, own_slots: np.ndarray, own_values: np.ndarray,
              other_slots: np.ndarray, *, robot: int = 0, other: int = 1, atol: float = DEFAULT_ATOL,
              max_realisations: int = DEFAULT_MAX_REALISATIONS, belief: Any = None) -> Verification:
    """VERIFYAC (§III-C) for robot *r* = ``robot`` against *r'* = ``other``.

    ``common`` is :math:`\\mathbb P(x\\mid{}^c\\mathcal H^{r,r'})` (a batch of one).  A robot that keeps
    only its own belief :math:`b^r` passes ``common=None, belief=b^r`` instead, and the common-history
    belief is obtained by down-dating its unshared observations, ``model.downdate(b^r, own_slots,
    own_values)`` (the form after eq. 14; the model must provide ``downdate``).  ``own_slots`` /
    ``own_values`` are :math:`\\Delta\\mathcal H^{r',r}` (the observations *r* has and *r'* lacks) with
    their actual values, ``other_slots`` is :math:`\\Delta\\mathcal H^{r,r'}` (values unknown to *r*).

    Step 3 evaluates :math:`J(b^{r|r'|r}(\\tilde z^r), a)` for all :math:`\\tilde z^r\\in\\Delta\\mathcal
    Z^{r',r}` in one batch; step 1 is the row of the actual :math:`z^r` (:math:`b^r` itself, eq. 10);
    step 2 evaluates :math:`J(b^{r'|r}(\\tilde z^{r'}), a)` for all :math:`\\tilde z^{r'}\\in\\Delta\\mathcal
    Z^{r,r'}`.  Cost :math:`O(|\\Delta\\mathcal Z^{r,r'}| + |\\Delta\\mathcal Z^{r',r}|)` evaluations.
    """
    own_slots = np.asarray(own_slots, dtype=np.int64).reshape(-1)
    own_values = np.asarray(own_values, dtype=np.int64).reshape(-1)
    other_slots = np.asarray(other_slots, dtype=np.int64).reshape(-1)
    if len(own_slots) != len(own_values):
        raise PlanningError(f"robot {robot}: {len(own_slots)} unshared slots but {len(own_values)} values")
    if common is None:
        if belief is None or not hasattr(model, "downdate"):
            raise PlanningError("verify_ac needs the common-history belief, or the robot's own belief and a "
                                "model with downdate(belief, slots, values)")
        common = model.downdate(belief, own_slots, own_values[None, :])  # type: ignore[attr-defined]
    if len(own_slots):
        keep = np.asarray(model.relevant(own_slots), dtype=bool)
        own_slots, own_values = own_slots[keep], own_values[keep]
    other_slots = _relevant(model, other_slots)

    sizes3 = np.asarray(model.sizes(own_slots), dtype=np.int64)
    if np.any(own_values < 0) or np.any(own_values >= sizes3):
        raise PlanningError(f"robot {robot}: an observation value lies outside its observation space")
    rows3 = realisations(sizes3, max_realisations)
    rows2 = realisations(model.sizes(other_slots), max_realisations)
    sel3 = _select_all(model, common, own_slots, rows3, atol)              # steps 1 and 3
    sel2 = _select_all(model, common, other_slots, rows2, atol)            # step 2
    own_row = int(np.ravel_multi_index(tuple(own_values), tuple(sizes3))) if len(own_slots) else 0
    action = int(sel3[own_row])                                            # step 1: ā
    ok2 = bool(np.all(sel2 == action))
    ok3 = bool(np.all(sel3 == action))
    favours = int(sel2[0]) if bool(np.all(sel2 == sel2[0])) else None
    send: list[str] = []
    if not ok3:
        send.append("T1")
    if favours is not None and favours != action:
        send.append("T2")
    return Verification(robot=robot, other=other, action=action, step2_consistent=ok2, step3_consistent=ok3,
                        step2_favours=favours, own_slots=own_slots, other_slots=other_slots,
                        step2_realisations=rows2, step3_realisations=rows3, step2_actions=sel2,
                        step3_actions=sel3, own_row=own_row, send=tuple(send), expect=not ok2)


def _common_belief(model: BeliefModel, ledger: Ledger, mask: np.ndarray) -> Any:
    slots = np.flatnonzero(mask)
    return model.update(model.prior, slots, ledger.value[slots][None, :])


def verify_pair(model: BeliefModel, ledger: Ledger, known: np.ndarray, robot: int, other: int, *,
                atol: float = DEFAULT_ATOL, max_realisations: int = DEFAULT_MAX_REALISATIONS,
                common: Any = None) -> Verification:
    """VERIFYAC of ``robot`` against ``other`` from a ledger and a knowledge matrix ``known[r, slot]``.

    Only what *r* may know is read: the values of slots in :math:`H^r`, and the *index* of :math:`H^{r'}`.
    ``common`` may pass :math:`\\mathbb P(x\\mid H^r\\cap H^{r'})` when the caller already has it."""
    mine, theirs = known[robot], known[other]
    own = ledger.order(np.flatnonzero(mine & ~theirs))
    missing = ledger.order(np.flatnonzero(theirs & ~mine))
    if common is None:
        common = _common_belief(model, ledger, mine & theirs)
    return verify_ac(model, common, own, ledger.value[own], missing,
                     robot=robot, other=other, atol=atol, max_realisations=max_realisations)


def own_actions(model: BeliefModel, ledger: Ledger, known: np.ndarray, atol: float = DEFAULT_ATOL) -> tuple[int, ...]:
    """Each robot's selection from its own history only, :math:`\\arg\\max_a J(\\mathbb P(x\\mid H^r), a)`
    — what the robots actually execute; used to count Not-AC independently of ENFORCEAC."""
    out = []
    per_robot = getattr(model, "robot_tie_ranks", None)  # a model may let each robot break ties its own way
    for r in range(known.shape[0]):
        belief = _common_belief(model, ledger, known[r])
        ranks = per_robot(r) if per_robot is not None else getattr(model, "tie_ranks", None)
        out.append(int(select_actions(model.objective(belief), atol, ranks)[0]))
    return tuple(out)


# ----------------------------------------------------------------------------------------------- ENFORCEAC


def _gains(model: BeliefModel, ledger: Ledger, known: np.ndarray, ver: Verification,
           atol: float) -> tuple[np.ndarray, np.ndarray]:
    """For each of *r*'s unshared relevant slots *j*: the fraction of step-3 and of step-2 realisations
    that select :math:`\\bar a` once :math:`z_j` is common (step 3 shrinks to the rows matching the actual
    :math:`z_j`; step 2 is re-evaluated on the grown common history)."""
    own = ver.own_slots
    common = known[ver.robot] & known[ver.other]
    actual = ledger.value[own]
    good3, good2 = np.empty(len(own)), np.empty(len(own))
    for j, slot in enumerate(own):
        rows = ver.step3_realisations[:, j] == actual[j]
        good3[j] = float(np.mean(ver.step3_actions[rows] == ver.action))
        grown = common.copy()
        grown[slot] = True
        sel2 = _select_all(model, _common_belief(model, ledger, grown), ver.other_slots,
                           ver.step2_realisations, atol)
        good2[j] = float(np.mean(sel2 == ver.action))
    return good3, good2


def _choose_slots(ver: Verification, policy: SendPolicy, gains: tuple[np.ndarray, np.ndarray] | None) -> list[int]:
    """Which of *r*'s unshared relevant observations to send to *r'* (the paper leaves this open).

    ``oldest``: the oldest one.  ``all``: every one.  ``greedy``: the one that, once common, leaves the
    largest fraction of step-2 plus step-3 realisations selecting :math:`\\bar a` (:func:`_gains`); ties go
    to the oldest."""
    own = ver.own_slots
    if len(own) == 0:
        return []
    if policy == "all":
        return [int(s) for s in own]
    if policy == "oldest" or len(own) == 1 or gains is None:
        return [int(own[0])]
    return [int(own[int(np.argmax(gains[0] + gains[1]))])]  # argmax → first (oldest) among ties


TriggerRule = Literal["paper", "useful"]


def enforce_ac(model: BeliefModel, ledger: Ledger, known: np.ndarray, *,
               link: bool | Callable[[int, int], bool] = True, policy: SendPolicy = "greedy",
               trigger: TriggerRule = "paper", atol: float = DEFAULT_ATOL,
               max_realisations: int = DEFAULT_MAX_REALISATIONS, max_rounds: int | None = None) -> EnforceResult:
    """ENFORCEAC (§III-D) for two or more robots.

    Each round, every robot runs :func:`verify_pair` against every other robot; for each pair that fails
    it self-triggers a COMM to the partner under rule T1 (its step 3 inconsistent) or T2 (its step 2
    consistent in favour of another action).  All COMMs of a round are delivered together (``link(s, r)``
    says whether the channel from *s* to *r* is up; a dropped COMM is reported in ``failed``), the
    knowledge matrix grows, and the next round re-verifies every pair.  The loop ends when every pair
    agrees (then all robots select the same action, Theorem 3.3) or when no COMM can be delivered.  Robots
    speak in id order within a round and skip an observation another robot is already sending to the same
    receiver (message headers are overheard), so each delivered COMM adds a new slot to a robot's history
    and ENFORCEAC ends after at most :math:`\\sum_{r}|\\bigcup_{r'} H^{r'}\\setminus H^{r}|` COMMs
    (:math:`2p` for two robots with *p* unshared steps each, Theorem 3.4).

    ``trigger="paper"`` applies T1/T2 as in §III-D.  ``trigger="useful"`` (our refinement) fires T2 alone
    only when sharing one of *r*'s observations would turn at least one step-2 realisation to
    :math:`\\bar a`; otherwise *r* waits for *r'* (who sees the mirror image and fires T1/T2).  If a
    failing pair exchanged nothing in a round, the next round falls back to the paper's rule, so the
    bound and the termination argument above still hold (one extra round at most, no extra COMM).
    ``policy`` chooses which observation a triggered robot sends (:func:`_choose_slots`).
    """
    if policy not in ("greedy", "oldest", "all"):
        raise PlanningError(f"unknown send policy {policy!r}; use 'greedy', 'oldest' or 'all'")
    if trigger not in ("paper", "useful"):
        raise PlanningError(f"unknown trigger rule {trigger!r}; use 'paper' or 'useful'")
    known = np.array(known, dtype=bool, copy=True)
    n_robots = known.shape[0]
    if n_robots < 2:
        raise PlanningError("action consistency needs at least two robots")
    if known.shape[1] != len(ledger):
        raise PlanningError(f"knowledge matrix has {known.shape[1]} slots but the ledger has {len(ledger)}")
    up = (lambda s, r: link) if isinstance(link, bool) else link
    comms: list[Communication] = []
    failed: list[Communication] = []
    quiet: set[frozenset[int]] = set()        # failing pairs that exchanged nothing last round
    silent = False                            # last round had no COMM at all
    limit = max_rounds if max_rounds is not None else 2 * int(known.size) + 2
    for rnd in range(limit + 1):
        commons = {pair: _common_belief(model, ledger, known[pair[0]] & known[pair[1]])
                   for pair in itertools.combinations(range(n_robots), 2)}
        vers = [verify_pair(model, ledger, known, r, o, atol=atol, max_realisations=max_realisations,
                            common=commons[min(r, o), max(r, o)])
                for r, o in itertools.permutations(range(n_robots), 2)]
        actions = tuple(_step1_actions(vers, n_robots))
        if all(v.agreed for v in vers):
            return EnforceResult(actions, True, tuple(comms), tuple(failed), rnd, known, tuple(vers))
        outgoing: list[Communication] = []
        queued: set[tuple[int, int]] = set()
        for ver in vers:                          # robots speak in id order (a TDMA round)
            if ver.agreed or not ver.send or len(ver.own_slots) == 0:
                continue
            need = policy == "greedy" or (trigger == "useful" and ver.send == ("T2",))
            gains = _gains(model, ledger, known, ver, atol) if need and len(ver.own_slots) else None
            if (trigger == "useful" and ver.send == ("T2",) and frozenset((ver.robot, ver.other)) not in quiet
                    and gains is not None and not np.any(gains[1] > 0)):
                continue                      # sharing any of my observations changes nothing for r'
            for slot in _choose_slots(ver, policy, gains):
                if (ver.other, slot) in queued:   # overheard: another robot sends it this round
                    continue
                queued.add((ver.other, slot))
                outgoing.append(Communication(ver.robot, ver.other, slot, int(ledger.owner[slot]),
                                              int(ledger.step[slot]), rnd, "+".join(ver.send),
                                              bool(up(ver.robot, ver.other))))
        delivered = [c for c in outgoing if c.delivered]
        failed.extend(c for c in outgoing if not c.delivered)
        talking = {frozenset((c.sender, c.receiver)) for c in outgoing}
        quiet = {frozenset((v.robot, v.other)) for v in vers if not v.agreed} - talking
        if not delivered:
            if outgoing:                      # the channel is down: each robot keeps its own choice
                return EnforceResult(actions, False, tuple(comms), tuple(failed), rnd, known, tuple(vers))
            if trigger == "paper" or silent:  # impossible by the argument of Theorem 3.4
                raise PlanningError("ENFORCEAC: verification failed but no robot triggered a COMM")
            silent = True
            continue
        silent = False
        for c in delivered:
            known[c.receiver, c.slot] = True
        comms.extend(delivered)
    raise PlanningError(f"ENFORCEAC did not converge within {limit} rounds")


def _step1_actions(vers: Sequence[Verification], n_robots: int) -> list[int]:
    """Step-1 action :math:`\\bar a` of each robot (identical across its pairs: it depends on :math:`H^r`)."""
    out = [-1] * n_robots
    for v in vers:
        if out[v.robot] < 0:
            out[v.robot] = v.action
    return out


# ----------------------------------------------------------------------------------------------- a generic model


class DiscreteBeliefModel:
    """Belief over a finite state space :math:`\\mathcal X` (eq. 1), one likelihood table per slot.

    ``likelihoods[j][z, x]`` is :math:`\\mathbb P(z_j = z\\mid x)` (strictly positive); ``objective`` maps a
    belief batch ``(n, |X|)`` to :math:`J(b, a)` of shape ``(n, m)``.  ``update`` is Bayes' rule and
    ``downdate`` its inverse, :math:`\\mathbb P(x\\mid{}^c\\mathcal H) \\propto b^r(x)/\\prod_j\\mathbb P(z_j\\mid x)`
    (the form after eq. 14).  ``relevant`` optionally marks the slots that can change a selection."""

    def __init__(self, prior: np.ndarray, likelihoods: Sequence[np.ndarray],
                 objective: Callable[[np.ndarray], np.ndarray],
                 relevant: np.ndarray | None = None) -> None:
        prior = np.asarray(prior, dtype=float).reshape(1, -1)
        if np.any(prior < 0) or not np.isclose(prior.sum(), 1.0):
            raise PlanningError("prior must be a probability vector")
        liks = tuple(np.asarray(L, dtype=float) for L in likelihoods)
        for j, L in enumerate(liks):
            if L.ndim != 2 or L.shape[1] != prior.shape[1]:
                raise PlanningError(f"likelihood of slot {j} must have shape (|Z|, {prior.shape[1]})")
            if np.any(L <= 0) or not np.allclose(L.sum(axis=0), 1.0):
                raise PlanningError(f"likelihood of slot {j} must be positive with columns summing to 1")
        self.prior = prior
        self.likelihoods = liks
        self.objective_fn = objective
        self.relevant_mask = None if relevant is None else np.asarray(relevant, dtype=bool)

    def sizes(self, slots: np.ndarray) -> np.ndarray:
        return np.array([self.likelihoods[int(s)].shape[0] for s in slots], dtype=np.int64)

    def update(self, beliefs: np.ndarray, slots: np.ndarray, values: np.ndarray) -> np.ndarray:
        values = np.atleast_2d(np.asarray(values, dtype=np.int64))
        out = np.broadcast_to(beliefs, (values.shape[0], beliefs.shape[1])).copy()
        for j, s in enumerate(slots):
            out *= self.likelihoods[int(s)][values[:, j]]
        return out / out.sum(axis=1, keepdims=True)

    def downdate(self, beliefs: np.ndarray, slots: np.ndarray, values: np.ndarray) -> np.ndarray:
        values = np.atleast_2d(np.asarray(values, dtype=np.int64))
        out = np.broadcast_to(beliefs, (values.shape[0], beliefs.shape[1])).copy()
        for j, s in enumerate(slots):
            out /= self.likelihoods[int(s)][values[:, j]]
        return out / out.sum(axis=1, keepdims=True)

    def objective(self, beliefs: np.ndarray) -> np.ndarray:
        return np.asarray(self.objective_fn(beliefs), dtype=float)

    def relevant(self, slots: np.ndarray) -> np.ndarray:
        if self.relevant_mask is None:
            return np.ones(len(slots), dtype=bool)
        return self.relevant_mask[np.asarray(slots, dtype=np.int64)]


def expected_reward(rewards: np.ndarray) -> Callable[[np.ndarray], np.ndarray]:
    """:math:`J(b,a) = \\mathbb E_{x\\sim b}[R(x,a)]` for a reward matrix ``rewards[x, a]`` (myopic, L = 1)."""
    rewards = np.asarray(rewards, dtype=float)
    return lambda b: b @ rewards


def information_gain(sensors: np.ndarray, costs: np.ndarray | None = None) -> Callable[[np.ndarray], np.ndarray]:
    """Belief-dependent objective :math:`J(b,a) = \\rho(b) + \\mathbb E_{z}[\\rho(b')] - c_a` with
    :math:`\\rho = -H` (eq. 2 with L = 1): action *a* takes a reading with likelihood ``sensors[a][z, x]``."""
    sensors = np.asarray(sensors, dtype=float)
    costs = np.zeros(sensors.shape[0]) if costs is None else np.asarray(costs, dtype=float)

    def entropy(p: np.ndarray, axis: int) -> np.ndarray:
        return entr(p).sum(axis=axis)

    def objective(b: np.ndarray) -> np.ndarray:
        h = entropy(b, 1)                                        # (n,)
        joint = b[:, None, None, :] * sensors[None]              # (n, m, |Z|, |X|)  P(z, x)
        pz = joint.sum(axis=3)                                   # (n, m, |Z|)
        post = joint / pz[..., None]
        exp_h = np.sum(pz * entropy(post, 3), axis=2)            # (n, m)
        return -h[:, None] - exp_h - costs[None, :]

    return objective
