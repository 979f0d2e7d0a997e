r"""Search and rescue on a grid with inconsistent beliefs — the study of seed 002, §IV and Table I.

World.  A ``width × height`` grid; each cell *i* independently holds a target (:math:`x_i = 1`) with
probability ``target_density`` (drawn once from the seed).  Robots know every robot's pose (assumption (a)
of §IV-A) and at every time step each robot observes the cell it stands on.

Observation model (the paper does not give one; ours): a noisy binary detector,

.. math::  \mathbb P(z = 1\mid x_i = 1) = p_d = 0.8,\qquad \mathbb P(z = 1\mid x_i = 0) = p_f = 0.2 .

Beliefs.  The cells stay independent (§IV-A), :math:`b_k = \prod_i b_k[x_i]`, and a cell's posterior
depends only on how many positive and negative readings of it a robot holds:

.. math::  \operatorname{logit} b_k[x_i{=}1] = \operatorname{logit} b_0[x_i{=}1] + n^+_i \log\frac{p_d}{p_f}
           + n^-_i \log\frac{1-p_d}{1-p_f}.

:class:`SARBeliefModel` therefore stores a belief as integer counts :math:`(n^+, n^-)` per cell, which makes
Bayes' rule exact and order independent, so two robots that hold the same observations hold bit-for-bit
the same belief however they received them.

Prior.  ``max-entropy``: :math:`b_0[x_i{=}1] = 0.5` for every cell (MaxEntropy-Init); ``entropy``: 0.7 on
cells that truly hold a target and 0.3 elsewhere (Entropy-Init).

Objective.  Reward :math:`\rho(b) = -H(b) = \sum_i\sum_j b[x_i{=}j]\log b[x_i{=}j]` (nats), horizon
:math:`L = 1`, so eq. (2) reads

.. math::  J(b_k, a) = \rho(b_k) + \mathbb E_{z_{k+1}}[\rho(b_{k+1})] = -2H(b_k) + I(x; z_{k+1}\mid a),

where the information gain of the joint action *a* sums, over the distinct cells the robots move to, the
mutual information between the cell and the :math:`c` readings taken there
(:math:`I = H(C) - b\,H(\mathrm{Bin}(c, p_d)) - (1-b)\,H(\mathrm{Bin}(c, p_f))` with *C* the count of
positive readings).  Candidate joint actions are all combinations of the robots' motion primitives that
stay on the grid: 4 (N, S, E, W) or 8 (plus NE, NW, SW, SE).

Episode.  For :math:`k = 1..E`: every robot observes its cell; the algorithm communicates
(``enforce`` = ENFORCEAC, ``baseline1`` = every robot sends its new observation to every other robot every
step — the paper's reading, the default: a message dropped on a restricted step is never repaired; with
``resend=True`` (our variant) it sends all its unshared observations, so the backlog is re-sent on the next
open step — ``baseline2`` = never); then every robot selects a joint action from *its own* history
only and executes its own component.  ``Not-AC`` counts steps where the robots' selected joint actions
differ.  ``comm_restr = m`` picks *m* random steps (from the seed, unknown to the algorithms) on which the
channel is down: COMMs attempted then are dropped.

Usage
-----
>>> from sim.sar import SARConfig, run_episode
>>> res = run_episode(SARConfig(epochs=20, seed=1), "enforce")
>>> res.not_ac, res.violations
(0, 0)
"""

from __future__ import annotations

import functools
import itertools
import math
import time
from collections.abc import Callable
from dataclasses import asdict, dataclass, field, replace
from typing import Literal

import numpy as np
from scipy.special import entr

from delkit.errors import SimulationError
from planners.consistency import Ledger, enforce_ac, own_actions

__all__ = [
    "ALGORITHMS",
    "PAPER_TABLE_I",
    "PRIMITIVES",
    "EpisodeResult",
    "SARBeliefModel",
    "SARConfig",
    "TableRow",
    "run_episode",
    "table_i",
    "table_inputs",
]

