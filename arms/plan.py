"""The primitive-plan format the arms execute (``delkit.arms.plan/1``): a view of :mod:`planners.primitive`,
where the format and its symbolic block-world trace live (they are planning concepts; the arms read them)."""

from planners.primitive import *  # noqa: F403
from planners.primitive import ACTIONS, FORMAT, Action, Plan, apply_action, load_plan, parse_plan, symbolic_trace  # noqa: F401
