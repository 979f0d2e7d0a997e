"""Occupancy grids for communication-restricted exploration (seed 000, §3.1 and §6).

* :func:`random_map` — the paper's cluttered world: a 50 m × 50 m square with 10–20 initially unknown
  1 m × 1 m obstacles, seeded.
* :func:`read_movingai` — MovingAI ``.map`` grids (``@``, ``O``, ``T``, ``W`` are obstacles).
* :class:`LidarModel` — a vectorised 2-D lidar: the beams of all rays are sampled at once and a cell is
  seen iff no occupied cell precedes it on its beam (range 5 m in the paper).
* :class:`OccupancyGrid` — the recursive Bayesian (log-odds) occupancy map
  ``l_t(m) = l_{t-1}(m) + log(p(m|z)/(1-p(m|z))) - l_0`` with clamping, and frontier extraction
  (explored free cells 4-adjacent to unknown cells: the set F of §3.1).

Coordinates are metres with the origin at the lower-left corner; a cell ``(r, c)`` covers
``[c·res, (c+1)·res) × [r·res, (r+1)·res)`` (row = y, column = x).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from delkit.errors import SimulationError

__all__ = ["WorldMap", "random_map", "read_movingai", "LidarModel", "OccupancyGrid", "frontier_mask",
           "UNKNOWN", "FREE", "OCCUPIED"]

UNKNOWN, FREE, OCCUPIED = 0, 1, 2


@dataclass(frozen=True)
class WorldMap:
    """The ground truth: ``occupied[r, c]`` is True for an obstacle cell; ``resolution`` metres per cell."""

    occupied: np.ndarray
    resolution: float = 0.5
    name: str = "map"

    @property
    def shape(self) -> tuple[int, int]:
        return self.occupied.shape  # type: ignore[return-value]

    @property
    def size(self) -> tuple[float, float]:
        """(width, height) in metres."""
        return self.occupied.shape[1] * self.resolution, self.occupied.shape[0] * self.resolution

    def cell(self, xy: np.ndarray) -> np.ndarray:
        """Cell indices (row, col) of points ``xy`` (… × 2), clipped to the grid."""
        xy = np.asarray(xy, dtype=float)
        col = np.clip((xy[..., 0] / self.resolution).astype(int), 0, self.shape[1] - 1)
        row = np.clip((xy[..., 1] / self.resolution).astype(int), 0, self.shape[0] - 1)
        return np.stack([row, col], axis=-1)

    def centre(self, cells: np.ndarray) -> np.ndarray:
        """Centres (x, y) in metres of cells given as (row, col)."""
        cells = np.asarray(cells)
        return np.stack([(cells[..., 1] + 0.5) * self.resolution, (cells[..., 0] + 0.5) * self.resolution], -1)

    def is_occupied(self, xy: np.ndarray) -> np.ndarray:
        """True where a point lies in an obstacle cell or outside the map."""
        xy = np.asarray(xy, dtype=float)
        w, h = self.size
        outside = (xy[..., 0] < 0) | (xy[..., 1] < 0) | (xy[..., 0] >= w) | (xy[..., 1] >= h)
        rc = self.cell(xy)
        return outside | self.occupied[rc[..., 0], rc[..., 1]]


def random_map(seed: int, *, size: float = 50.0, resolution: float = 0.5, n_obstacles: tuple[int, int] = (10, 20),
               obstacle_size: float = 1.0, keep_free: list[tuple[float, float, float]] | None = None) -> WorldMap:
    """The cluttered map of §6: ``size`` × ``size`` metres with U{10..20} square obstacles of side 1 m.

    ``keep_free`` lists discs ``(x, y, radius)`` (home base, task sites) that obstacles must not touch.
    The same seed gives the same map.
    """
    rng = np.random.default_rng(seed)
    n = int(size / resolution)
    side = max(1, int(round(obstacle_size / resolution)))
    occ = np.zeros((n, n), dtype=bool)
    count = int(rng.integers(n_obstacles[0], n_obstacles[1] + 1))
    placed = 0
    keep = keep_free or []
    for _ in range(count * 50):
        if placed == count:
            break
        r, c = rng.integers(1, n - side - 1, size=2)
        cx, cy = (c + side / 2) * resolution, (r + side / 2) * resolution
        if any(np.hypot(cx - x, cy - y) < rad + obstacle_size for x, y, rad in keep):
            continue
        if occ[max(r - 1, 0):r + side + 1, max(c - 1, 0):c + side + 1].any():
            continue
        occ[r:r + side, c:c + side] = True
        placed += 1
    return WorldMap(occ, resolution, name=f"random-{seed}")


def read_movingai(path: str | Path, resolution: float = 1.0) -> WorldMap:
    """Read a MovingAI benchmark ``.map`` file (``type octile``, ``height``, ``width``, ``map``, rows).

    Passable terrain is ``.``, ``G``, ``S``; everything else (``@ O T W``) is an obstacle. Row 0 of the file is
    the top of the map, so rows are flipped to put y upwards.
    """
    path = Path(path)
    try:
        from delkit.paths import read_input

        lines = read_input(path, "MovingAI map", encoding="ascii").splitlines()
    except OSError as exc:
        raise SimulationError(f"{path}: cannot read MovingAI map ({exc.strerror or exc})") from None
    except UnicodeDecodeError as exc:  # a binary file, or not the ASCII the format is written in
        raise SimulationError(f"{path}: not a MovingAI .map file (byte {exc.start} is not ASCII text)") from None
    try:
        header = {}
        i = 0
        while i < len(lines) and lines[i].strip().lower() != "map":
            key, _, value = lines[i].partition(" ")
            header[key.strip().lower()] = value.strip()
            i += 1
        height, width = int(header["height"]), int(header["width"])
    except (KeyError, ValueError):
        raise SimulationError(f"{path}: not a MovingAI .map file (need 'height', 'width' and 'map' lines)") from None
    if i >= len(lines):
        raise SimulationError(f"{path}: not a MovingAI .map file (no 'map' line before the rows)")
    if not (1 <= height <= 100_000 and 1 <= width <= 100_000):
        raise SimulationError(f"{path}: height {height} and width {width} must be 1..100000 cells")
    rows = lines[i + 1:i + 1 + height]
    if len(rows) != height or any(len(r) < width for r in rows):
        raise SimulationError(f"{path}: expected {height} rows of {width} characters after 'map'")
    bad = sorted({ch for r in rows for ch in r[:width]} - set(".GS@OTW"))
    if bad:
        raise SimulationError(f"{path}: unknown terrain {bad[0]!r} in the rows (MovingAI uses . G S @ O T W)")
    grid = np.array([[ch not in ".GS" for ch in r[:width]] for r in rows], dtype=bool)
    return WorldMap(grid[::-1].copy(), resolution, name=path.stem)


@dataclass(frozen=True)
class LidarModel:
    """A planar lidar of ``max_range`` metres with ``n_rays`` beams, sampled every half cell."""

    max_range: float = 5.0
    n_rays: int = 90
    resolution: float = 0.5
    offsets: np.ndarray = field(init=False, repr=False)

    def __post_init__(self) -> None:
        step = self.resolution / 2
        radii = np.arange(step, self.max_range + 1e-9, step)
        ang = np.linspace(0, 2 * np.pi, self.n_rays, endpoint=False)
        offs = np.stack([np.cos(ang)[:, None] * radii[None, :], np.sin(ang)[:, None] * radii[None, :]], -1)
        object.__setattr__(self, "offsets", offs)  # rays × samples × 2

    def scan(self, occupied: np.ndarray, xy: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Cells seen from ``xy`` on the boolean grid ``occupied``.

        Returns ``(free_cells, hit_cells)`` as flat indices. A beam stops at the first occupied cell (a hit);
        the cells before it are free observations. Points outside the grid end the beam.
        """
        h, w = occupied.shape
        pts = self.offsets + np.asarray(xy, dtype=float)
        col = np.floor(pts[..., 0] / self.resolution).astype(int)
        row = np.floor(pts[..., 1] / self.resolution).astype(int)
        inside = (col >= 0) & (col < w) & (row >= 0) & (row < h)
        flat = np.where(inside, row.clip(0, h - 1) * w + col.clip(0, w - 1), -1)
        occ = np.where(inside, occupied.ravel()[flat.clip(0)], True)
        blocked_before = np.cumsum(occ, axis=1) - occ  # number of blocking samples strictly before
        free = (blocked_before == 0) & ~occ
        hit = (blocked_before == 0) & occ & inside
        return flat[free], flat[hit]  # may repeat cells; every consumer is idempotent per cell


