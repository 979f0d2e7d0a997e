"""Belief and empathy particles p_ij,k (eq. 2) with the resets of eqs. 15–19, driven by the DEL model."""

from __future__ import annotations

import numpy as np
import pytest

from sim.explore import Mission, MissionConfig
from sim.grid import LidarModel, OccupancyGrid
from sim.particles import BeliefParticles, CommonBelief
from sim.status_model import STATUSES

EXPLORING, TASK = STATUSES.index("exploring"), STATUSES.index("task")


def _common(xy):
    grid = OccupancyGrid((60, 60), 0.5)
    lidar = LidarModel(5.0, 45, 0.5)
    return CommonBelief(0.0, grid, xy, [[] for _ in xy], np.array([3.0, 3.0]), lidar, delta=20.0, eta_g=1.0,
                        eta_o=5.0, rho_o=1.0, v_max=2.5)


def _bank(cls, xy):
    return cls(xy, np.array([3.0, 3.0]), eta_g=1.0, eta_o=5.0, rho_o=1.0, v_max=2.5, linger=5.0)


def _scenario(cls):
    """Three robots: all connected, split (common set), 0 and 1 meet, then 1 leaves with status *task*.

    Returns a list of (name, ok) for the resets of eqs. 15, 16, 19, the Q revision and the DEL status."""
    x = np.array([[5.0, 5.0], [8.0, 5.0], [5.0, 8.0]])
    b = _bank(cls, x)
    believed = np.full((3, 3, 3), EXPLORING, dtype=np.int8)
    out = []
    b.update(0.0, np.array([0, 0, 0]), x, [None] * 3, believed, None, False)
    out.append(("eq15", all(np.allclose(b.of(i), np.broadcast_to(x, (3, 3, 2))) for i in range(3))))
    common = _common(x)
    b.update(0.5, np.array([0, 1, 2]), x, [None] * 3, believed, common, True)
    out.append(("common set after the split", bool((b.rec[0, 0, 1:] == 3 + np.arange(1, 3)).all())))
    for t in np.arange(1.0, 5.0, 0.5):
        common.step(0.5)
        b.step(t, 0.5, common)
        b.update(t, np.array([0, 1, 2]), x, [None] * 3, believed, common, False)
    x = x + np.array([[4.0, 0.0], [3.0, 1.0], [0.0, 5.0]])
    b.update(5.0, np.array([0, 0, 1]), x, [None, (25.0, 5.0), None], believed, common, False)  # 0 and 1 meet
    out.append(("eq19 p_ji,i <- x_i", np.allclose(b.of(1)[0, 0], x[0]) and np.allclose(b.of(0)[1, 1], x[1])))
    out.append(("robot 2 unchanged", bool((b.rec[2, :, :2] >= 3).all())))
    believed[:2, :2, 1] = TASK  # the DEL model: 0 and 1 believe (and believe each other believe) σ_1 = task
    b.update(5.5, np.array([0, 1, 2]), x, [None, (25.0, 5.0), None], believed, common, False)  # they part
    for t in np.arange(6.0, 10.0, 0.5):
        common.step(0.5)
        b.step(t, 0.5, common)
    p01 = b.of(0)[0, 1]  # where 0 believes 1 is: on its way to the announced task, not at c_1
    closer = np.hypot(*(p01 - [25.0, 5.0])) < np.hypot(*(x[1] - [25.0, 5.0])) - 3
    out.append(("task particle heads to the task", bool(closer)))
    out.append(("Q revision", float(b.stamps(0)[0, 1]) == 5.0 and float(b.stamps(0)[0, 2]) == 0.0))
    out.append(("second order differs", not np.allclose(b.of(0)[0, 1], b.of(0)[2, 1])))
    return out


def test_resets_of_eqs_15_to_19():
    bad = [name for name, ok in _scenario(BeliefParticles) if not ok]
    assert not bad, bad


