"""Inverse kinematics for the two Pandas: one mink QP for both arms, and a pinocchio CLIK fallback.

**mink (differential IK as a QP).** At configuration q, with body twist error e_i = log(T_i(q)⁻¹ T*_i) of
the TCP of arm i (the right-minus of mink's ``FrameTask``), one step solves

    min_Δq  Σ_i ‖J_i(q) Δq + e_i‖²_{W_i} + w_p ‖Δq − (q_post − q)‖² + λ‖Δq‖²
    s.t.    q_min ≤ q + Δq ≤ q_max                         (ConfigurationLimit)
            |Δq_j| ≤ v_max,j · dt                           (VelocityLimit)
            ḋ_k(q)·dt ≥ −ξ (d_k − d_s)/(d_i − d_s)  for every arm-1/arm-2 geom pair with d_k < d_i
                                                            (CollisionAvoidanceLimit)

and integrates q ← q ⊕ Δq. The collision constraint is a *linearisation* that only switches on once a
pair is closer than the detection distance d_i; the velocity limit keeps each step shorter than d_i, which
is what keeps the arms from stepping through each other (``tests/arms/test_ik.py`` shows both cases).
To reach a pose exactly, the posture task (which biases the fixed point by O(w_p)) is dropped once the
error is below 1 cm ("polish" phase), so the residual goes to the QP's tolerance.

**pinocchio.** The same URDF, loaded with ``pin.buildModelFromUrdf``: forward kinematics of every
solution is compared with MuJoCo's (they agree to ~1e-15 m), and a damped-least-squares CLIK
(Δq = argmin ‖JΔq − e‖² + λ‖Δq‖² within the joint limits, e = log₆(T(q)⁻¹T*) in the local frame,
λ = λ₀ + ‖e‖²) serves as a fallback solver.

**Starts and restarts.** Both solvers start from the configurations of a precomputed
:class:`SeedLibrary` whose TCP poses are nearest to the target, then restart from random configurations
within the joint limits, until the time budget is spent; the result says whether they converged and
the residual.
"""

from __future__ import annotations

import math
import time
from collections.abc import Mapping
from dataclasses import dataclass, field

import daqp
import mink
import mujoco
import numpy as np
import pinocchio as pin
from scipy.linalg.lapack import dposv

from arms.scene import ARM_JOINTS, TCP_BODY, build_scene, panda_urdf_path
from arms.world import Layout

__all__ = [
    "IKResult", "SeedLibrary", "PinocchioArm", "DualArmIK", "pose", "pose_error", "random_reachable_poses",
    "VELOCITY_LIMITS", "POS_TOL", "ROT_TOL",
]

#: Panda joint velocity limits (rad/s), from the URDF.
VELOCITY_LIMITS = np.array([2.175, 2.175, 2.175, 2.175, 2.61, 2.61, 2.61])
POS_TOL = 1e-5
ROT_TOL = 1e-4
#: TCP pointing straight down (z_tcp = −z_world), fingers opening along world x (y_tcp = x_world), so that
#: the 20 cm wide hand lies across the row of stacks (which runs along y), not over the neighbours.
DOWN = np.array([[0.0, 1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, -1.0]])


def pose(position, rotation=DOWN) -> np.ndarray:
    """4×4 homogeneous transform from a position and a rotation matrix."""
    t = np.eye(4)
    t[:3, :3] = np.asarray(rotation, dtype=float)
    t[:3, 3] = np.asarray(position, dtype=float)
    return t


def pose_error(current: np.ndarray, target: np.ndarray) -> tuple[float, float]:
    """(‖p − p*‖ in m, ‖log(Rᵀ R*)‖ in rad) between two 4×4 poses.

    The angle is atan2(½‖skew(R)‖, ½(tr R − 1)) for R = Rᵀ R*, accurate near 0 and near π alike.
    """
    d = current[:3, 3] - target[:3, 3]
    dp = math.sqrt(float(d @ d))
    r = (current[:3, :3].T @ target[:3, :3]).tolist()
    s = 0.5 * math.sqrt((r[2][1] - r[1][2]) ** 2 + (r[0][2] - r[2][0]) ** 2 + (r[1][0] - r[0][1]) ** 2)
    c = 0.5 * (r[0][0] + r[1][1] + r[2][2] - 1.0)
    ang = math.atan2(s, c)
    return dp, ang


