"""World description shared by the planners and the simulator: robots, stacks, blocks, the shared table.

The e-PICO set-up (seed 004, Sec. 4.4): two arms, ``robot1`` and ``robot2``; in front of each a table with
three stacks of coloured blocks; between them a *shared table* (the "barrier") on which one robot leaves a
block for the other. A block's place is symbolic: ``stack(robot, s, level)`` (level 0 = on the table) or
``barrier(level)`` or ``held(robot)``. This module holds that symbolic state, the primitive actions' effect
on it (Listing 5: ``pick(black, red, 1, 2)`` = pick *black*, which lies on *red*, from stack 2, level 1)
and the geometry that maps a symbolic place to a position in metres.

Nothing here imports MuJoCo: the planners can build and check a world without the physics.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field, replace
from types import MappingProxyType

import numpy as np

from delkit.errors import DelkitError

__all__ = [
    "COLORS", "ArmsError", "PlanError", "Layout", "Location", "World", "SymbolicState",
    "rgba_of", "initial_state",
]

#: Named colours (RGBA) a world description may use.
COLORS: Mapping[str, tuple[float, float, float, float]] = MappingProxyType({
    "red": (0.85, 0.1, 0.1, 1.0), "green": (0.1, 0.7, 0.2, 1.0), "blue": (0.15, 0.3, 0.9, 1.0),
    "yellow": (0.95, 0.85, 0.1, 1.0), "black": (0.08, 0.08, 0.08, 1.0), "white": (0.95, 0.95, 0.95, 1.0),
    "orange": (1.0, 0.5, 0.0, 1.0), "purple": (0.5, 0.15, 0.7, 1.0), "cyan": (0.1, 0.8, 0.85, 1.0),
    "magenta": (0.9, 0.1, 0.7, 1.0), "grey": (0.5, 0.5, 0.5, 1.0), "brown": (0.5, 0.3, 0.1, 1.0),
    "pink": (1.0, 0.6, 0.7, 1.0),
})


class ArmsError(DelkitError):
    """Bad input to a block world: world description, primitive plan file, options (the arms layer raises it
    too, as ``arms.world.ArmsError``)."""


class PlanError(ArmsError):
    """A primitive action whose symbolic precondition does not hold (e.g. picking a block that is covered)."""


def rgba_of(color: str | list[float] | tuple[float, ...], *, where: str = "colour") -> tuple[float, ...]:
    """RGBA of a colour given by name or as 3 or 4 numbers in [0, 1]."""
    if isinstance(color, str):
        key = color.strip().lower()
        if key not in COLORS:
            raise ArmsError(f"{where}: unknown colour {color!r}; use one of {', '.join(sorted(COLORS))} "
                            "or an [r, g, b] list")
        return COLORS[key]
    if not isinstance(color, (list, tuple)) or not all(
            isinstance(c, (int, float)) and not isinstance(c, bool) for c in color):
        raise ArmsError(f"{where}: a colour is a name such as 'red' or a list [r, g, b] of numbers in [0, 1], "
                        f"got {color!r}")
    vals = tuple(float(c) for c in color)
    if len(vals) not in (3, 4) or not all(0.0 <= v <= 1.0 for v in vals):
        raise ArmsError(f"{where}: a colour list must have 3 or 4 numbers in [0, 1], got {list(color)}")
    return vals if len(vals) == 4 else (*vals, 1.0)


@dataclass(frozen=True)
class Layout:
    """Geometry of the cell, in metres, world frame: z up, table tops at ``table_z``.

    Robot *i* stands at ``(0, ±base_y)`` facing +x (the two bases mirror each other in the plane y = 0);
    its stack *s* (0-based, s = 0..n-1) is at ``(stack_x, base_y_i + (s - (n-1)/2)·stack_pitch)`` on its
    own table, and the shared table (barrier) is at ``(stack_x, 0)``, between the two robots' tables.
    """

    base_y: float = 0.36
    stack_x: float = 0.5
    stack_pitch: float = 0.1
    table_z: float = 0.0
    block_size: float = 0.04

    def base_pos(self, robot_index: int) -> np.ndarray:
        """Position of robot *i*'s base (robot1 at −y, robot2 at +y)."""
        return np.array([0.0, -self.base_y if robot_index == 0 else self.base_y, 0.0])

    def stack_xy(self, robot_index: int, stack: int, n_stacks: int = 3) -> np.ndarray:
        """x, y of a stack; the mirror image of robot1's stack s is robot2's stack s (y → −y)."""
        y1 = -self.base_y + (stack - (n_stacks - 1) / 2.0) * self.stack_pitch
        return np.array([self.stack_x, y1 if robot_index == 0 else -y1])

    def barrier_xy(self) -> np.ndarray:
        """x, y of the shared table's block slot."""
        return np.array([self.stack_x, 0.0])

    def block_z(self, level: int) -> float:
        """Height of the centre of a block at ``level`` (0 = resting on the table)."""
        return self.table_z + self.block_size * (level + 0.5)


