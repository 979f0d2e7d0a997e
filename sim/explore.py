"""Communication-restricted exploration with epistemic task allocation (seed 000, §5–6, Case Studies I–II).

Three team methods share the map, sensing, motion and task model:

* ``epistemic`` — the paper's method. Each robot keeps its own log-odds map and task knowledge, and its
  N × N belief/empathy particles p_ij,k (eq. 2, :class:`sim.particles.BeliefParticles`) with timestamps Q.
  The statuses the robots act on live in the delkit epistemic model
  (:class:`sim.status_model.FactoredStatusModel`): a robot's status change is an ontic event of that model
  (σ_i := s, observed by its connected group; robots out of range are oblivious and keep a now false
  belief), statuses are announced again to robots that join a group (perceive, §5.3.1), and the decisions
  read the model: a robot's own status is K_i σ_i; the particles propagate with B_i B_j σ_k; ruleset 1 is a
  belief revision (robot i, not finding j, comes to believe σ_j ∈ {gossiping, task} — possibly falsely —
  and plans without j until j's status is announced to it again); a robot follows its empathy particle while
  it believes the robots out of range believe it is exploring (B_i B_j σ_i). While the whole team is
  connected every particle is the true state (eq. 15);
  when it breaks, the common belief set C (:class:`sim.particles.CommonBelief`) is propagated from the last
  global state and every robot follows its empathy particle's frontier goal (§5.2). Robots that meet
  exchange maps, tasks, allocations, gossip plans and particles (the local announcement, eq. 19:
  p_ji,i ← x_i, and the most recent version of every particle wins). A robot that finds a task runs
  Algorithms 1–3 for its connected group, bidding on behalf of the others from its particles; gossipers
  travel to the most recent particle of the robot they must tell (the cascade of Algorithm 3 is delivered:
  a robot told later learns its own gossip bundle); if it is not there, that robot is excluded and the task
  re-auctioned (ruleset 1 of §5.3.2); a task that a common-belief particle of another robot covered earlier
  is assumed to be handled by that robot (ruleset 2). Eqs. 14 and 18 are model-checked on the driving model.
* ``ideal`` — unlimited communication: one shared map, Voronoi frontier assignment with the true positions,
  immediate allocation (Algorithms 1–2) of every discovered task.
* ``flock`` — the team never leaves the communication range: a virtual leader follows the A* path to the
  frontier (or task) nearest to it, the robots hold formation slots within r_c/2 of it, so every pair stays
  within r_c. The leader waits when a robot lags.

Statuses: exploring / gossiping / task / home. Case I: one task needing an unknown number of robots;
the mission ends when it is done and every robot is home. Case II: an unknown number of tasks with
Σ N_τ ≤ N_a; the whole map must be covered, all tasks done, all robots home.
"""

from __future__ import annotations

import time as _time
from collections.abc import Callable
from dataclasses import dataclass, field, replace

import numpy as np
from scipy.sparse.csgraph import connected_components

from delkit.errors import SimulationError
from planners.allocation import Robot as BidRobot
from planners.allocation import Task as AllocTask
from planners.allocation import allocate, euclidean_cost
from sim.grid import LidarModel, OccupancyGrid, WorldMap, frontier_mask, random_map, read_movingai
from sim.motion import GridGraph, integrate, line_free
from sim.particles import (
    BeliefParticles,
    CommonBelief,
    Navigator,
    choose_frontier,
    graph_for,
    obstacle_points,
    select_frontier,
)
from sim.status_model import BUSY

__all__ = ["UNSPECIFIED_PARAMETERS", "MissionConfig", "TaskSpec", "MissionResult", "MissionHistory", "Mission",
           "run_mission",
           "make_scenario", "METHODS", "STATUSES"]

METHODS = ("epistemic", "flock", "ideal")
STATUSES = ("exploring", "gossiping", "task", "home")


#: Every parameter the paper (seed 000) does not give: name → (value, unit, why this value).
UNSPECIFIED_PARAMETERS: dict[str, tuple[object, str, str]] = {
    "dt": (0.5, "s", "integration step; one lidar scan and one decision per step"),
    "resolution": (0.5, "m", "grid cell of the occupancy map and of A*; 100 × 100 cells on the 50 m map"),
    "maps": ("seeded", "", "50 m × 50 m with U{10..20} 1 m × 1 m obstacles as §6; the paper's 15 maps are not "
             "published, ours are random_map(seed 0..14)"),
    "home/tasks": ("(3, 3) m", "", "home base corner; tasks ≥ 12 m from home, N_τ ~ U{2..N} (Case I) or "
                   "U{1..min(3, N)} until Σ N_τ would exceed N (Case II, ≤ 4 tasks)"),
    "lidar_rays": (90, "", "rays per 360° scan; no gaps at the 5 m range with 0.5 m cells"),
    "task_radius r_t": (1.0, "m", "a task is done when N_τ robots are within r_t of it"),
    "noise_std": (0.2, "m/s", "σ of the process noise v of eq. 1"),
    "rho_o": (1.0, "m", "eq. 7 influence distance of obstacles and other robots (η_g = 1, η_o = 5 are the paper's)"),
    "delta Δ": (20.0, "m", "eq. 10 penalty for a frontier outside the particle's Voronoi cell"),
    "particle_speed": (0.85, "× v_max", "the common-belief particles move slower than the robots so that a "
                       "robot can catch up with its empathy particle after detours around unknown obstacles"),
    "linger": (10.0, "s", "a particle believed at a task stays there this long (assumed completion) before "
               "rejoining its common-belief particle"),
    "wait_timeout": (120.0, "s", "a robot at a task gives up waiting for the others after this long "
                     "(wait_rule='fixed'; wait_rule='travel' ties it to the gossip round trip instead)"),
    "stall_time": (20.0, "s", "ruleset 1 also fires when a gossiper gets no nearer to the believed state for this "
                   "long (exclude_rule='reached-or-stalled'; the paper's reading 'visited' has no such rule)"),
    "home radius": (3.5, "m", "a robot within this distance of home base counts as home"),
    "lookahead": (3.0, "m", "path smoothing: farthest visible A* point within this path length; with η_g = 1, "
                  "eq. 6 gives v_max = 3 m/s at that distance"),
    "clearance_cost": (3.0, "×", "A* cost of cells next to an obstacle"),
    "flock_radius": (3.0, "m", "flock formation slots (inside the r_c/2 disk the connectivity constraint allows; "
                     "4 m and 4.5 m measured slower / stalling)"),
    "flock leader speed": (1.0, "× v_max", "the virtual leader's speed limit"),
    "t_max": (1500.0, "s", "give up a mission after this simulated time"),
}


