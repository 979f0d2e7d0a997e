"""Run a primitive plan in MuJoCo physics and check the world against the symbolic state after each action.

Control: every ``control_dt`` (10 ms) the IK gives the joint set-points q*, which the position servos
of the scene track for ``control_dt / timestep`` physics steps. With ``ik="analytic"`` (the default) a
tick uses the closed-form Panda IK of :mod:`arms.ik_analytic` for each arm whose target changed, the
redundancy resolved as a minimum-norm differential IK resolves it: q7 within one velocity step of the
arm's current q7 minimising Σ (Δq_j / (v_max,j dt))² (``AnalyticArm.track``), the branch within the joint
limits, moving no joint faster than its velocity limit and passing the pinocchio FK check;
and only *while the two arms are provably apart*: a lower bound on their distance (bounding spheres of
every arm geom, from the simulation) above ``ANALYTIC_CLEARANCE``, farther than the QP's
collision-detection distance, so that its avoidance constraint would be inactive anyway. Otherwise
(arms near each other, or no such branch) the tick is one mink QP step (both arms, TCP frame tasks,
posture, configuration and velocity limits, arm–arm collision avoidance), and the rest of that move
(and the waits after it) stays on the QP: the QP's set-points lag the path, and switching back to the
exact closed form would catch the lag up at the joints' velocity limits — a jolt that let a friction-held
block slip 10.6 mm on γ/3. ``ik="mink"`` uses the QP on every tick (the reference the analytic ticks are compared with);
``Executor.ik_ticks`` counts the ticks of each.

A Cartesian move follows a minimum-jerk profile s(τ) = 10τ³ − 15τ⁴ + 6τ⁵ from the commanded pose to the
target: the position on the straight line, the rotation on the SO(3) geodesic (``_pose_path``; the SE(3)
geodesic gives the same path whenever the rotation does not change, as in every move of the skills after
the first). The idle arm holds its TCP pose (its frame task stays on, weighted 10× the
moving arm's, so that when the arms meet the moving one gives way).

Verification: after action *i* the symbolic state s_i (``arms.plan.symbolic_trace``) says where every
block must be; the executor measures every block's centre in the simulation and fails the run at the
first block farther than ``tolerance`` (default 1 cm) from its symbolic place, naming the action, the
block and the distance. A held block must be within ``tolerance`` of its grasp pose on the TCP.

Grasps hold the block by finger friction (default); ``grasp="weld"`` adds a weld constraint at grasp
time and is for debugging only. A block that slips or drops fails the per-action check.

Sensing (``sense``) is observation: the robot moves its palm camera above each column to be sensed and
:func:`arms.sensing.look` casts rays; only the top block of a column is seen (see :mod:`arms.sensing`).
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field

import mink
import mujoco
import numpy as np

from arms.ik import VELOCITY_LIMITS, DualArmIK, pose, pose_error
from arms.plan import Action, Plan, apply_action
from arms.scene import FINGER_OPEN, Scene, build_scene
from arms.sensing import ColumnView, Sighting, look, look_side
from arms.skills import pick, place
from arms.world import ArmsError, PlanError, SymbolicState, World, initial_state

__all__ = ["ActionOutcome", "RunResult", "Executor", "MotionError", "run_plan", "IK_MODES", "ANALYTIC_CLEARANCE"]

#: per-tick IK: the analytic IK while the arms are apart (mink QP otherwise), or the mink QP always
IK_MODES = ("analytic", "mink")
#: the per-tick IK of an Executor built without ``ik=`` (benchmarks switch it to compare)
DEFAULT_IK = "analytic"
#: lower bound on the arm–arm distance (m) above which a tick may use the analytic IK: the QP's collision
#: detection distance (0.12 m) plus 5 cm for the tick's motion and the servo's lag
ANALYTIC_CLEARANCE = 0.17
#: lower bound on the arm–arm distance (m) above which a tick's physics steps skip the contact count
CONTACT_SKIP = 0.05


class MotionError(ArmsError):
    """A move that the arm could not complete (IK residual or tracking error too large)."""


@dataclass(frozen=True)
class ActionOutcome:
    """What happened to one action: success, the worst block error after it, and a message."""

    index: int
    action: str
    robot: str
    text: str
    success: bool
    message: str
    max_block_error: float
    worst_block: str | None
    sim_time: float
    observed: Mapping[str, str] = field(default_factory=dict)

    def to_json(self) -> dict:
        return {"index": self.index, "action": self.action, "robot": self.robot, "text": self.text,
                "success": self.success,
                "message": self.message,   # NaN (not measured: the action failed) is null in JSON
                "max_block_error_m": None if math.isnan(self.max_block_error) else self.max_block_error,
                "worst_block": self.worst_block, "sim_time_s": self.sim_time, "observed": dict(self.observed)}


@dataclass(frozen=True)
class RunResult:
    """The whole run: success, per-action outcomes, final block poses, timing, rendered files."""

    success: bool
    actions: tuple[ActionOutcome, ...]
    final_poses: Mapping[str, Mapping[str, list[float]]]
    sim_seconds: float
    wall_seconds: float
    arm_contacts: int
    grasp: str
    max_slip: float = 0.0
    fk_disagreement: float = 0.0
    failure: str | None = None
    files: Mapping[str, str] = field(default_factory=dict)

    @property
    def realtime_factor(self) -> float:
        """Simulated seconds per wall-clock second."""
        return self.sim_seconds / self.wall_seconds if self.wall_seconds > 0 else float("inf")

    def to_json(self) -> dict:
        return {"success": self.success, "failure": self.failure, "grasp": self.grasp,
                "actions": [a.to_json() for a in self.actions], "final_poses": {
                    b: dict(p) for b, p in self.final_poses.items()},
                "sim_seconds": self.sim_seconds, "wall_seconds": self.wall_seconds,
                "realtime_factor": self.realtime_factor if math.isfinite(self.realtime_factor) else None,
                "arm_contacts": self.arm_contacts,
                "max_slip_m": self.max_slip, "max_fk_disagreement_m": self.fk_disagreement,
                "files": dict(self.files)}


def _min_jerk(tau: float) -> float:
    return tau * tau * tau * (10.0 - 15.0 * tau + 6.0 * tau * tau)


def _pose_path(start: np.ndarray, goal: np.ndarray) -> Callable[[float], np.ndarray]:
    """s ∈ [0, 1] ↦ 4×4 pose: position p₀ + s(p₁ − p₀), rotation R₀ Exp(s Log(R₀ᵀR₁)) (pinocchio's
    log3/exp3, a few µs where mink's SE3.interpolate took ~0.1 ms)."""
    import pinocchio as pin

    p0, dp = start[:3, 3].copy(), goal[:3, 3] - start[:3, 3]
    r0 = start[:3, :3].copy()
    w = pin.log3(r0.T @ goal[:3, :3])

    def at(s: float) -> np.ndarray:
        t = np.eye(4)
        t[:3, :3] = r0 @ pin.exp3(s * w)
        t[:3, 3] = p0 + s * dp
        return t

    return at


class Executor:
    """Physics, control and verification for one world (see module docstring)."""

    def __init__(self, world: World, *, grasp: str = "friction", tolerance: float = 0.01,
                 control_dt: float = 0.01, record_fps: float = 0.0, ik: str | None = None,
                 occluders: tuple[tuple[float, float, float], ...] = ()) -> None:
        ik = DEFAULT_IK if ik is None else ik
        if ik not in IK_MODES:
            raise ArmsError(f"ik must be one of {', '.join(IK_MODES)}, not {ik!r}")
        self.world = world
        self.scene: Scene = build_scene(world, grasp=grasp, occluders=occluders)
        self.model = self.scene.model
        self.data = mujoco.MjData(self.model)
        mujoco.mj_resetDataKeyframe(self.model, self.data, self.model.key("home").id)
        mujoco.mj_forward(self.model, self.data)
        self.grasp = grasp
        self.tolerance = tolerance
        self.control_dt = control_dt
        self.n_sub = max(1, round(control_dt / self.model.opt.timestep))
        self.ik = DualArmIK(world.robots, world.layout)
        self.ik_mode = ik
        self.ik_ticks = {"analytic": 0, "mink": 0}
        self.analytic = {}
        if ik == "analytic":
            from arms.ik_analytic import AnalyticArm

            self.analytic = {r: AnalyticArm(arm=self.ik.pin[r]) for r in world.robots}
        self._max_step = VELOCITY_LIMITS * control_dt  # joint motion allowed in one tick (rad)
        self._solved: dict[str, tuple[np.ndarray, np.ndarray]] = {}  # robot -> (target, q) of its last tick
        self._qp_latched = False  # a QP tick happened in the current move
        self.q_ik = self.ik.full_q()
        self.tcp_cmd = {r: self.ik.tcp_pose(self.q_ik, r) for r in world.robots}
        self.held: dict[str, str] = {}
        self._grasp_offset: dict[str, np.ndarray] = {}
        self.slips: list[float] = []  # block displacement in the hand between grasp and release (m)
        self.record_fps = record_fps
        self.frames: list[np.ndarray] = []
        self._next_frame = 0.0
        self.arm_contacts = 0
        self.fk_disagreement = 0.0
        g1, g2 = (set(self.scene.arm_geoms(r)) for r in world.robots)
        self._arm_pairs = (g1, g2)
        self._arm_of_geom = np.zeros(self.model.ngeom, dtype=np.int64)
        self._arm_of_geom[list(g1)] = 1
        self._arm_of_geom[list(g2)] = 2
        self._arm_adr = {r: self.scene.arm_qpos_adr(r) for r in world.robots}
        self._arm_act = {r: self.scene.arm_actuators(r) for r in world.robots}
        self._tcp_id = {r: self.model.body(self.scene.tcp_body(r)).id for r in world.robots}
        self._sphere_geoms = [np.array(sorted(g), dtype=np.int64) for g in (g1, g2)]
        rb = self.model.geom_rbound
        self._rbound_sum = rb[self._sphere_geoms[0]][:, None] + rb[self._sphere_geoms[1]][None, :]
        self.sightings: list[Sighting] = []  # what the last sense action saw
        self._record()

    # -- low level -----------------------------------------------------------------------------------
    def _record(self) -> None:
        if self.record_fps > 0 and self.data.time >= self._next_frame - 1e-9:
            self.frames.append(self.data.qpos.copy())
            self._next_frame += 1.0 / self.record_fps

    def _physics(self, n: int, clearance: float | None = None) -> None:
        """n physics steps; arm–arm contacts are counted after every step, except when ``clearance`` (a
        lower bound on the arm–arm distance at the start, m) exceeds ``CONTACT_SKIP``: no geom moves that
        far in n steps of 2 ms (that would take > 5 m/s), so no arm–arm contact can occur."""
        m, d, lut = self.model, self.data, self._arm_of_geom
        count = clearance is None or clearance < CONTACT_SKIP
        for _ in range(n):
            mujoco.mj_step(m, d)
            if count and d.ncon:  # a contact between a geom of arm 1 (lut 1) and one of arm 2 (lut 2): product 2
                self.arm_contacts += int(np.count_nonzero(lut[d.contact.geom1] * lut[d.contact.geom2] == 2))
            if self.record_fps > 0:
                self._record()

    def arm_clearance_bound(self) -> float:
        """A lower bound on the distance between the two arms in the simulation (m): the smallest gap
        between the bounding spheres (``geom_rbound``) of a geom of arm 1 and one of arm 2."""
        g1, g2 = self._sphere_geoms
        if not len(g1) or not len(g2):
            return float("inf")
        x = self.data.geom_xpos
        diff = x[g1][:, None, :] - x[g2][None, :, :]
        return float((np.sqrt(np.einsum("ijk,ijk->ij", diff, diff)) - self._rbound_sum).min())

    def _analytic_tick(self, targets: Mapping[str, np.ndarray], clearance: float) -> np.ndarray | None:
        """Set-points from the closed-form IK, or None if this tick needs the QP (see module docstring)."""
        if clearance < ANALYTIC_CLEARANCE:
            return None
        q = self.q_ik.copy()
        for r, t in targets.items():
            adr = self.ik.qadr[r]
            prev = q[adr]
            last = self._solved.get(r)
            if last is not None and np.array_equal(last[0], t) and np.array_equal(last[1], prev):
                continue  # same target, already there (an arm holding still)
            res = self.analytic[r].track(t, prev, max_step=self._max_step)
            if not res.converged:
                return None
            q[adr] = res.q["arm"]
            self._solved[r] = (np.array(t, dtype=float), q[adr].copy())
        return q

    def _tick(self, targets: Mapping[str, np.ndarray], *, posture: bool = True) -> None:
        clearance = self.arm_clearance_bound()
        q = self._analytic_tick(targets, clearance) if self.analytic and not self._qp_latched else None
        if q is None:
            try:
                q = self.ik.step(self.q_ik, targets, self.control_dt, posture=posture)
            except mink.NoSolutionFound:
                raise MotionError(f"the IK QP has no solution at t = {self.data.time:.2f} s (limits or the "
                                  "arm–arm distance constraint cannot be met)") from None
            self.ik_ticks["mink"] += 1
            self._qp_latched = True  # the rest of this move stays on the QP (see module docstring)
        else:
            self.ik_ticks["analytic"] += 1
        self.q_ik = q
        for r in self.world.robots:
            self.data.ctrl[self._arm_act[r]] = self.q_ik[self.ik.qadr[r]]
        self._physics(self.n_sub, clearance)

    def _hold_targets(self) -> dict[str, np.ndarray]:
        return dict(self.tcp_cmd)

    # -- the Motion protocol used by arms.skills -------------------------------------------------------
    def tcp(self, robot: str) -> np.ndarray:
        """Commanded TCP pose (4×4)."""
        return self.tcp_cmd[robot]

    def tcp_actual(self, robot: str) -> np.ndarray:
        t = np.eye(4)
        t[:3, :3] = self.data.xmat[self._tcp_id[robot]].reshape(3, 3)
        t[:3, 3] = self.data.xpos[self._tcp_id[robot]]
        return t

    def block_position(self, block: str) -> np.ndarray:
        return self.data.xpos[self.scene.block_body(block)].copy()

    def move(self, robot: str, target: np.ndarray, *, speed: float = 0.3) -> float:
        """Cartesian min-jerk move of one TCP; returns the final IK position error (m)."""
        self._qp_latched = False
        path = _pose_path(self.tcp_cmd[robot], np.asarray(target, dtype=float))
        dp, dr = pose_error(self.tcp_cmd[robot], target)
        duration = max(0.2, dp / speed, dr / 1.5)
        n = max(1, math.ceil(duration / self.control_dt))
        targets = self._hold_targets()
        self._priority(robot)
        for k in range(1, n + 1):
            targets[robot] = path(_min_jerk(k / n))
            self._tick(targets)
        targets[robot] = np.asarray(target, dtype=float)
        self.tcp_cmd[robot] = targets[robot]
        err = np.inf
        for _ in range(100):  # settle (posture off, so the fixed point is the exact target): at most 1 s
            err, _rot = pose_error(self.ik.tcp_pose(self.q_ik, robot), targets[robot])
            track = np.max(np.abs(self.data.qpos[self._arm_adr[robot]] - self.data.ctrl[self._arm_act[robot]]))
            if err < 3e-4 and track < 3e-3:
                break
            self._tick(targets, posture=False)
        # every IK solution is cross-checked against pinocchio's FK of the same URDF
        self.fk_disagreement = max(self.fk_disagreement, self.ik.fk_disagreement(self.q_ik))
        if self.fk_disagreement > 1e-9:
            raise MotionError(f"MuJoCo and pinocchio FK disagree by {self.fk_disagreement:.2e} m")
        if err > 5e-3:
            raise MotionError(f"{robot} cannot reach {np.round(targets[robot][:3, 3], 3).tolist()} "
                              f"(IK residual {err * 1000:.1f} mm)")
        return float(err)

    def _priority(self, moving: str | None) -> None:
        """Weight the idle arm's TCP task 10× the moving arm's: when the collision constraint forces a
        compromise, the arm that was told to move gives way, not the one holding still."""
        for r, task in self.ik.frame_tasks.items():
            w = 1.0 if (moving is None or r == moving) else 10.0
            task.set_position_cost(w)
            task.set_orientation_cost(w)

    def wait(self, seconds: float) -> None:
        targets = self._hold_targets()
        for _ in range(max(1, round(seconds / self.control_dt))):
            self._tick(targets)

    def gripper(self, robot: str, opening: float) -> None:
        """Command the finger opening (m per finger, 0 … 0.04) and wait until the fingers stop."""
        self.data.ctrl[self.scene.gripper_actuator(robot)] = float(np.clip(opening, 0.0, FINGER_OPEN))
        adr = self.scene.finger_qpos_adr(robot)
        prev = self.data.qpos[adr].copy()
        for _ in range(60):
            self.wait(self.control_dt)
            now = self.data.qpos[adr].copy()
            if np.max(np.abs(now - prev)) < 2e-5 and self.data.time > 0:
                break
            prev = now
        self.wait(0.05)

    def attach(self, robot: str, block: str) -> None:
        """Grasp: the block must lie between the fingers; with ``weld`` the weld is switched on here."""
        tcp = self.tcp_actual(robot)
        off = self.block_position(block) - tcp[:3, 3]
        if np.linalg.norm(off) > 0.015:
            raise MotionError(f"{robot} missed {block!r}: the block centre is {np.linalg.norm(off) * 1000:.1f} mm"
                              " from the TCP at closing")
        if self.grasp == "weld":
            eq = self.scene.weld_id(robot, block)
            b1, b2 = self._tcp_id[robot], self.scene.block_body(block)
            r1 = self.data.xmat[b1].reshape(3, 3)
            relpos = r1.T @ (self.data.xpos[b2] - self.data.xpos[b1])
            q1inv = np.zeros(4)
            mujoco.mju_negQuat(q1inv, self.data.xquat[b1])
            relquat = np.zeros(4)
            mujoco.mju_mulQuat(relquat, q1inv, self.data.xquat[b2])
            self.model.eq_data[eq, 0:3] = 0.0
            self.model.eq_data[eq, 3:6] = relpos
            self.model.eq_data[eq, 6:10] = relquat
            self.model.eq_data[eq, 10] = 1.0
            self.data.eq_active[eq] = 1
        self.held[robot] = block
        self._grasp_offset[robot] = self._local_offset(robot, block)
        self.wait(0.05)

    def _local_offset(self, robot: str, block: str) -> np.ndarray:
        tcp = self.tcp_actual(robot)
        return tcp[:3, :3].T @ (self.block_position(block) - tcp[:3, 3])

    def detach(self, robot: str) -> None:
        """Release: record how far the block slipped in the hand since the grasp, switch the weld off."""
        block = self.held.get(robot)
        if block is not None:
            slip = np.linalg.norm(self._local_offset(robot, block) - self._grasp_offset.pop(robot))
            self.slips.append(float(slip))
        block = self.held.pop(robot, None)
        if block is not None and self.grasp == "weld":
            self.data.eq_active[self.scene.weld_id(robot, block)] = 0

    def held_offset(self, robot: str) -> np.ndarray:
        """Block centre minus TCP position of the held block (world frame)."""
        return self.block_position(self.held[robot]) - self.tcp_actual(robot)[:3, 3]

    # -- verification --------------------------------------------------------------------------------
    def block_errors(self, state: SymbolicState) -> dict[str, float]:
        """Distance (m) of every block's centre from where the symbolic state puts it."""
        out: dict[str, float] = {}
        for b, loc in state.places.items():
            actual = self.block_position(b)
            if loc.kind == "held":
                expected = self.tcp_actual(loc.robot)[:3, 3]
                out[b] = max(0.0, float(np.linalg.norm(actual - expected)) - 0.5 * self.tolerance)
            else:
                out[b] = float(np.linalg.norm(actual - self.world.position(loc)))
        return out

    def final_poses(self) -> dict[str, dict[str, list[float]]]:
        return {b: {"pos": self.block_position(b).round(5).tolist(),
                    "quat": self.data.xquat[self.scene.block_body(b)].round(5).tolist()}
                for b in self.world.blocks}

    # -- actions -------------------------------------------------------------------------------------
    def _travel_z(self, state: SymbolicState) -> float:
        lay = self.world.layout
        tops = [loc.level for loc in state.places.values() if loc.kind != "held"]
        return lay.table_z + lay.block_size * (max(tops, default=0) + 2) + 0.08

    def sense_columns(self, robot: str, columns: list[tuple[str, np.ndarray]], travel: float) -> list[Sighting]:
        """Move the palm camera above each (name, xy) column in turn and look (line of sight)."""
        lay = self.world.layout
        z_view = max(travel, lay.table_z + 0.25)
        out = []
        for name, xy in columns:
            cur = self.tcp_cmd[robot][:3, 3]
            if cur[2] < z_view - 1e-3:
                self.move(robot, pose([cur[0], cur[1], z_view]))
            self.move(robot, pose([xy[0], xy[1], z_view]))
            self.wait(0.1)
            out.append(look(self.model, self.data, self.scene.camera_site(robot), xy, table_z=lay.table_z,
                            block_size=lay.block_size, column=name))
        return out

    def sense_side(self, robot: str, view: str = "low", *, see_through: bool = False) -> list[ColumnView]:
        """The robot's side camera (``view`` low or high) looks at each of its stacks and at the shared
        table (:func:`arms.sensing.look_side`); the arms hold still for 0.1 s (the exposure)."""
        lay = self.world.layout
        self.wait(0.1)
        site = self.scene.side_camera_site(robot, view)
        return [look_side(self.model, self.data, site, xy, table_z=lay.table_z, block_size=lay.block_size,
                          column=name, view=view, see_through=see_through)
                for name, xy in self.columns(robot, barrier=True)]

    def columns(self, robot: str, stacks: list[int] | None = None, *, barrier: bool = False,
                ) -> list[tuple[str, np.ndarray]]:
        """(name, xy) of the robot's stacks (all, or the given ones) and optionally the shared table."""
        lay, i = self.world.layout, self.world.robot_index(robot)
        n = len(self.world.stacks[robot])
        cols = [(f"{robot} stack {s}", lay.stack_xy(i, s, n)) for s in (range(n) if stacks is None else stacks)]
        return ([("shared table", lay.barrier_xy())] if barrier else []) + cols

    def _sense(self, action: Action, state: SymbolicState, travel: float) -> dict[str, str]:
        """Look at the named stack, or at the stack where the named block should be, or at all the robot's
        stacks; returns {block: colour} of the blocks actually seen (``self.sightings`` has the details)."""
        a, r = action.args, action.robot
        if "stack" in a:
            stacks = [int(a["stack"])]
        elif "block" in a:
            if a["block"] not in state.places:
                raise PlanError(f"sense: unknown block {a['block']!r}")
            loc = state.places[a["block"]]
            if loc.kind == "barrier":
                self.sightings = self.sense_columns(r, self.columns(r, [], barrier=True), travel)
                return {x.block: x.colour for x in self.sightings if x.block}
            stacks = [loc.stack] if loc.kind == "stack" and loc.robot == r else []
            if not stacks:
                raise PlanError(f"sense: {a['block']!r} is not on {r}'s table ({loc.describe()})")
        else:
            stacks = None
        self.sightings = self.sense_columns(r, self.columns(r, stacks), travel)
        return {x.block: x.colour for x in self.sightings if x.block}

    def drop(self, robot: str, lower_to: float) -> None:
        """Fault injection: lower the held block to ``lower_to`` (z of its centre) and let it go."""
        cur = self.tcp_cmd[robot][:3, 3]
        self.move(robot, pose([cur[0], cur[1], lower_to]), speed=0.12)
        self.held.pop(robot, None)
        self._grasp_offset.pop(robot, None)
        if self.grasp == "weld":
            for b in self.world.blocks:
                self.data.eq_active[self.scene.weld_id(robot, b)] = 0
        self.gripper(robot, 0.04)
        self.move(robot, pose([cur[0], cur[1], cur[2]]), speed=0.15)

    def execute(self, action: Action, state: SymbolicState) -> dict[str, str]:
        """Drive the arms through one action (no checking); returns the sensed colours for ``sense`` and
        the announcement's fields for ``announce``."""
        r, a = action.robot, action.args
        travel = self._travel_z(state)
        if action.name in ("pick", "take_from_barrier"):
            pick(self, r, a["block"], travel)
        elif action.name in ("place", "put_on_barrier"):
            nxt = apply_action(self.world, state, action)
            target = self.world.position(nxt.places[a["block"]])
            offset = self.held_offset(r)
            place(self, r, target - offset, travel)
            if action.name == "put_on_barrier":  # clear the shared table for the other arm
                lay = self.world.layout
                base_y = lay.base_pos(self.world.robot_index(r))[1]
                self.move(r, pose([lay.stack_x - 0.12, base_y, travel]))  # above its own table
            self.wait(0.2)
        elif action.name == "sense":
            return self._sense(action, state, travel)
        elif action.name == "announce":  # purely epistemic: nothing moves; the content is reported
            return {k: (", ".join(map(str, v)) if isinstance(v, list) else str(v)) for k, v in a.items()}
        return {}

    def run(self, plan: Plan, *, progress: Callable[[int, Action], None] | None = None) -> RunResult:
        """Execute every action, verify after each, stop at the first failure."""
        if plan.world is not self.world and plan.world != self.world:
            raise ArmsError("the plan's world is not the executor's world")
        t0 = time.perf_counter()
        state = initial_state(self.world)
        outcomes: list[ActionOutcome] = []
        failure = None
        errs = self.block_errors(state)
        if errs and max(errs.values()) > self.tolerance:
            b = max(errs, key=errs.get)
            failure = f"initial state: block {b!r} is {errs[b] * 100:.2f} cm off"
        for i, act in enumerate(plan.actions if failure is None else ()):
            if progress is not None:
                progress(i, act)
            observed: dict[str, str] = {}
            try:
                nxt = apply_action(self.world, state, act)
                observed = self.execute(act, state)
            except (PlanError, MotionError) as exc:
                kind = "precondition" if isinstance(exc, PlanError) else "motion"
                msg = f"action {i} ({act}) failed ({kind}): {exc}"
                outcomes.append(ActionOutcome(i, act.name, act.robot, str(act), False, msg, float("nan"), None,
                                              float(self.data.time), observed))
                failure = msg
                break
            errs = self.block_errors(nxt)
            worst = max(errs, key=errs.get) if errs else None
            worst_err = errs[worst] if worst else 0.0
            ok = worst_err <= self.tolerance
            if ok:
                msg = f"ok ({act})"
            else:
                want = nxt.places[worst]
                msg = (f"action {i} ({act}): block {worst!r} is {worst_err * 100:.2f} cm from its symbolic "
                       f"place ({want.describe()}); tolerance {self.tolerance * 100:.1f} cm")
            outcomes.append(ActionOutcome(i, act.name, act.robot, str(act), ok, msg, worst_err, worst,
                                          float(self.data.time), observed))
            state = nxt
            if not ok:
                failure = msg
                break
        return RunResult(success=failure is None and len(outcomes) == len(plan.actions),
                         actions=tuple(outcomes), final_poses=self.final_poses(),
                         sim_seconds=float(self.data.time), wall_seconds=time.perf_counter() - t0,
                         arm_contacts=self.arm_contacts, grasp=self.grasp,
                         max_slip=max(self.slips, default=0.0), fk_disagreement=self.fk_disagreement,
                         failure=failure)


def run_plan(plan: Plan, *, grasp: str = "friction", tolerance: float = 0.01, record_fps: float = 0.0,
             progress: Callable[[int, Action], None] | None = None) -> tuple[RunResult, Executor]:
    """Build the scene for the plan's world and run it; returns the result and the executor."""
    ex = Executor(plan.world, grasp=grasp, tolerance=tolerance, record_fps=record_fps)
    return ex.run(plan, progress=progress), ex
