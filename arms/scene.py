"""The MuJoCo scene: two Franka Pandas, their tables, the shared table and the blocks (``mujoco.MjSpec``).

The arm is the Panda URDF that the ``example-robot-data`` package ships (located with
``importlib.metadata``, no network), read by MuJoCo's URDF importer with ``fusestatic="false"`` so the
fixed frames (``panda_hand``, ``panda_hand_tcp``) survive as bodies, and with the STL collision meshes
(the DAE visual meshes are discarded). What the URDF lacks is added here:

* position actuators on the seven arm joints, τ = k_p (q* − q) − k_v q̇, with gravity compensation on
  every arm body (so the steady-state error of the servo is ~0);
* a gripper that closes evenly: a fixed tendon L = ½(q_f1 + q_f2) driven by one position actuator,
  plus the URDF's mimic constraint q_f1 = q_f2 (which MuJoCo turns into a soft joint equality);
* MuJoCo's sleeping islands (``mjENBL_SLEEP``): bodies at rest are skipped until touched;
* contact filtering (contype/conaffinity bits) so that an arm never collides with itself, but does with
  the other arm, the tables and the blocks;
* one inactive weld equality per (robot, block), switched on by the executor at grasp time (only with
  ``grasp="weld"``, a debugging option; the default grasp holds the block by finger friction alone);
* a camera site ``<robot>/camera`` in the palm, on the gripper axis 6 cm behind the fingertip centre,
  looking along the TCP's z axis (down when the hand points down): the line-of-sight colour sensor of
  :mod:`arms.sensing` casts its rays from there. The arms' geoms are in geom group ``ARM_GROUP`` so the
  sensor's rays pass through the robot's own fingers (a palm camera sees between them).

Two arms are attached with the prefixes ``robot1/`` and ``robot2/`` at mirrored base poses (see
:class:`arms.world.Layout`).
"""

from __future__ import annotations

import functools
import importlib.metadata
from dataclasses import dataclass
from pathlib import Path

import mujoco
import numpy as np

from arms.world import ArmsError, World

__all__ = [
    "ARM_JOINTS", "ARM_GROUP", "CAMERA_OFFSET", "HOME_Q", "TCP_BODY", "Scene", "panda_description_dir",
    "panda_urdf_path", "panda_spec", "build_scene", "save_mjcf",
]

ARM_JOINTS = tuple(f"panda_joint{i}" for i in range(1, 8))
FINGER_JOINTS = ("panda_finger_joint1", "panda_finger_joint2")
TCP_BODY = "panda_hand_tcp"
HAND_BODY = "panda_hand"
#: The Panda's usual "ready" posture.
HOME_Q = np.array([0.0, -0.785398, 0.0, -2.356194, 0.0, 1.570796, 0.785398])
KP = np.array([4500.0, 4500.0, 3500.0, 3500.0, 2000.0, 2000.0, 2000.0])
KV = np.array([450.0, 450.0, 350.0, 350.0, 200.0, 200.0, 200.0])
GRIPPER_KP = 300.0
FINGER_OPEN = 0.04
#: geom group of the arms' geoms (the colour sensor's rays only see group 0: tables, blocks, floor)
ARM_GROUP = 1
#: camera site position in the TCP frame (m): on the gripper axis, behind the fingertips
CAMERA_OFFSET = (0.0, 0.0, -0.06)

# contact bits: 1 = world (tables, blocks, floor); 2 = robot1; 4 = robot2.
_WORLD_BITS = (1, 1 | 2 | 4)
_ARM_BITS = ((2, 1 | 4), (4, 1 | 2))


@functools.cache
def panda_description_dir() -> Path:
    """The ``panda_description`` folder of the installed ``example-robot-data`` distribution (looked up
    once per process: listing the distribution's files costs ~10 ms, and every scene build asks)."""
    try:
        dist = importlib.metadata.distribution("example-robot-data")
    except importlib.metadata.PackageNotFoundError:
        raise ArmsError("the Python package 'example-robot-data' is not installed; "
                        "install it with `pip install example-robot-data`") from None
    for f in dist.files or ():
        if str(f).endswith("panda_description/urdf/panda.urdf"):
            return Path(dist.locate_file(f)).resolve().parent.parent
    raise ArmsError("example-robot-data is installed but has no panda_description/urdf/panda.urdf")


