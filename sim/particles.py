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

:class:`BeliefParticles` holds every robot's N × N particles p_ij,k (eq. 2) — belief particles about the
others and the empathy particles p_ij,i — with their timestamps (the set Q), as views into a bank of
distinct deterministic trajectories, with the resets of eqs. 15–19.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from sim.grid import FREE, UNKNOWN, LidarModel, OccupancyGrid, frontier_mask
from sim.motion import GridGraph, ShortestPaths, apf_velocity, integrate, smooth_waypoint

__all__ = ["select_frontier", "choose_frontier", "graph_for", "Navigator", "CommonBelief",
           "BeliefParticles", "obstacle_points"]


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
                v_max: float, robots: np.ndarray | None = None, cruise: bool = False) -> np.ndarray:
        """Eqs. 6–8 towards the smoothed A* waypoint; the threats are the known obstacles within ρ_o and the
        other ``robots`` (positions) within ρ_o.

        ``cruise`` (off by default, not in the paper) adds the missing speed along the attractive direction
        while more than 1 m from the goal, so that a robot keeps v_max between look-ahead waypoints instead of
        the η_g ρ_g of eq. 6 (which slows it when the waypoint is near); ``bench/explore.py`` measures both.
        """
        if self.goal_xy is None or len(self.path_xy) == 0:
            return np.zeros(2)
        wp = smooth_waypoint(self.path_xy, xy, blocked, self.res, margin=self.margin)
        if np.hypot(*(self.goal_xy - xy)) < 0.2:
            return np.zeros(2)
        obs = obstacle_points(blocked, self.res, xy, rho_o)
        if robots is not None and len(robots):
            obs = np.vstack([obs, robots])
        u = apf_velocity(xy, wp, obs, eta_g=eta_g, eta_o=eta_o, rho_o=rho_o, v_max=v_max)
        if cruise:
            att = wp - xy
            n = np.hypot(*att)
            if n > 1e-9 and np.hypot(*u) < v_max and np.hypot(*(self.goal_xy - xy)) > 1.0:
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
                 v_max: float, homing: list[bool] | None = None, cruise: bool = False) -> None:
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
        self.params = dict(eta_g=eta_g, eta_o=eta_o, rho_o=rho_o, v_max=v_max, cruise=cruise)
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


STATUS_CODES = ("exploring", "gossiping", "task", "home")


