"""Occupancy grids, lidar, frontiers, MovingAI maps (sim.grid)."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from delkit.errors import SimulationError
from sim.grid import FREE, OCCUPIED, UNKNOWN, LidarModel, OccupancyGrid, frontier_mask, random_map, read_movingai


@pytest.mark.parametrize("seed", range(6))
def test_random_map_is_the_papers_world(seed):
    m = random_map(seed, keep_free=[(3.0, 3.0, 3.0)])
    assert m.size == (50.0, 50.0)
    # obstacles are 1 m × 1 m = 2 × 2 cells at 0.5 m resolution, between 10 and 20 of them
    assert m.occupied.sum() % 4 == 0
    assert 10 <= m.occupied.sum() // 4 <= 20
    assert not m.is_occupied(np.array([[3.0, 3.0], [4.5, 3.0], [3.0, 4.5]])).any()
    again = random_map(seed, keep_free=[(3.0, 3.0, 3.0)])
    assert np.array_equal(m.occupied, again.occupied)


def test_random_maps_differ_between_seeds():
    assert not np.array_equal(random_map(1).occupied, random_map(2).occupied)


def test_read_movingai(tmp_path):
    text = "type octile\nheight 3\nwidth 4\nmap\n....\n.@T.\nG..S\n"
    p = tmp_path / "tiny.map"
    p.write_text(text)
    m = read_movingai(p, resolution=1.0)
    assert m.shape == (3, 4)
    # the file's first row is the top of the map (y up): row 1 of the file is row 1 of the grid
    assert m.occupied[1, 1] and m.occupied[1, 2]
    assert m.occupied.sum() == 2
    with pytest.raises(SimulationError, match="MovingAI"):
        bad = tmp_path / "bad.map"
        bad.write_text("hello\n")
        read_movingai(bad)


def test_lidar_stops_at_walls_and_range():
    occ = np.zeros((40, 40), dtype=bool)
    occ[:, 20] = True  # a wall at x ∈ [10, 10.5)
    lidar = LidarModel(5.0, 180, 0.5)
    free, hit = lidar.scan(occ, np.array([8.0, 10.0]))
    free_c = set((free % 40).tolist())
    hit_c = set((hit % 40).tolist())
    assert hit_c == {20}
    assert max(free_c) < 20  # nothing seen behind the wall
    free2, _ = lidar.scan(np.zeros((40, 40), bool), np.array([10.0, 10.0]))
    xy = np.stack([(free2 % 40 + 0.5) * 0.5, (free2 // 40 + 0.5) * 0.5], 1)
    assert np.hypot(*(xy - [10.0, 10.0]).T).max() <= 5.0 + 0.5


def test_log_odds_update_merge_and_frontier():
    g = OccupancyGrid((10, 10), 1.0)
    free = np.array([11, 12, 13])
    hit = np.array([14])
    assert g.update(free, hit) is True
    s = g.state
    assert s.ravel()[11] == FREE and s.ravel()[14] == OCCUPIED and s.ravel()[0] == UNKNOWN
    assert g.update(free, hit) is False  # obstacle already known: no replan needed
    other = OccupancyGrid((10, 10), 1.0)
    other.update(np.array([50]), np.array([]))
    before = g.logodds.copy()
    g.merge(other)
    g.merge(other)  # idempotent
    assert g.observed.ravel()[50] and g.logodds.ravel()[50] < 0
    assert np.array_equal(g.logodds.ravel()[[11, 14]], before.ravel()[[11, 14]])


@settings(max_examples=40, deadline=None)
@given(st.lists(st.sampled_from([UNKNOWN, FREE, OCCUPIED]), min_size=36, max_size=36))
def test_frontier_definition(cells):
    s = np.array(cells, dtype=np.int8).reshape(6, 6)
    f = frontier_mask(s)
    for r in range(6):
        for c in range(6):
            nbrs = [(r + dr, c + dc) for dr, dc in ((1, 0), (-1, 0), (0, 1), (0, -1))
                    if 0 <= r + dr < 6 and 0 <= c + dc < 6]
            expect = s[r, c] == FREE and any(s[a, b] == UNKNOWN for a, b in nbrs)
            assert f[r, c] == expect