def panda_urdf_path() -> Path:
    """Path of the Panda URDF (shared by MuJoCo and pinocchio)."""
    return panda_description_dir() / "urdf" / "panda.urdf"


@functools.cache
def _urdf_text() -> str:
    return panda_urdf_path().read_text()


def panda_spec() -> mujoco.MjSpec:
    """One Panda as an ``MjSpec``, read from the URDF with the collision meshes and fixed links kept."""
    root = panda_description_dir()
    text = _urdf_text()
    head = text.index(">", text.index("<robot")) + 1
    compiler = (f'<mujoco><compiler meshdir="{root / "meshes" / "collision"}" fusestatic="false" '
                'discardvisual="true" strippath="true" balanceinertia="true"/></mujoco>')
    return mujoco.MjSpec.from_string(text[:head] + compiler + text[head:])


@dataclass(frozen=True)
class Scene:
    """A compiled scene and the names that the IK, skills and executor look up."""

    spec: mujoco.MjSpec
    model: mujoco.MjModel
    world: World | None
    robots: tuple[str, ...]
    grasp: str

    def prefix(self, robot: str) -> str:
        return f"{robot}/"

    def arm_joint_names(self, robot: str) -> list[str]:
        return [self.prefix(robot) + j for j in ARM_JOINTS]

    def arm_qpos_adr(self, robot: str) -> np.ndarray:
        """qpos addresses of the robot's seven arm joints."""
        return np.array([self.model.joint(n).qposadr[0] for n in self.arm_joint_names(robot)])

    def arm_dof_adr(self, robot: str) -> np.ndarray:
        return np.array([self.model.joint(n).dofadr[0] for n in self.arm_joint_names(robot)])

    def finger_qpos_adr(self, robot: str) -> np.ndarray:
        return np.array([self.model.joint(self.prefix(robot) + j).qposadr[0] for j in FINGER_JOINTS])

    def arm_actuators(self, robot: str) -> np.ndarray:
        return np.array([self.model.actuator(f"{robot}/act{i}").id for i in range(1, 8)])

    def gripper_actuator(self, robot: str) -> int:
        return int(self.model.actuator(f"{robot}/gripper").id)

    def tcp_body(self, robot: str) -> str:
        return self.prefix(robot) + TCP_BODY

    def arm_geoms(self, robot: str) -> list[int]:
        """Geom ids of one arm (links, hand, fingers)."""
        m = self.model
        return [g for g in range(m.ngeom)
                if m.body(m.geom_bodyid[g]).name.startswith(self.prefix(robot))]

    def block_body(self, block: str) -> int:
        return int(self.model.body(f"block/{block}").id)

    def camera_site(self, robot: str) -> int:
        return int(self.model.site(f"{robot}/camera").id)

    def side_camera_site(self, robot: str, view: str = "low") -> int:
        return int(self.model.site(f"{robot}/side_camera_{view}").id)

    def weld_id(self, robot: str, block: str) -> int:
        return int(self.model.equality(f"{robot}/grasp/{block}").id)


def _look_at(eye, target) -> list[float]:
    """Camera ``xyaxes`` for a camera at ``eye`` looking at ``target`` (MuJoCo cameras look along −z)."""
    f = np.asarray(target, dtype=float) - np.asarray(eye, dtype=float)
    f /= np.linalg.norm(f)
    x = np.cross(f, [0.0, 0.0, 1.0])
    if np.linalg.norm(x) < 1e-6:
        x = np.array([0.0, -1.0, 0.0])
    x /= np.linalg.norm(x)
    y = np.cross(x, f)
    return [*x.tolist(), *y.tolist()]


