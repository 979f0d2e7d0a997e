"""Analytical IK for one Panda: He & Liu's geometric solver over q7, every answer checked by pinocchio FK.

**The closed form.** With the redundant joint q7 fixed, the Panda's position and orientation of the
flange (``panda_link8``) have at most four solutions in closed form (He & Liu, "Analytical Inverse
Kinematics for Franka Emika Panda – a Geometrical Solver for 7-DOF Manipulators with Unconventional
Design", ICCMA 2021). The closed form is ``frankik.ik_full`` (PyPI ``frankik``, MIT, a C++ binding of
the authors' solver). Its kinematic constants are the Panda's (d1 0.333, d3 0.316, d5 0.384, a4 0.0825,
a7 0.088, d7 0.107 m); that they are the scene's URDF (example-robot-data's ``panda.urdf``) is *checked*,
not assumed: :class:`AnalyticArm` solves the FK poses of a few random configurations when it is built
and raises :class:`arms.world.ArmsError` unless every branch puts the TCP there to 1e-9 by the URDF's FK
(and every answer it ever returns is re-checked against pinocchio FK of the URDF, see below). frankik
returns at most four branches per q7 (one q4 of the two that the geometry can allow), so the sweep over
q7, not the branch set of one q7, is what makes the search complete. The TCP offset (flange →
``panda_hand_tcp``: −45° about z and 0.1034 m along it) is read from the URDF through pinocchio, not
typed in (frankik's own constant rounds the rotation to 0.707, a 1e-4 rad error).

**q7.** Every query sweeps q7 within its limits: the seed's own q7 first, then 16 values spread evenly
over the range (both ends included); all branches of all of them that are within *every* joint limit are
kept and the one nearest the seed (Euclidean in joint space) is chosen; q7 is then refined around it
(pattern search with steps of half, a quarter, ... of the grid pitch) to bring the answer nearer the
seed. If no q7 of a level gives an in-limit branch, the next level halves the pitch (32, 64, 128, 256
more values) before giving up on the closed form. ``track`` (the executor's per-tick use) tries only
the seed's q7 and its branch nearest the seed first, and sweeps only if that fails.

**Checked.** A candidate is returned only if pinocchio FK of the URDF puts the TCP within 1e-6 m and
1e-6 rad of the target and every joint is within the URDF limits; a candidate that fails the FK check is
counted (``extra["rejected"]``) and the next nearest is tried.

**Fallback.** When no q7 has an in-limit branch (the pose needs a q7 window narrower than the finest
pitch, or is outside the reachable set), a damped-least-squares CLIK runs on a *batch* of starts at
once (numpy over starts: batched FK and Jacobian of the URDF chain, one batched 6×6 solve per
iteration): the closed-form branches that were rejected only for their limits, clipped into the limits,
and random configurations; members that stall are redrawn until the time budget is spent. Its answer is
checked like the analytic ones. The result says which path answered (``solver``) and, on a failure, why
(``reason``).
"""

from __future__ import annotations

import math
import time

import numpy as np
import pinocchio as pin
from frankik import ik_full

from arms.ik import IKResult, PinocchioArm, pose_error
from arms.world import ArmsError

__all__ = ["AnalyticArm", "BatchCLIK", "FLANGE_FRAME", "CHECK_POS", "CHECK_ROT", "ANALYTIC"]

FLANGE_FRAME = "panda_link8"
#: acceptance of an answer, re-measured by pinocchio FK of the URDF (1e-6 m, 1e-6 rad)
CHECK_POS = 1e-6
CHECK_ROT = 1e-6
ANALYTIC = "analytic (He & Liu, frankik)"
#: a closed-form branch this close (rad) outside a joint limit is rounding (a pose whose solution has a joint
#: exactly at its limit): it is clipped onto the limit, and the FK check decides
LIMIT_SLACK = 1e-9
_LEVELS = (16, 32, 64, 128, 256)


def _inv(t: np.ndarray) -> np.ndarray:
    out = np.eye(4)
    r = t[:3, :3].T
    out[:3, :3] = r
    out[:3, 3] = -r @ t[:3, 3]
    return out


