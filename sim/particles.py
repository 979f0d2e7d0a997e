"""Belief and empathy particles (seed 000, §5.1–5.2): the common-belief team and per-robot belief records.

After the last *global* announcement (all robots connected, eq. 15: p_ij,k ← x_k for all i, j, k) every
robot holds the same common belief set C_i = {c_ij}: one particle per robot, propagated from the last
globally shared state with the same deterministic policy (no noise), on the map everybody knew at that
moment. Because the propagation is a function of common knowledge only, every robot computes the same
particles — :class:`CommonBelief` computes them once and all robots read it (the particle p_ij,j that robot
i tracks for robot j, and the empathy particle p_ij,i = c_ii that robot i itself follows).

Coverage by the particles is the epistemic frontier method of §5.2: the frontier F of the particles' map
(the shared map plus everything the particles' simulated lidars have covered, unknown cells being
assumed free) is split into the Voronoi cells of the particles (eq. 9); particle j's utility of frontier
point f is its path length plus the penalty Δ when f lies outside its cell (eq. 10); the particle goes to
the minimiser (eqs. 11–12). A particle with a task queue (tasks its robot announced before the
disconnection) first visits those tasks, then explores, then goes home when no frontier is left.

:class:`BeliefRecord` is the most recent information robot i has about robot j — position, status,
destination and timestamp q_ij (the set Q of §5.3.1); :func:`believed_position` turns it into the
particle p_ij,j: a robot last seen heading to a task is predicted to move there in a straight line at top
speed and then to rejoin its common-belief particle; otherwise p_ij,j = c_ij.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from sim.grid import FREE, UNKNOWN, LidarModel, OccupancyGrid, frontier_mask
from sim.motion import GridGraph, ShortestPaths, apf_velocity, integrate, smooth_waypoint

__all__ = ["select_frontier", "choose_frontier", "graph_for", "Navigator", "CommonBelief", "BeliefRecord",
           "believed_position", "obstacle_points"]


def obstacle_points(blocked: np.ndarray, res: float, xy: np.ndarray, radius: float) -> np.ndarray:
    """Nearest points of the blocked cells within ``radius`` of ``xy`` (for the repulsive field, eq. 7)."""
    h, w = blocked.shape
    k = int(np.ceil(radius / res)) + 1
    c0, r0 = int(xy[0] / res), int(xy[1] / res)
    rs, cs = slice(max(r0 - k, 0), min(r0 + k + 1, h)), slice(max(c0 - k, 0), min(c0 + k + 1, w))
    rr, cc = np.nonzero(blocked[rs, cs])
    if len(rr) == 0:
        return np.empty((0, 2))
    rr, cc = rr + rs.start, cc + cs.start
    lo = np.stack([cc * res, rr * res], 1)
    return np.clip(xy[None, :], lo, lo + res)


_GRAPH_CACHE: dict[tuple[bytes, float], GridGraph] = {}


def graph_for(blocked: np.ndarray, res: float) -> GridGraph:
    """The free-space graph of ``blocked``, shared by every robot whose map has the same obstacles."""
    key = (np.packbits(blocked).tobytes(), res)
    g = _GRAPH_CACHE.get(key)
    if g is None:
        if len(_GRAPH_CACHE) > 64:
            _GRAPH_CACHE.clear()
        g = _GRAPH_CACHE[key] = GridGraph(blocked, res)
    return g


def select_frontier(sp: ShortestPaths, frontier: np.ndarray, sites: np.ndarray, me: int, delta: float,
                    shape: tuple[int, int], res: float) -> int | None:
    """Eqs. 9–12: the frontier cell minimising path length + Δ·[f ∉ V_me], V the Voronoi cells of ``sites``."""
    best = _best_frontier(sp, frontier, sites, me, delta, shape, res)
    return None if best is None else best[0]


def _best_frontier(sp: ShortestPaths, frontier: np.ndarray, sites: np.ndarray, me: int, delta: float,
                   shape: tuple[int, int], res: float) -> tuple[int, float] | None:
    if len(frontier) == 0:
        return None
    d = sp.dist[frontier]
    ok = np.isfinite(d)
    if not ok.any():
        return None
    f = frontier[ok]
    fxy = np.stack([(f % shape[1] + 0.5) * res, (f // shape[1] + 0.5) * res], 1)
    owner = np.argmin(np.linalg.norm(fxy[:, None, :] - sites[None, :, :], axis=2), axis=1)  # eq. 9
    util = d[ok] + delta * (owner != me)  # eq. 10
    k = int(np.argmin(util))
    return int(f[k]), float(util[k])  # eqs. 11–12


def choose_frontier(graph: GridGraph, source: int, frontier: np.ndarray, sites: np.ndarray, me: int,
                    delta: float, shape: tuple[int, int], res: float,
                    limit: float = 10.0) -> tuple[int | None, ShortestPaths]:
    """Exact eqs. 9–12 with a bounded search first: every frontier beyond ``limit`` metres has utility
    ≥ limit, so a minimiser below ``limit`` found by the bounded Dijkstra is the global one."""
    sp = graph.from_cell(source, limit=limit)
    best = _best_frontier(sp, frontier, sites, me, delta, shape, res)
    if best is not None and best[1] < limit:
        return best[0], sp
    sp = graph.from_cell(source)
    best = _best_frontier(sp, frontier, sites, me, delta, shape, res)
    return (None if best is None else best[0]), sp


class Navigator:
    """A* path (from a Dijkstra tree) to a goal, followed with line-of-sight smoothing and the APF."""

    def __init__(self, res: float, margin: int = 0) -> None:
        self.res = res
        self.margin = margin
        self.goal: int | None = None
        self.goal_xy: np.ndarray | None = None
        self.path_xy = np.empty((0, 2))
        self.version = -1
        self.now = 0.0  # simulation time, set by the owner before planning (for the stuck test)
        self._best = np.inf
        self._since = 0.0

    def stuck(self, xy: np.ndarray, t: float, window: float = 10.0) -> bool:
        """True when the distance to the goal has not shrunk by 0.5 m during the last ``window`` seconds."""
        if self.goal_xy is None:
            return False
        d = float(np.hypot(*(self.goal_xy - xy)))
        if d < self._best - 0.5:
            self._best, self._since = d, t
        return t - self._since > window

    def set_path(self, sp: ShortestPaths, goal: int, shape: tuple[int, int], version: int,
                 goal_xy: np.ndarray | None = None) -> None:
        cells = np.array(sp.path(goal), dtype=int)
        if goal != self.goal:
            self._best, self._since = np.inf, self.now
        self.goal, self.version = goal, version
        gxy = np.array([(goal % shape[1] + 0.5) * self.res, (goal // shape[1] + 0.5) * self.res])
        self.goal_xy = gxy if goal_xy is None else np.asarray(goal_xy, float)
        if len(cells) == 0:
            self.path_xy = np.empty((0, 2))
            return
        self.path_xy = np.stack([(cells % shape[1] + 0.5) * self.res, (cells // shape[1] + 0.5) * self.res], 1)
        if goal_xy is not None:
            self.path_xy = np.vstack([self.path_xy, np.asarray(goal_xy, float)[None, :]])

    def clear(self) -> None:
        self.goal, self.goal_xy, self.path_xy = None, None, np.empty((0, 2))

    def control(self, xy: np.ndarray, blocked: np.ndarray, *, eta_g: float, eta_o: float, rho_o: float,
                v_max: float) -> np.ndarray:
        if self.goal_xy is None or len(self.path_xy) == 0:
            return np.zeros(2)
        wp = smooth_waypoint(self.path_xy, xy, blocked, self.res, margin=self.margin)
        if np.hypot(*(self.goal_xy - xy)) < 0.2:
            return np.zeros(2)
        obs = obstacle_points(blocked, self.res, xy, rho_o)
        u = apf_velocity(xy, wp, obs, eta_g=eta_g, eta_o=eta_o, rho_o=rho_o, v_max=v_max)
        # keep full speed while cruising: the attractive term eq. 6 is proportional to ρ_g, which would slow
        # the robot near each look-ahead waypoint; the saturation keeps |u| ≤ v_max.
        att = wp - xy
        n = np.hypot(*att)
        remaining = np.hypot(*(self.goal_xy - xy))
        if n > 1e-9 and np.hypot(*u) < v_max and remaining > 1.0:
            u = u + att / n * (v_max - np.hypot(*u))
        return u


@dataclass
class _Particle:
    xy: np.ndarray
    queue: list[np.ndarray]
    status: str
    nav: Navigator


class CommonBelief:
    """The common belief set C (one particle per robot) propagated from the last global announcement."""

    def __init__(self, t0: float, base: OccupancyGrid, positions: np.ndarray, queues: list[list[np.ndarray]],
                 home: np.ndarray, lidar: LidarModel, *, delta: float, eta_g: float, eta_o: float, rho_o: float,
                 v_max: float, homing: list[bool] | None = None) -> None:
        self.t0, self.t = t0, t0
        self.res = base.resolution
        self.shape = base.shape
        self.blocked = base.occupied_mask().copy()
        self.observed = base.observed.copy()
        self.graph = graph_for(self.blocked, self.res)
        self.seen_time = np.where(self.observed, -np.inf, np.inf)
        self.seen_by = np.full(self.shape, -1, dtype=int)
        self.home = home
        self.lidar = lidar
        self.params = dict(eta_g=eta_g, eta_o=eta_o, rho_o=rho_o, v_max=v_max)
        self.delta = delta
        homing = homing or [False] * len(positions)
        self.particles = [_Particle(np.array(p, float), [np.array(q, float) for q in qs],
                                    "home" if hm else "exploring", Navigator(self.res))
                          for p, qs, hm in zip(positions, queues, homing, strict=True)]
        self.history: list[np.ndarray] = []
        self.given_up: set[int] = set()

    @property
    def positions(self) -> np.ndarray:
        return np.array([p.xy for p in self.particles])

    def goal_of(self, j: int) -> int | None:
        p = self.particles[j]
        return p.nav.goal if p.status == "exploring" and not p.queue else None

    def state(self) -> np.ndarray:
        s = np.full(self.shape, UNKNOWN, dtype=np.int8)
        s[self.observed] = FREE
        s[self.blocked] = 2
        return s

    def _occupied_at(self, pts: np.ndarray) -> np.ndarray:
        h, w = self.shape
        c = (pts[:, 0] / self.res).astype(int)
        r = (pts[:, 1] / self.res).astype(int)
        out = (pts[:, 0] < 0) | (pts[:, 1] < 0) | (c >= w) | (r >= h)
        return out | self.blocked[r.clip(0, h - 1), c.clip(0, w - 1)]

    def _cell(self, xy: np.ndarray) -> int:
        return int(min(int(xy[1] / self.res), self.shape[0] - 1) * self.shape[1]
                   + min(int(xy[0] / self.res), self.shape[1] - 1))

    def step(self, dt: float) -> None:
        """Advance every particle by ``dt`` (deterministic: the same on every robot)."""
        frontier = None
        sites = self.positions
        for j, p in enumerate(self.particles):
            p.nav.now = self.t
            stuck = p.nav.stuck(p.xy, self.t)  # no progress for 10 s (an APF local minimum in a tight gap)
            if p.queue:
                tgt = p.queue[0]
                if np.hypot(*(tgt - p.xy)) < 0.8 or stuck:
                    p.queue.pop(0)
                    p.nav.clear()
                    continue
                if p.nav.goal_xy is None or np.hypot(*(p.nav.goal_xy - tgt)) > 1e-6:
                    sp = self.graph.to_cell(self._cell(p.xy), self._cell(tgt))
                    p.nav.set_path(sp, self._cell(tgt), self.shape, 0, goal_xy=tgt)
            elif p.status == "home":
                if p.nav.goal_xy is None:
                    sp = self.graph.to_cell(self._cell(p.xy), self._cell(self.home))
                    p.nav.set_path(sp, self._cell(self.home), self.shape, 0, goal_xy=self.home)
            elif p.status == "exploring":
                if frontier is None:
                    fmask = frontier_mask(self.state())
                    if self.given_up:
                        fmask.ravel()[list(self.given_up)] = False
                    frontier = np.flatnonzero(fmask)
                    fset = fmask.ravel()
                if stuck and p.nav.goal is not None:
                    self.given_up.add(p.nav.goal)
                    fset[p.nav.goal] = False
                    frontier = frontier[frontier != p.nav.goal]
                if p.nav.goal is None or not fset[p.nav.goal]:
                    g, sp = choose_frontier(self.graph, self._cell(p.xy), frontier, sites, j, self.delta,
                                            self.shape, self.res)
                    if g is None:
                        p.status = "home"
                        sp = self.graph.to_cell(self._cell(p.xy), self._cell(self.home))
                        p.nav.set_path(sp, self._cell(self.home), self.shape, 0, goal_xy=self.home)
                    else:
                        p.nav.set_path(sp, g, self.shape, 0)
            u = p.nav.control(p.xy, self.blocked, **self.params)
            p.xy = integrate(p.xy, u, dt, self._occupied_at, None)
            free, hit = self.lidar.scan(self.blocked, p.xy)
            new = free[~self.observed.ravel()[free]]
            if len(new):
                self.observed.ravel()[new] = True
                self.seen_time.ravel()[new] = self.t + dt
                self.seen_by.ravel()[new] = j
        self.t += dt


@dataclass(frozen=True)
class BeliefRecord:
    """What robot i last heard about robot j: time q_ij, position, status and destination (if any)."""

    time: float
    xy: tuple[float, float]
    status: str
    target: tuple[float, float] | None = None


def believed_position(rec: BeliefRecord, common: CommonBelief | None, j: int, t: float, v_max: float,
                      linger: float = 10.0) -> np.ndarray:
    """The particle p_ij,j at time t (see module docstring)."""
    if common is not None and rec.time <= common.t0 + 1e-9:
        return common.particles[j].xy.copy()
    xy = np.array(rec.xy, float)
    if rec.target is not None:
        tgt = np.array(rec.target, float)
        d = float(np.hypot(*(tgt - xy)))
        travelled = v_max * (t - rec.time)
        if travelled < d:
            return xy + (tgt - xy) * (travelled / max(d, 1e-9))
        if common is None or travelled < d + v_max * linger:
            return tgt
    if common is not None:
        return common.particles[j].xy.copy()
    return xy
