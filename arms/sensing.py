"""Line-of-sight colour sensing, two cameras per robot.

**Side cameras (``look_side``, the sensor of e-PICO's ``sense_table``).** Each robot has a fixed camera in
front of its table (``<robot>/side_camera_low``, eye at 6 cm above the table top, 40 cm in front of the
stacks, looking back across them) and a second viewpoint higher up (``<robot>/side_camera_high``, 60 cm).
A look at a *column* (one stack, or the shared table) casts a vertical fan of rays (``mujoco.mj_ray``: 3
columns × every 1 cm from the table top to 6 block heights) at the column's front face. Each ray stops at
the first geom it meets (group 0: tables, blocks, floor, obstacles; the arms are in another group):

* a block geom inside the column's footprint — seen: its name (the body: identity, not colour) and the
  colour of the geom as rendered (RGBA → nearest named colour);
* any geom nearer to the camera than the column's face — the view of that part of the column is
  **occluded** (a block or an obstacle in front): the column view is incomplete;
* anything at or beyond the face (the table top behind, the floor) — free space.

A block anywhere in the column that is not occluded meets at least one ray (rays are 1 cm apart, blocks
4 cm high), so a complete view sees every block of the column, covered ones included: what the domain's
``sense_table`` reveals. Nothing here reads the plan or the symbolic state — only geometry and colours.

**Palm camera (``look``)** — the original sensor of ``delkit arms run``'s ``sense`` action:

A robot senses a *column* (one of its stacks, or the shared table) by holding its hand above it, the
gripper pointing down, and casting a small fan of rays (``mujoco.mj_ray``) from its camera site
(``<robot>/camera``, see :mod:`arms.scene`) towards points spread over the column's footprint at table
height. Each ray stops at the first geom it meets (tables, blocks, floor — the arms' own geoms are in
another geom group and are not seen). A ray that stops on a block reports

* the block (its body: the anchoring of a physical object to its name, as e-PICO's anchoring step
  does; the identity, not the colour),
* the *colour* of that geom as rendered (its RGBA, mapped to the nearest named colour), and
* the *level* at which it was seen, from the height of the hit point above the table top.

Rays from above meet the top face of the highest block of the column, so a block with another block on
it is never seen: nothing in this module reads the plan or the symbolic state — only geometry and
the rendered colours.
"""

from __future__ import annotations

from dataclasses import dataclass

import mujoco
import numpy as np

from arms.world import COLORS

__all__ = ["Sighting", "nearest_colour", "look", "ColumnView", "look_side", "SIDE_VIEWS"]

#: ray targets around the column centre, in metres (3 × 3 grid over the inner part of a block's top face)
_GRID = tuple((dx, dy) for dx in (-0.008, 0.0, 0.008) for dy in (-0.008, 0.0, 0.008))


def nearest_colour(rgba: np.ndarray) -> str:
    """The named colour (``arms.world.COLORS``) nearest to an RGBA in RGB distance."""
    return min(COLORS, key=lambda c: float(np.sum((np.array(COLORS[c][:3]) - np.asarray(rgba)[:3]) ** 2)))


@dataclass(frozen=True)
class Sighting:
    """What the sensor saw in one column: the top block, its colour and level, or nothing (``block=None``)."""

    column: str          # e.g. "robot1 stack 2" or "shared table"
    block: str | None
    colour: str | None
    level: int           # level of the seen block (0 = on the table); -1 if the column is empty
    rays: int            # how many of the rays hit that block
    height: float        # z of the highest hit point (m)

    def to_json(self) -> dict:
        return {"column": self.column, "block": self.block, "colour": self.colour, "level": self.level,
                "rays": self.rays}