Algorithm = Literal["enforce", "baseline1", "baseline2"]
ALGORITHMS: tuple[Algorithm, ...] = ("baseline2", "baseline1", "enforce")
ALGORITHM_NAMES = {"baseline2": "Baseline-II", "baseline1": "Baseline-I", "enforce": "ENFORCEAC"}
INIT_NAMES = {"max-entropy": "MaxEntropy-Init", "entropy": "Entropy-Init"}

#: (dx, dy) of the motion primitives, in the order N, S, E, W, NE, NW, SW, SE (y grows northwards).
PRIMITIVES: tuple[tuple[int, int], ...] = ((0, 1), (0, -1), (1, 0), (-1, 0), (1, 1), (-1, 1), (-1, -1), (1, -1))

#: Table I of seed 002 (E = 200, Julia on an i7-6500U): (comm_restr, primitives, init) → algorithm →
#: (Not-AC, COMM, time in s).
PAPER_TABLE_I: dict[tuple[int, int, str], dict[str, tuple[int, int, float]]] = {
    (0, 4, "max-entropy"): {"baseline2": (181, 0, 1.3), "baseline1": (0, 400, 1.3), "enforce": (0, 238, 12.4)},
    (0, 4, "entropy"): {"baseline2": (185, 0, 1.3), "baseline1": (0, 400, 1.4), "enforce": (0, 268, 8.7)},
    (0, 8, "max-entropy"): {"baseline2": (194, 0, 3.6), "baseline1": (0, 400, 3.5), "enforce": (0, 248, 36.4)},
    (0, 8, "entropy"): {"baseline2": (188, 0, 3.6), "baseline1": (0, 400, 3.6), "enforce": (0, 278, 31.1)},
    (20, 8, "max-entropy"): {"baseline2": (194, 0, 3.3), "baseline1": (14, 360, 4.3),
                             "enforce": (13, 224, 94.9)},
    (20, 8, "entropy"): {"baseline2": (188, 0, 3.2), "baseline1": (14, 360, 3.6), "enforce": (10, 251, 31.2)},
    (30, 8, "max-entropy"): {"baseline2": (188, 0, 3.4), "baseline1": (22, 340, 4.0),
                             "enforce": (20, 238, 46.9)},
}


@dataclass(frozen=True)
class SARConfig:
    """One search-and-rescue set-up (defaults: our choices where the paper is silent)."""

    width: int = 10
    height: int = 10
    robots: int = 2
    primitives: int = 4
    init: Literal["max-entropy", "entropy"] = "max-entropy"
    target_density: float = 0.3
    p_detect: float = 0.8
    p_false: float = 0.2
    epochs: int = 200
    comm_restr: int = 0
    seed: int = 0
    policy: Literal["greedy", "oldest", "all"] = "all"
    # ties among ε-maximisers of J: 'random' (one random order per step shared by all robots: ours — the paper
    # does not say), 'index' (lowest joint-action index) or 'own' (each robot its own random order: what the
    # paper's Baseline-II figures imply; only the executed choices use it, ENFORCEAC's reasoning about
    # the partner keeps the common order)
    tie_break: Literal["random", "index", "own"] = "random"
    trigger: Literal["paper", "useful"] = "paper"
    resend: bool = False  # Baseline-I re-sends a lost backlog: our variant, not the paper's
    # exact pruning of irrelevant observations (readings of cells no candidate action moves to cannot change a
    # selection): ours, not the paper's; the verdicts are the same with prune=False, only slower
    prune: bool = True

    def __post_init__(self) -> None:
        if self.width < 2 or self.height < 2:
            raise SimulationError(f"grid must be at least 2×2, got {self.width}×{self.height}")
        if self.primitives not in (4, 8):
            raise SimulationError(f"primitives must be 4 or 8, got {self.primitives}")
        if self.init not in INIT_NAMES:
            raise SimulationError(f"init must be 'max-entropy' or 'entropy', got {self.init!r}")
        if not 2 <= self.robots <= min(6, self.width * self.height):
            raise SimulationError(f"robots must be between 2 and 6, got {self.robots}")
        if not 0.0 < self.p_false < self.p_detect < 1.0:
            raise SimulationError("sensor needs 0 < p_false < p_detect < 1 "
                                  f"(got p_false={self.p_false}, p_detect={self.p_detect})")
        if not 0 <= self.comm_restr <= self.epochs:
            raise SimulationError(f"comm_restr must lie in [0, epochs={self.epochs}], got {self.comm_restr}")
        if self.tie_break not in ("random", "index", "own"):
            raise SimulationError(f"tie_break must be 'random', 'index' or 'own', got {self.tie_break!r}")
        if not 0.0 <= self.target_density <= 1.0:
            raise SimulationError(f"target_density must lie in [0, 1], got {self.target_density}")

    @property
    def cells(self) -> int:
        return self.width * self.height


