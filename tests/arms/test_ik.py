"""IK: mink over both arms, pinocchio cross-check, CLIK fallback, arm–arm collision avoidance."""

from __future__ import annotations

import time

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from arms.ik import POS_TOL, ROT_TOL, DualArmIK, PinocchioArm, pose, pose_error, random_reachable_poses
from arms.world import Layout


@pytest.fixture(scope="module")
def ik():
    return DualArmIK()


def test_pinocchio_and_mujoco_fk_agree(ik):
    rng = np.random.default_rng(3)
    for _ in range(50):
        arms = {r: rng.uniform(ik.pin[r].lower, ik.pin[r].upper) for r in ik.robots}
        assert ik.fk_disagreement(ik.full_q(arms)) < 1e-9


def test_fk_matches_the_urdf_chain_at_zero():
    """At q = 0 the TCP is straight above the base: z = 0.333 + 0.316 + 0.384 - 0.107 - 0.1034 ... check x."""
    arm = PinocchioArm()
    t = arm.fk(np.zeros(7))
    # joint offsets along the URDF: x = 0.0825 - 0.0825 + 0.088, z = 0.333 + 0.316 + 0.384 - 0.107 - 0.1034
    assert np.allclose(t[:3, 3], [0.088, 0.0, 0.333 + 0.316 + 0.384 - 0.107 - 0.1034], atol=1e-9)


def test_both_arms_reach_targets_in_one_qp(ik):
    lay = Layout()
    for k, (dx, dz) in enumerate([(0.0, 0.15), (-0.1, 0.25), (0.08, 0.1)]):
        targets = {r: pose([lay.stack_x + dx, lay.stack_xy(i, 0)[1], dz]) for i, r in enumerate(ik.robots)}
        res = ik.solve(targets, budget=0.5, seed=k, clock=time.thread_time)  # CPU clock: load-independent
        assert res.converged, res
        assert res.position_error < POS_TOL and res.orientation_error < ROT_TOL
        assert res.fk_disagreement < 1e-9
        q = ik.full_q(res.q)
        for r, t in targets.items():
            dp, dr = pose_error(ik.pin[r].fk(q[ik.qadr[r]]), t)
            assert dp < POS_TOL and dr < ROT_TOL
        assert ik.min_arm_distance(q) > 0


def test_clik_fallback_solves_random_reachable_poses(ik):
    _, poses = random_reachable_poses(60, seed=11)
    results = [ik.solve_clik({"robot1": t}, budget=0.05, seed=i, clock=time.thread_time)  # load-independent
               for i, t in enumerate(poses)]
    rate = np.mean([r.converged for r in results])
    assert rate >= 0.95
    for r, t in zip(results, poses, strict=True):
        if r.converged:
            assert pose_error(ik.pin["robot1"].fk(r.q["robot1"]), t)[0] < POS_TOL


def test_unreachable_target_is_reported_not_converged(ik):
    res = ik.solve({"robot1": pose([1.6, -0.36, 0.3])}, budget=0.05)
    assert not res.converged and res.position_error > 0.5


def _min_distance_along(ik, steps=150):
    target = pose([Layout().stack_x, 0.0, 0.15])
    q = ik.full_q()
    worst = ik.min_arm_distance(q)
    for _ in range(steps):
        q = ik.step(q, {"robot1": target, "robot2": target}, 0.01)
        worst = min(worst, ik.min_arm_distance(q))
    return worst


def test_arms_never_interpenetrate_when_commanded_to_the_same_point(ik):
    assert _min_distance_along(ik) > 0.005


def test_without_velocity_limit_collision_avoidance_is_stepped_past():
    """The linearised avoidance constraint only acts within the detection distance; a step longer than
    that jumps over it. This is why the velocity limit is part of the QP."""
    assert _min_distance_along(DualArmIK(velocity_limit=False)) < 0.0


_unit = st.lists(st.floats(0.0, 1.0), min_size=7, max_size=7)


