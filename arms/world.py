"""The block world the arms execute in: robots, stacks, blocks, the shared table (a view of
:mod:`planners.blocks`, where the world description lives, because the planners build and check it without
the physics)."""

from planners.blocks import *  # noqa: F403
from planners.blocks import (  # noqa: F401
    COLORS,
    ArmsError,
    Layout,
    Location,
    PlanError,
    SymbolicState,
    World,
    initial_state,
    pick_effect,
    place_effect,
    replace_layout,
    rgba_of,
)