def _binary_entropy(p: np.ndarray) -> np.ndarray:
    """:math:`H(p) = -p\\log p - (1-p)\\log(1-p)` in nats, elementwise (``scipy.special.entr``)."""
    return entr(p) + entr(1.0 - p)


@functools.lru_cache(maxsize=64)
def _binomial(k: int, q: float) -> tuple[np.ndarray, float]:
    """pmf of Bin(k, q) over 0..k and its entropy (nats)."""
    pmf = np.array([math.comb(k, c) * q**c * (1 - q) ** (k - c) for c in range(k + 1)])
    return pmf, float(_pmf_entropy(pmf))


def _pmf_entropy(p: np.ndarray, axis: int = -1) -> np.ndarray:
    """Shannon entropy (nats) of pmfs along ``axis``."""
    return entr(p).sum(axis=axis)


class SARBeliefModel:
    """The :class:`planners.consistency.BeliefModel` of the grid at one planning time.

    A belief batch is an int array ``(n, 2, X)`` of positive/negative reading counts per cell; ``cells[j]``
    is the cell observed by ledger slot *j*; ``poses`` the robots' current cells (known to all)."""

    def __init__(self, config: SARConfig, prior_logit: np.ndarray, cells: np.ndarray, poses: np.ndarray,
                 step: int = 0) -> None:
        self.config = config
        self.prior_logit = prior_logit
        self.cells = np.asarray(cells, dtype=np.int64)
        self.poses = np.asarray(poses, dtype=np.int64)
        self.prior = np.zeros((1, 2, config.cells), dtype=np.int64)
        self.moves, self.next_cells = candidate_actions(config, self.poses)
        self.targets, inverse = np.unique(self.next_cells, return_inverse=True)
        self.target_index = inverse.reshape(self.next_cells.shape)          # (m, N) into self.targets
        same = self.next_cells[:, :, None] == self.next_cells[:, None, :]
        self.multiplicity = same.sum(axis=2)                                 # (m, N)
        self._log_pos = np.log(config.p_detect / config.p_false)
        self._log_neg = np.log((1 - config.p_detect) / (1 - config.p_false))
        kmax = int(self.multiplicity.max())
        self.step = step
        if config.tie_break in ("random", "own"):  # common to all robots: drawn from (seed, step) only
            tie_rng = np.random.default_rng([config.seed, step, 0x7E])
            self.tie_ranks: np.ndarray | None = tie_rng.permutation(len(self.moves))
        else:
            self.tie_ranks = None
        self._bin = [(_binomial(k, config.p_detect), _binomial(k, config.p_false)) for k in range(1, kmax + 1)]
        self._target_mask = np.zeros(config.cells, dtype=bool)
        self._target_mask[self.targets] = True

    # -- BeliefModel protocol ------------------------------------------------------------------------------
    def sizes(self, slots: np.ndarray) -> np.ndarray:
        return np.full(len(slots), 2, dtype=np.int64)

    def update(self, beliefs: np.ndarray, slots: np.ndarray, values: np.ndarray) -> np.ndarray:
        """Bayes' rule on counts: add one positive (z = 1) or negative (z = 0) reading per slot, exactly."""
        values = np.atleast_2d(np.asarray(values, dtype=np.int64))
        n, x = values.shape[0], self.config.cells
        out = np.broadcast_to(beliefs, (n, 2, x)).copy()
        if len(slots) == 0:
            return out
        flat = (np.arange(n)[:, None] * x + self.cells[np.asarray(slots, dtype=np.int64)][None, :]).ravel()
        pos = np.bincount(flat, weights=values.ravel(), minlength=n * x).reshape(n, x).astype(np.int64)
        tot = np.bincount(flat, minlength=n * x).reshape(n, x)
        out[:, 0] += pos
        out[:, 1] += tot - pos
        return out

    def probabilities(self, beliefs: np.ndarray) -> np.ndarray:
        """:math:`b[x_i = 1]` for a batch of count beliefs, shape ``(n, X)``."""
        logit = self.prior_logit[None, :] + beliefs[:, 0] * self._log_pos + beliefs[:, 1] * self._log_neg
        return 1.0 / (1.0 + np.exp(-logit))

    def objective(self, beliefs: np.ndarray) -> np.ndarray:
        """:math:`J(b,a) = -2H(b) + I(x; z_{k+1}\\mid a)` for every candidate joint action, ``(n, m)``."""
        p = self.probabilities(beliefs)
        total_h = _binary_entropy(p).sum(axis=1)                              # (n,)
        pt = p[:, self.targets]                                             # (n, |C|)
        gains = []
        for (bd, hd), (bf, hf) in self._bin:
            mix = pt[..., None] * bd + (1 - pt[..., None]) * bf             # (n, |C|, k+1)
            gains.append(_pmf_entropy(mix) - pt * hd - (1 - pt) * hf)
        mi = np.stack(gains, axis=2)                                        # (n, |C|, kmax)
        per_robot = mi[:, self.target_index, self.multiplicity - 1] / self.multiplicity  # (n, m, N)
        return -2.0 * total_h[:, None] + per_robot.sum(axis=2)

    def robot_tie_ranks(self, robot: int) -> np.ndarray | None:
        """The tie-break order robot ``robot`` executes with (``tie_break='own'``: its own, from (seed, step,
        robot); otherwise the common one)."""
        if self.config.tie_break != "own":
            return self.tie_ranks
        return np.random.default_rng([self.config.seed, self.step, 0x7E, robot + 1]).permutation(len(self.moves))

    def relevant(self, slots: np.ndarray) -> np.ndarray:
        """Exact reduction: only readings of cells some candidate action moves to can change a selection
        (:math:`H(b_k)` shifts every action's *J* equally)."""
        slots = np.asarray(slots, dtype=np.int64)
        if not self.config.prune:
            return np.ones(len(slots), dtype=bool)
        return self._target_mask[self.cells[slots]]


