"""Line-of-sight colour sensing: rays from the palm camera, the colour of the first geom each ray hits.

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

__all__ = ["Sighting", "nearest_colour", "look"]

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
