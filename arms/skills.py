"""Pick-and-place skills as sequences of Cartesian moves and gripper commands.

A skill never teleports anything: it only sets TCP targets (tracked by the mink QP and the joint
position servos) and gripper commands; the block moves because the fingers (and, with ``grasp="weld"``,
a weld constraint switched on when the fingers have closed) carry it.

``pick``:  open → above (block + h_approach) → down to the block centre → close (+ weld) → lift.
``place``: (travel height) → above target → down to target + clearance → release (weld off, open) → up.
The TCP always points down (z_tcp = −z_world) with the fingers opening along world x, so they close on
two faces of an axis-aligned block and the wide hand stays clear of the neighbouring stacks.
"""

from __future__ import annotations

from typing import Protocol

import numpy as np

from arms.ik import DOWN, pose

__all__ = ["Motion", "pick", "place", "APPROACH", "PLACE_CLEARANCE"]

APPROACH = 0.10       # m above the grasp / place point where the vertical approach starts
PLACE_CLEARANCE = 0.004  # m: a placed block is released this far above its resting height


class Motion(Protocol):
    """What a skill needs from the executor."""

    def tcp(self, robot: str) -> np.ndarray: ...
    def move(self, robot: str, target: np.ndarray, *, speed: float = ...) -> float: ...
    def gripper(self, robot: str, opening: float) -> None: ...
    def attach(self, robot: str, block: str) -> None: ...
    def detach(self, robot: str) -> None: ...
    def block_position(self, block: str) -> np.ndarray: ...


def _via_travel_height(m: Motion, robot: str, xyz: np.ndarray, travel_z: float) -> None:
    """Lift to ``travel_z``, go across at that height, stop above ``xyz``."""
    cur = m.tcp(robot)[:3, 3]
    z = max(travel_z, xyz[2] + APPROACH)
    if cur[2] < z - 1e-3:
        m.move(robot, pose([cur[0], cur[1], z]))
    m.move(robot, pose([xyz[0], xyz[1], z]))
    if z > xyz[2] + APPROACH + 1e-3:
        m.move(robot, pose([xyz[0], xyz[1], xyz[2] + APPROACH]))


def pick(m: Motion, robot: str, block: str, travel_z: float) -> None:
    """Approach, grasp and lift ``block`` (its position is measured in the simulation: perception)."""
    p = m.block_position(block)
    m.gripper(robot, 0.04)
    _via_travel_height(m, robot, p, travel_z)
    m.move(robot, pose(p, DOWN), speed=0.12)
    m.gripper(robot, 0.0)
    m.attach(robot, block)
    m.move(robot, pose([p[0], p[1], max(travel_z, p[2] + APPROACH)]), speed=0.15)


def place(m: Motion, robot: str, target: np.ndarray, travel_z: float) -> None:
    """Carry the held block to ``target`` (block centre), release it and retreat upwards."""
    t = np.asarray(target, dtype=float)
    _via_travel_height(m, robot, t, travel_z)
    m.move(robot, pose([t[0], t[1], t[2] + PLACE_CLEARANCE], DOWN), speed=0.12)
    m.detach(robot)
    m.gripper(robot, 0.04)
    m.move(robot, pose([t[0], t[1], t[2] + APPROACH]), speed=0.15)