def _score(dp: float, dr: float, pos_tol: float, rot_tol: float) -> float:
    """Residual in units of the tolerances (< 1 for both ⇔ converged); used to keep the best iterate."""
    return max(dp / pos_tol, dr / rot_tol)


@dataclass(frozen=True)
class IKResult:
    """Outcome of an IK solve: joint angles per robot, whether every TCP is within tolerance, residuals."""

    q: Mapping[str, np.ndarray]
    converged: bool
    position_error: float
    orientation_error: float
    iterations: int
    restarts: int
    seconds: float
    solver: str
    fk_disagreement: float = float("nan")
    extra: Mapping[str, float] = field(default_factory=dict)
    #: why a solve failed (empty when it converged)
    reason: str = ""


class SeedLibrary:
    """Precomputed joint vectors and their TCP poses (base frame) of one Panda: "roadmap" seeding.

    n configurations uniform within the limits (fixed seed, independent of any query); a pose is the
    feature vector (p, w·vec(R)) — position in m and the rotation matrix entries weighted by w = 0.15 m
    — and a k-d tree (scipy ``cKDTree``) returns the k stored configurations whose TCP is nearest to a
    target. Starting Gauss–Newton there halves the median iteration count and, used for the restarts,
    cuts the 99.7th percentile of iterations by about half as well (bench/RESULTS.md (Franka arms section)).
    """

    def __init__(self, arm: PinocchioArm, n: int = 16384, seed: int = 12345, rot_weight: float = 0.15):
        from scipy.spatial import cKDTree

        rng = np.random.default_rng(seed)
        self.rot_weight = rot_weight
        self.q = rng.uniform(arm.lower, arm.upper, size=(n, 7))
        model, data, frame = arm.model, arm.data, arm.frame
        qf = pin.neutral(model)
        feats = np.empty((n, 12))
        for i, q in enumerate(self.q):
            qf[:7] = q
            pin.framesForwardKinematics(model, data, qf)
            feats[i] = self._feature(data.oMf[frame].homogeneous)
        self.tree = cKDTree(feats)

    def _feature(self, t: np.ndarray) -> np.ndarray:
        return np.concatenate([t[:3, 3], self.rot_weight * t[:3, :3].ravel()])

    def nearest(self, target_in_base: np.ndarray, k: int) -> np.ndarray:
        """The k stored configurations (k × 7) nearest to a TCP pose given in the arm's base frame."""
        _, idx = self.tree.query(self._feature(target_in_base), k=k)
        return self.q[np.atleast_1d(idx)]


_LIBRARIES: dict[tuple[int, int], SeedLibrary] = {}