def _add_arm(spec: mujoco.MjSpec, robot: str, index: int, base: np.ndarray, *, with_pedestal: bool,
             z_floor: float) -> None:
    arm = panda_spec()
    frame = spec.worldbody.add_frame(pos=base.tolist())
    spec.attach(arm, prefix=f"{robot}/", frame=frame)
    contype, conaff = _ARM_BITS[index]
    for body in spec.bodies:
        if not body.name.startswith(f"{robot}/"):
            continue
        body.gravcomp = 1.0
        if body.name == f"{robot}/{TCP_BODY}":
            body.add_site(name=f"{robot}/camera", pos=list(CAMERA_OFFSET), size=[0.005, 0.005, 0.005],
                          rgba=[0.1, 0.1, 0.1, 0.0])
        for g in body.geoms:
            g.contype, g.conaffinity = contype, conaff
            g.group = ARM_GROUP
            g.rgba = [0.92, 0.92, 0.94, 1.0] if "finger" not in body.name else [0.25, 0.25, 0.28, 1.0]
            if "finger" in body.name:
                g.friction = [1.5, 0.01, 0.001]
                g.condim = 4
    for j, (kp, kv) in enumerate(zip(KP, KV, strict=True), start=1):
        joint = spec.joint(f"{robot}/panda_joint{j}")
        joint.armature = 0.1
        joint.damping[0] = 1.0
        act = spec.add_actuator(name=f"{robot}/act{j}", target=f"{robot}/panda_joint{j}",
                                trntype=mujoco.mjtTrn.mjTRN_JOINT)
        act.set_to_position(kp=float(kp), kv=float(kv))
        act.ctrlrange = list(joint.range)
        act.ctrllimited = mujoco.mjtLimited.mjLIMITED_TRUE
        act.forcerange = [-87.0, 87.0] if j <= 4 else [-12.0, 12.0]
        act.forcelimited = mujoco.mjtLimited.mjLIMITED_TRUE
    tendon = spec.add_tendon(name=f"{robot}/split")
    for fj in FINGER_JOINTS:
        tendon.wrap_joint(f"{robot}/{fj}", 0.5)
    grip = spec.add_actuator(name=f"{robot}/gripper", target=f"{robot}/split",
                             trntype=mujoco.mjtTrn.mjTRN_TENDON)
    grip.set_to_position(kp=GRIPPER_KP, kv=10.0)
    grip.ctrlrange = [0.0, FINGER_OPEN]
    grip.ctrllimited = mujoco.mjtLimited.mjLIMITED_TRUE
    grip.forcerange = [-70.0, 70.0]
    grip.forcelimited = mujoco.mjtLimited.mjLIMITED_TRUE
    if with_pedestal:
        h = (base[2] - z_floor) / 2.0
        spec.worldbody.add_geom(name=f"{robot}/pedestal", type=mujoco.mjtGeom.mjGEOM_BOX,
                                pos=[base[0] - 0.05, base[1], z_floor + h], size=[0.15, 0.15, h],
                                rgba=[0.3, 0.3, 0.33, 1.0], contype=0, conaffinity=0)


def _add_cell(spec: mujoco.MjSpec, world: World | None, z_floor: float) -> None:
    """Floor, the robots' tables and the shared table (boxes whose tops are at ``table_z``)."""
    lay = world.layout if world is not None else None
    spec.worldbody.add_geom(name="floor", type=mujoco.mjtGeom.mjGEOM_PLANE, pos=[0, 0, z_floor],
                            size=[3, 3, 0.1], material="floor_mat", contype=1, conaffinity=7)
    if lay is None:
        return
    tz = lay.table_z
    h = (tz - z_floor) / 2.0
    n1 = len(world.stacks[world.robots[0]])
    span = (n1 - 1) * lay.stack_pitch / 2.0 + 0.07
    for i, robot in enumerate(world.robots):
        cy = float(np.mean([lay.stack_xy(i, s, n1)[1] for s in range(n1)]))
        spec.worldbody.add_geom(name=f"{robot}/table", type=mujoco.mjtGeom.mjGEOM_BOX,
                                pos=[lay.stack_x, cy, tz - h], size=[0.14, span, h],
                                rgba=[0.62, 0.47, 0.32, 1.0], contype=_WORLD_BITS[0],
                                conaffinity=_WORLD_BITS[1])
    bxy = lay.barrier_xy()
    spec.worldbody.add_geom(name="shared_table", type=mujoco.mjtGeom.mjGEOM_BOX,
                            pos=[bxy[0], bxy[1], tz - h - 0.001], size=[0.14, 0.08, h],
                            rgba=[0.35, 0.55, 0.75, 1.0], contype=_WORLD_BITS[0],
                            conaffinity=_WORLD_BITS[1])