def candidate_actions(config: SARConfig, poses: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """All joint actions (primitive index per robot, lexicographic) that keep every robot on the grid,
    and the cells they lead to; both ``(m, N)``."""
    d = np.array(PRIMITIVES[: config.primitives], dtype=np.int64)
    poses = np.asarray(poses, dtype=np.int64)
    x = poses[:, None] % config.width + d[None, :, 0]
    y = poses[:, None] // config.width + d[None, :, 1]
    ok = (x >= 0) & (x < config.width) & (y >= 0) & (y < config.height)        # (N, P)
    valid = [np.flatnonzero(row) for row in ok]
    grids = np.meshgrid(*valid, indexing="ij")                                  # lexicographic order
    moves = np.stack([g.ravel() for g in grids], axis=1)
    robots = np.arange(len(poses))[None, :]
    cells = (y * config.width + x)[robots, moves]
    return moves, cells


@dataclass(frozen=True)
class EpisodeResult:
    """Counts of one episode.  ``comms``: one-way messages delivered; ``observations_sent``: observations
    they carried (equal for ENFORCEAC, whose messages carry one each); ``violations``: steps where
    ENFORCEAC reported agreement but the robots, run on their own histories, selected different actions
    (Theorem 3.3 says 0); ``max_unshared``: the largest number of one robot's observations the partner
    lacked at planning time (*p*); ``time_s`` / ``cpu_s``: wall-clock and process CPU time of the episode
    loop; ``team_j``: per step, *J* of the executed joint action under the belief
    that holds every observation; ``not_ac_steps`` / ``restricted_steps``: the steps with Not-AC and the
    steps on which the channel was down."""

    config: SARConfig
    algorithm: str
    not_ac: int
    comms: int
    observations_sent: int
    failed_comms: int
    violations: int
    max_unshared: int
    max_comms_per_step: int
    time_s: float
    cpu_s: float = 0.0
    team_j: tuple[float, ...] = field(repr=False, default=())
    since_comm: tuple[int, ...] = field(repr=False, default=())
    not_ac_steps: tuple[int, ...] = field(repr=False, default=())
    restricted_steps: tuple[int, ...] = field(repr=False, default=())

    def as_dict(self) -> dict:
        d = asdict(self)
        d["config"] = asdict(self.config)
        d["mean_team_j"] = float(np.mean(self.team_j)) if self.team_j else None
        return d


def _world(config: SARConfig) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, set[int]]:
    """Truth, prior logits, start poses, pre-drawn sensor uniforms and restricted steps, from the seed.

    Separate streams, so the world and the sensor noise are the same for every algorithm and every
    comm-restr (common random numbers)."""
    ss = np.random.SeedSequence(config.seed)
    world_rng, noise_rng, restr_rng = (np.random.default_rng(s) for s in ss.spawn(3))
    truth = world_rng.random(config.cells) < config.target_density
    poses = world_rng.choice(config.cells, size=config.robots, replace=False).astype(np.int64)
    if config.init == "max-entropy":
        prior = np.full(config.cells, 0.5)
    else:
        prior = np.where(truth, 0.7, 0.3)
    logit = np.log(prior / (1 - prior))
    uniforms = noise_rng.random((config.epochs + 1, config.robots))
    restricted = set((restr_rng.choice(config.epochs, size=config.comm_restr, replace=False) + 1).tolist())
    return truth, logit, poses, uniforms, restricted