@dataclass(frozen=True)
class MissionConfig:
    """All parameters of one mission (defaults: seed 000 §6; what the paper does not give is listed with its
    reason in :data:`UNSPECIFIED_PARAMETERS`)."""

    case: int = 2
    n_robots: int = 3
    method: str = "epistemic"
    seed: int = 0
    size: float = 50.0
    resolution: float = 0.5
    dt: float = 0.5
    v_max: float = 3.0
    lidar_range: float = 5.0
    lidar_rays: int = 90
    comm_range: float = 10.0
    task_radius: float = 1.0
    noise_std: float = 0.2
    eta_g: float = 1.0  # §6: "we set η_g at 1 and η_o at 5"
    eta_o: float = 5.0
    rho_o: float = 1.0
    delta: float = 20.0
    particle_speed: float = 0.85
    # formation slot radius inside the r_c/2 disk the connectivity constraint allows (None: r_c/2 − 0.5 m);
    # 3 m is the fastest measured (bench/RESULTS-explore.md: 4.5 m stalls the leader, 4 m is slower)
    flock_radius: float | None = 3.0
    flock_leader_speed: float = 1.0  # × v_max
    t_max: float = 1500.0
    wait_timeout: float = 120.0
    # 'fixed': give up waiting after wait_timeout s; 'travel' (the reading the paper implies): wait as long
    # as a gossiper needs to reach the believed state of the missing robot and that robot to reach the task
    wait_rule: str = "fixed"
    # ruleset 1: 'reached-or-stalled' (ours: the believed state reached, or no nearer for stall_time s) or
    # 'visited' (the paper's reading: only once the gossiper has been at the believed state / nearest point)
    exclude_rule: str = "reached-or-stalled"
    stall_time: float = 20.0
    # where a gossiper looks for robot j: 'recent' (the particle with the most recent timestamp, §5.3.2 as
    # written), 'common' (j's common-belief particle c_j, the one j itself tracks while disconnected, §5.1) or
    # 'both' (the most recent one first, then c_j; ruleset 1 only after both were visited)
    gossip_target: str = "recent"
    map_path: str | None = None
    record: bool = True
    status_model: bool = True  # model-check eqs. 14 and 18 on the DEL model that drives the run
    linger: float = 10.0
    robot_repulsion: bool = True
    cruise: bool = False

    def validate(self) -> None:
        if self.method not in METHODS:
            raise SimulationError(f"unknown method {self.method!r}; use one of {', '.join(METHODS)}")
        if self.case not in (1, 2):
            raise SimulationError(f"unknown case study {self.case}; use 1 (single task) or 2 (multiple tasks)")
        if not 1 <= self.n_robots <= 32:
            raise SimulationError(f"--robots must be between 1 and 32 (got {self.n_robots})")
        if self.dt <= 0 or self.t_max <= 0:
            raise SimulationError("dt and t_max must be positive")
        if self.wait_rule not in ("fixed", "travel"):
            raise SimulationError(f"unknown wait_rule {self.wait_rule!r}; use fixed or travel")
        if self.gossip_target not in ("recent", "common", "both"):
            raise SimulationError(f"unknown gossip_target {self.gossip_target!r}; use recent, common or both")
        if self.exclude_rule not in ("reached-or-stalled", "visited"):
            raise SimulationError(f"unknown exclude_rule {self.exclude_rule!r}; use reached-or-stalled or visited")


@dataclass(frozen=True)
class TaskSpec:
    """Ground-truth task: position, number of robots N_τ and reward λ_τ."""

    id: int
    xy: tuple[float, float]
    n_required: int
    reward: float = 100.0


@dataclass(frozen=True)
class MissionHistory:
    """Recorded trajectories for plots: times, robot positions, statuses, common-belief particles, events."""

    world: WorldMap
    tasks: tuple[TaskSpec, ...]
    home: tuple[float, float]
    times: np.ndarray
    positions: np.ndarray
    statuses: np.ndarray
    particles: np.ndarray
    events: tuple[tuple[float, str, str], ...]
    explored: np.ndarray


@dataclass(frozen=True)
class MissionResult:
    """Outcome of one mission (the row of the experiment CSV) and, optionally, its history."""

    method: str
    case: int
    n_robots: int
    seed: int
    mission_time: float
    distance: float
    tasks_done: int
    n_tasks: int
    communications: int
    success: bool
    all_home: bool
    collisions: int
    min_completers_ok: bool
    explored: float
    wall_time: float
    task_completers: tuple[tuple[int, ...], ...] = ()
    epistemic_checks: tuple[tuple[str, int, int], ...] = ()
    cascade: tuple[int, int] = (0, 0)
    min_separation: float = float("inf")
    history: MissionHistory | None = field(default=None, repr=False, compare=False)
    #: ruleset-1 exclusions: (t, gossiper, excluded, why, excluded robot's true status, its distance [m] from
    #: the state the gossiper sought, and from its common-belief particle c_j) — why: 'reached', 'unreachable'
    #: or 'stalled'
    exclusions: tuple[tuple[float, int, int, str, str, float, float], ...] = ()
    #: waits at a task: (robot, task, start, end, gave up)
    waits: tuple[tuple[int, int, float, float, bool], ...] = ()
    #: (task, discovered at, completed at or None)
    task_times: tuple[tuple[int, float, float | None], ...] = ()

    def diagnosis(self) -> dict:
        """What :mod:`sim.diagnosis` reads: ruleset-1 exclusions, waits at tasks, task discovery/completion."""
        return {"exclusions": [list(e) for e in self.exclusions], "waits": [list(w) for w in self.waits],
                "task_times": [list(t) for t in self.task_times]}

    def row(self) -> dict:
        return {k: getattr(self, k) for k in ("method", "case", "n_robots", "seed", "mission_time", "distance",
                                              "tasks_done", "n_tasks", "communications", "success", "all_home",
                                              "collisions", "min_completers_ok", "explored", "wall_time")} | {
            "min_separation": self.min_separation, "cascade_assigned": self.cascade[0],
            "cascade_delivered": self.cascade[1]}


def make_scenario(cfg: MissionConfig) -> tuple[WorldMap, tuple[TaskSpec, ...], np.ndarray, np.ndarray]:
    """World map, tasks, home base and start positions for ``cfg`` (all from ``cfg.seed``).

    Home base is at (3, 3) m; robots start on a small arc around it. Case I: one task with N_τ ~ U{1..N_a}
    (≥ 2 when N_a ≥ 2, a multi-robot task). Case II: tasks with N_τ ~ U{1..min(3, N_a)} drawn until the next
    one would break Σ N_τ ≤ N_a (at most 4 tasks). Tasks lie in free space at least 12 m from home.
    """
    rng = np.random.default_rng([cfg.seed, 7])
    home = np.array([3.0, 3.0])
    if cfg.map_path:
        world = read_movingai(cfg.map_path, cfg.resolution)
    else:
        world = random_map(cfg.seed, size=cfg.size, resolution=cfg.resolution, keep_free=[(3.0, 3.0, 3.0)])
    n = cfg.n_robots
    ang = np.linspace(0, np.pi / 2, n + 2)[1:-1]
    starts = home[None, :] + 1.5 * np.stack([np.cos(ang), np.sin(ang)], 1)
    w, h = world.size
    if cfg.case == 1:
        reqs = [int(rng.integers(2 if n >= 2 else 1, n + 1))]
    else:
        reqs, total = [], 0
        while len(reqs) < 4:
            k = int(rng.integers(1, min(3, n) + 1))
            if total + k > n:
                break
            reqs.append(k)
            total += k
    tasks = []
    free = ~world.occupied
    for tid, k in enumerate(reqs):
        for _ in range(1000):
            xy = rng.uniform([2.0, 2.0], [w - 2.0, h - 2.0])
            rc = world.cell(xy)
            r0, c0 = int(rc[0]), int(rc[1])
            if np.hypot(*(xy - home)) < 12 or not free[max(r0 - 3, 0):r0 + 4, max(c0 - 3, 0):c0 + 4].all():
                continue
            if any(np.hypot(xy[0] - t.xy[0], xy[1] - t.xy[1]) < 5 for t in tasks):
                continue
            tasks.append(TaskSpec(tid, (float(xy[0]), float(xy[1])), k))
            break
        else:
            raise SimulationError(f"no room for task {tid} on map {world.name}")
    return world, tuple(tasks), home, starts


