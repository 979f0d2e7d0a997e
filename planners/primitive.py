"""The primitive-plan JSON format (what the e-PICO pipeline emits and ``delkit arms run`` executes).

::

    {"format": "delkit.arms.plan/1",
     "world": {"robots": ["robot1", "robot2"],
               "stacks": {"robot1": [["green"], ["red", "black"], []], "robot2": [["blue"], [], []]},
               "barrier": [],
               "colors": {"green": "green", "red": "red", "black": "black", "blue": [0.1, 0.2, 0.9]}},
     "actions": [
        {"robot": "robot1", "action": "sense", "stack": 1},
        {"robot": "robot1", "action": "pick", "args": ["black", "red", 1, 1]},
        {"robot": "robot1", "action": "place", "block": "black", "onto": "green", "level": 1, "stack": 0},
        {"robot": "robot1", "action": "pick", "args": ["red", "table", 0, 1]},
        {"robot": "robot1", "action": "put_on_barrier", "args": ["red"]},
        {"robot": "robot1", "action": "announce", "args": ["red"], "to": ["robot2"]},
        {"robot": "robot2", "action": "take_from_barrier", "args": ["red"]},
        {"robot": "robot2", "action": "place", "args": ["red", "table", 0, 1]}]}

The positional ``args`` follow seed 004, Listing 5: ``pick(block, on, level, stack)``,
``place(block, onto, level, stack)``, ``put_on_barrier(block)``, ``take_from_barrier(block)``; keyword
fields (``block``, ``on``/``onto``, ``level``, ``stack``) may be given instead. Optional: ``task`` (any
action; the epistemic task it belongs to, as the e-PICO hierarchy writes it) and ``color`` (``announce``:
the colour announced). Any other field is an error. ``announce`` and
``sense`` are purely epistemic: they change no block. Stacks and levels are 0-based.
"""

from __future__ import annotations

import json
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from types import MappingProxyType
from typing import Any

from planners.blocks import (
    ArmsError,
    PlanError,
    SymbolicState,
    World,
    initial_state,
    pick_effect,
    place_effect,
)

__all__ = ["Action", "Plan", "ACTIONS", "load_plan", "parse_plan", "apply_action", "symbolic_trace"]

FORMAT = "delkit.arms.plan/1"
#: action name ↦ names of its positional arguments
ACTIONS: Mapping[str, tuple[str, ...]] = MappingProxyType({
    "pick": ("block", "on", "level", "stack"),
    "place": ("block", "onto", "level", "stack"),
    "put_on_barrier": ("block",),
    "take_from_barrier": ("block",),
    "announce": ("block",),
    "sense": ("block",),
})
ONTIC = frozenset({"pick", "place", "put_on_barrier", "take_from_barrier"})


@dataclass(frozen=True)
class Action:
    """One primitive action of a robot, with its arguments by name."""

    robot: str
    name: str
    args: Mapping[str, Any] = field(default_factory=dict)

    def __str__(self) -> str:
        pos = [str(self.args[a]) for a in ACTIONS[self.name] if a in self.args]
        return f"{self.robot}: {self.name}({', '.join(pos)})"

    def to_json(self) -> dict:
        return {"robot": self.robot, "action": self.name, **dict(self.args)}


@dataclass(frozen=True)
class Plan:
    """A world description and the primitive actions to run in it."""

    world: World
    actions: tuple[Action, ...]

    def to_json(self) -> dict:
        return {"format": FORMAT, "world": self.world.to_json(), "actions": [a.to_json() for a in self.actions]}


def _action(obj: Any, i: int, world: World, source: str) -> Action:
    where = f"{source}: action {i}"
    if not isinstance(obj, Mapping):
        raise ArmsError(f"{where}: must be an object with 'robot' and 'action'")
    name = obj.get("action")
    if not isinstance(name, str) or name not in ACTIONS:
        raise ArmsError(f"{where}: unknown action {name!r}; known: {', '.join(ACTIONS)}")
    robot = obj.get("robot")
    if not isinstance(robot, str) or robot not in world.robots:
        raise ArmsError(f"{where}: 'robot' must be one of {', '.join(world.robots)}, got {robot!r}")
    allowed = {*ACTIONS[name], "stack", "level"} if name == "sense" else set(ACTIONS[name])
    allowed |= {"to", "color"} if name == "announce" else set()
    allowed |= {"task"}  # the epistemic task the action belongs to (e-PICO's hierarchy writes it)
    unknown = sorted(k for k in obj if k not in ("robot", "action", "args") and k not in allowed)
    if unknown:  # a misspelt field would silently be ignored
        raise ArmsError(f"{where}: unknown field {unknown[0]!r} for {name}; fields: robot, action, args, "
                        f"{', '.join(sorted(allowed))}")
    args: dict[str, Any] = {k: v for k, v in obj.items() if k not in ("robot", "action", "args")}
    pos = obj.get("args", [])
    if not isinstance(pos, list) or len(pos) > len(ACTIONS[name]):
        raise ArmsError(f"{where}: 'args' must be a list of at most {len(ACTIONS[name])} values "
                        f"({', '.join(ACTIONS[name])})")
    for key, val in zip(ACTIONS[name], pos, strict=False):
        if key in args and args[key] != val:
            raise ArmsError(f"{where}: '{key}' is given twice, as {args[key]!r} and in 'args' as {val!r}")
        args.setdefault(key, val)
    if name in ONTIC and "block" not in args:
        raise ArmsError(f"{where}: {name} needs a block")
    for key in ("level", "stack"):
        if key in args:
            val = args[key]
            if isinstance(val, str) and val.strip().lstrip("-").isdigit():
                val = int(val)  # "1" as written by some plan emitters
            if isinstance(val, bool) or not isinstance(val, (int, float)) or val != val or \
                    val in (float("inf"), float("-inf")) or int(val) != val:
                raise ArmsError(f"{where}: '{key}' must be an integer, got {json.dumps(val)[:40]}")
            args[key] = int(val)
    for key in ("task", "color"):
        if key in args and not isinstance(args[key], str):
            raise ArmsError(f"{where}: '{key}' must be a string, got {json.dumps(args[key])[:40]}")
    for key in ("block", "on", "onto"):  # block names (or "table"): strings, e.g. "red"
        if key in args and not isinstance(args[key], str):
            raise ArmsError(f"{where}: '{key}' must be a block name (a string), got {json.dumps(args[key])[:40]}")
    if name in ("place",) and "stack" not in args:
        raise ArmsError(f"{where}: place needs a 'stack'")
    _check_against_world(args, robot, name, world, where)
    return Action(robot=robot, name=name, args=MappingProxyType(args))


