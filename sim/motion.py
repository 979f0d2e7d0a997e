"""Motion: shortest paths on the known map, smoothing, the artificial potential field (seed 000, eqs. 3–8).

* :class:`GridGraph` — the 8-connected free-space graph of a map (unknown cells count as free, known
  obstacles are removed, corner cutting is forbidden, cells next to obstacles cost ``clearance_cost`` times
  more). Shortest paths come from :func:`scipy.sparse.csgraph.dijkstra` — A* with the zero heuristic, which
  returns the same optimal path — because one single-source run also gives the distance from the robot to
  *every* frontier, which the frontier utility of eq. 10 needs.
* :func:`smooth_waypoint` — path smoothing by line of sight (pure pursuit on the A* path).
* :func:`apf_velocity` — eqs. 6–8: ``F_att = η_g ρ_g`` towards the waypoint and
  ``F_rep = η_o (1/ρ − 1/ρ_o)(1/ρ²) ∇ρ`` away from every known obstacle closer than ρ_o, saturated at v_max.
* :func:`integrate` — single integrator ``x ← x + (u + v) dt`` with ``v ~ N(0, σ²)`` (eq. 1 with A = 0,
  B = I), and contact with the *true* obstacles: a step that would enter an obstacle slides along the free
  axis or stops, so no robot ever enters an obstacle.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
from scipy.ndimage import binary_dilation
from scipy.sparse.csgraph import dijkstra

__all__ = ["GridGraph", "ShortestPaths", "smooth_waypoint", "apf_velocity", "integrate", "line_free"]

_NEIGHBOURS = [(-1, 0), (1, 0), (0, -1), (0, 1), (-1, -1), (-1, 1), (1, -1), (1, 1)]


@dataclass(frozen=True)
class ShortestPaths:
    """Distances (metres) from one source cell to all cells and the predecessor tree."""

    source: int
    dist: np.ndarray
    pred: np.ndarray

    def path(self, target: int) -> list[int]:
        """Cells from source to target (empty if unreachable)."""
        if not np.isfinite(self.dist[target]):
            return []
        out = [int(target)]
        while out[-1] != self.source:
            p = int(self.pred[out[-1]])
            if p < 0:
                return []
            out.append(p)
        return out[::-1]


class GridGraph:
    """Free-space graph of a boolean obstacle grid (see module docstring)."""

    def __init__(self, blocked: np.ndarray, resolution: float, clearance_cost: float = 3.0) -> None:
        self.blocked = blocked.copy()
        self.resolution = resolution
        self.shape = blocked.shape
        h, w = blocked.shape
        padded = np.pad(blocked, 1, constant_values=True)  # the map border counts as an obstacle
        near = binary_dilation(padded, iterations=1)[1:-1, 1:-1] & ~blocked
        cell_cost = np.where(near, clearance_cost, 1.0).ravel()
        idx = np.arange(h * w).reshape(h, w)
        rows, cols, wts = [], [], []
        free = ~blocked
        for dr, dc in _NEIGHBOURS:
            r0, r1 = max(0, -dr), h - max(0, dr)
            c0, c1 = max(0, -dc), w - max(0, dc)
            a = idx[r0:r1, c0:c1]
            b = idx[r0 + dr:r1 + dr, c0 + dc:c1 + dc]
            ok = free[r0:r1, c0:c1] & free[r0 + dr:r1 + dr, c0 + dc:c1 + dc]
            if dr and dc:  # no corner cutting
                ok &= free[r0 + dr:r1 + dr, c0:c1] & free[r0:r1, c0 + dc:c1 + dc]
            length = resolution * (np.sqrt(2.0) if dr and dc else 1.0)
            a, b = a[ok], b[ok]
            rows.append(a)
            cols.append(b)
            wts.append(length * 0.5 * (cell_cost[a] + cell_cost[b]))
        self.matrix = sp.csr_matrix((np.concatenate(wts), (np.concatenate(rows), np.concatenate(cols))),
                                    shape=(h * w, h * w))

    def from_cell(self, source: int, limit: float = np.inf) -> ShortestPaths:
        """Single-source shortest paths (Dijkstra) from flat cell ``source``, searched up to ``limit`` metres."""
        dist, pred = dijkstra(self.matrix, indices=int(source), return_predecessors=True, limit=limit)
        return ShortestPaths(int(source), dist, pred)

    def to_cell(self, source: int, target: int) -> ShortestPaths:
        """Shortest path source → target; the search is bounded by a multiple of the straight-line distance
        (as an A* search would be) and widened only when the target is not reached."""
        h, w = self.shape
        d = self.resolution * float(np.hypot(source // w - target // w, source % w - target % w))
        sp = self.from_cell(source, limit=2.0 * d + 5.0)
        if not np.isfinite(sp.dist[target]):
            sp = self.from_cell(source)
        return sp


def line_free(blocked: np.ndarray, resolution: float, a: np.ndarray, b: np.ndarray, margin: int = 0) -> bool:
    """True when the segment a→b crosses no blocked cell (sampled every quarter cell), nor any cell within
    ``margin`` cells of one."""
    n = max(2, int(np.ceil(np.hypot(*(b - a)) / (resolution / 4))) + 1)
    pts = a[None, :] + np.linspace(0, 1, n)[:, None] * (b - a)[None, :]
    h, w = blocked.shape
    c = (pts[:, 0] / resolution).astype(int)
    r = (pts[:, 1] / resolution).astype(int)
    if margin:
        d = np.arange(-margin, margin + 1)
        r = (r[:, None, None] + d[None, :, None]).repeat(len(d), 2).ravel()
        c = (c[:, None, None] + d[None, None, :]).repeat(len(d), 1).ravel()
    return not blocked[np.clip(r, 0, h - 1), np.clip(c, 0, w - 1)].any()


def smooth_waypoint(path_xy: np.ndarray, xy: np.ndarray, blocked: np.ndarray, resolution: float,
                    lookahead: float = 3.0, margin: int = 1) -> np.ndarray:
    """The farthest path point within ``lookahead`` metres (along the path) visible from ``xy`` with a clearance
    of ``margin`` cells (so that the shortcut does not graze a corner the APF would then fight)."""
    if len(path_xy) == 0:
        return xy
    d = np.hypot(*(path_xy - xy).T)
    k0 = int(np.argmin(d))
    seg = np.r_[0.0, np.cumsum(np.hypot(*np.diff(path_xy[k0:], axis=0).T))]
    cand = k0 + np.flatnonzero(seg <= lookahead)
    for m in dict.fromkeys((margin, 0)):  # in a tight spot no shortcut has the margin: fall back to none
        for k in cand[::-1]:
            if line_free(blocked, resolution, xy, path_xy[k], margin=m):
                return path_xy[k]
    return path_xy[min(k0 + 1, len(path_xy) - 1)]


def apf_velocity(xy: np.ndarray, target: np.ndarray, obstacles: np.ndarray, *, eta_g: float = 1.0,
                 eta_o: float = 5.0, rho_o: float = 1.0, v_max: float = 3.0) -> np.ndarray:
    """Control from the composite potential field, eqs. 3–8.

    ``F_att = η_g ρ_g(p)`` along the unit vector to ``target`` (eq. 6); for each obstacle point with
    ``ρ ≤ ρ_o``: ``F_rep = η_o (1/ρ − 1/ρ_o) (1/ρ)² ∇ρ`` with ∇ρ the unit vector away from the obstacle
    (eq. 7); ``F = F_att + F_rep`` (eq. 8), saturated at ``v_max``.
    """
    delta = target - xy
    rho_g = float(np.hypot(*delta))
    force = eta_g * delta  # = η_g ρ_g · unit vector
    if len(obstacles):
        diff = xy[None, :] - obstacles
        rho = np.hypot(diff[:, 0], diff[:, 1])
        near = (rho <= rho_o) & (rho > 1e-6)
        if near.any():
            r = rho[near]
            grad = diff[near] / r[:, None]
            force = force + ((eta_o * (1 / r - 1 / rho_o) / r**2)[:, None] * grad).sum(axis=0)
    speed = float(np.hypot(*force))
    if speed > v_max:
        force = force * (v_max / speed)
    if rho_g < 1e-9 and speed < 1e-9:
        return np.zeros(2)
    return force


def integrate(xy: np.ndarray, u: np.ndarray, dt: float, occupied_at, rng: np.random.Generator | None,
              noise_std: float = 0.2) -> np.ndarray:
    """One step of ``ẋ = u + v`` with collision handling against the true map (``occupied_at(points)``)."""
    v = rng.normal(0.0, noise_std, 2) if rng is not None and noise_std > 0 else np.zeros(2)
    step = (u + v) * dt
    for cand in (step, np.array([step[0], 0.0]), np.array([0.0, step[1]])):
        n = max(2, int(np.ceil(np.hypot(*cand) / 0.1)) + 1)
        pts = xy[None, :] + np.linspace(0, 1, n)[:, None] * cand[None, :]
        if not occupied_at(pts).any():
            return xy + cand
    return xy.copy()