@dataclass
class _TaskKnowledge:
    spec: TaskSpec
    completed: bool = False
    assigned: tuple[int, ...] = ()
    version: float = -1.0
    eta: dict[int, float] = field(default_factory=dict)
    assumed_by: int | None = None

    def merged(self, other: _TaskKnowledge) -> _TaskKnowledge:
        best = other if other.version > self.version else self
        out = replace(best, completed=self.completed or other.completed, eta=dict(best.eta))
        if out.assumed_by is None and best is other:
            out.assumed_by = self.assumed_by
        return out


class _Robot:
    def __init__(self, i: int, xy: np.ndarray, grid: OccupancyGrid, n: int) -> None:
        self.id = i
        self.xy = xy.astype(float)
        self._status = "exploring"
        self.model = None  # the delkit status model (epistemic method): the status is read from it
        self.nav = Navigator(grid.resolution)
        self.map = grid
        self.graph: GridGraph | None = None
        self.graph_version = -1
        self.tasks: dict[int, _TaskKnowledge] = {}
        self.gossip: list[int] = []
        # Algorithm 3's gossip bundles of this allocation round, for every informer (also those told later):
        # (version, informer) -> ordered targets. They travel with the allocation (merged on every local
        # announcement), so a robot that is told later learns its own gossip bundle and continues the cascade.
        self.plans: dict[tuple[float, int], tuple[int, ...]] = {}
        self.adopted: set[float] = set()
        self.excluded: set[int] = set()
        self.wait_since: float | None = None
        self.wait_task: int | None = None
        self.wait_limit: float = 0.0
        self.gave_up: set[int] = set()
        self.done_exploring = False
        self.blacklist: set[int] = set()
        self.distance = 0.0
        self.target: tuple[float, float] | None = None
        self.approach: tuple[tuple[int, int], object] | None = None  # cache of Mission._approach
        self.seek_stage: dict[int, int] = {}  # gossip_target='both': 1 once the most recent belief was visited
        self.seek: tuple[int, float, float] | None = None  # (gossip target, best distance, since when)

    @property
    def status(self) -> str:
        """The status the robot acts on: σ_i as robot i knows it in the delkit model (epistemic method; every
        change is an ontic event of that model, :meth:`Mission._set_status`), else the simulator's."""
        return self._status if self.model is None else self.model.own_status(self.id)

    def bundle(self) -> list[int]:
        mine = [t for t, k in self.tasks.items() if not k.completed and self.id in k.assigned
                and t not in self.gave_up]
        return sorted(mine, key=lambda t: (self.tasks[t].eta.get(self.id, 0.0), t))