class PinocchioArm:
    """One Panda in pinocchio (same URDF), at a base pose: FK of the TCP and a DLS CLIK solver."""

    def __init__(self, base: np.ndarray | None = None) -> None:
        self.model = pin.buildModelFromUrdf(str(panda_urdf_path()))
        self.data = self.model.createData()
        self.frame = self.model.getFrameId(TCP_BODY)
        self.base = pin.SE3(np.eye(4) if base is None else np.asarray(base, dtype=float))
        self.lower = self.model.lowerPositionLimit[:7].copy()
        self.upper = self.model.upperPositionLimit[:7].copy()
        self._q = pin.neutral(self.model)

    def library(self, n: int = 16384, seed: int = 12345) -> SeedLibrary:
        """The (cached, shared by all arms: same URDF, base-frame poses) seed library."""
        key = (n, seed)
        if key not in _LIBRARIES:
            _LIBRARIES[key] = SeedLibrary(PinocchioArm(), n, seed)
        return _LIBRARIES[key]

    def seeds(self, target: np.ndarray, k: int = 32) -> np.ndarray:
        """k library configurations whose TCP is nearest to a world-frame target pose."""
        return self.library().nearest(self.base.actInv(pin.SE3(np.asarray(target, dtype=float))).homogeneous, k)

    def _fk_se3(self, q7: np.ndarray) -> pin.SE3:
        self._q[:7] = q7
        pin.framesForwardKinematics(self.model, self.data, self._q)
        return self.base * self.data.oMf[self.frame]

    def fk(self, q7: np.ndarray) -> np.ndarray:
        """World pose (4×4) of ``panda_hand_tcp`` for the seven arm angles."""
        return self._fk_se3(np.asarray(q7, dtype=float)).homogeneous

    def random_q(self, rng: np.random.Generator) -> np.ndarray:
        return rng.uniform(self.lower, self.upper)

    def _restart(self, rng: np.random.Generator, target: pin.SE3, candidates: int) -> np.ndarray:
        """A random start; with ``candidates`` > 1 the one of that many whose TCP is closest to the target
        (‖Δp‖ + 0.3‖Δθ‖, one FK each — cheaper than an iteration)."""
        if candidates <= 1:
            return self.random_q(rng)
        qs = rng.uniform(self.lower, self.upper, size=(candidates, 7))
        best, best_q = np.inf, qs[0]
        for qc in qs:
            err = self._fk_se3(qc).actInv(target)
            d = float(np.linalg.norm(err.translation)) + 0.3 * float(np.linalg.norm(pin.log3(err.rotation)))
            if d < best:
                best, best_q = d, qc
        return best_q

    def clik(self, target: np.ndarray, q0: np.ndarray | None = None, *, budget: float = 0.005,
             seed: int = 0, damping: float = 1e-6, max_iter: int = 30, stall: int = 4, stall_ratio: float = 0.6,
             pos_tol: float = POS_TOL, rot_tol: float = ROT_TOL, clock=time.perf_counter,
             candidates: int = 8, library: bool = True, library_k: int = 32) -> IKResult:
        """Damped least squares CLIK with random restarts inside ``budget`` seconds.

        Iteration (Levenberg–Marquardt with error-adaptive damping, Sugihara 2011): e = log₆(T(q)⁻¹ T*)
        (local frame), J = local frame Jacobian, λ = λ₀ + ‖e‖², and the damped least-squares step
        Δq = argmin ‖J Δq − e‖² + λ‖Δq‖² subject to q_min ≤ q + Δq ≤ q_max. Without the box this is
        Δq = Jᵀ(JJᵀ + λI)⁻¹e; only when that step leaves the box is the 7-variable box QP solved (daqp).
        (Clipping the unconstrained step instead stalls at the joint limits and costs ~2 points of
        success rate.) ``clock`` is the time source of the budget (``time.perf_counter``: wall time;
        ``time.thread_time``: this thread's CPU time).
        A restart happens after ``max_iter`` iterations, or when the error has not dropped below
        ``stall_ratio`` times its value ``stall`` iterations earlier (stuck at a joint limit or a
        singularity; Gauss–Newton near a solution shrinks the error far faster); it draws ``candidates``
        configurations uniformly within the limits and starts from the one whose TCP is nearest the
        target. Starts: ``q0`` if given; else with ``library`` the ``library_k`` configurations of the
        :class:`SeedLibrary` nearest to the target, in order, then the random restarts; without the
        library the middle of the joint ranges (TRAC-IK's seed), then random restarts.
        """
        t0 = clock()
        rng = np.random.default_rng(seed)
        target_se3 = pin.SE3(np.asarray(target, dtype=float))
        target_base = self.base.actInv(target_se3)  # iterate in the base frame: one SE3 product less
        p_target = target_base.translation.copy()
        queue: list[np.ndarray] = []
        if q0 is not None:
            q = np.array(q0, dtype=float)
        elif library:
            queue = list(self.library().nearest(target_base.homogeneous, library_k))
            q = queue.pop(0)
        else:
            q = (self.lower + self.upper) / 2.0
        lower, upper = self.lower, self.upper
        best_score, best = np.inf, (np.inf, np.inf, q.copy())
        iters = restarts = k = 0
        history: list[float] = []
        diag6 = np.diag_indices(6)
        diag7 = np.diag_indices(7)
        no_rows = np.zeros((0, 7))
        model, data, frame, qf = self.model, self.data, self.frame, self._q
        while True:
            qf[:7] = q
            pin.computeJointJacobians(model, data, qf)  # FK and joint Jacobians in one pass
            pin.updateFramePlacement(model, data, frame)
            cur = data.oMf[frame]
            e = pin.log6(cur.actInv(target_base)).vector
            dpv = cur.translation - p_target
            dp = math.sqrt(dpv @ dpv)
            dr = math.sqrt(e[3:] @ e[3:])
            score = max(dp / pos_tol, dr / rot_tol)
            if score < best_score:
                best_score, best = score, (dp, dr, q.copy())
            if score < 1.0 or clock() - t0 > budget:
                break
            history.append(dp + dr)
            if k >= max_iter or (k > stall and history[-1] > stall_ratio * history[-1 - stall]):
                if queue:  # next-nearest library configuration
                    q = queue.pop(0)
                else:  # alternate nearest-of-candidates (exploit) with plain random restarts (explore)
                    q = self._restart(rng, target_se3, candidates if restarts % 2 == 0 else 1)
                restarts += 1
                k = 0
                history.clear()
                continue
            jac = pin.getFrameJacobian(model, data, frame, pin.LOCAL)[:, :7]
            lam = damping + float(e @ e)
            gram = jac @ jac.T
            gram[diag6] += lam
            dq = jac.T @ dposv(gram, e)[1]  # Cholesky solve (LAPACK, SPD); the box is rarely active:
            qn = q + dq
            if not ((lower <= qn) & (qn <= upper)).all():  # ...only then solve the box QP
                hess = jac.T @ jac
                hess[diag7] += lam
                dqb, _f, flag, _info = daqp.solve(hess, -(jac.T @ e), no_rows, upper - q, lower - q)
                if flag >= 1:
                    qn = q + dqb
                qn = np.minimum(np.maximum(qn, lower), upper)
            q = qn
            iters += 1
            k += 1
        dp, dr, qb = best
        return IKResult(q={"arm": qb}, converged=bool(dp < pos_tol and dr < rot_tol), position_error=dp,
                        orientation_error=dr, iterations=iters, restarts=restarts,
                        seconds=clock() - t0, solver="pinocchio-clik")