class BeliefParticles:
    """Every robot's belief and empathy particles p_ij,k (eq. 2), N × N per robot.

    ``rec[i, j, k]`` indexes a *bank* of distinct particles; robot i's particle set is ``xy[rec[i]]``, an
    N × N × 2 array (row j: what i believes j believes about every robot; p_ij,i are i's empathy particles),
    and ``time[rec[i]]`` the timestamps q_ij,k of the set Q. Propagation is deterministic, so every particle
    that starts from the same shared state with the same believed status follows the same trajectory: the
    bank holds one trajectory per distinct (robot, last shared state, believed status) and the N³ particles
    are views into it (that is what keeps 8 robots fast). Bank entries:

    * ``LIVE(k)`` (index k): robot k's true state — the particle of everybody connected to k (eq. 15 when the
      whole team is connected, eq. 19 ``p_ji,i ← x_i`` inside a connected group);
    * ``COMMON(k)`` (index N + k): the common belief particle c_k of :class:`CommonBelief` (the set C_i);
    * a *snapshot*: robot k's state when it was last shared (time q, position, believed status, destination),
      propagated with the same smoothed A* + APF as the robots on the common-belief map: to the announced
      destination when the believed status is *task*/*gossiping* (and, after ``linger`` seconds there —
      the assumed task completion — on towards c_k), home when it is *home*, towards c_k when *exploring*;
      once it reaches c_k it merges into ``COMMON(k)`` (§5.3.1: "then the particle will propagate toward its
      common belief").

    :meth:`update` applies the resets: everybody in a connected group takes, per particle, the most recent
    version any member holds (the Q revision), particles of group members inside the group are their true
    states (eqs. 15, 16, 19), and a ``LIVE`` particle whose believer lost contact is frozen into a snapshot
    with the status the DEL model says the believer believes (``believed[i, j, k]``).
    """

    def __init__(self, xy: np.ndarray, home: np.ndarray, *, eta_g: float, eta_o: float, rho_o: float,
                 v_max: float, linger: float = 10.0, cruise: bool = False) -> None:
        n = len(xy)
        self.n = n
        self.home = np.asarray(home, float)
        self.params = dict(eta_g=eta_g, eta_o=eta_o, rho_o=rho_o, v_max=v_max, cruise=cruise)
        self.linger = linger
        self.rec = np.broadcast_to(np.arange(n), (n, n, n)).copy()
        self.xy = np.vstack([xy, xy]).astype(float)
        self.time = np.zeros(2 * n)
        self.owner = np.r_[np.arange(n), np.arange(n)]
        self.status = np.zeros(2 * n, dtype=np.int8)
        self.target = np.full((2 * n, 2), np.nan)
        self.phase = np.zeros(2 * n, dtype=np.int8)  # 0: to destination, 1: lingering, 2: to c_k
        self.since = np.zeros(2 * n)
        self.navs: dict[int, Navigator] = {}
        self.snapshots = 0
        self._last_target: list[np.ndarray | None] = [None] * n

    # ------------------------------------------------------------------ views
    def of(self, i: int) -> np.ndarray:
        """Robot i's particles p_ij,k as an N × N × 2 array."""
        return self.xy[self.rec[i]]

    def stamps(self, i: int) -> np.ndarray:
        """Robot i's timestamps q_ij,k (N × N)."""
        return self.time[self.rec[i]]

    def believed_xy(self, i: int, k: int) -> np.ndarray:
        """Where robot i looks for robot k: the particle p_ij,k with the most recent timestamp (§5.3.2)."""
        j = int(np.argmax(self.time[self.rec[i, :, k]]))
        return self.xy[self.rec[i, j, k]].copy()

    # ------------------------------------------------------------------ resets
    def _snapshot(self, k: int, status: int, target: np.ndarray | None) -> int:
        idx = len(self.time)
        self.xy = np.vstack([self.xy, self.xy[k]])
        self.time = np.r_[self.time, self.time[k]]
        self.owner = np.r_[self.owner, k]
        self.status = np.r_[self.status, np.int8(max(status, 0))]
        self.target = np.vstack([self.target, np.full(2, np.nan) if target is None else target])
        self.phase = np.r_[self.phase, np.int8(0 if status in (1, 2) and target is not None else 2)]
        self.since = np.r_[self.since, 0.0]
        self.snapshots += 1
        return idx

    def update(self, t: float, labels: np.ndarray, xy: np.ndarray, targets: list, believed: np.ndarray,
               common: CommonBelief | None, reset_to_common: bool) -> None:
        """Resets on announce/perceive for the connected groups ``labels`` (see class docstring).

        ``xy`` and ``targets`` are the robots' current states; ``believed`` the DEL table B_i B_j σ_k.
        """
        n = self.n
        same = labels[:, None] == labels[None, :]
        inside = same[:, None, :] & same[None, :, :]  # i, j and k in one group
        live = self.rec == np.arange(n)[None, None, :]
        lost = live & ~inside
        if lost.any():  # contact lost: freeze the last shared state (still in xy[:n], time[:n])
            if reset_to_common and common is not None:
                self.rec[lost] = n + np.nonzero(lost)[2]
            else:
                ii, jj, kk = np.nonzero(lost)
                made: dict[tuple[int, int], int] = {}
                for i, j, k in zip(ii.tolist(), jj.tolist(), kk.tolist(), strict=True):
                    key = (k, int(believed[i, j, k]))
                    if key not in made:
                        made[key] = self._snapshot(k, key[1], self._last_target[k])
                    self.rec[i, j, k] = made[key]
        self.xy[:n] = xy
        self.time[:n] = t
        if common is not None:
            self.xy[n:2 * n] = common.positions
            self.time[n:2 * n] = common.t0
        for c in np.unique(labels):
            g = np.flatnonzero(labels == c)
            if len(g) > 1:  # Q revision: per particle, the most recent version any member holds
                sub = self.rec[g]
                best = np.argmax(self.time[sub], axis=0)
                self.rec[g] = np.take_along_axis(sub, best[None], axis=0)
        kk = np.broadcast_to(np.arange(n), (n, n, n))
        self.rec[inside] = kk[inside]
        self._last_target = [None if tg is None else np.asarray(tg, float) for tg in targets]

    # ------------------------------------------------------------------ propagation
    def step(self, t: float, dt: float, common: CommonBelief | None) -> None:
        """Propagate every snapshot particle still believed by someone (A* + APF on the common map)."""
        n = self.n
        used = np.unique(self.rec)
        active = used[used >= 2 * n]
        if common is None or not len(active):
            return
        remap = np.arange(len(self.time))
        for e in active.tolist():
            k = int(self.owner[e])
            st = int(self.status[e])
            if st == 3:
                goal = self.home
            elif self.phase[e] == 0:
                goal = self.target[e]
                if np.hypot(*(goal - self.xy[e])) < 0.8:
                    self.phase[e], self.since[e] = 1, t
            if self.phase[e] == 1:
                if t - self.since[e] < self.linger:
                    continue
                self.phase[e] = 2
            if st != 3 and self.phase[e] == 2:
                goal = common.particles[k].xy
                if np.hypot(*(goal - self.xy[e])) < 1.0:
                    remap[e] = n + k  # rejoined its common belief particle
                    continue
            nav = self.navs.get(e)
            if nav is None:
                nav = self.navs[e] = Navigator(common.res)
            if nav.goal_xy is None or np.hypot(*(nav.goal_xy - goal)) > 2.0:
                src, dst = common._cell(self.xy[e]), common._cell(goal)
                nav.set_path(common.graph.to_cell(src, dst), dst, common.shape, 0, goal_xy=goal)
            elif len(nav.path_xy):
                nav.path_xy[-1] = goal
                nav.goal_xy = np.asarray(goal, float)
            u = nav.control(self.xy[e], common.blocked, **self.params)
            self.xy[e] = integrate(self.xy[e], u, dt, common._occupied_at, None)
        if (remap != np.arange(len(remap))).any():
            self.rec = remap[self.rec]
            for e in np.flatnonzero(remap != np.arange(len(remap))).tolist():
                self.navs.pop(e, None)