class BatchCLIK:
    """Damped least squares CLIK on a batch of starts at once (numpy over the batch), within the limits.

    Batched FK of the URDF chain (revolute-z joints at pinocchio's joint placements, then the TCP frame's
    placement), the world-frame geometric Jacobian, error e = (p* − p, log(R* Rᵀ)), damping
    λ = λ₀ + ‖e‖² per member, Δq = Jᵀ(JJᵀ + λI)⁻¹e (one batched 6×6 solve); the joints that this step
    would push through a limit are held there (their Jacobian columns zeroed) and the step re-solved for
    the rest (plain clipping stalls at a limit); q ← clip(q + Δq).
    """

    def __init__(self, arm: PinocchioArm):
        m = arm.model
        self.lower, self.upper = arm.lower, arm.upper
        self.placements = [m.jointPlacements[j].homogeneous for j in range(1, 8)]
        frame = m.frames[arm.frame]
        if frame.parentJoint != 7:
            raise ArmsError(f"the TCP frame's parent joint is {frame.parentJoint}, expected panda_joint7")
        self.tcp = frame.placement.homogeneous

    def fk_jac(self, q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(T: B×4×4 TCP poses in the base frame, J: B×6×7 world-frame Jacobians [v; ω])."""
        b = q.shape[0]
        t = np.broadcast_to(np.eye(4), (b, 4, 4)).copy()
        axes = np.empty((b, 7, 3))
        origins = np.empty((b, 7, 3))
        c, s = np.cos(q), np.sin(q)
        rz = np.zeros((b, 4, 4))
        rz[:, 2, 2] = rz[:, 3, 3] = 1.0
        for j, placement in enumerate(self.placements):
            t = t @ placement
            rz[:, 0, 0] = rz[:, 1, 1] = c[:, j]
            rz[:, 0, 1] = -s[:, j]
            rz[:, 1, 0] = s[:, j]
            t = t @ rz
            axes[:, j] = t[:, :3, 2]
            origins[:, j] = t[:, :3, 3]
        t = t @ self.tcp
        jac = np.empty((b, 6, 7))
        jac[:, :3, :] = np.cross(axes, t[:, None, :3, 3] - origins).transpose(0, 2, 1)
        jac[:, 3:, :] = axes.transpose(0, 2, 1)
        return t, jac

    @staticmethod
    def errors(t: np.ndarray, target: np.ndarray) -> np.ndarray:
        """B×6 world-frame error (p* − p, log(R* Rᵀ)) of each pose against one target."""
        e = np.empty((t.shape[0], 6))
        e[:, :3] = target[:3, 3] - t[:, :3, 3]
        r = target[:3, :3] @ t[:, :3, :3].transpose(0, 2, 1)
        w = np.stack([r[:, 2, 1] - r[:, 1, 2], r[:, 0, 2] - r[:, 2, 0], r[:, 1, 0] - r[:, 0, 1]], axis=1) * 0.5
        sin = np.linalg.norm(w, axis=1)
        cos = 0.5 * (r[:, 0, 0] + r[:, 1, 1] + r[:, 2, 2] - 1.0)
        ang = np.arctan2(sin, cos)
        scale = np.where(sin > 1e-12, ang / np.maximum(sin, 1e-12), 1.0)
        e[:, 3:] = w * scale[:, None]
        return e

    @staticmethod
    def _dls(jac: np.ndarray, e: np.ndarray, lam: np.ndarray, eye6: np.ndarray) -> np.ndarray:
        gram = jac @ jac.transpose(0, 2, 1) + lam[:, None, None] * eye6
        return np.einsum("bji,bj->bi", jac, np.linalg.solve(gram, e[:, :, None])[:, :, 0])

    def solve(self, target: np.ndarray, starts: np.ndarray, rng: np.random.Generator, *, deadline: float,
              clock, batch: int = 8, max_iter: int = 40, damping: float = 1e-6, pos_tol: float = CHECK_POS,
              rot_tol: float = CHECK_ROT) -> tuple[np.ndarray | None, int, int]:
        """Iterate a batch; returns (q of the first member within tolerance or None, iterations, restarts).

        ``starts`` (k × 7) fill the batch first, then random configurations; a member is redrawn after
        ``max_iter`` iterations without converging."""
        lo, hi = self.lower, self.upper
        queue = list(np.clip(starts, lo, hi)) if len(starts) else []
        q = np.empty((batch, 7))
        for i in range(batch):
            q[i] = queue.pop(0) if queue else rng.uniform(lo, hi)
        age = np.zeros(batch, dtype=np.int64)
        eye6 = np.eye(6)
        iters = restarts = 0
        while True:
            t, jac = self.fk_jac(q)
            e = self.errors(t, target)
            dp = np.linalg.norm(e[:, :3], axis=1)
            dr = np.linalg.norm(e[:, 3:], axis=1)
            ok = (dp < pos_tol) & (dr < rot_tol)
            if ok.any():
                return q[int(np.argmax(ok))].copy(), iters, restarts
            if clock() > deadline:
                return None, iters, restarts
            lam = damping + np.einsum("bi,bi->b", e, e)
            dq = self._dls(jac, e, lam, eye6)
            blocked = (q + dq < lo) | (q + dq > hi)
            if blocked.any():  # joints the step pushes through a limit are held there; the rest re-solve
                dq = self._dls(jac * ~blocked[:, None, :], e, lam, eye6)
            q = np.minimum(np.maximum(q + dq, lo), hi)
            iters += 1
            age += 1
            old = age >= max_iter
            if old.any():
                for i in np.flatnonzero(old):
                    q[i] = queue.pop(0) if queue else rng.uniform(lo, hi)
                    age[i] = 0
                    restarts += 1


class AnalyticArm:
    """The closed-form IK of one Panda at a base pose (see the module docstring)."""

    def __init__(self, base: np.ndarray | None = None, arm: PinocchioArm | None = None, *, check_model: bool = True):
        self.arm = arm if arm is not None else PinocchioArm(base)
        m, d = self.arm.model, self.arm.data
        self.lower, self.upper = self.arm.lower, self.arm.upper
        self.mid = (self.lower + self.upper) / 2.0
        self._lo_slack, self._hi_slack = self.lower - LIMIT_SLACK, self.upper + LIMIT_SLACK
        qf = pin.neutral(m)
        pin.framesForwardKinematics(m, d, qf)
        flange = m.getFrameId(FLANGE_FRAME)
        # flange → TCP from the URDF (pinocchio), and the base pose of this arm
        self.tcp_in_flange = d.oMf[flange].actInv(d.oMf[self.arm.frame]).homogeneous
        self._flange_of_tcp = _inv(self.tcp_in_flange)
        self.base = self.arm.base.homogeneous
        self._base_inv = _inv(self.base)
        self.batch = BatchCLIK(self.arm)
        q7 = (self.lower[6], self.upper[6])
        self.levels = [np.concatenate([[q7[0], q7[1]], q7[0] + (np.arange(_LEVELS[0]) + 0.5) * (q7[1] - q7[0])
                                       / _LEVELS[0]])]
        self.levels += [q7[0] + (np.arange(n) + 0.5) * (q7[1] - q7[0]) / n for n in _LEVELS[1:]]
        self.pitch = [(q7[1] - q7[0]) / n for n in _LEVELS]
        if check_model:
            self._check_model()

    # -- the closed form ---------------------------------------------------------------------------
    def flange_target(self, target: np.ndarray) -> np.ndarray:
        """The flange pose in the arm's base frame for a world-frame TCP target."""
        return self._base_inv @ np.asarray(target, dtype=float) @ self._flange_of_tcp

    def branches(self, flange: np.ndarray, q7: float, ref: np.ndarray) -> np.ndarray:
        """All closed-form branches (k × 7, k ≤ 4) for this q7, NaN rows removed, *not* limit-filtered."""
        s = ik_full(flange, ref, float(q7))
        return s[~np.isnan(s).any(axis=1)]

    def _in_limits(self, s: np.ndarray) -> np.ndarray:
        return ((s >= self.lower) & (s <= self.upper)).all(axis=1)

    def _feasible(self, s: np.ndarray) -> np.ndarray:
        """Mask of the rows within the limits up to ``LIMIT_SLACK`` (NaN rows compare false: excluded)."""
        return ((s >= self._lo_slack) & (s <= self._hi_slack)).all(axis=1)

    def _check_model(self) -> None:
        """Refuse to run if the closed form's constants are not the URDF's: for random configurations q,
        every branch of the closed form at q's q7 must put the TCP where pinocchio FK of q puts it."""
        rng = np.random.default_rng(2021)
        for _ in range(8):
            q = rng.uniform(self.lower, self.upper)
            target = self.arm.fk(q)
            s = self.branches(self.flange_target(target), q[6], q)
            errs = [self.check(x, target) for x in s]
            if not errs or max(max(e) for e in errs) > 1e-9:
                raise ArmsError("the analytic Panda IK (frankik) does not reproduce the URDF's forward "
                                f"kinematics (q = {np.round(q, 4).tolist()}); the URDF "
                                f"({self.arm.model.name}) is not the Panda the closed form assumes")

    def check(self, q: np.ndarray, target: np.ndarray) -> tuple[float, float]:
        """(position m, orientation rad) error of q's TCP against the target, by pinocchio FK."""
        return pose_error(self.arm.fk(q), target)

    def _accept(self, q: np.ndarray, target: np.ndarray, pos_tol: float, rot_tol: float) -> tuple[bool, float, float]:
        if not ((q >= self.lower) & (q <= self.upper)).all():
            return False, math.inf, math.inf
        dp, dr = self.check(q, target)
        return dp <= pos_tol and dr <= rot_tol, dp, dr

    # -- solving -----------------------------------------------------------------------------------
    def solve(self, target: np.ndarray, q0: np.ndarray | None = None, *, budget: float = 0.005, seed: int = 0,
              clock=time.perf_counter, refine: int = 3, fallback: bool = True, quick: float = 0.0,
              pos_tol: float = CHECK_POS, rot_tol: float = CHECK_ROT) -> IKResult:
        """The in-limit solution nearest ``q0`` (default: the middle of the joint ranges).

        ``quick`` (rad, a number or one per joint) > 0: accept the nearest branch at q0's own q7 at once if
        no joint moves more than ``quick`` from q0 (continuous tracking); otherwise the full sweep.
        ``budget`` (s on ``clock``) bounds the whole call, the numerical fallback included; ``seed`` seeds
        the fallback's restarts (deterministic for a given seed)."""
        t0 = clock()
        ref = self.mid if q0 is None else np.asarray(q0, dtype=float)
        target = np.asarray(target, dtype=float)
        flange = self.flange_target(target)
        calls = rejected = 0
        near_misses: list[np.ndarray] = []

        def finish(q, dp, dr, solver, *, ok=True, iters=0, restarts=0, reason=""):
            return IKResult(q={"arm": q}, converged=ok, position_error=dp, orientation_error=dr,
                            iterations=calls + iters, restarts=restarts, seconds=clock() - t0, solver=solver,
                            extra={"rejected": float(rejected), "q7": float(q[6])}, reason=reason)

        lo, hi = self.lower, self.upper

        def candidates(q7s):
            """In-limit branches (k × 7) of these q7 values and the q7 of each (one numpy pass)."""
            nonlocal calls
            q7s = np.asarray(q7s, dtype=float)
            if not len(q7s):
                return np.zeros((0, 7)), q7s
            s = np.concatenate([ik_full(flange, ref, q7) for q7 in q7s.tolist()])
            calls += len(q7s)
            q7_of = np.repeat(q7s, 4)
            inside = self._feasible(s)
            real = ~np.isnan(s).any(axis=1)
            if len(near_misses) < 16 and (real & ~inside).any():
                near_misses.extend(s[real & ~inside][:16])
            return np.minimum(np.maximum(s[inside], lo), hi), q7_of[inside]

        q7_ref = float(np.clip(ref[6], self.lower[6], self.upper[6]))
        quick = np.asarray(quick, dtype=float)
        if (quick > 0.0).all():
            s, _ = candidates([q7_ref])
            if len(s):
                dist = (np.abs(s - ref) / quick).max(axis=1)
                i = int(np.argmin(dist))
                if dist[i] <= 1.0:
                    ok, dp, dr = self._accept(s[i], target, pos_tol, rot_tol)
                    if ok:
                        return finish(s[i], dp, dr, ANALYTIC)
                    rejected += 1
        for level, q7s in enumerate(self.levels):
            s, q7_of = candidates(np.concatenate([[q7_ref], q7s]) if level == 0 else q7s)
            if not len(s):
                if clock() - t0 > budget:
                    break
                continue
            d2 = ((s - ref) ** 2).sum(axis=1)
            order = np.argsort(d2, kind="stable")
            best, best_q7, best_d2 = None, None, math.inf
            for i in order:
                ok, dp, dr = self._accept(s[i], target, pos_tol, rot_tol)
                if ok:
                    best, best_q7, best_d2, best_err = s[i], q7_of[i], d2[i], (dp, dr)
                    break
                rejected += 1
            if best is None:
                continue
            step = self.pitch[level] / 2.0
            for _ in range(refine):  # pattern search on q7 towards the seed: both sides in one pass
                sides = [q7 for q7 in (best_q7 - step, best_q7 + step) if self.lower[6] <= q7 <= self.upper[6]]
                c, c_q7 = candidates(sides)
                improved = False
                if len(c):
                    d2c = ((c - ref) ** 2).sum(axis=1)
                    for j in np.argsort(d2c, kind="stable"):
                        if d2c[j] >= best_d2:
                            break
                        ok, dp, dr = self._accept(c[j], target, pos_tol, rot_tol)
                        if ok:
                            best, best_q7, best_d2, best_err = c[j], c_q7[j], d2c[j], (dp, dr)
                            improved = True
                            break
                        rejected += 1
                if not improved:
                    step /= 2.0
            return finish(best, *best_err, ANALYTIC)
        reason = (f"no q7 on a grid of pitch {self.pitch[-1]:.4f} rad gives a branch within the joint limits"
                  + (f" ({len(near_misses)} branches outside them)" if near_misses else
                     " (no closed-form branch at all: outside the workspace)"))
        if not fallback:
            return finish(ref.copy(), math.inf, math.inf, ANALYTIC, ok=False, reason=reason)
        rng = np.random.default_rng(seed)
        q, iters, restarts = self.batch.solve(self._base_inv @ target, np.array(near_misses).reshape(-1, 7), rng,
                                              deadline=t0 + budget, clock=clock, pos_tol=pos_tol, rot_tol=rot_tol)
        if q is not None:
            ok, dp, dr = self._accept(q, target, pos_tol, rot_tol)
            if ok:
                return finish(q, dp, dr, "batch CLIK (fallback)", iters=iters, restarts=restarts)
            rejected += 1
        return finish(ref.copy(), math.inf, math.inf, "batch CLIK (fallback)", ok=False, iters=iters,
                      restarts=restarts, reason=reason + f"; the batch CLIK found none within the budget "
                                                         f"({restarts} restarts)")

    def _nearest_branch(self, flange, q_prev, q7, step) -> tuple[np.ndarray | None, float, float]:
        """(branch at this q7 nearest q_prev in Σ(Δq/step)², that cost, its largest |Δq|/step)."""
        s = ik_full(flange, q_prev, q7)
        s = np.minimum(np.maximum(s[self._feasible(s)], self.lower), self.upper)
        if not len(s):
            return None, math.inf, math.inf
        r = (s - q_prev) / step
        cost = np.einsum("ij,ij->i", r, r)
        i = int(np.argmin(cost))
        return s[i], float(cost[i]), float(np.abs(r[i]).max())

    def track(self, target: np.ndarray, q_prev: np.ndarray, *, max_step=0.2, sweep: bool = False,
              budget: float = 0.005, clock=time.perf_counter) -> IKResult:
        """The executor's per-tick IK, the redundancy resolved as a minimum-norm differential IK resolves it:
        q7 ∈ q_prev's q7 + [−h, h] (h = ``max_step`` of q7) minimising Σ_j (Δq_j / max_step_j)² over the
        nearest in-limit branch — the cost at −h, 0, +h, then at the vertex of the parabola through them
        (so q7 moves smoothly from tick to tick) — accepted if no joint moves more than ``max_step`` (rad, a
        number or one per joint) and it passes the FK check. Otherwise (``sweep``) the full sweep nearest
        q_prev, or (default) a non-converged result saying why."""
        if sweep:
            return self.solve(target, q_prev, budget=budget, clock=clock, quick=max_step)
        t0 = clock()
        q_prev = np.asarray(q_prev, dtype=float)
        step = np.broadcast_to(np.asarray(max_step, dtype=float), (7,))
        flange = self.flange_target(np.asarray(target, dtype=float))
        lo7, hi7 = self.lower[6], self.upper[6]
        h = float(step[6])
        q7s = [min(max(q_prev[6] + o, lo7), hi7) for o in (-h, 0.0, h)]
        tries = [self._nearest_branch(flange, q_prev, q7, step) for q7 in q7s]
        cm, c0, cp = (t[1] for t in tries)
        curv = cm - 2.0 * c0 + cp
        if math.isfinite(curv) and curv > 0.0:
            vertex = min(max(q_prev[6] + h * (cm - cp) / (2.0 * curv), q7s[0]), q7s[2])
            tries.append(self._nearest_branch(flange, q_prev, vertex, step))
        tries.sort(key=lambda t: t[1])
        q, dp, dr, why = q_prev.copy(), math.inf, math.inf, "no in-limit branch at these q7"
        for branch, _cost, ratio in tries:
            if branch is None:
                continue
            if ratio > 1.0:
                why = f"every in-limit branch near this q7 moves a joint {ratio:.2f}× max_step"
                break  # the cheapest branch already moves too fast; the others are worse in the norm
            ok, dp, dr = self._accept(branch, target, CHECK_POS, CHECK_ROT)
            if ok:
                q, why = branch, ""
                break
            why = f"the branch fails the FK check ({dp:.1e} m, {dr:.1e} rad)"
        return IKResult(q={"arm": q}, converged=not why, position_error=dp, orientation_error=dr,
                        iterations=len(tries), restarts=0, seconds=clock() - t0, solver=ANALYTIC, reason=why)