def look(model: mujoco.MjModel, data: mujoco.MjData, camera_site: int, column_xy: np.ndarray, *,
         table_z: float, block_size: float, column: str = "") -> Sighting:
    """Cast the ray fan from the camera site at one column and report what is seen first.

    Only geoms of group 0 (tables, blocks, floor) are hit. The block seen is the one most rays hit
    first; its level is round((z_hit − table_z) / block_size) − 1 for the hit point on its top face.
    """
    origin = data.site_xpos[camera_site].copy()
    group = np.array([1, 0, 0, 0, 0, 0], dtype=np.uint8)
    geomid = np.zeros(1, dtype=np.int32)
    hits: dict[int, list[float]] = {}
    top_z = -np.inf
    for dx, dy in _GRID:
        aim = np.array([column_xy[0] + dx, column_xy[1] + dy, table_z])
        vec = aim - origin
        vec /= np.linalg.norm(vec)
        dist = mujoco.mj_ray(model, data, origin, vec, group, 1, -1, geomid)
        if dist < 0:
            continue
        z = float(origin[2] + dist * vec[2])
        top_z = max(top_z, z)
        hits.setdefault(int(geomid[0]), []).append(z)
    block_geoms = {g: zs for g, zs in hits.items() if model.geom(g).name.startswith("block/")}
    if not block_geoms:
        return Sighting(column, None, None, -1, 0, float(top_z))
    g = max(block_geoms, key=lambda k: (len(block_geoms[k]), max(block_geoms[k])))
    z = max(block_geoms[g])
    level = int(round((z - table_z) / block_size)) - 1
    name = model.geom(g).name.split("/", 1)[1]
    return Sighting(column, name, nearest_colour(model.geom_rgba[g]), max(level, 0), len(block_geoms[g]), z)


#: viewpoint name ↦ (metres in front of the stacks, metres above the table top) of the side cameras
SIDE_VIEWS = {"low": (0.40, 0.06), "high": (0.40, 0.60)}
_FAN_Y = (-0.01, 0.0, 0.01)


@dataclass(frozen=True)
class ColumnView:
    """What a side camera saw of one column: the blocks (name ↦ colour) and how many rays were occluded."""

    column: str
    view: str
    blocks: dict
    rays: int
    occluded: int

    @property
    def complete(self) -> bool:
        return self.occluded == 0

    def to_json(self) -> dict:
        return {"column": self.column, "view": self.view, "blocks": dict(self.blocks), "rays": self.rays,
                "occluded_rays": self.occluded}


def look_side(model: mujoco.MjModel, data: mujoco.MjData, camera_site: int, column_xy: np.ndarray, *,
              table_z: float, block_size: float, column: str = "", view: str = "low", levels: int = 6,
              see_through: bool = False) -> ColumnView:
    """Cast the side camera's ray fan at one column (see module docstring). ``see_through`` is the mutation
    the property test must catch: every block geom on a ray counts, as if the camera saw through blocks."""
    origin = data.site_xpos[camera_site].copy()
    group = np.array([1, 0, 0, 0, 0, 0], dtype=np.uint8)
    geomid = np.zeros(1, dtype=np.int32)
    half = 0.5 * block_size
    toward = np.sign(origin[0] - column_xy[0]) or 1.0
    face_x = column_xy[0] + toward * half
    seen: dict[str, str] = {}
    rays = occluded = 0
    for dy in _FAN_Y:
        for k in range(int(levels * block_size / 0.01)):
            aim = np.array([face_x, column_xy[1] + dy, table_z + 0.004 + 0.01 * k])
            vec = aim - origin
            reach = float(np.linalg.norm(vec))
            vec /= reach
            rays += 1
            start, exclude = origin.copy(), -1
            while True:
                dist = mujoco.mj_ray(model, data, start, vec, group, 1, exclude, geomid)
                if dist < 0:
                    break
                hit = start + dist * vec
                g = int(geomid[0])
                name = model.geom(g).name
                inside = (abs(hit[0] - column_xy[0]) <= half + 0.004 and abs(hit[1] - column_xy[1]) <= 1.5 * half
                          and hit[2] >= table_z - 1e-3)
                if name.startswith("block/") and inside:
                    seen[name.split("/", 1)[1]] = nearest_colour(model.geom_rgba[g])
                    if not see_through:
                        break
                elif float(np.linalg.norm(hit - origin)) < reach - 1e-3:
                    if not see_through or not name.startswith("block/"):
                        occluded += 1
                        break
                else:
                    break
                start, exclude = hit, int(model.geom_bodyid[g])  # see_through only: go on behind the block
                if float(np.linalg.norm(start - origin)) > reach + 2 * block_size:
                    break
    return ColumnView(column, view, seen, rays, occluded)