def _check_against_world(args: dict[str, Any], robot: str, name: str, world: World, where: str) -> None:
    """Everything an action names must exist before anything moves: blocks, stacks, levels, recipients."""
    blocks = world.blocks
    for key in ("block", "on", "onto"):
        if key in args and args[key] not in blocks and not (key != "block" and args[key] == "table"):
            raise ArmsError(f"{where}: {key} {args[key]!r} is not a block of the world (blocks: "
                            f"{', '.join(blocks) or 'none'}{'; or table' if key != 'block' else ''})")
    n_stacks = len(world.stacks[robot])
    if "stack" in args and not 0 <= args["stack"] < n_stacks:
        raise ArmsError(f"{where}: {robot} has stacks 0..{n_stacks - 1}, not stack {args['stack']}")
    if "level" in args and not 0 <= args["level"] < max(1, len(blocks)):
        raise ArmsError(f"{where}: level {args['level']} is impossible with {len(blocks)} block(s) "
                        f"(levels are 0..{max(0, len(blocks) - 1)})")
    if name == "announce":
        to = args.get("to", [])
        if not isinstance(to, list) or not all(isinstance(r, str) for r in to):
            raise ArmsError(f"{where}: 'to' must be a list of robot names, got {json.dumps(to)[:40]}")
        strangers = [r for r in to if r not in world.robots]
        if strangers:
            raise ArmsError(f"{where}: announces to {strangers[0]!r}, which is not a robot of the world "
                            f"({', '.join(world.robots)})")


def parse_plan(obj: Any, *, source: str = "<plan>") -> Plan:
    """Validate a plan object (see module docstring); errors say which field of which action."""
    if not isinstance(obj, Mapping):
        raise ArmsError(f"{source}: a plan is a JSON object with 'world' and 'actions'")
    fmt = obj.get("format", FORMAT)
    if fmt != FORMAT:
        raise ArmsError(f"{source}: unsupported format {fmt!r}; this reader knows {FORMAT!r}")
    if "world" not in obj or "actions" not in obj:
        raise ArmsError(f"{source}: a plan needs both 'world' and 'actions'")
    world = World.from_json(obj["world"], source=f"{source}: world")
    unknown = sorted(set(obj) - {"format", "world", "actions"})
    if unknown:
        raise ArmsError(f"{source}: unknown entry {unknown[0]!r}; a plan has 'format', 'world' and 'actions'")
    acts = obj["actions"]
    if not isinstance(acts, list):
        raise ArmsError(f"{source}: 'actions' must be a list")
    return Plan(world=world, actions=tuple(_action(a, i, world, source) for i, a in enumerate(acts)))


def load_plan(path: str | Path) -> Plan:
    """Read a plan file."""
    path = Path(path)
    try:
        from delkit.paths import read_input

        obj = json.loads(read_input(path, "plan file"))
    except FileNotFoundError:
        raise ArmsError(f"{path}: no such plan file") from None
    except json.JSONDecodeError as exc:
        raise ArmsError(f"{path}:{exc.lineno}:{exc.colno}: not valid JSON ({exc.msg})") from None
    except UnicodeDecodeError:
        raise ArmsError(f"{path}: not a text file; a plan is UTF-8 JSON (see arms/README.md)") from None
    except OSError as exc:  # a directory, no permission, ...
        raise ArmsError(f"{path}: cannot read the plan file: {exc.strerror}") from None
    return parse_plan(obj, source=str(path))


def apply_action(world: World, state: SymbolicState, action: Action) -> SymbolicState:
    """Symbolic effect of one action (epistemic actions leave the block places unchanged)."""
    a = action.args
    if action.name == "pick":
        return pick_effect(world, state, action.robot, a["block"], on=a.get("on"), level=a.get("level"),
                           stack=a.get("stack"))
    if action.name == "take_from_barrier":
        return pick_effect(world, state, action.robot, a["block"], from_barrier=True)
    if action.name == "place":
        return place_effect(world, state, action.robot, a["block"], onto=a.get("onto"),
                            level=a.get("level"), stack=a.get("stack"))
    if action.name == "put_on_barrier":
        return place_effect(world, state, action.robot, a["block"], on_barrier=True)
    return state


def symbolic_trace(plan: Plan) -> list[SymbolicState]:
    """States s₀, s₁, …, s_n of the plan; raises :class:`PlanError` naming the first inapplicable action."""
    states = [initial_state(plan.world)]
    for i, act in enumerate(plan.actions):
        try:
            states.append(apply_action(plan.world, states[-1], act))
        except PlanError as exc:
            raise PlanError(f"action {i} ({act}): {exc}") from None
    return states