class Mission:
    """One simulated mission; call :meth:`run` (or :meth:`step` repeatedly)."""

    def __init__(self, cfg: MissionConfig) -> None:
        cfg.validate()
        self.cfg = cfg
        self.world, self.task_specs, self.home, starts = make_scenario(cfg)
        if self.world.is_occupied(starts).any():
            raise SimulationError("a start position lies in an obstacle")
        self.rng = np.random.default_rng([cfg.seed, 11, cfg.n_robots, METHODS.index(cfg.method)])
        self.lidar = LidarModel(cfg.lidar_range, cfg.lidar_rays, self.world.resolution)
        self.shape = self.world.shape
        self.res = self.world.resolution
        self.n = cfg.n_robots
        self.t = 0.0
        shared = OccupancyGrid(self.shape, self.res) if cfg.method != "epistemic" else None
        self.robots = [_Robot(i, starts[i], shared if shared is not None else OccupancyGrid(self.shape, self.res),
                              self.n) for i in range(self.n)]
        self.task_cells = np.array([int(self.world.cell(np.array(t.xy))[0] * self.shape[1]
                                        + self.world.cell(np.array(t.xy))[1]) for t in self.task_specs], dtype=int)
        self.completed = [False] * len(self.task_specs)
        self.completers: list[tuple[int, ...]] = [()] * len(self.task_specs)
        self.common: CommonBelief | None = None
        self.components = np.zeros(self.n, dtype=int)
        self.prev_adj = np.ones((self.n, self.n), dtype=bool)
        self.communications = 0
        self.collisions = 0
        self.cascade_assigned = 0  # gossip bundles given to robots outside the allocating group (Algorithm 3)
        self.cascade_delivered = 0  # ... that reached their informer (it was told and took the bundle on)
        self.cascade_pending: set[tuple[float, int]] = set()
        self._alloc_t, self._alloc_count = -1.0, 0
        self.min_sep = float("inf")
        self.events: list[tuple[float, str, str]] = []
        # diagnosis (MissionResult.exclusions / waits / task_times)
        self.exclusions: list[tuple[float, int, int, str, str, float, float]] = []
        self.waits: list[tuple[int, int, float, float, bool]] = []
        self.discovered_at: dict[int, float] = {}
        self.completed_at: dict[int, float] = {}
        self.cost = euclidean_cost(cfg.v_max)
        self.done = False
        self.anchor = self.robots[0].xy.copy() if self.n else self.home.copy()
        self.anchor_nav = Navigator(self.res, margin=0)  # the virtual leader has no body to keep clear
        self.anchor_blacklist: set[int] = set()
        self._hist_t: list[float] = []
        self._hist_x: list[np.ndarray] = []
        self._hist_s: list[np.ndarray] = []
        self._hist_p: list[np.ndarray] = []
        self.checks = {"eq14": [0, 0], "eq18": [0, 0], "outsiders_unchanged": [0, 0]}
        self.false_beliefs = 0  # robot-steps with a false first-order belief B_i σ_k (σ_k untrue)
        self.false_suspicions = 0  # ruleset-1 exclusions of a robot that was in fact not busy (a false belief)
        self.del_model = None
        self.beliefs = None
        if cfg.method == "epistemic":
            from sim.status_model import FactoredStatusModel

            self.del_model = FactoredStatusModel(self.n)
            for r in self.robots:
                r.model = self.del_model
            self._told = [("exploring", frozenset(range(self.n)))] * self.n
            self.beliefs = BeliefParticles(starts, self.home, eta_g=cfg.eta_g, eta_o=cfg.eta_o, rho_o=cfg.rho_o,
                                           v_max=cfg.particle_speed * cfg.v_max, linger=cfg.linger,
                                           cruise=cfg.cruise)
        for r in self.robots:
            self._scan(r)

    # ------------------------------------------------------------------ helpers
    def _cell(self, xy: np.ndarray) -> int:
        rc = self.world.cell(xy)
        return int(rc[0] * self.shape[1] + rc[1])

    def _graph(self, r: _Robot) -> GridGraph:
        if r.graph is None or r.graph_version != r.map.version:
            r.graph, r.graph_version = graph_for(r.map.occupied_mask(), self.res), r.map.version
        return r.graph

    def _event(self, kind: str, detail: str) -> None:
        self.events.append((round(self.t, 3), kind, detail))

    def _scan(self, r: _Robot) -> None:
        free, hit = self.lidar.scan(self.world.occupied, r.xy)
        r.map.update(free, hit)
        seen = np.isin(self.task_cells, free)
        for k in np.flatnonzero(seen):
            spec = self.task_specs[k]
            if spec.id not in r.tasks:
                r.tasks[spec.id] = _TaskKnowledge(spec, completed=self.completed[k])
                if not self.completed[k]:
                    self._event("discover", f"robot {r.id} finds task {spec.id} (N={spec.n_required})")
                    self.discovered_at.setdefault(spec.id, self.t)
                    self._on_discovery(r, spec)
            if self.completed[k]:
                r.tasks[spec.id].completed = True  # perceive(completed τ)

    def _at_home(self, r: _Robot) -> bool:
        return bool(np.hypot(*(r.xy - self.home)) < 3.5)

    def _mission_over_for(self, r: _Robot) -> bool:
        """Case I: the single task is known to be done, or allocated to others (then go home)."""
        if self.cfg.case != 1:
            return False
        for k in r.tasks.values():
            if k.completed or (k.assigned and r.id not in k.assigned):
                return True
        return False

    # ------------------------------------------------------------------ communication
    def _adjacency(self) -> np.ndarray:
        x = np.array([r.xy for r in self.robots])
        if self.cfg.method != "epistemic":
            return np.ones((self.n, self.n), dtype=bool)
        d = np.linalg.norm(x[:, None, :] - x[None, :, :], axis=2)
        return d <= self.cfg.comm_range

    def _share(self, members: list[int]) -> None:
        """Local announcement to a connected group (eq. 19 and the Q revision of §5.3.1)."""
        group = [self.robots[m] for m in members]
        if self.cfg.method == "epistemic":
            for a in group[1:]:
                group[0].map.merge(a.map)
            for a in group[1:]:
                a.map.merge(group[0].map)  # idempotent: every member ends with the same map
        tids = set().union(*(a.tasks.keys() for a in group))
        for tid in tids:
            ks = [a.tasks[tid] for a in group if tid in a.tasks]
            best = ks[0]
            for k in ks[1:]:
                best = best.merged(k)
            if best.assumed_by is not None and best.assumed_by in members and not best.completed:
                best = replace(best, assumed_by=None)  # ruleset 2 verified on contact: allocate it if undone
            for a in group:
                a.tasks[tid] = replace(best, eta=dict(best.eta))
        plans: dict[tuple[float, int], tuple[int, ...]] = {}
        for a in group:
            plans.update(a.plans)
        for a in group:
            a.plans = dict(plans)
            self._adopt_gossip(a)
            a.gossip = [g for g in a.gossip if g not in members]
            a.excluded -= set(members)

    def _adopt_gossip(self, a: _Robot) -> None:
        """Take on the gossip bundle Algorithm 3 gave robot ``a`` in an allocation it has now heard of."""
        for (version, informer), targets in sorted(a.plans.items()):
            if informer != a.id or version in a.adopted:
                continue
            a.adopted.add(version)
            a.gossip += [g for g in targets if g not in a.gossip and g != a.id]
            if (version, informer) in self.cascade_pending:
                self.cascade_pending.discard((version, informer))
                self.cascade_delivered += 1

    def _communicate(self) -> None:
        adj = self._adjacency()
        ncomp, labels = connected_components(adj, directed=False)
        self.components = labels
        new_links = adj & ~self.prev_adj
        if new_links.any() and self.cfg.method == "epistemic":
            self.communications += int(new_links.sum() // 2)
            for i, j in zip(*np.nonzero(np.triu(new_links, 1)), strict=True):
                self._event("connect", f"robots {i} and {j} connect")
        self.prev_adj = adj
        split_now = False
        if self.cfg.method == "epistemic":
            if ncomp == 1:
                if self.common is not None:
                    self._event("global", "all robots connected: global announcement (eq. 15)")
                    self.communications += 1
                    for r in self.robots:
                        r.done_exploring = False
                self.common = None
            elif self.common is None:
                self._start_common_belief()
                split_now = True
            self._update_beliefs(labels, ncomp, split_now)
        for c in range(ncomp):
            members = [int(m) for m in np.flatnonzero(labels == c)]
            if len(members) > 1 or self.cfg.method != "epistemic":
                self._share(members)
            if self.cfg.method == "epistemic" and len(members) > 1:
                self._allocate_pending(self.robots[members[0]], members)

    def _start_common_belief(self) -> None:
        base = self.robots[0].map
        queues, homing = [], []
        for r in self.robots:
            queues.append([np.array(r.tasks[t].spec.xy) for t in r.bundle()])
            homing.append(r.done_exploring or self._mission_over_for(r))
        self.common = CommonBelief(self.t, base, np.array([r.xy for r in self.robots]), queues, self.home,
                                   self.lidar, delta=self.cfg.delta, eta_g=self.cfg.eta_g, eta_o=self.cfg.eta_o,
                                   rho_o=self.cfg.rho_o, v_max=self.cfg.particle_speed * self.cfg.v_max,
                                   homing=homing, cruise=self.cfg.cruise)
        self._event("disconnect", "team splits: common belief set C propagated from here")

    # ------------------------------------------------------------------ allocation
    def _believed_xy(self, r: _Robot, j: int, members: list[int]) -> np.ndarray:
        if j in members or self.cfg.method != "epistemic":
            return self.robots[j].xy.copy()
        return self.beliefs.believed_xy(r.id, j)

    def _on_discovery(self, r: _Robot, spec: TaskSpec) -> None:
        if self.cfg.method == "epistemic" and self.common is not None:
            c = self.task_cells[spec.id]
            j = int(self.common.seen_by.ravel()[c])
            seen = self.common.seen_time.ravel()[c]
            if j not in (-1, r.id) and seen < self.t and self._q(r.id, j) <= self.common.t0 + 1e-9:
                r.tasks[spec.id].assumed_by = j  # ruleset 2: j's particle covered it first
                self._event("assume", f"robot {r.id} assumes robot {j} handles task {spec.id}")
                return
        members = [int(m) for m in np.flatnonzero(self.components == self.components[r.id])]
        self._allocate_pending(r, members)

    def _allocate_pending(self, r: _Robot, members: list[int]) -> None:
        """Algorithms 1–3 run by robot r for its connected group ``members``."""
        new = [k for k in r.tasks.values() if not k.completed and not k.assigned and k.assumed_by is None]
        if not new:
            return
        avail = [j for j in range(self.n) if not self._suspected(r, j)]
        new = [k for k in new if k.spec.n_required <= len(avail)]
        if not new:
            return
        bidders = [BidRobot(j, tuple(self._believed_xy(r, j, members))) for j in avail]
        current = {j: [] for j in avail}
        for tid, k in r.tasks.items():
            if not k.completed and k.assigned:
                for j in k.assigned:
                    if j in current:
                        current[j].append(tid)
        for j in current:
            current[j].sort(key=lambda t: (r.tasks[t].eta.get(j, 0.0), t))
        context = [AllocTask(t, r.tasks[t].spec.xy, r.tasks[t].spec.n_required, r.tasks[t].spec.reward)
                   for t in sorted({t for b in current.values() for t in b})]
        todo = [AllocTask(k.spec.id, k.spec.xy, k.spec.n_required, k.spec.reward) for k in new]
        locked = {j: b for j, b in current.items() if j not in members}
        # a disconnected robot's bid is made by the group member with the most recent record of it (set Q)
        informer = {j: (j if j in members else max(members, key=lambda m: (self._q(m, j), m == r.id)))
                    for j in avail}
        newly = {t.id for t in todo}
        if self.cfg.case == 1:
            must = list(avail)  # everybody must hear that the single task is found (and who does it)
        else:
            must = None
        alloc = allocate(bidders, todo, self.cost, connected=[m for m in members if m in avail] or [r.id],
                         informer=informer, locked=locked, initial=current, context=context, must_know=must)
        if must is None:
            need = [j for j, b in alloc.bundles.items() if set(b) & newly]
            from planners.allocation import gossip_auction
            pos = {b.id: b.xy for b in bidders}
            alloc = replace(alloc, gossip=gossip_auction([m for m in members if m in avail] or [r.id], need,
                                                         pos, self.cost))
        # the version orders allocations (most recent wins on merge); several in one step (re-auctions after
        # ruleset 1) each get their own, so one round's gossip plans never mix with another's
        self._alloc_count = self._alloc_count + 1 if self._alloc_t == self.t else 0
        self._alloc_t = self.t
        version = self.t + 1e-3 * self._alloc_count + 1e-6 * (r.id + 1)
        for tid in {t for b in alloc.bundles.values() for t in b}:
            k = r.tasks[tid]
            k.assigned = tuple(sorted(j for j, b in alloc.bundles.items() if tid in b))
            k.version = version
            k.eta = {j: alloc.start.get(tid, 0.0) + 1e-3 * b.index(tid) for j, b in alloc.bundles.items()
                     if tid in b}
        r.plans.update({(version, v): tuple(gs) for v, gs in alloc.gossip.items() if gs})
        for v, gs in alloc.gossip.items():
            if gs and v not in members:  # a cascade informer: it learns its bundle when it is told
                self.cascade_pending.add((version, v))
                self.cascade_assigned += 1
        for m in members:
            self.robots[m].plans.update(r.plans)
            self._adopt_gossip(self.robots[m])
        self._event("allocate", f"robot {r.id} allocates {sorted(newly)}: "
                    + ", ".join(f"{j}:{list(b)}" for j, b in alloc.bundles.items() if b)
                    + (f"; gossip {dict(alloc.gossip)}" if alloc.gossip else ""))
        if len(members) > 1 or self.cfg.method != "epistemic":
            self._share(members)

    def _exclude(self, r: _Robot, j: int) -> None:
        """Ruleset 1: robot j was not at its believed state — exclude it and re-auction its untold tasks."""
        if self.del_model is not None:
            self.del_model.suspect(r.id, j)  # r now believes j is busy (possibly falsely)
            self.false_suspicions += int(self.del_model.statuses[j] not in BUSY)
        else:
            r.excluded.add(j)
        self._event("exclude", f"robot {r.id} does not find robot {j}; excludes it")
        for k in r.tasks.values():
            if not k.completed and j in k.assigned:
                k.assigned, k.eta = (), {}
        members = [int(m) for m in np.flatnonzero(self.components == self.components[r.id])]
        self._allocate_pending(r, members)

    def _sought_xy(self, r: _Robot, j: int, members: list[int]) -> np.ndarray:
        """Where gossiper r looks for robot j (``MissionConfig.gossip_target``)."""
        recent = self._believed_xy(r, j, members)
        if self.common is None or self.cfg.method != "epistemic" or j in members:
            return recent
        mode = self.cfg.gossip_target
        if mode == "common" or (mode == "both" and r.seek_stage.get(j, 0) == 1):
            return self.common.particles[j].xy.copy()
        return recent

    def _end_wait(self, r: _Robot, *, gave_up: bool) -> None:
        self.waits.append((r.id, int(r.wait_task), round(float(r.wait_since), 3), round(self.t, 3), gave_up))
        r.wait_since = None

    def _wait_limit(self, r: _Robot, k: _TaskKnowledge, members: list[int]) -> float:
        """How long r waits at task k for the robots assigned to it that are out of range (fixed when the wait
        starts; see :meth:`_still_coming` for those in range).

        wait_rule='fixed': ``wait_timeout``. wait_rule='travel' (what the paper's rulesets imply: a robot told by
        gossip is on its way): for each missing assigned robot j out of range, a gossip round trip — the path
        length on r's map from the task to where j is sought, twice (there and back with j), at the particles'
        speed — plus ``linger``; the longest of them, at least one linger."""
        if self.cfg.wait_rule == "fixed":
            return self.cfg.wait_timeout
        speed = self.cfg.particle_speed * self.cfg.v_max
        limits = [self.cfg.linger]
        src = self._cell(np.array(k.spec.xy))
        for j in k.assigned:
            if j == r.id or j in members:
                continue
            dst = self._cell(self._sought_xy(r, j, members))
            dist = float(self._graph(r).to_cell(src, dst).dist[dst])
            if not np.isfinite(dist):
                dist = 1.5 * float(np.hypot(*(self._sought_xy(r, j, members) - np.array(k.spec.xy))))
            limits.append(2.0 * dist / speed + self.cfg.linger)
        return max(limits)

    def _still_coming(self, r: _Robot, k: _TaskKnowledge, members: list[int]) -> bool:
        """wait_rule='travel': a robot in range that has task k in its bundle is on its way (observed)."""
        if self.cfg.wait_rule == "fixed":
            return False
        txy = np.array(k.spec.xy)
        return any(j != r.id and j in members and k.spec.id in self.robots[j].bundle()
                   and float(np.hypot(*(self.robots[j].xy - txy))) > self.cfg.task_radius * 1.5  # not there yet
                   for j in k.assigned)

    # ------------------------------------------------------------------ control
    def _goto(self, r: _Robot, goal_xy: np.ndarray, tol: float = 2.0) -> None:
        g = self._graph(r)
        planned = None if r.nav.goal is None else self.world.centre(np.array(divmod(r.nav.goal, self.shape[1])))
        need = (planned is None or r.nav.goal_xy is None or np.hypot(*(planned - goal_xy)) > tol
                or r.nav.version != r.map.version)
        if need and np.hypot(*(goal_xy - r.xy)) < 8.0 and r.nav.version == r.map.version and \
                line_free(r.map.occupied_mask(), self.res, r.xy, np.asarray(goal_xy, float)):
            # in sight on the known map: the A* path is the straight segment, no search needed
            r.nav.goal = self._cell(goal_xy)
            r.nav.goal_xy = np.asarray(goal_xy, float)
            k = max(2, int(np.hypot(*(r.nav.goal_xy - r.xy)) / self.res) + 2)
            r.nav.path_xy = r.xy[None, :] + np.linspace(0, 1, k)[:, None] * (r.nav.goal_xy - r.xy)[None, :]
            return
        if need:
            cell = self._cell(goal_xy)
            sp = g.to_cell(self._cell(r.xy), cell)
            if not np.isfinite(sp.dist[cell]):
                r.nav.clear()
                return
            r.nav.set_path(sp, cell, self.shape, r.map.version, goal_xy=goal_xy)
        elif len(r.nav.path_xy):  # small move of the goal: retarget the end of the path, no new search
            r.nav.path_xy[-1] = goal_xy
            r.nav.goal_xy = np.asarray(goal_xy, float)

    def _approach(self, r: _Robot, xy: np.ndarray) -> np.ndarray | None:
        """The point of r's map nearest to ``xy`` that r can reach: ``xy`` itself when reachable, else the centre
        of the reachable cell nearest to it (a believed state may lie in an obstacle r has since mapped, or
        behind one); None when r can reach no other cell. Cached per (target cell, map version): as r moves it
        stays in the same free-space component, so the answer does not change."""
        xy = np.asarray(xy, float)
        key = (self._cell(xy), r.map.version)
        if r.approach is None or r.approach[0] != key:
            cell, src = key[0], self._cell(r.xy)
            sp = self._graph(r).to_cell(src, cell)
            if np.isfinite(sp.dist[cell]):
                sub: np.ndarray | bool | None = True
            else:
                ok = np.flatnonzero(np.isfinite(sp.dist))
                ok = ok[ok != src]
                sub = None
                if len(ok):
                    centres = np.stack([(ok % self.shape[1] + 0.5) * self.res,
                                        (ok // self.shape[1] + 0.5) * self.res], 1)
                    sub = centres[int(np.argmin(np.hypot(*(centres - xy[None, :]).T)))]
            r.approach = (key, sub)
        sub = r.approach[1]
        return xy if sub is True else (None if sub is None else sub.copy())

    def _explore_goal(self, r: _Robot, members: list[int]) -> bool:
        """Pick/keep a frontier goal for r (eqs. 9–12); False when nothing is left to explore.

        Disconnected (epistemic): the frontier is that of r's own map with the cells that the *other*
        robots' common-belief particles have covered counted as explored, the Voronoi sites are the common
        belief particles C_i, and the utility is r's path length (+Δ outside its cell). Connected (or the
        ideal method): the sites are the true positions and the map is the shared one.
        """
        state = r.map.state
        sites = np.array([self._believed_xy(r, j, members) for j in range(self.n)])
        if self.common is not None and self.cfg.method == "epistemic":
            others = self.common.observed & (self.common.seen_by != r.id)
            state = state.copy()
            state[(state == 0) & others] = 1
            sites = self.common.positions
        fmask = frontier_mask(state).ravel()
        r.nav.now = self.t
        if r.nav.goal is not None and fmask[r.nav.goal] and r.nav.goal not in r.blacklist:
            if np.hypot(*(r.nav.goal_xy - r.xy)) < 0.6 or r.nav.stuck(r.xy, self.t):
                r.blacklist.add(r.nav.goal)
            else:
                if r.nav.version != r.map.version:  # new obstacles: same goal, new path
                    sp = self._graph(r).to_cell(self._cell(r.xy), r.nav.goal)
                    if np.isfinite(sp.dist[r.nav.goal]):
                        r.nav.set_path(sp, r.nav.goal, self.shape, r.map.version)
                        return True
                else:
                    return True
        if r.blacklist:
            fmask[list(r.blacklist)] = False
        frontier = np.flatnonzero(fmask)
        goal, sp = choose_frontier(self._graph(r), self._cell(r.xy), frontier, sites, r.id, self.cfg.delta,
                                   self.shape, self.res)
        if goal is None:
            return False
        r.nav.set_path(sp, goal, self.shape, r.map.version)
        return True

    def _decide(self, r: _Robot) -> None:
        members = [int(m) for m in np.flatnonzero(self.components == self.components[r.id])]
        r.target = None
        while r.gossip:
            j = r.gossip[0]
            if j in members:
                r.gossip.pop(0)
                continue
            sought = self._sought_xy(r, j, members)
            goal = self._approach(r, sought)
            d = np.inf if goal is None else float(np.hypot(*(goal - r.xy)))
            if r.seek is None or r.seek[0] != j or d < r.seek[1] - 0.5:
                r.seek = (j, d, self.t)  # progress towards j's believed state
            stalled = self.cfg.exclude_rule == "reached-or-stalled" and self.t - r.seek[2] > self.cfg.stall_time
            if goal is None or d < 2.0 or stalled:
                # ruleset 1: r is at j's believed state (or as near to it as r's map lets it get, or — our rule,
                # exclude_rule='reached-or-stalled' — can get no nearer for stall_time s) and j is not in range:
                # j is excluded and its untold tasks re-auctioned
                why = "unreachable" if goal is None else ("reached" if d < 2.0 else "stalled")
                if self.cfg.gossip_target == "both" and r.seek_stage.get(j, 0) == 0 and self.common is not None \
                        and float(np.hypot(*(self.common.particles[j].xy - sought))) > 2.0:
                    r.seek_stage[j] = 1  # not at the most recent belief: look at j's common-belief particle
                    r.seek = None
                    continue
                r.seek_stage.pop(j, None)
                believed = sought
                cj = self.common.particles[j].xy if self.common is not None else believed
                self.exclusions.append((round(self.t, 3), r.id, j, why, self.robots[j].status,
                                        round(float(np.hypot(*(self.robots[j].xy - believed))), 2),
                                        round(float(np.hypot(*(self.robots[j].xy - cj))), 2)))
                r.seek = None
                r.gossip.pop(0)
                self._exclude(r, j)
                continue
            self._set_status(r, "gossiping")
            self._goto(r, goal)
            return
        bundle = r.bundle()
        if bundle:
            k = r.tasks[bundle[0]]
            txy = np.array(k.spec.xy)
            self._set_status(r, "task")
            r.target = k.spec.xy
            near = np.hypot(*(txy - r.xy))
            if near <= self.cfg.task_radius * 1.5:  # at the task (noise may push it in and out of r_t)
                if r.wait_since is None or r.wait_task != k.spec.id:
                    if r.wait_since is not None:
                        self._end_wait(r, gave_up=False)
                    r.wait_since, r.wait_task = self.t, k.spec.id
                    r.wait_limit = self._wait_limit(r, k, members)
                elif self.t - r.wait_since > r.wait_limit and not self._still_coming(r, k, members):
                    r.gave_up.add(k.spec.id)
                    self._event("timeout", f"robot {r.id} stops waiting at task {k.spec.id} after "
                                           f"{self.t - r.wait_since:.1f} s")
                    self._end_wait(r, gave_up=True)
                    return
            if near <= self.cfg.task_radius * 0.6:
                r.nav.clear()
                return
            self._goto(r, txy, tol=0.1)
            return
        if r.wait_since is not None:
            self._end_wait(r, gave_up=False)
        if not r.done_exploring and not self._mission_over_for(r):
            if self.common is not None and self.common.particles[r.id].status == "exploring" and \
                    self._empathy_exploring(r, members):
                # track the empathy particle c_ii = p_ij,i: be where the others believe r is (§5.1)
                self._set_status(r, "exploring")
                self._goto(r, self.common.particles[r.id].xy, tol=3.0)
                return
            if self._explore_goal(r, members):
                self._set_status(r, "exploring")
                return
            r.done_exploring = True
            self._event("done", f"robot {r.id} sees nothing left to explore; heads home")
        self._set_status(r, "home")
        r.target = (float(self.home[0]), float(self.home[1]))
        self._goto(r, self.home, tol=0.5)

    # ------------------------------------------------------------------ flock
    def _flock_step(self) -> list[np.ndarray]:
        lead = self.robots[0]
        xs = np.array([r.xy for r in self.robots])
        pending = sorted({t for r in self.robots for t in r.bundle()},
                         key=lambda t: (min(lead.tasks[t].eta.values(), default=0.0), t))
        g = self._graph(lead)
        goal_xy: np.ndarray | None = None
        task_here: int | None = None
        if pending:
            goal_xy = np.array(lead.tasks[pending[0]].spec.xy)
            if np.hypot(*(goal_xy - self.anchor)) < 1.0:
                task_here = pending[0]
        elif not lead.done_exploring and not self._mission_over_for(lead):
            fmask = frontier_mask(lead.map.state).ravel()
            self.anchor_nav.now = self.t
            if self.anchor_nav.goal is not None and self.anchor_nav.stuck(self.anchor, self.t):
                self.anchor_blacklist.add(self.anchor_nav.goal)
            if self.anchor_blacklist:
                fmask[list(self.anchor_blacklist)] = False
            if self.anchor_nav.goal is not None and fmask[self.anchor_nav.goal] \
                    and self.anchor_nav.version == lead.map.version:
                goal_xy = self.anchor_nav.goal_xy
            else:
                sp = g.from_cell(self._cell(self.anchor))
                cell = select_frontier(sp, np.flatnonzero(fmask), self.anchor[None, :], 0, 0.0, self.shape,
                                       self.res)
                if cell is None:
                    for r in self.robots:
                        r.done_exploring = True
                    self._event("done", "flock: nothing left to explore; heads home")
                else:
                    self.anchor_nav.set_path(sp, cell, self.shape, lead.map.version)
                    goal_xy = self.anchor_nav.goal_xy
        if goal_xy is None:
            goal_xy = self.home
        if self.anchor_nav.goal_xy is None or np.hypot(*(self.anchor_nav.goal_xy - goal_xy)) > 0.5 \
                or self.anchor_nav.version != lead.map.version:
            sp = g.to_cell(self._cell(self.anchor), self._cell(goal_xy))
            self.anchor_nav.set_path(sp, self._cell(goal_xy), self.shape, lead.map.version, goal_xy=goal_xy)
        spread = np.linalg.norm(xs - self.anchor[None, :], axis=1).max()
        if spread < self._flock_disk():
            # the leader is virtual: it follows the (clearance-weighted) A* path without obstacle repulsion
            u = self.anchor_nav.control(self.anchor, lead.map.occupied_mask(), eta_g=self.cfg.eta_g,
                                        eta_o=0.0, rho_o=self.cfg.rho_o,
                                        v_max=self.cfg.flock_leader_speed * self.cfg.v_max)
            moved = integrate(self.anchor, u, self.cfg.dt, self.world.is_occupied, None)
            # the leader only moves where every robot stays within r_c/2 of it (pairwise ≤ r_c); a shorter step
            # is taken when the full one would leave a robot behind
            for frac in (1.0, 0.5, 0.25):
                cand = self.anchor + frac * (moved - self.anchor)
                if np.linalg.norm(xs - cand[None, :], axis=1).max() <= self._flock_disk():
                    self.anchor = cand
                    break
            else:  # blocked by a robot held back (e.g. behind an obstacle): regroup towards it
                self._flock_regroup(xs)
        else:
            self._flock_regroup(xs)
        slots = []
        radius = self._flock_radius() if self.n > 1 else 0.0
        if np.hypot(*(goal_xy - self.home)) < 1e-6 and np.hypot(*(self.anchor - self.home)) < 3.0:
            radius = min(radius, 1.5)  # gather at home base
        for k, r in enumerate(self.robots):
            ang = 2 * np.pi * k / max(self.n, 1)
            slot = self.anchor + radius * np.array([np.cos(ang), np.sin(ang)])
            w, h = self.world.size
            slot = np.clip(slot, 0.6, [w - 0.6, h - 0.6])
            near_obstacle = obstacle_points(lead.map.occupied_mask(), self.res, slot, 0.7)
            if len(near_obstacle):
                slot = self.anchor.copy()
            self._set_status(r, "task" if pending else ("home" if r.done_exploring else "exploring"))
            if task_here is not None and r.id in lead.tasks[task_here].assigned:
                slot = np.array(lead.tasks[task_here].spec.xy)
            slots.append(slot)
        return slots

    def _flock_regroup(self, xs: np.ndarray) -> None:
        """Move the leader half a metre towards the robot farthest from it, if that keeps everyone inside."""
        far = xs[int(np.argmax(np.linalg.norm(xs - self.anchor[None, :], axis=1)))]
        d = float(np.hypot(*(far - self.anchor)))
        if d < 1.0:
            return
        cand = self.anchor + (far - self.anchor) * (0.5 / d)
        if np.linalg.norm(xs - cand[None, :], axis=1).max() <= self._flock_disk() and \
                not self.world.is_occupied(cand[None, :]).any():
            self.anchor = cand

    def _flock_radius(self) -> float:
        return self.cfg.comm_range / 2 - 0.5 if self.cfg.flock_radius is None else self.cfg.flock_radius

    def _flock_disk(self) -> float:
        return self.cfg.comm_range / 2 - 0.1

    def _flock_clip(self, old: np.ndarray, new: np.ndarray) -> np.ndarray:
        """Keep a flock robot inside the disk of radius r_c/2 − 0.1 around the leader (connectivity)."""
        off = new - self.anchor
        d = float(np.hypot(*off))
        if d <= self._flock_disk():
            return new
        cand = self.anchor + off * (self._flock_disk() / d)
        if not self.world.is_occupied(np.linspace(old, cand, 8)).any():
            return cand
        return old  # inside the disk already: the leader only moves when everyone stays inside

    # ------------------------------------------------------------------ main loop
    def _tasks_step(self) -> None:
        for k, spec in enumerate(self.task_specs):
            if self.completed[k]:
                continue
            near = [r.id for r in self.robots if np.hypot(r.xy[0] - spec.xy[0], r.xy[1] - spec.xy[1])
                    <= self.cfg.task_radius]
            if len(near) >= spec.n_required:
                self.completed[k] = True
                self.completers[k] = tuple(near)
                self._event("complete", f"task {spec.id} completed by robots {near}")
                self.completed_at[spec.id] = self.t
                for w in self.robots:
                    if w.wait_since is not None and w.wait_task == spec.id:
                        self._end_wait(w, gave_up=False)
                for r in self.robots:
                    if r.id in near and spec.id in r.tasks:
                        r.tasks[spec.id].completed = True

    def _finished(self) -> bool:
        if not all(self._at_home(r) for r in self.robots):
            return False
        if self.cfg.method == "epistemic" and len(set(self.components.tolist())) > 1:
            return False
        r0 = self.robots[0]
        if self.cfg.case == 1 and any(k.completed for k in r0.tasks.values()):
            return True
        if any(not k.completed for k in r0.tasks.values()):  # a known task is not done: allocate it again
            pending_possible = [k for k in r0.tasks.values() if not k.completed]
            for r in self.robots:
                r.gave_up.clear()
                r.done_exploring = False
            for k in pending_possible:
                k.assigned, k.eta, k.assumed_by = (), {}, None
            for r in self.robots:
                r.excluded.clear()
            self._allocate_pending(r0, list(range(self.n)))
            return False
        fmask = frontier_mask(r0.map.state).ravel()
        ignored = set(self.anchor_blacklist).union(*(r.blacklist for r in self.robots))
        if ignored:
            fmask[list(ignored)] = False
        sp = self._graph(r0).from_cell(self._cell(r0.xy))
        if np.isfinite(sp.dist[np.flatnonzero(fmask)]).any():
            for r in self.robots:
                r.done_exploring = False
            return False
        return True  # Case I with the task never found (unreachable) ends here too; success is False then

    def step(self) -> None:
        cfg = self.cfg
        self._communicate()
        if self.common is not None:
            self.common.step(cfg.dt)
            self.beliefs.step(self.t, cfg.dt, self.common)
        slots = self._flock_step() if cfg.method == "flock" else None
        for r in self.robots:
            if slots is None:
                self._decide(r)
            else:
                self._goto(r, slots[r.id], tol=1.0)
            x = np.array([o.xy for o in self.robots if o is not r])
            near = x[np.hypot(*(x - r.xy).T) <= cfg.rho_o] if len(x) and cfg.robot_repulsion else None
            u = r.nav.control(r.xy, r.map.occupied_mask(), eta_g=cfg.eta_g, eta_o=cfg.eta_o, rho_o=cfg.rho_o,
                              v_max=cfg.v_max, robots=near, cruise=cfg.cruise)
            new = integrate(r.xy, u, cfg.dt, self.world.is_occupied, self.rng, cfg.noise_std)
            if slots is not None:
                new = self._flock_clip(r.xy, new)
            r.distance += float(np.hypot(*(new - r.xy)))
            r.xy = new
            if self.world.is_occupied(r.xy[None, :]).any():
                self.collisions += 1
            self._scan(r)
        if self.n > 1:  # robot–robot separation, measured every step
            x = np.array([r.xy for r in self.robots])
            d = np.linalg.norm(x[:, None, :] - x[None, :, :], axis=2)
            self.min_sep = min(self.min_sep, float(d[np.triu_indices(self.n, 1)].min()))
        self._tasks_step()
        self.t += cfg.dt
        if cfg.record:
            self._hist_t.append(self.t)
            self._hist_x.append(np.array([r.xy for r in self.robots]))
            self._hist_s.append(np.array([STATUSES.index(r.status) for r in self.robots], dtype=np.int8))
            self._hist_p.append(self.common.positions if self.common is not None
                                else np.full((self.n, 2), np.nan))
        if self._finished():
            self.done = True

    # ------------------------------------------------------------------ the DEL model in the decisions
    def _set_status(self, r: _Robot, status: str) -> None:
        """Robot r's decision rule changes its status: for the epistemic method an ontic event of the delkit
        model (σ_r := status, observed by r's connected group, the others oblivious — they keep a belief that
        is now false); r then reads its status back from the model (:attr:`_Robot.status`)."""
        dm = self.del_model
        if dm is None:
            r._status = status
            return
        if dm.own_status(r.id) == status:
            return
        group = frozenset(int(m) for m in np.flatnonzero(self.components == self.components[r.id]))
        before = dm.believed().copy() if self.cfg.status_model else None
        dm.tell(r.id, status, group, "status")
        self._told[r.id] = (status, group)
        if before is not None:
            self._check_model(len(set(self.components.tolist())), {0: sorted(group)}, {0}, before)

    def _suspected(self, r: _Robot, j: int) -> bool:
        """Ruleset 1: r does not plan with robot j — r believes j busy (B_r σ_j ∈ BUSY, the belief left by
        not finding j where r believed it was; revised when j's status is announced to r again)."""
        if self.del_model is None:
            return j in r.excluded
        return self.del_model.believes_busy(r.id, j)

    def _empathy_exploring(self, r: _Robot, members: list[int]) -> bool:
        """B_r B_j σ_r = exploring for every robot j out of r's range: the others (as r believes) believe r is
        still exploring, so r follows the particle they propagate for it (its empathy particle, §5.1)."""
        if self.del_model is None:
            return True
        table = self.del_model.believed()
        return all(table[r.id, j, r.id] == 0 for j in range(self.n) if j not in members)

    def _check_model(self, ncomp: int, groups: dict[int, list[int]], told: set[int], before: np.ndarray) -> None:
        """Eq. 14 (team connected) or eq. 18 and "outsiders unchanged" (per told group) on the driving model."""
        dm = self.del_model
        if ncomp == 1:
            edges = [(i, j) for i in range(self.n) for j in range(self.n) if i != j and self.prev_adj[i, j]]
            ok = dm.check_eq14(edges)
            self.checks["eq14"][0] += int(ok)
            self.checks["eq14"][1] += 1
            return
        after = dm.believed()
        for c in told:
            g = groups[c]
            if len(g) < 2:
                continue
            ok = dm.check_eq18(g)
            self.checks["eq18"][0] += int(ok)
            self.checks["eq18"][1] += 1
            out = [m for m in range(self.n) if m not in g]
            same = bool(np.array_equal(before[np.ix_(out, out)][..., g], after[np.ix_(out, out)][..., g])
                        ) if out else True
            self.checks["outsiders_unchanged"][0] += int(same)
            self.checks["outsiders_unchanged"][1] += 1

    def _q(self, i: int, j: int) -> float:
        """q_ii,j: the time of robot i's most recent information about robot j (set Q)."""
        return float(self.beliefs.stamps(i)[i, j])

    def _update_beliefs(self, labels: np.ndarray, ncomp: int, split_now: bool) -> None:
        """announce/perceive in the delkit model, then the particle resets (eqs. 15–19); checks eqs. 14, 18.

        Robot k's status is announced to its connected group when it changed or when the group gained a
        robot since k last announced (perceive on meeting); robots outside the group are oblivious.
        """
        dm = self.del_model
        groups = {int(c): [int(m) for m in np.flatnonzero(labels == c)] for c in np.unique(labels)}
        told_groups: set[int] = set()
        before = dm.believed().copy()
        for k, r in enumerate(self.robots):
            c = int(labels[k])
            g = frozenset(groups[c])
            status, last = self._told[k]
            if r.status != status or not g <= last:
                dm.tell(k, r.status, g)
                told_groups.add(c)
            self._told[k] = (r.status, g)
        if told_groups and self.cfg.status_model:
            self._check_model(ncomp, groups, told_groups, before)
        self.false_beliefs += dm.false_beliefs()
        targets = [r.target for r in self.robots]
        self.beliefs.update(self.t, labels, np.array([r.xy for r in self.robots]), targets, dm.believed(),
                            self.common, split_now)

    def run(self, progress: Callable[[float, float], None] | None = None) -> MissionResult:
        wall = _time.perf_counter()
        while not self.done and self.t < self.cfg.t_max:
            self.step()
            if progress is not None:
                progress(self.t, self.cfg.t_max)
        return self.result(_time.perf_counter() - wall)

    def result(self, wall: float) -> MissionResult:
        hist = None
        if self.cfg.record:
            explored = np.zeros(self.shape, dtype=bool)
            for r in self.robots:
                explored |= r.map.observed
            hist = MissionHistory(self.world, self.task_specs, (float(self.home[0]), float(self.home[1])),
                                  np.array(self._hist_t), np.array(self._hist_x).reshape(-1, self.n, 2),
                                  np.array(self._hist_s).reshape(-1, self.n),
                                  np.array(self._hist_p).reshape(-1, self.n, 2), tuple(self.events), explored)
        free = ~self.world.occupied
        explored = np.zeros(self.shape, dtype=bool)
        for r in self.robots:
            explored |= r.map.observed
        ok = all(len(c) >= s.n_required for c, s in zip(self.completers, self.task_specs, strict=True)
                 if c) and all(self.completed)
        return MissionResult(self.cfg.method, self.cfg.case, self.n, self.cfg.seed, round(self.t, 3),
                             round(sum(r.distance for r in self.robots), 3), sum(self.completed),
                             len(self.task_specs), self.communications, bool(self.done and all(self.completed)),
                             all(self._at_home(r) for r in self.robots), self.collisions, ok,
                             round(float((explored & free).sum() / free.sum()), 4), round(wall, 3),
                             tuple(self.completers), tuple((k, v[0], v[1]) for k, v in self.checks.items()),
                             (self.cascade_assigned, self.cascade_delivered), round(self.min_sep, 3), hist,
                             tuple(self.exclusions),
                             tuple(self.waits) + tuple((r.id, int(r.wait_task), round(float(r.wait_since), 3),
                                                        round(self.t, 3), False)
                                                       for r in self.robots if r.wait_since is not None),
                             tuple((t, self.discovered_at[t], self.completed_at.get(t))
                                   for t in sorted(self.discovered_at)))


def run_mission(cfg: MissionConfig, progress: Callable[[float, float], None] | None = None) -> MissionResult:
    """Build and run one mission."""
    return Mission(cfg).run(progress)