class _NoRevision(BeliefParticles):
    """Deliberately broken: a meeting does not reset the group's particles (no eq. 19, no Q revision)."""

    def update(self, t, labels, xy, targets, believed, common, reset_to_common):
        if len(set(labels.tolist())) not in (1, len(labels)):
            labels = np.arange(len(labels))
        super().update(t, labels, xy, targets, believed, common, reset_to_common)


class _StraightLine(BeliefParticles):
    """Deliberately broken: ignores the believed status (always chases the common particle)."""

    def _snapshot(self, k, status, target):
        return super()._snapshot(k, EXPLORING, None)


@pytest.mark.parametrize("broken", [_NoRevision, _StraightLine])
def test_broken_variants_are_caught(broken):
    assert not all(ok for _, ok in _scenario(broken))


def test_eight_robot_case2_runs_on_n2_particles_and_del_statuses():
    m = Mission(MissionConfig(case=2, n_robots=8, method="epistemic", seed=0, record=False))
    n = m.n
    seen_second_order = seen_split = 0
    while not m.done and m.t < m.cfg.t_max:
        x = np.array([r.xy for r in m.robots])  # the states announced at the start of the step
        m.step()
        labels = m.components
        for i in range(n):
            p = m.beliefs.of(i)
            assert p.shape == (n, n, 2)
            g = np.flatnonzero(labels == labels[i])
            assert np.allclose(p[np.ix_(g, g)], x[g][None, :, :])  # eq. 19 (eq. 15 when g is everyone)
        if len(set(labels.tolist())) > 1:
            seen_split += 1
            p = np.stack([m.beliefs.of(i) for i in range(n)])
            seen_second_order += int(np.ptp(p, axis=1).max() > 1.0)  # p_ij,k differs over j: 2nd order
    res = m.result(0.0)
    assert res.success and seen_split and seen_second_order
    # the statuses come from the delkit model: it was updated, held false beliefs, and eqs. 14/18 held on it
    assert m.del_model.updates > n and m.false_beliefs > 0
    checks = {k: (p, t) for k, p, t in res.epistemic_checks}
    assert checks["eq18"][1] > 0 and all(p == t for p, t in checks.values())
    # snapshot particles carry the DEL status they were frozen with
    assert m.beliefs.snapshots > 0


def _allocate_at_believed(m: Mission, i: int, j: int) -> tuple[int, ...]:
    """Robot i finds a one-robot task at the place where it believes robot j is; who does Algorithm 1 give it to?"""
    from sim.explore import TaskSpec, _TaskKnowledge

    xy = m.beliefs.believed_xy(i, j)
    spec = TaskSpec(99, (float(xy[0]), float(xy[1])), 1)
    r = m.robots[i]
    r.tasks[99] = _TaskKnowledge(spec)
    members = [int(x) for x in np.flatnonzero(m.components == m.components[i])]
    m._allocate_pending(r, members)
    return r.tasks[99].assigned


def test_decisions_read_the_del_model_corrupting_a_belief_changes_the_allocation():
    """Ruleset 1 lives in the DEL model: robot i plans without j exactly when B_i σ_j ∈ {gossiping, task}.
    A corrupted model (i falsely believes j busy) must change i's allocation; the true model must not."""
    import copy

    m = Mission(MissionConfig(case=2, n_robots=8, method="epistemic", seed=0, record=False, status_model=False))
    while len(set(m.components.tolist())) == 1 or m.t < 20:
        m.step()
        assert m.t < 200
    i = 0
    j = next(k for k in range(m.n) if m.components[k] != m.components[i])
    honest = copy.deepcopy(m)
    assert _allocate_at_believed(honest, i, j) == (j,)  # j's believed state is on the task: j wins the bid
    corrupted = copy.deepcopy(m)
    corrupted.del_model.suspect(i, j)  # i now (falsely) believes j is busy: the model says so, nothing else
    assert corrupted.del_model.believes_busy(i, j) and corrupted.del_model.statuses[j] == m.del_model.statuses[j]
    assert j not in _allocate_at_believed(corrupted, i, j)
    # the robots act on the statuses of the model: each knows its own (K_i σ_i), outsiders may be wrong
    assert [r.status for r in m.robots] == m.del_model.statuses