def run_episode(config: SARConfig, algorithm: Algorithm) -> EpisodeResult:
    """Run one episode of E = ``config.epochs`` planning steps with ``algorithm``."""
    if algorithm not in ALGORITHMS:
        raise SimulationError(f"unknown algorithm {algorithm!r}; use one of {', '.join(ALGORITHMS)}")
    truth, logit, poses, uniforms, restricted = _world(config)
    n, cap = config.robots, config.robots * config.epochs
    owner = np.zeros(cap, dtype=np.int64)
    step = np.zeros(cap, dtype=np.int64)
    value = np.zeros(cap, dtype=np.int64)
    cells = np.zeros(cap, dtype=np.int64)
    known = np.zeros((n, cap), dtype=bool)
    not_ac = comms = sent = failed = violations = max_unshared = max_step_comms = 0
    since, last_comm = [], 0
    team_j: list[float] = []
    not_ac_steps: list[int] = []
    slots = 0
    start, cpu_start = time.perf_counter(), time.process_time()
    for k in range(1, config.epochs + 1):
        for r in range(n):  # every robot observes the cell it stands on
            p1 = config.p_detect if truth[poses[r]] else config.p_false
            owner[slots], step[slots], cells[slots] = r, k, poses[r]
            value[slots] = int(uniforms[k, r] < p1)
            known[r, slots] = True
            slots += 1
        ledger = Ledger(owner[:slots], step[:slots], value[:slots])
        kn = known[:, :slots]
        model = SARBeliefModel(config, logit, cells[:slots], poses, k)
        up = k not in restricted
        unshared = max(int(np.sum(kn[r] & ~kn[o])) for r, o in itertools.permutations(range(n), 2))
        max_unshared = max(max_unshared, unshared)
        step_comms = 0
        agreed = False
        if algorithm == "baseline1":
            snapshot = kn.copy()
            if not config.resend:  # only this step's readings: what a dropped message lost stays lost
                snapshot[:, : slots - n] = False
            for r, o in itertools.permutations(range(n), 2):
                missing = snapshot[r] & ~snapshot[o]
                if missing.any():
                    if up:
                        kn[o] |= missing
                        step_comms += 1
                        sent += int(missing.sum())
                    else:
                        failed += 1
        elif algorithm == "enforce":
            res = enforce_ac(model, ledger, kn, link=up, policy=config.policy, trigger=config.trigger)
            kn[:] = res.known
            step_comms = res.messages
            sent += len(res.comms)
            failed += len(res.failed)
            agreed = res.agreed
        comms += step_comms
        max_step_comms = max(max_step_comms, step_comms)
        if step_comms:
            last_comm = k
        since.append(k - last_comm)
        chosen = own_actions(model, ledger, kn)          # each robot on its own history only
        if len(set(chosen)) > 1:
            not_ac += 1
            not_ac_steps.append(k)
            violations += int(agreed)
        executed = np.array([model.moves[chosen[r], r] for r in range(n)])
        row = int(np.flatnonzero((model.moves == executed).all(axis=1))[0])
        full = model.update(model.prior, np.arange(slots), value[:slots][None, :])
        team_j.append(float(model.objective(full)[0, row]))
        poses = np.array([model.next_cells[chosen[r], r] for r in range(n)], dtype=np.int64)
    elapsed, cpu = time.perf_counter() - start, time.process_time() - cpu_start
    return EpisodeResult(config=config, algorithm=algorithm, not_ac=not_ac, comms=comms, observations_sent=sent,
                         failed_comms=failed, violations=violations, max_unshared=max_unshared,
                         max_comms_per_step=max_step_comms, time_s=elapsed, cpu_s=cpu, team_j=tuple(team_j),
                         since_comm=tuple(since), not_ac_steps=tuple(not_ac_steps),
                         restricted_steps=tuple(sorted(restricted)))