class DualArmIK:
    """mink IK over both arms at once (one QP): TCP frame tasks, posture, limits, arm–arm avoidance.

    ``robots`` may name one arm only (used by the benchmark). Joint vectors passed in and out are the
    seven arm angles per robot; fingers are held where they are.
    """

    def __init__(self, robots: tuple[str, ...] = ("robot1", "robot2"), layout: Layout | None = None, *,
                 velocity_limit: bool = True, collision: bool = True, posture_cost: float = 1e-2,
                 min_distance: float = 0.02, detection_distance: float = 0.12,
                 lm_damping: float = 0.1) -> None:
        from arms.world import World

        layout = layout or Layout()
        self.robots = tuple(robots)
        self.layout = layout
        if len(self.robots) not in (1, 2):
            raise ValueError("DualArmIK takes one or two robots")
        # a world with no blocks only carries names and layout; cell=False keeps only the arms. A single
        # arm stands at the first robot's base pose.
        names = self.robots if len(self.robots) == 2 else (self.robots[0], f"{self.robots[0]}_other")
        world = World(robots=names, stacks={r: ((),) for r in names}, layout=layout)
        self.scene = build_scene(world, robots=self.robots, cell=False)
        self.model = self.scene.model
        self.configuration = mink.Configuration(self.model)
        self.qadr = {r: self.scene.arm_qpos_adr(r) for r in self.robots}
        self.frame_tasks = {r: mink.FrameTask(f"{r}/{TCP_BODY}", "body", position_cost=1.0,
                                              orientation_cost=1.0, lm_damping=lm_damping)
                            for r in self.robots}
        self.posture = mink.PostureTask(self.model, cost=posture_cost)
        q_home = self.model.key("home").qpos.copy()
        self.q_home = q_home
        self.posture.set_target(q_home)
        self.limits: list = [mink.ConfigurationLimit(self.model)]
        if velocity_limit:
            vel = {f"{r}/{j}": float(v) for r in self.robots for j, v in zip(ARM_JOINTS, VELOCITY_LIMITS,
                                                                             strict=True)}
            self.limits.append(mink.VelocityLimit(self.model, vel))
        self.collision_limit = None
        if collision and len(self.robots) == 2:
            g1, g2 = (self.scene.arm_geoms(r) for r in self.robots)
            self.collision_limit = mink.CollisionAvoidanceLimit(
                self.model, [(g1, g2)], minimum_distance_from_collisions=min_distance,
                collision_detection_distance=detection_distance)
            self.limits.append(self.collision_limit)
        self.pin = {r: PinocchioArm(pose(layout.base_pos(i), np.eye(3)))
                    for i, r in enumerate(self.robots)}
        self._geoms = ([self.scene.arm_geoms(r) for r in self.robots] if len(self.robots) == 2 else None)
        self._tcp_ids = {r: self.model.body(f"{r}/{TCP_BODY}").id for r in self.robots}

    # -- configuration helpers -------------------------------------------------------------------------
    def full_q(self, arms: Mapping[str, np.ndarray] | None = None) -> np.ndarray:
        """Full model configuration with the given arm angles (others at home)."""
        q = self.q_home.copy()
        for r, qa in (arms or {}).items():
            q[self.qadr[r]] = qa
        return q

    def arms_of(self, q: np.ndarray) -> dict[str, np.ndarray]:
        return {r: q[self.qadr[r]].copy() for r in self.robots}

    def tcp_pose(self, q: np.ndarray, robot: str) -> np.ndarray:
        """MuJoCo FK: world pose of the robot's TCP at full configuration q."""
        self.configuration.update(q)
        return self.configuration.get_transform_frame_to_world(f"{robot}/{TCP_BODY}", "body").as_matrix()

    def fk_disagreement(self, q: np.ndarray) -> float:
        """max over arms of ‖p_MuJoCo − p_pinocchio‖ (m) plus the rotation-matrix difference (Frobenius)."""
        worst = 0.0
        for r in self.robots:
            a = self.tcp_pose(q, r)
            b = self.pin[r].fk(q[self.qadr[r]])
            worst = max(worst, float(np.linalg.norm(a[:3, 3] - b[:3, 3])),
                        float(np.linalg.norm(a[:3, :3] - b[:3, :3])))
        return worst

    def min_arm_distance(self, q: np.ndarray) -> float:
        """Smallest signed distance between a geom of arm 1 and one of arm 2 (negative: penetration)."""
        if self._geoms is None:
            return float("inf")
        self.configuration.update(q)
        m, d = self.model, self.configuration.data
        best = np.inf
        fromto = np.zeros(6)
        for g1 in self._geoms[0]:
            for g2 in self._geoms[1]:
                best = min(best, mujoco.mj_geomDistance(m, d, g1, g2, 0.5, fromto))
        return float(best)

    # -- one QP step ---------------------------------------------------------------------------------
    def set_targets(self, targets: Mapping[str, np.ndarray]) -> None:
        for r, t in targets.items():
            self.frame_tasks[r].set_target(mink.SE3.from_matrix(np.asarray(t, dtype=float)))

    def _qp_delta(self, tasks: list, dt: float, limits: list) -> np.ndarray:
        """Δq of the IK QP at the current configuration (mink builds it, daqp solves it directly)."""
        problem = mink.build_ik(self.configuration, tasks, dt, 1e-9, limits)
        h = problem.h
        dq, _f, flag, _info = daqp.solve(problem.P, problem.q, problem.G, h, np.full(h.shape, -1e30))
        if flag < 1:
            raise mink.NoSolutionFound("daqp")
        return dq

    def step(self, q: np.ndarray, targets: Mapping[str, np.ndarray] | None, dt: float, *,
             posture: bool = True, limits: bool = True) -> np.ndarray:
        """One differential-IK step from full configuration q towards the TCP targets; returns new q."""
        if targets:
            self.set_targets(targets)
        self.configuration.update(q)
        return self._step_here(dt, posture=posture, limits=limits)

    def _step_here(self, dt: float, *, posture: bool = True, limits: bool = True) -> np.ndarray:
        tasks = [self.frame_tasks[r] for r in self.robots]
        if posture:
            tasks.append(self.posture)
        dq = self._qp_delta(tasks, dt, self.limits if limits else [self.limits[0]])
        self.configuration.integrate_inplace(dq / dt, dt)
        return self.configuration.q.copy()

    def _errors_here(self, targets: Mapping[str, np.ndarray]) -> tuple[float, float]:
        """max over arms of (position, orientation) error at the configuration already computed."""
        d = self.configuration.data
        ep = er = 0.0
        for r, t in targets.items():
            b = self._tcp_ids[r]
            cur = np.eye(4)
            cur[:3, :3] = d.xmat[b].reshape(3, 3)
            cur[:3, 3] = d.xpos[b]
            dp, dr = pose_error(cur, t)
            ep, er = max(ep, dp), max(er, dr)
        return ep, er

    def solve(self, targets: Mapping[str, np.ndarray], q0: Mapping[str, np.ndarray] | None = None, *,
              budget: float = 0.05, seed: int = 0, dt: float = 0.1, max_iter: int = 30, stall: int = 4,
              stall_ratio: float = 0.6,
              pos_tol: float = POS_TOL, rot_tol: float = ROT_TOL, check_fk: bool = True,
              clock=time.perf_counter, candidates: int = 8, library: bool = True,
              library_k: int = 32, fallback_budget: float = 0.0) -> IKResult:
        """Iterate :meth:`step` until every TCP is within tolerance; random restarts within ``budget`` s.

        Phase 1 (error ≥ 1 cm): frame tasks + posture. Phase 2 (polish): frame tasks alone, so that the
        fixed point is the exact target. The result carries the pinocchio/MuJoCo FK disagreement of the
        returned configuration. A restart (as in :meth:`PinocchioArm.clik`: the best of ``candidates``
        random configurations) follows ``max_iter`` iterations or a stall (error above ``stall_ratio``
        times its value ``stall`` iterations earlier). Without ``q0`` the starts are the
        :class:`SeedLibrary` configurations nearest to each target (``library=False``: home posture,
        then random restarts). ``clock`` as in :meth:`PinocchioArm.clik`. If mink has not converged
        and ``fallback_budget`` > 0, the pinocchio CLIK gets that many more seconds, starting from
        mink's best configuration; its answer is taken if it converges with the arms apart
        (``solver`` then says ``pinocchio-clik (fallback)``).
        """
        t0 = clock()
        rng = np.random.default_rng(seed)
        q = self.full_q(q0)
        queues: dict[str, list[np.ndarray]] = {}
        if q0 is None and library:  # roadmap seeding, as in PinocchioArm.clik
            queues = {r: list(self.pin[r].seeds(t, library_k)) for r, t in targets.items()}
            for r in targets:
                q[self.qadr[r]] = queues[r].pop(0)
        best = (np.inf, np.inf, q.copy())
        iters = restarts = k = 0
        history: list[float] = []
        pin_targets = {r: pin.SE3(np.asarray(t, dtype=float)) for r, t in targets.items()}
        # an arm without a target holds its pose (its frame task stays in the QP)
        self.set_targets({**{r: self.tcp_pose(q, r) for r in self.robots if r not in targets}, **targets})
        self.configuration.update(q)
        while True:
            ep, er = self._errors_here(targets)
            done = ep < pos_tol and er < rot_tol
            if done or _score(ep, er, pos_tol, rot_tol) < _score(best[0], best[1], pos_tol, rot_tol):
                best = (ep, er, q.copy())
            if done or clock() - t0 > budget:
                break
            history.append(ep + er)
            if k >= max_iter or (k > stall and history[-1] > stall_ratio * history[-1 - stall]):
                q = q.copy()
                for r in targets:
                    if queues.get(r):
                        q[self.qadr[r]] = queues[r].pop(0)
                    else:
                        q[self.qadr[r]] = self.pin[r]._restart(rng, pin_targets[r], candidates)
                self.configuration.update(q)
                restarts += 1
                k = 0
                history.clear()
                continue
            try:
                q = self._step_here(dt, posture=ep >= 1e-2)
            except mink.NoSolutionFound:
                k = max_iter
            iters += 1
            k += 1
        ep, er, qb = best
        disagreement = self.fk_disagreement(qb) if check_fk else float("nan")
        result = IKResult(q=self.arms_of(qb), converged=bool(ep < pos_tol and er < rot_tol),
                          position_error=ep, orientation_error=er, iterations=iters, restarts=restarts,
                          seconds=clock() - t0, solver="mink", fk_disagreement=disagreement)
        if result.converged or fallback_budget <= 0.0:
            return result
        # fallback: the pinocchio CLIK, arm by arm; accepted only if the arms stay apart
        fb = self.solve_clik(targets, {r: qb[self.qadr[r]] for r in targets}, budget=fallback_budget,
                             seed=seed)
        if fb.converged and self.min_arm_distance(self.full_q({**result.q, **fb.q})) > 0.0:
            return IKResult(q={**result.q, **fb.q}, converged=True, position_error=fb.position_error,
                            orientation_error=fb.orientation_error, iterations=iters + fb.iterations,
                            restarts=restarts + fb.restarts, seconds=clock() - t0,
                            solver="pinocchio-clik (fallback)", fk_disagreement=fb.fk_disagreement)
        return result

    def solve_clik(self, targets: Mapping[str, np.ndarray], q0: Mapping[str, np.ndarray] | None = None, *,
                   budget: float = 0.005, seed: int = 0, clock=time.perf_counter) -> IKResult:
        """The pinocchio CLIK fallback, arm by arm (it knows nothing of the other arm); ``clock`` as in
        :meth:`PinocchioArm.clik`."""
        t0 = time.perf_counter()
        qs: dict[str, np.ndarray] = {}
        ep = er = 0.0
        conv = True
        iters = restarts = 0
        for r, t in targets.items():
            res = self.pin[r].clik(t, None if q0 is None else q0.get(r), budget=budget, seed=seed, clock=clock)
            qs[r] = res.q["arm"]
            ep, er = max(ep, res.position_error), max(er, res.orientation_error)
            conv = conv and res.converged
            iters += res.iterations
            restarts += res.restarts
        full = self.full_q(qs)
        return IKResult(q=qs, converged=conv, position_error=ep, orientation_error=er, iterations=iters,
                        restarts=restarts, seconds=time.perf_counter() - t0, solver="pinocchio-clik",
                        fk_disagreement=self.fk_disagreement(full))


def random_reachable_poses(n: int, seed: int = 0, robot_index: int = 0, layout: Layout | None = None,
                           ) -> tuple[np.ndarray, np.ndarray]:
    """n random joint vectors within the limits and their TCP poses (pinocchio FK): reachable targets.

    This is TRAC-IK's benchmark protocol (random q in the limits → FK → solve IK for that pose).
    """
    layout = layout or Layout()
    arm = PinocchioArm(pose(layout.base_pos(robot_index), np.eye(3)))
    rng = np.random.default_rng(seed)
    qs = np.array([arm.random_q(rng) for _ in range(n)])
    poses = np.array([arm.fk(q) for q in qs])
    return qs, poses