def _add_blocks(spec: mujoco.MjSpec, world: World, robots: tuple[str, ...]) -> None:
    from arms.world import initial_state

    state = initial_state(world)
    half = world.layout.block_size / 2.0
    for b in world.blocks:
        pos = world.position(state.places[b])
        body = spec.worldbody.add_body(name=f"block/{b}", pos=pos.tolist())
        body.add_freejoint(name=f"block/{b}")
        body.add_geom(name=f"block/{b}", type=mujoco.mjtGeom.mjGEOM_BOX, size=[half] * 3,
                      rgba=list(world.colors[b]), mass=0.05, friction=[1.0, 0.01, 0.001], condim=4,
                      contype=_WORLD_BITS[0], conaffinity=_WORLD_BITS[1])
        for r in robots:
            eq = spec.add_equality(name=f"{r}/grasp/{b}", type=mujoco.mjtEq.mjEQ_WELD,
                                   objtype=mujoco.mjtObj.mjOBJ_BODY, name1=f"{r}/{TCP_BODY}",
                                   name2=f"block/{b}")
            eq.active = False
            eq.solref = [0.004, 1.0]


def _add_side_cameras(spec: mujoco.MjSpec, world: World) -> None:
    """The fixed side cameras of :func:`arms.sensing.look_side`: per robot and viewpoint a site in front of
    the robot's table, on the line of its middle stack."""
    from arms.sensing import SIDE_VIEWS

    lay = world.layout
    for i, robot in enumerate(world.robots):
        n = len(world.stacks[robot])
        cy = float(np.mean([lay.stack_xy(i, s, n)[1] for s in range(n)]))
        for view, (dx, dz) in SIDE_VIEWS.items():
            spec.worldbody.add_site(name=f"{robot}/side_camera_{view}", pos=[lay.stack_x + dx, cy, lay.table_z + dz],
                                    size=[0.006, 0.006, 0.006], rgba=[0.1, 0.1, 0.1, 1.0], group=2)