def frontier_mask(state: np.ndarray) -> np.ndarray:
    """Frontier F (§3.1): FREE cells with a 4-neighbour that is UNKNOWN (vectorised by shifts)."""
    unk = state == UNKNOWN
    nb = np.zeros_like(unk)
    nb[1:, :] |= unk[:-1, :]
    nb[:-1, :] |= unk[1:, :]
    nb[:, 1:] |= unk[:, :-1]
    nb[:, :-1] |= unk[:, 1:]
    return (state == FREE) & nb


@dataclass
class OccupancyGrid:
    """A log-odds occupancy grid (recursive Bayesian estimation) with a version counter for obstacle changes.

    ``update`` adds ``l_free`` to cells observed free and ``l_occ`` to cells hit, clamped to
    ``[-l_max, l_max]``; ``state`` classifies cells as UNKNOWN (never observed), FREE (l < 0) or
    OCCUPIED (l > 0). ``merge`` fuses another robot's map by taking, per cell, the log-odds of larger
    magnitude (a conservative fusion that is idempotent, so repeated exchanges do not double-count).
    """

    shape: tuple[int, int]
    resolution: float = 0.5
    l_free: float = -0.85
    l_occ: float = 2.2
    l_max: float = 6.0
    logodds: np.ndarray = field(init=False)
    observed: np.ndarray = field(init=False)
    version: int = 0

    def __post_init__(self) -> None:
        self.logodds = np.zeros(self.shape)
        self.observed = np.zeros(self.shape, dtype=bool)

    def copy(self) -> OccupancyGrid:
        g = OccupancyGrid(self.shape, self.resolution, self.l_free, self.l_occ, self.l_max)
        g.logodds = self.logodds.copy()
        g.observed = self.observed.copy()
        g.version = self.version
        return g

    def update(self, free_cells: np.ndarray, hit_cells: np.ndarray) -> bool:
        """Log-odds update from one scan; True when the set of occupied cells changed (replan needed)."""
        free_cells = np.asarray(free_cells, dtype=np.intp)
        hit_cells = np.asarray(hit_cells, dtype=np.intp)
        lo, ob = self.logodds.ravel(), self.observed.ravel()
        before = lo[hit_cells] > 0
        lo[free_cells] = np.clip(lo[free_cells] + self.l_free, -self.l_max, self.l_max)
        lo[hit_cells] = np.clip(lo[hit_cells] + self.l_occ, -self.l_max, self.l_max)
        ob[free_cells] = True
        ob[hit_cells] = True
        changed = bool((~before).any())
        if changed:
            self.version += 1
        return changed

    def merge(self, other: OccupancyGrid) -> bool:
        """Fuse ``other`` into this map; True when the known obstacles changed."""
        occ_before = self.occupied_mask()
        take = np.abs(other.logodds) > np.abs(self.logodds)
        self.logodds[take] = other.logodds[take]
        self.observed |= other.observed
        changed = bool((self.occupied_mask() != occ_before).any())
        if changed:
            self.version += 1
        return changed

    def occupied_mask(self) -> np.ndarray:
        return self.observed & (self.logodds > 0)

    @property
    def state(self) -> np.ndarray:
        s = np.full(self.shape, UNKNOWN, dtype=np.int8)
        s[self.observed & (self.logodds <= 0)] = FREE
        s[self.occupied_mask()] = OCCUPIED
        return s

    def frontiers(self) -> np.ndarray:
        """Flat indices of frontier cells."""
        return np.flatnonzero(frontier_mask(self.state))

    def explored_fraction(self) -> float:
        return float(self.observed.mean())