@dataclass(frozen=True)
class TableRow:
    """One row of Table I: our episode beside the paper's figures (``None`` for inputs it did not run)."""

    comm_restr: int
    primitives: int
    init: str
    algorithm: str
    ours: EpisodeResult
    paper: tuple[int, int, float] | None

    def as_dict(self) -> dict:
        out = {"comm_restr": self.comm_restr, "primitives": self.primitives, "init": self.init,
               "algorithm": ALGORITHM_NAMES[self.algorithm], "not_ac": self.ours.not_ac, "comm": self.ours.comms,
               "observations_sent": self.ours.observations_sent, "failed_comms": self.ours.failed_comms,
               "violations": self.ours.violations, "max_unshared": self.ours.max_unshared,
               "time_s": round(self.ours.time_s, 4), "cpu_s": round(self.ours.cpu_s, 4),
               "mean_team_j": round(float(np.mean(self.ours.team_j)), 4)}
        if self.paper is not None:
            out.update(paper_not_ac=self.paper[0], paper_comm=self.paper[1], paper_time_s=self.paper[2])
        return out


def table_inputs() -> list[tuple[int, int, str]]:
    """The seven input groups of Table I, in the paper's order."""
    return list(PAPER_TABLE_I)


def table_i(base: SARConfig | None = None, *, on_run: Callable[[TableRow], None] | None = None) -> list[TableRow]:
    """Every row of Table I (7 inputs × Baseline-II, Baseline-I, ENFORCEAC) with ``base``'s grid, sensor,
    epochs and seed; ``on_run`` is called after each episode (progress bars).  For E ≠ 200 the number of
    restricted steps is scaled to keep the paper's fraction (``round(m·E/200)``)."""
    base = base or SARConfig()
    rows = []
    for restr, prims, init in table_inputs():
        m = round(restr * base.epochs / 200)        # the paper's m is for E = 200: keep the fraction
        cfg = replace(base, comm_restr=m, primitives=prims, init=init)  # type: ignore[arg-type]
        for alg in ALGORITHMS:
            row = TableRow(restr, prims, init, alg, run_episode(cfg, alg), PAPER_TABLE_I[(restr, prims, init)][alg])
            rows.append(row)
            if on_run is not None:
                on_run(row)
    return rows