@settings(max_examples=40, deadline=None)
@given(_unit)
def test_clik_round_trip_property(u):
    """For any q within the limits: IK(FK(q)) reaches FK(q) to 1e-5 m / 1e-4 rad (not necessarily q)."""
    arm = _ARM
    q = arm.lower + np.asarray(u) * (arm.upper - arm.lower)
    target = arm.fk(q)
    # a deterministic budget (a clock that ticks 1 ms per reading, 20 000 readings) so that the property
    # does not depend on how loaded the machine is; the 5 ms wall-clock budget is the benchmark's business
    ticks = iter(range(1, 10**9))
    res = arm.clik(target, budget=20.0, clock=lambda: next(ticks) * 1e-3)
    assert res.converged, res
    dp, dr = pose_error(arm.fk(res.q["arm"]), target)
    assert dp < POS_TOL and dr < ROT_TOL
    assert np.all(res.q["arm"] >= arm.lower) and np.all(res.q["arm"] <= arm.upper)


@settings(max_examples=30, deadline=None)
@given(_unit, _unit)
def test_pinocchio_mujoco_fk_agree_property(u1, u2):
    ik = _dual()
    arms = {"robot1": _ARM.lower + np.asarray(u1) * (_ARM.upper - _ARM.lower),
            "robot2": _ARM.lower + np.asarray(u2) * (_ARM.upper - _ARM.lower)}
    assert ik.fk_disagreement(ik.full_q(arms)) < 1e-9


_ARM = PinocchioArm()
_DUAL: list[DualArmIK] = []


def _dual() -> DualArmIK:
    if not _DUAL:
        _DUAL.append(DualArmIK())
    return _DUAL[0]


def test_seed_library_returns_configurations_near_the_target():
    arm = PinocchioArm(pose(Layout().base_pos(0), np.eye(3)))
    _, poses = random_reachable_poses(20, seed=4)
    rng = np.random.default_rng(0)
    for t in poses:
        seeds = arm.seeds(t, k=4)
        assert seeds.shape == (4, 7)
        assert np.all(seeds >= arm.lower) and np.all(seeds <= arm.upper)
        near = np.linalg.norm(arm.fk(seeds[0])[:3, 3] - t[:3, 3])
        rand = np.median([np.linalg.norm(arm.fk(arm.random_q(rng))[:3, 3] - t[:3, 3]) for _ in range(20)])
        assert near < rand  # the nearest stored pose is closer than a typical random one
    # with and without the library the solver reaches the target
    for lib in (True, False):
        res = arm.clik(poses[0], budget=0.2, library=lib)
        assert res.converged


def test_clik_is_the_fallback_when_mink_runs_out_of_budget(ik):
    lay = Layout()
    target = {"robot1": pose([lay.stack_x - 0.05, lay.stack_xy(0, 2)[1], 0.12])}
    home = ik.arms_of(ik.q_home)
    alone = ik.solve(target, home, budget=1e-6)
    assert not alone.converged and alone.solver == "mink"
    res = ik.solve(target, home, budget=1e-6, fallback_budget=0.05)
    assert res.converged and res.solver == "pinocchio-clik (fallback)"
    assert res.fk_disagreement < 1e-9
    dp, dr = pose_error(ik.pin["robot1"].fk(res.q["robot1"]), target["robot1"])
    assert dp < POS_TOL and dr < ROT_TOL


# -- the analytic IK --------------------------------------------------------------------------------------

def _ticks(step: float = 1e-3):
    """A deterministic clock (``step`` s per reading): budgets that do not depend on the machine's load."""
    ticks = iter(range(1, 10**9))
    return lambda: next(ticks) * step


def _analytic(arm: PinocchioArm | None = None, **kw):
    from arms.ik_analytic import AnalyticArm

    return AnalyticArm(arm=arm or _ARM, **kw)


_AN: list = []


def _an():
    if not _AN:
        _AN.append(_analytic())
    return _AN[0]


def _assert_solution(arm: PinocchioArm, q: np.ndarray, target: np.ndarray) -> None:
    """What every returned solution must satisfy: pinocchio FK of the URDF within 1e-6 m / 1e-6 rad of
    the target, and every joint within the URDF's limits."""
    from arms.ik_analytic import CHECK_POS, CHECK_ROT

    dp, dr = pose_error(arm.fk(q), target)
    assert dp <= CHECK_POS and dr <= CHECK_ROT, (dp, dr)
    assert np.all(q >= arm.lower) and np.all(q <= arm.upper), q