def build_scene(world: World | None = None, *, robots: tuple[str, ...] | None = None,
                grasp: str = "friction", cell: bool = True, timestep: float = 0.002,
                occluders: tuple[tuple[float, float, float], ...] = ()) -> Scene:
    """Build and compile the scene for a world description (``world=None``: the two arms alone).

    ``cell=False`` leaves out floor, tables and pedestals (the kinematic model the IK uses); ``robots``
    may name a subset of the world's robots (each keeps its base pose). ``occluders``: (x, y, height) of
    grey blocks (``block/occluder<k>``, 3 cm deep, 7 cm wide) standing on the table in front of a
    stack (geom group 0, so the cameras see them; no contacts: they are there for the cameras only) — the
    occlusion fault of ``arms.mission``.
    """
    if grasp not in ("weld", "friction"):
        raise ArmsError(f"grasp must be 'weld' or 'friction', not {grasp!r}")
    if robots is None:
        robots = world.robots if world is not None else ("robot1", "robot2")
    layout = world.layout if world is not None else None
    if layout is None:
        from arms.world import Layout
        layout = Layout()
    spec = mujoco.MjSpec()
    spec.modelname = "delkit_two_pandas"
    spec.meshdir = str(panda_description_dir() / "meshes" / "collision")  # so that saved MJCF finds the STLs
    spec.option.timestep = timestep
    spec.option.integrator = mujoco.mjtIntegrator.mjINT_IMPLICITFAST
    spec.option.cone = mujoco.mjtCone.mjCONE_ELLIPTIC
    spec.option.impratio = 10.0
    # islands at rest (the blocks standing in their stacks while an arm works elsewhere) sleep: MuJoCo skips
    # them until an awake body touches them. Halves the cost of a physics step on the 8-block layout
    # (same outcomes, block positions equal to < 0.01 mm on the α/4 mission)
    spec.option.enableflags |= int(mujoco.mjtEnableBit.mjENBL_SLEEP)
    spec.visual.global_.offwidth = 1280
    spec.visual.global_.offheight = 960
    spec.visual.headlight.ambient = [0.35, 0.35, 0.35]
    spec.visual.headlight.diffuse = [0.45, 0.45, 0.45]
    tex = spec.add_texture(name="floor_tex", type=mujoco.mjtTexture.mjTEXTURE_2D,
                           builtin=mujoco.mjtBuiltin.mjBUILTIN_CHECKER, width=256, height=256,
                           rgb1=[0.82, 0.82, 0.84], rgb2=[0.7, 0.7, 0.73])
    mat = spec.add_material(name="floor_mat", texrepeat=[6, 6], reflectance=0.05)
    mat.textures[mujoco.mjtTextureRole.mjTEXROLE_RGB] = tex.name
    z_floor = layout.table_z - 0.75
    all_robots = world.robots if world is not None else ("robot1", "robot2")
    for r in robots:
        i = all_robots.index(r)
        _add_arm(spec, r, i, layout.base_pos(i), with_pedestal=cell, z_floor=z_floor)
    if cell:
        _add_cell(spec, world, z_floor)
        spec.worldbody.add_light(name="key", pos=[0.6, -0.8, 2.0], dir=[-0.2, 0.4, -1.0],
                                 diffuse=[0.7, 0.7, 0.7], castshadow=True)
        spec.worldbody.add_light(name="fill", pos=[-0.6, 0.6, 2.0], dir=[0.3, -0.2, -1.0],
                                 diffuse=[0.35, 0.35, 0.35], castshadow=False)
        for name, eye, look in (("overview", (1.75, -0.95, 1.15), (0.25, 0.0, 0.18)),
                                ("front", (1.6, 0.0, 0.7), (0.35, 0.0, 0.12)),
                                ("top", (0.45, 0.0, 1.9), (0.45, 0.0, 0.0))):
            spec.worldbody.add_camera(name=name, pos=list(eye), xyaxes=_look_at(eye, look))
    if world is not None and cell:
        _add_blocks(spec, world, robots)
        _add_side_cameras(spec, world)
        for k, (x, y, hgt) in enumerate(occluders):
            spec.worldbody.add_geom(name=f"block/occluder{k}", type=mujoco.mjtGeom.mjGEOM_BOX,
                                    pos=[x, y, layout.table_z + hgt / 2.0],
                                    size=[0.015, 0.035, hgt / 2.0],
                                    rgba=[0.5, 0.5, 0.5, 1.0], contype=0, conaffinity=0)
    model = spec.compile()
    # home keyframe: arms at HOME_Q with open hands, blocks at their initial places.
    data = mujoco.MjData(model)
    scene = Scene(spec=spec, model=model, world=world, robots=tuple(robots), grasp=grasp)
    for r in robots:
        data.qpos[scene.arm_qpos_adr(r)] = HOME_Q
        data.qpos[scene.finger_qpos_adr(r)] = FINGER_OPEN
        data.ctrl[scene.arm_actuators(r)] = HOME_Q
        data.ctrl[scene.gripper_actuator(r)] = FINGER_OPEN
    spec.add_key(name="home", qpos=data.qpos.tolist(), ctrl=data.ctrl.tolist())
    model = spec.compile()
    return Scene(spec=spec, model=model, world=world, robots=tuple(robots), grasp=grasp)


def save_mjcf(scene: Scene, path: str | Path) -> Path:
    """Write the scene as MJCF (mesh files referenced by absolute path into example-robot-data)."""
    from arms.world import ArmsError

    path = Path(path)
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(scene.spec.to_xml())
    except OSError as exc:  # a directory, no permission, ...
        raise ArmsError(f"{path}: cannot write the MJCF file: {exc.strerror}; give a writable file path") from None
    return path
