"""IK benchmark: random q within the limits → FK → IK of that pose, in two protocols.

Success for one target = position error < 1e-5 m and orientation error < 1e-4 rad within the time
budget (5 ms per target by default), both re-measured with pinocchio FK.

``trac-ik`` (default; TRAC-IK's own protocol): every query starts from the middle of the joint ranges
(TRAC-IK's seed), random restarts are allowed inside the budget, the time of every query (successful or
not) is inside the timed region, and mean and median are both reported. Only this protocol is
comparable with TRAC-IK's published figures (which are means).

``seed-table`` (a variant, not comparable with TRAC-IK): both solvers start from the configurations of
a precomputed seed library nearest to the target (``arms.ik.SeedLibrary``, 16,384 solved
configurations drawn from the same distribution as the targets, built once outside the timed region).
TRAC-IK's published figures for the Franka Panda (results table of the TRAC-IK README, traclabs/trac_ik,
as quoted in TRAC-IK's paper): TRAC-IK 99.70 % at 0.38 ms mean, KDL 61.77 % at 2.14 ms.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from arms.ik import POS_TOL, ROT_TOL, DualArmIK, pose_error, random_reachable_poses

__all__ = ["SolverStats", "benchmark_ik", "TRAC_IK_PANDA", "PROTOCOLS"]

#: the benchmark protocols: TRAC-IK's (midpoint seed) and the seed-table variant
PROTOCOLS = ("trac-ik", "seed-table")

#: (solver, success rate %, mean solve time ms) for the Panda from the TRAC-IK README.
TRAC_IK_PANDA = (("TRAC-IK", 99.70, 0.38), ("KDL", 61.77, 2.14))


@dataclass(frozen=True)
class SolverStats:
    """Success rate and solve times (seconds) of one solver over the targets."""

    solver: str
    n: int
    successes: int
    median_s: float
    p95_s: float
    mean_s: float
    max_fk_disagreement: float
    us_per_iteration: float = float("nan")
    #: (target index, why) of every target not solved within the budget
    failures: tuple[tuple[int, str], ...] = ()

    @property
    def rate(self) -> float:
        return self.successes / self.n if self.n else 0.0

    def to_json(self) -> dict:
        return {"solver": self.solver, "targets": self.n, "successes": self.successes,
                "success_rate": self.rate, "median_ms": self.median_s * 1e3, "p95_ms": self.p95_s * 1e3,
                "mean_ms": self.mean_s * 1e3, "max_fk_disagreement_m": self.max_fk_disagreement,
                "us_per_iteration": self.us_per_iteration,
                "failures": [{"target": i, "reason": r} for i, r in self.failures]}


def benchmark_ik(n: int, *, seed: int = 0, budget: float = 0.005, clock: str = "wall",
                 protocol: str = "trac-ik",
                 progress: Callable[[int, str], None] | None = None) -> list[SolverStats]:
    """Run the analytic IK, mink and the pinocchio CLIK on the same n random reachable TCP poses of robot1.

    ``protocol`` is ``trac-ik`` (midpoint seed, random restarts; see the module docstring) or
    ``seed-table`` (nearest configurations of the precomputed seed library first). The analytic solver
    (:class:`arms.ik_analytic.AnalyticArm`) needs no start: it is seeded at the midpoint in both protocols
    (the seed only decides which of the solutions it returns).

    A solve counts as a success only if it reports convergence and the residuals, re-measured here with
    pinocchio FK, are within 1e-5 m / 1e-4 rad, within ``budget`` seconds of wall time.
    ``clock`` is ``wall`` (``time.perf_counter``, as TRAC-IK measures) or ``cpu`` (``time.thread_time``:
    the CPU time of this thread, which does not count time the OS gave to other processes — use it on a
    loaded machine). ``progress(k, solver)`` is called after each of the 3n solves.
    """
    if clock not in ("wall", "cpu"):
        raise ValueError("clock must be 'wall' or 'cpu'")
    if protocol not in PROTOCOLS:
        raise ValueError(f"protocol must be one of {', '.join(PROTOCOLS)}")
    tick = time.perf_counter if clock == "wall" else time.thread_time
    from arms.ik_analytic import ANALYTIC, AnalyticArm

    ik = DualArmIK(("robot1",), velocity_limit=False, collision=False)
    arm = ik.pin["robot1"]
    analytic = AnalyticArm(arm=arm)
    mid_q = (arm.lower + arm.upper) / 2.0
    solve_analytic = {ANALYTIC: lambda t, s: analytic.solve(t, mid_q, budget=budget, seed=s, clock=tick)}
    _, poses = random_reachable_poses(n, seed=seed)
    if protocol == "seed-table":
        arm.library()  # one-off precomputation (the seed library), like a solver's set-up: not timed
        solvers = {
            **solve_analytic,
            "mink (QP, daqp)": lambda t, s: ik.solve({"robot1": t}, budget=budget, seed=s, check_fk=False,
                                                          clock=tick),
            "pinocchio CLIK (DLS)": lambda t, s: arm.clik(t, budget=budget, seed=s, clock=tick),
        }
    else:
        mid = {"robot1": (arm.lower + arm.upper) / 2.0}  # TRAC-IK's seed: the middle of the joint ranges
        solvers = {
            **solve_analytic,
            "mink (QP, daqp)": lambda t, s: ik.solve({"robot1": t}, mid, budget=budget, seed=s, check_fk=False,
                                                          clock=tick),
            "pinocchio CLIK (DLS)": lambda t, s: arm.clik(t, budget=budget, seed=s, clock=tick, library=False),
        }
    out = []
    done = 0
    for name, solve in solvers.items():
        times, ok, disagreement, iters, failures = [], 0, 0.0, 0, []
        for i, target in enumerate(poses):
            t0 = tick()
            res = solve(target, seed + i)
            dt = tick() - t0
            q = res.q["robot1"] if "robot1" in res.q else res.q["arm"]
            fk = arm.fk(q)
            dp, dr = pose_error(fk, target)
            if res.solver == "mink":
                disagreement = max(disagreement, ik.fk_disagreement(ik.full_q({"robot1": q})))
            solved = bool(res.converged and dp < POS_TOL and dr < ROT_TOL and dt <= budget)
            ok += solved
            if not solved:
                failures.append((i, res.reason or (f"{dt * 1e3:.2f} ms > budget" if res.converged
                                                   else "not converged within the budget")))
            if not ((q >= arm.lower) & (q <= arm.upper)).all():
                raise AssertionError(f"{name} returned a configuration outside the joint limits (target {i})")
            times.append(dt)
            iters += res.iterations + res.restarts
            done += 1
            if progress is not None:
                progress(done, name)
        ts = np.array(times)
        out.append(SolverStats(name, n, ok, float(np.median(ts)), float(np.percentile(ts, 95)),
                               float(ts.mean()), disagreement, 1e6 * float(ts.sum()) / max(iters, 1),
                               tuple(failures)))
    return out