@settings(max_examples=60, deadline=None)
@given(_unit, _unit)
def test_analytic_solutions_satisfy_fk_and_limits_property(u, useed):
    """For any reachable pose (FK of a q within the limits) and any seed within the limits, the analytic
    IK returns a configuration that pinocchio FK puts on the pose (1e-6 m, 1e-6 rad), within the limits."""
    an = _an()
    q = _ARM.lower + np.asarray(u) * (_ARM.upper - _ARM.lower)
    seed = _ARM.lower + np.asarray(useed) * (_ARM.upper - _ARM.lower)
    target = _ARM.fk(q)
    res = an.solve(target, seed, budget=1.0, clock=_ticks(1e-5))
    assert res.converged, res
    _assert_solution(_ARM, res.q["arm"], target)


def test_analytic_is_deterministic_and_solves_all_benchmark_poses():
    an = _an()
    qs = np.random.default_rng(7).uniform(_ARM.lower, _ARM.upper, size=(150, 7))
    for i, t in enumerate(_ARM.fk(q) for q in qs):
        a = an.solve(t, budget=1.0, seed=i, clock=_ticks(1e-5))
        b = an.solve(t, budget=1.0, seed=i, clock=_ticks(1e-5))
        assert a.converged and a.solver.startswith("analytic"), a
        assert np.array_equal(a.q["arm"], b.q["arm"])
        _assert_solution(_ARM, a.q["arm"], t)


def _broken_arm(joint: int = 4, dx: float = 1e-3) -> PinocchioArm:
    """The URDF's Panda with one joint's offset moved by ``dx`` m along its parent's x axis."""
    import pinocchio as pin

    arm = PinocchioArm()
    m = arm.model.jointPlacements[joint]
    arm.model.jointPlacements[joint] = pin.SE3(m.rotation, m.translation + np.array([dx, 0.0, 0.0]))
    arm.data = arm.model.createData()
    return arm


def test_breaking_one_joint_offset_fails_the_fk_check():
    """The closed form's constants are the Panda's; on a URDF with joint 4's offset moved by 1 mm its
    branches no longer satisfy FK: the model check refuses the arm, the property's check fails on the raw
    branches, and the solver rejects every branch (it returns none of them)."""
    from arms.ik_analytic import CHECK_POS, CHECK_ROT, AnalyticArm
    from arms.world import ArmsError

    broken = _broken_arm()
    with pytest.raises(ArmsError, match="does not reproduce"):
        AnalyticArm(arm=broken)
    an = AnalyticArm(arm=broken, check_model=False)
    rng = np.random.default_rng(5)
    checked = 0
    for _ in range(20):
        q = rng.uniform(broken.lower, broken.upper)
        target = broken.fk(q)
        raw = an.branches(an.flange_target(target), q[6], q)
        if len(raw):
            checked += 1
            for branch in raw:  # every branch misses the pose by more than the tolerance
                dp, dr = pose_error(broken.fk(branch), target)
                assert dp > CHECK_POS or dr > CHECK_ROT
            with pytest.raises(AssertionError):
                _assert_solution(broken, raw[0], target)
        res = an.solve(target, budget=1.0, clock=_ticks(1e-5), fallback=False)
        assert not res.converged
    assert checked >= 10
    # the intact model passes the same raw-branch check
    good = _an()
    q = rng.uniform(_ARM.lower, _ARM.upper)
    t = _ARM.fk(q)
    raw = good.branches(good.flange_target(t), q[6], q)
    _assert_solution(_ARM, raw[np.argmin(np.abs(raw - q).max(axis=1))], t)


def test_unreachable_pose_is_reported_with_the_reason():
    an = _an()
    res = an.solve(pose([1.5, 0.0, 0.3]), budget=0.02, clock=_ticks(1e-4))
    assert not res.converged and "outside the workspace" in res.reason
    assert np.all(res.q["arm"] >= _ARM.lower) and np.all(res.q["arm"] <= _ARM.upper)