@dataclass(frozen=True, order=True)
class Location:
    """Symbolic place of a block: ``kind`` is ``stack`` (robot, stack, level), ``barrier`` (level) or ``held``."""

    kind: str
    robot: str = ""
    stack: int = -1
    level: int = 0

    def describe(self) -> str:
        if self.kind == "stack":
            return f"{self.robot} stack {self.stack} level {self.level}"
        if self.kind == "barrier":
            return f"shared table level {self.level}"
        return f"held by {self.robot}"


@dataclass(frozen=True)
class World:
    """A world description: robots, their stacks (bottom → top), the shared table, block colours.

    This is the ``world`` object of the primitive-plan JSON (see ``arms/README.md``).
    """

    robots: tuple[str, ...]
    stacks: Mapping[str, tuple[tuple[str, ...], ...]]
    barrier: tuple[str, ...] = ()
    colors: Mapping[str, tuple[float, ...]] = field(default_factory=dict)
    layout: Layout = field(default_factory=Layout)

    @property
    def blocks(self) -> tuple[str, ...]:
        """All block names, in a fixed order (robot by robot, stack by stack, bottom to top, then barrier)."""
        out: list[str] = []
        for r in self.robots:
            for st in self.stacks[r]:
                out.extend(st)
        out.extend(self.barrier)
        return tuple(out)

    def robot_index(self, robot: str) -> int:
        if robot not in self.robots:
            raise ArmsError(f"unknown robot {robot!r}; the world has {', '.join(self.robots)}")
        return self.robots.index(robot)

    def position(self, loc: Location) -> np.ndarray:
        """Centre of a block at a symbolic place (not defined for ``held``)."""
        lay = self.layout
        if loc.kind == "stack":
            xy = lay.stack_xy(self.robot_index(loc.robot), loc.stack, len(self.stacks[loc.robot]))
        elif loc.kind == "barrier":
            xy = lay.barrier_xy()
        else:
            raise ArmsError(f"a held block has no table position ({loc.describe()})")
        return np.array([xy[0], xy[1], lay.block_z(loc.level)])

    def to_json(self) -> dict:
        """The ``world`` object of the plan format."""
        lay = self.layout
        return {
            "robots": list(self.robots),
            "stacks": {r: [list(s) for s in self.stacks[r]] for r in self.robots},
            "barrier": list(self.barrier),
            "colors": {b: list(self.colors[b]) for b in self.blocks},
            "layout": {"base_y": lay.base_y, "stack_x": lay.stack_x, "stack_pitch": lay.stack_pitch,
                       "table_z": lay.table_z, "block_size": lay.block_size},
        }

    @staticmethod
    def from_json(obj: Mapping, *, source: str = "<world>") -> World:
        """Read and validate a ``world`` object (names unique, two robots, colour per block)."""
        if not isinstance(obj, Mapping):
            raise ArmsError(f"{source}: 'world' must be an object")
        unknown = sorted(set(obj) - {"robots", "stacks", "barrier", "colors", "layout"})
        if unknown:
            raise ArmsError(f"{source}: unknown entry {unknown[0]!r}; a world has robots, stacks, barrier, colors, "
                            "layout")
        raw_robots = obj.get("robots", ["robot1", "robot2"])
        if not isinstance(raw_robots, list) or not all(isinstance(r, str) for r in raw_robots):
            raise ArmsError(f"{source}: 'robots' must be a list of two robot names, got {raw_robots!r}")
        robots = tuple(raw_robots)
        if len(robots) != 2 or len(set(robots)) != 2:
            raise ArmsError(f"{source}: 'robots' must name exactly two distinct robots, got {list(robots)}")
        raw_stacks = obj.get("stacks")
        if not isinstance(raw_stacks, Mapping) or set(raw_stacks) != set(robots):
            raise ArmsError(f"{source}: 'stacks' must map each of {list(robots)} to a list of stacks")
        for r in robots:
            if not isinstance(raw_stacks[r], list) or not all(
                    isinstance(st, list) and all(isinstance(b, str) for b in st) for st in raw_stacks[r]):
                raise ArmsError(f"{source}: stacks of {r} must be a list of stacks, each a list of block names "
                                f"from the table up, e.g. [[\"green\"], [\"red\", \"black\"], []]")
        stacks = {r: tuple(tuple(st) for st in raw_stacks[r]) for r in robots}
        for r in robots:
            if not 1 <= len(stacks[r]) <= 5:
                raise ArmsError(f"{source}: {r} must have 1 to 5 stacks, has {len(stacks[r])}")
        raw_barrier = obj.get("barrier", [])
        if not isinstance(raw_barrier, list) or not all(isinstance(b, str) for b in raw_barrier):
            raise ArmsError(f"{source}: 'barrier' must be a list of block names, got {raw_barrier!r}")
        barrier = tuple(raw_barrier)
        names = [b for r in robots for st in stacks[r] for b in st] + list(barrier)
        dup = sorted({b for b in names if names.count(b) > 1})
        if dup:
            raise ArmsError(f"{source}: block names must be unique; repeated: {', '.join(dup)}")
        raw_colors = obj.get("colors", {})
        if not isinstance(raw_colors, Mapping):
            raise ArmsError(f"{source}: 'colors' must map block names to colours, got {raw_colors!r}")
        colors: dict[str, tuple[float, ...]] = {}
        for b in names:
            c = raw_colors.get(b, b)
            colors[b] = rgba_of(c, where=f"{source}: colour of block {b!r}")
        extra = sorted(set(raw_colors) - set(names))
        if extra:
            raise ArmsError(f"{source}: 'colors' names blocks that are not placed: {', '.join(extra)}")
        lay_obj = obj.get("layout", {})
        try:
            if not isinstance(lay_obj, Mapping) or any(
                    isinstance(v, bool) or not isinstance(v, (int, float)) for v in lay_obj.values()):
                raise TypeError("an object of numbers (metres) is needed")
            layout = Layout(**{k: float(v) for k, v in lay_obj.items()})
            if not all(np.isfinite(getattr(layout, k)) for k in lay_obj):
                raise TypeError("every value must be a finite number")
            if not (0.005 <= layout.block_size <= 0.2 and layout.stack_pitch >= layout.block_size
                    and 0 < layout.base_y <= 2 and 0 < layout.stack_x <= 2 and abs(layout.table_z) <= 1):
                raise TypeError("need 0.005 <= block_size <= 0.2, stack_pitch >= block_size, 0 < base_y <= 2, "
                                "0 < stack_x <= 2, |table_z| <= 1")
        except TypeError as exc:
            raise ArmsError(f"{source}: bad 'layout' ({exc}); keys: base_y, stack_x, stack_pitch, "
                            "table_z, block_size") from None
        return World(robots=robots, stacks=MappingProxyType(stacks), barrier=barrier,
                     colors=MappingProxyType(colors), layout=layout)


