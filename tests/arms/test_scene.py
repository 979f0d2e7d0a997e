"""The MjSpec scene: arms from the example-robot-data URDF, actuators, gripper, contact filtering."""

from __future__ import annotations

import itertools

import mujoco
import numpy as np
import pytest

from arms.demo import demo_plan
from arms.scene import ARM_JOINTS, build_scene, panda_urdf_path, save_mjcf


@pytest.fixture(scope="module")
def scene():
    return build_scene(demo_plan().world)


def test_urdf_comes_from_the_installed_package():
    path = panda_urdf_path()
    assert path.is_file() and "example-robot-data" in str(path)


def test_scene_has_two_prefixed_arms_blocks_and_actuators(scene):
    m = scene.model
    world = demo_plan().world
    for r in ("robot1", "robot2"):
        for j in ARM_JOINTS:
            assert m.joint(f"{r}/{j}").id >= 0
        # fixed frames survive (fusestatic="false")
        assert m.body(f"{r}/panda_hand_tcp").id >= 0 and m.body(f"{r}/panda_hand").id >= 0
        assert len(scene.arm_actuators(r)) == 7 and scene.gripper_actuator(r) >= 0
        assert all(m.body_gravcomp[m.body(f"{r}/panda_link{i}").id] == 1.0 for i in range(1, 8))
    assert m.nu == 16
    for b in world.blocks:
        body = scene.block_body(b)
        assert m.body_jntnum[body] == 1 and m.jnt_type[m.body_jntadr[body]] == mujoco.mjtJoint.mjJNT_FREE
        assert np.allclose(m.geom_size[m.body_geomadr[body]], 0.02)
    # one weld per (robot, block), all off at start
    assert sum(m.eq_type == mujoco.mjtEq.mjEQ_WELD) == 2 * len(world.blocks)
    assert not m.eq_active0[m.eq_type == mujoco.mjtEq.mjEQ_WELD].any()


def test_arm_never_collides_with_itself_but_with_the_other_arm(scene):
    m = scene.model
    g1, g2 = scene.arm_geoms("robot1"), scene.arm_geoms("robot2")
    assert len(g1) >= 10 and len(g2) == len(g1)

    def can_touch(a, b):
        return bool((m.geom_contype[a] & m.geom_conaffinity[b]) | (m.geom_contype[b] & m.geom_conaffinity[a]))

    for arm in (g1, g2):
        assert not any(can_touch(a, b) for a, b in itertools.combinations(arm, 2))
    assert all(can_touch(a, b) for a in g1 for b in g2)
    block = m.body_geomadr[scene.block_body("red")]
    assert all(can_touch(a, block) for a in g1 + g2)


def test_gripper_closes_evenly_and_arms_hold_home(scene):
    m = scene.model
    d = mujoco.MjData(m)
    mujoco.mj_resetDataKeyframe(m, d, m.key("home").id)
    d.ctrl[scene.gripper_actuator("robot1")] = 0.01
    for _ in range(500):
        mujoco.mj_step(m, d)
    f = d.qpos[scene.finger_qpos_adr("robot1")]
    assert abs(f[0] - f[1]) < 1e-3 and abs(f.mean() - 0.01) < 2e-3
    # gravity compensation + position servos: the arms stay at the set-point
    for r in ("robot1", "robot2"):
        assert np.max(np.abs(d.qpos[scene.arm_qpos_adr(r)] - d.ctrl[scene.arm_actuators(r)])) < 1e-3
    # blocks rest on their tables
    for b in demo_plan().world.blocks:
        assert abs(d.xpos[scene.block_body(b)][2] % 0.04 - 0.02) < 1e-3


def test_save_mjcf_round_trip(scene, tmp_path):
    path = save_mjcf(scene, tmp_path / "scene.xml")
    m2 = mujoco.MjModel.from_xml_path(str(path))
    assert (m2.nq, m2.nu, m2.neq, m2.ngeom) == (scene.model.nq, scene.model.nu, scene.model.neq,
                                                 scene.model.ngeom)


def test_scene_follows_the_world_description():
    from arms.world import World, initial_state

    world = World.from_json({
        "robots": ["left", "right"],
        "stacks": {"left": [["a", "b", "c"], ["d"]], "right": [[], ["e"]]},
        "barrier": ["f"],
        "colors": {"a": "red", "b": [0.2, 0.4, 0.6], "c": "yellow", "d": "green", "e": "blue", "f": "white"},
        "layout": {"block_size": 0.05},
    })
    sc = build_scene(world)
    m = sc.model
    d = mujoco.MjData(m)
    mujoco.mj_resetDataKeyframe(m, d, m.key("home").id)
    mujoco.mj_forward(m, d)
    state = initial_state(world)
    for b in world.blocks:
        body = sc.block_body(b)
        assert np.allclose(d.xpos[body], world.position(state.places[b]))
        assert np.allclose(m.geom_rgba[m.body_geomadr[body]], world.colors[b])
        assert np.allclose(m.geom_size[m.body_geomadr[body]], 0.025)
    assert np.allclose(m.geom_rgba[m.body_geomadr[sc.block_body("b")]][:3], [0.2, 0.4, 0.6])
    assert m.body("left/panda_hand_tcp").id >= 0 and m.body("right/panda_hand_tcp").id >= 0
