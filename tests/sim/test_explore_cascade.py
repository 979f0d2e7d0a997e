"""Algorithm 3's cascade is delivered: a robot told later learns the gossip bundle the auction gave it (§5.4.3)."""

from __future__ import annotations

import numpy as np

from sim.explore import Mission, MissionConfig, TaskSpec


def _split_team_with_task(n: int = 5, seed: int = 1):
    """Run until robot 0 is on its own, then put a task needing the whole team at robot 0 (Case I)."""
    m = Mission(MissionConfig(case=1, n_robots=n, method="epistemic", seed=seed))
    m.task_specs = ()
    m.task_cells = np.array([], dtype=int)
    m.completed, m.completers = [], []
    while (m.components == m.components[0]).sum() > 1:
        m.step()
        assert m.t < 400, "robot 0 never left the others"
    finder = m.robots[0]
    spec = TaskSpec(0, (float(finder.xy[0]), float(finder.xy[1])), n)
    m.task_specs = (spec,)
    m.task_cells = np.array([m._cell(finder.xy)])
    m.completed, m.completers = [False], [()]
    m._scan(finder)  # perceive(task) → Algorithms 1–3 for the group {0}
    return m, finder


def test_cascade_informer_learns_its_bundle_when_told():
    m, finder = _split_team_with_task()
    assert finder.gossip, "robot 0 must gossip to its disconnected teammates"
    first = finder.gossip[0]
    told = m.robots[first]
    assert not told.gossip  # it has not heard of the allocation yet
    # robot 0 reaches robot `first`: local announcement to the pair
    m._share([finder.id, first])
    # Case I, 5 robots, one informer: the auction must use the cascade (robot 0 alone would tell all 4)
    everyone_told = set(finder.gossip) | set(told.gossip)
    assert told.gossip, "the robot told first was given gossip targets by Algorithm 3 but never learns them"
    assert everyone_told | {finder.id, first} == set(range(m.n))


def test_cascade_bundles_reach_their_informers_in_a_mission():
    res = Mission(MissionConfig(case=1, n_robots=5, method="epistemic", seed=1, record=False)).run()
    assigned, delivered = res.cascade
    assert res.success
    assert delivered == assigned
