"""A* paths, the artificial potential field (eqs. 3–8) and contact handling (sim.motion)."""

from __future__ import annotations

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from sim.grid import random_map
from sim.motion import GridGraph, apf_velocity, integrate, line_free


def test_shortest_path_on_empty_grid_is_octile():
    g = GridGraph(np.zeros((20, 20), bool), 1.0, clearance_cost=1.0)
    sp = g.from_cell(0)
    target = 5 * 20 + 9  # row 5, col 9
    assert np.isclose(sp.dist[target], 5 * np.sqrt(2) + 4)
    path = sp.path(target)
    assert path[0] == 0 and path[-1] == target
    assert np.isclose(g.to_cell(0, target).dist[target], sp.dist[target])


def test_path_avoids_obstacles_and_corners():
    blocked = np.zeros((10, 10), bool)
    blocked[2:8, 5] = True
    g = GridGraph(blocked, 1.0)
    sp = g.from_cell(5 * 10 + 2)
    path = sp.path(5 * 10 + 8)
    cells = np.array(path)
    assert not blocked.ravel()[cells].any()
    for a, b in zip(cells[:-1], cells[1:], strict=True):  # no diagonal squeeze between two blocked cells
        ra, ca, rb, cb = a // 10, a % 10, b // 10, b % 10
        if ra != rb and ca != cb:
            assert not blocked[ra, cb] and not blocked[rb, ca]


def test_unreachable_goal_has_no_path():
    blocked = np.zeros((6, 6), bool)
    blocked[:, 3] = True
    sp = GridGraph(blocked, 1.0).from_cell(0)
    assert sp.path(5) == [] and not np.isfinite(sp.dist[5])


def test_apf_matches_equations_6_to_8():
    xy = np.array([0.0, 0.0])
    target = np.array([0.5, 0.0])
    # attraction only: F_att = η_g ρ_g along the unit vector (eq. 6)
    assert np.allclose(apf_velocity(xy, target, np.empty((0, 2)), eta_g=1.0), [0.5, 0.0])
    # one obstacle at distance 0.5 below, ρ_o = 1: F_rep = η_o (1/ρ − 1/ρ_o)(1/ρ²) ∇ρ = 5·1·4 = 20 upwards
    f = apf_velocity(xy, xy, np.array([[0.0, -0.5]]), eta_g=1.0, eta_o=5.0, rho_o=1.0, v_max=100.0)
    assert np.allclose(f, [0.0, 20.0])
    # beyond ρ_o there is no repulsion (eq. 7), and the output is saturated at v_max
    assert np.allclose(apf_velocity(xy, xy, np.array([[0.0, -1.5]]), rho_o=1.0), [0.0, 0.0])
    far = apf_velocity(xy, np.array([30.0, 40.0]), np.empty((0, 2)), v_max=3.0)
    assert np.isclose(np.hypot(*far), 3.0)


@settings(max_examples=60, deadline=None)
@given(st.floats(-3, 3), st.floats(-3, 3), st.integers(0, 10_000))
def test_integrate_never_enters_an_obstacle(ux, uy, seed):
    world = random_map(seed % 7)
    rng = np.random.default_rng(seed)
    free = np.argwhere(~world.occupied)
    xy = world.centre(free[rng.integers(len(free))]).astype(float)
    for _ in range(20):
        xy = integrate(xy, np.array([ux, uy]), 0.5, world.is_occupied, rng, 0.2)
        assert not world.is_occupied(xy[None, :]).any()


def test_line_free():
    blocked = np.zeros((10, 10), bool)
    blocked[5, 5] = True
    assert line_free(blocked, 1.0, np.array([0.5, 0.5]), np.array([9.5, 0.5]))
    assert not line_free(blocked, 1.0, np.array([0.5, 5.5]), np.array([9.5, 5.5]))