@dataclass(frozen=True)
class SymbolicState:
    """Where every block is, symbolically: block name ↦ :class:`Location`."""

    places: Mapping[str, Location]

    def on_top(self, loc_kind: str, robot: str = "", stack: int = -1) -> list[tuple[int, str]]:
        """(level, block) of the blocks in one stack (or the barrier), bottom to top."""
        return sorted((p.level, b) for b, p in self.places.items()
                      if p.kind == loc_kind and p.robot == robot and p.stack == stack)

    def height(self, kind: str, robot: str = "", stack: int = -1) -> int:
        return len(self.on_top(kind, robot, stack))

    def held_by(self, robot: str) -> str | None:
        for b, p in self.places.items():
            if p.kind == "held" and p.robot == robot:
                return b
        return None

    def below(self, block: str) -> str:
        """Name of the block under ``block``, or ``table`` / ``barrier`` at level 0."""
        p = self.places[block]
        if p.level == 0:
            return "table" if p.kind == "stack" else "barrier"
        for b, q in self.places.items():
            if q.kind == p.kind and q.robot == p.robot and q.stack == p.stack and q.level == p.level - 1:
                return b
        raise PlanError(f"block {block!r} floats: nothing at level {p.level - 1} under it")

    def _with(self, block: str, loc: Location) -> SymbolicState:
        new = dict(self.places)
        new[block] = loc
        return SymbolicState(MappingProxyType(new))