def test_batch_clik_fallback_solves_reachable_poses():
    """The numerical fallback alone (a batch of 8 starts per iteration) on random reachable poses."""
    from arms.ik_analytic import BatchCLIK

    batch = BatchCLIK(_ARM)
    qs = np.random.default_rng(1).uniform(_ARM.lower, _ARM.upper, size=(5, 7))
    t, jac = batch.fk_jac(qs)
    for qi, ti, ji in zip(qs, t, jac, strict=True):  # batched FK and Jacobian = pinocchio's
        assert np.allclose(ti, _ARM.fk(qi), atol=1e-12)
        eps = 1e-7
        num = np.stack([(batch.fk_jac((qi + eps * np.eye(7)[j])[None])[0][0][:3, 3] - ti[:3, 3]) / eps
                        for j in range(7)], axis=1)
        assert np.allclose(ji[:3], num, atol=1e-5)
    solved = 0
    for i, q in enumerate(np.random.default_rng(9).uniform(_ARM.lower, _ARM.upper, size=(20, 7))):
        target = _ARM.fk(q)
        clock = _ticks(1e-4)
        q, _it, _re = batch.solve(target, np.zeros((0, 7)), np.random.default_rng(i), deadline=clock() + 1.0,
                                  clock=clock)
        if q is not None:
            _assert_solution(_ARM, q, target)
            solved += 1
    assert solved == 20


def test_track_follows_a_straight_line_continuously():
    """The executor's per-tick use: along a 20 cm vertical line the answers move each joint by little."""
    an = _an()
    from arms.scene import HOME_Q

    q = HOME_Q.copy()
    start = _ARM.fk(q)
    for k in range(1, 41):
        t = start.copy()
        t[2, 3] -= 0.2 * k / 40
        res = an.track(t, q, clock=_ticks(1e-5))
        assert res.converged
        assert np.abs(res.q["arm"] - q).max() < 0.05
        q = res.q["arm"]
        _assert_solution(_ARM, q, t)


# -- the executor's per-tick IK ---------------------------------------------------------------------------

@pytest.fixture(scope="module")
def executor():
    from arms.demo import demo_plan
    from arms.executor import Executor

    return Executor(demo_plan().world)


def test_clearance_bound_never_exceeds_the_true_arm_distance(executor):
    """The bound that lets a tick skip the QP's collision constraint (and the contact count) is a lower
    bound on the exact geom–geom distance (mj_geomDistance) for random configurations of both arms."""
    import mujoco

    ex = executor
    rng = np.random.default_rng(2)
    g1, g2 = ex._sphere_geoms
    fromto = np.zeros(6)
    near = 0
    for _ in range(40):
        for r in ex.world.robots:
            ex.data.qpos[ex._arm_adr[r]] = rng.uniform(_ARM.lower, _ARM.upper)
        mujoco.mj_kinematics(ex.model, ex.data)
        bound = ex.arm_clearance_bound()
        true = min(mujoco.mj_geomDistance(ex.model, ex.data, int(a), int(b), 2.0, fromto) for a in g1 for b in g2)
        assert bound <= true + 1e-9, (bound, true)
        near += bound < 0.17
    assert near >= 5  # the sample does reach configurations where the QP is needed


def test_executor_uses_the_analytic_ik_by_default_and_mink_on_request():
    from arms.demo import demo_plan
    from arms.executor import Executor
    from arms.world import ArmsError

    world = demo_plan().world
    lay = world.layout
    target = pose([lay.stack_x, lay.stack_xy(0, 1)[1], lay.table_z + 0.2])
    for ik, used in (("analytic", "analytic"), ("mink", "mink")):
        ex = Executor(world, ik=ik)
        err = ex.move("robot1", target)
        assert err < 3e-4
        assert ex.ik_ticks[used] > 0
        if ik == "mink":
            assert ex.ik_ticks["analytic"] == 0
        else:  # every analytic set-point the arm was sent to is within the limits (checked per tick)
            q = ex.q_ik[ex.ik.qadr["robot1"]]
            assert np.all(q >= _ARM.lower) and np.all(q <= _ARM.upper)
        assert np.linalg.norm(ex.tcp_actual("robot1")[:3, 3] - target[:3, 3]) < 5e-3
    with pytest.raises(ArmsError, match="ik must be"):
        Executor(world, ik="ikfast")