def initial_state(world: World) -> SymbolicState:
    """The symbolic state a world description starts in."""
    places: dict[str, Location] = {}
    for r in world.robots:
        for s, st in enumerate(world.stacks[r]):
            for lvl, b in enumerate(st):
                places[b] = Location("stack", r, s, lvl)
    for lvl, b in enumerate(world.barrier):
        places[b] = Location("barrier", "", -1, lvl)
    return SymbolicState(MappingProxyType(places))


def pick_effect(world: World, state: SymbolicState, robot: str, block: str, *, on: str | None = None,
                level: int | None = None, stack: int | None = None, from_barrier: bool = False,
                ) -> SymbolicState:
    """Effect of ``pick(block, on, level, stack)`` / ``take_from_barrier(block)``; checks the precondition.

    Precondition: the robot's gripper is empty, the block is clear (nothing on it), and — when the action
    names them — it lies on ``on`` at ``level`` in ``stack`` of the robot's own table (or on the barrier).
    """
    world.robot_index(robot)
    if block not in state.places:
        raise PlanError(f"unknown block {block!r}")
    held = state.held_by(robot)
    if held is not None:
        raise PlanError(f"{robot} already holds {held!r}")
    p = state.places[block]
    if from_barrier:
        if p.kind != "barrier":
            raise PlanError(f"{block!r} is not on the shared table but at {p.describe()}")
    else:
        if p.kind != "stack" or p.robot != robot:
            raise PlanError(f"{block!r} is not on {robot}'s table but at {p.describe()}")
        if stack is not None and p.stack != stack:
            raise PlanError(f"{block!r} is in stack {p.stack}, not in stack {stack}")
    if level is not None and p.level != level:
        raise PlanError(f"{block!r} is at level {p.level}, not at level {level}")
    if on is not None:
        under = state.below(block)
        if on != under and not (on == "table" and under in ("table", "barrier")):
            raise PlanError(f"{block!r} lies on {under!r}, not on {on!r}")
    top = state.on_top(p.kind, p.robot, p.stack)
    if top[-1][1] != block:
        raise PlanError(f"{block!r} is covered by {top[-1][1]!r}")
    return state._with(block, Location("held", robot))


def place_effect(world: World, state: SymbolicState, robot: str, block: str, *, onto: str | None = None,
                 level: int | None = None, stack: int | None = None, on_barrier: bool = False,
                 ) -> SymbolicState:
    """Effect of ``place(block, onto, level, stack)`` / ``put_on_barrier(block)``; checks the precondition.

    Precondition: the robot holds the block; the target is the top of the named stack of the robot's own
    table (``onto`` its current top block, or ``table`` if empty) or the shared table.
    """
    if state.held_by(robot) != block:
        raise PlanError(f"{robot} does not hold {block!r}")
    if on_barrier:
        lvl = state.height("barrier")
        new_loc = Location("barrier", "", -1, lvl)
    else:
        n = len(world.stacks[robot])
        if stack is None or not 0 <= stack < n:
            raise PlanError(f"stack {stack} does not exist on {robot}'s table (0..{n - 1})")
        lvl = state.height("stack", robot, stack)
        new_loc = Location("stack", robot, stack, lvl)
    if level is not None and level != lvl:
        raise PlanError(f"the target level is {level} but the free level there is {lvl}")
    if onto is not None:
        top = state.on_top(new_loc.kind, new_loc.robot, new_loc.stack)
        under = top[-1][1] if top else "table"
        if onto != under and not (onto in ("table", "barrier") and under == "table"):
            raise PlanError(f"the top there is {under!r}, not {onto!r}")
    return state._with(block, new_loc)


def replace_layout(world: World, layout: Layout) -> World:
    """The same world on another geometry."""
    return replace(world, layout=layout)
