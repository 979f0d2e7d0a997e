"""Sensor ≡ sensing event: the side cameras' observation selects exactly the event of the planner's
``sense_table ?ag`` that holds in the true world (random layouts, both robots, with and without a block
standing in front of a stack), and a camera never reports a block that another block hides from it."""

from __future__ import annotations

from types import MappingProxyType

import mujoco
import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

pytest.importorskip("planners.hierarchy")

from arms import sensing  # noqa: E402
from arms.beliefs import BeliefState  # noqa: E402
from arms.scene import build_scene  # noqa: E402
from arms.world import World  # noqa: E402
from planners.epico import PALETTE, Layout, generate  # noqa: E402
from planners.hierarchy import epistemic_task  # noqa: E402
from planners.spaces import make_space  # noqa: E402

ROBOTS = ("robot1", "robot2")


@st.composite
def layouts(draw):
    """Random e-PICO layouts: 1–4 colours, per robot 3 stacks of 0–3 blocks (at least one block each),
    and maybe a grey block standing in front of one stack (robot, stack, height)."""
    n = draw(st.integers(1, 4))
    pal = PALETTE[:n]
    stacks, colours = {}, {}
    for r in ROBOTS:
        while True:
            sizes = [draw(st.integers(0, 3)) for _ in range(3)]
            if sum(sizes):
                break
        st_r = []
        for s, k in enumerate(sizes):
            col = []
            for lvl in range(k):
                name = f"{r[-1]}s{s}l{lvl}"
                colours[name] = draw(st.sampled_from(pal))
                col.append(name)
            st_r.append(tuple(col))
        stacks[r] = tuple(st_r)
    occ = draw(st.one_of(st.none(), st.tuples(st.sampled_from(ROBOTS), st.integers(0, 2),
                                                 st.floats(0.03, 0.09))))
    return n, Layout(MappingProxyType(stacks), MappingProxyType(colours)), occ


def _hidden(origin, face_points, box_pos, box_half) -> bool:
    """Independent oracle (slab test, numpy): every segment camera → point crosses the box."""
    for p in face_points:
        d = p - origin
        with np.errstate(divide="ignore", invalid="ignore"):
            t1 = (box_pos - box_half - origin) / d
            t2 = (box_pos + box_half - origin) / d
        lo = np.nanmax(np.minimum(t1, t2))
        hi = np.nanmin(np.maximum(t1, t2))
        if not (lo < hi and 0 < hi and lo < 1):
            return False
    return True


def _sat(pre, vals, props, agents) -> bool:
    """A propositional precondition at the one-world model of a valuation."""
    from delkit.models.kripke import KripkeModel

    w = KripkeModel.build([{p for p, v in vals.items() if v}], {a: [[0]] for a in agents}, designated=[0],
                          props=list(props), agents=list(agents))
    return w.holds(pre)


def check_layout(n, layout, occ, *, see_through=False):
    world = World.from_json(layout.to_world())
    lay = world.layout
    occluders = ()
    if occ is not None:
        r, s, h = occ
        xy = lay.stack_xy(ROBOTS.index(r), s, 3)
        occluders = ((float(xy[0] + 0.10), float(xy[1]), h),)
    scene = build_scene(world, occluders=occluders)
    model, data = scene.model, mujoco.MjData(scene.model)
    mujoco.mj_resetDataKeyframe(model, data, model.key("home").id)
    mujoco.mj_forward(model, data)
    inst = generate("alpha", n, layout=layout, symmetric=True)
    task, _, _ = epistemic_task(inst, macros=False)
    belief = BeliefState(task, make_space(task))
    for i, r in enumerate(ROBOTS):
        columns = [(f"{r} stack {s}", lay.stack_xy(i, s, 3)) for s in range(3)] + [("shared table", lay.barrier_xy())]

        def look(view, r=r, columns=columns):
            site = scene.side_camera_site(r, view)
            return [sensing.look_side(model, data, site, xy, table_z=lay.table_z, block_size=lay.block_size,
                                      column=name, view=view, see_through=see_through) for name, xy in columns]

        low = look("low")
        # (b) a camera does not see through blocks: a block the oracle finds hidden is not reported
        if occ is not None and occ[0] == r:
            g = model.geom("block/occluder0").id
            origin = data.site_xpos[scene.side_camera_site(r, "low")]
            for b in layout.stacks[r][occ[1]]:
                c = data.xpos[scene.block_body(b)]
                half = lay.block_size / 2
                face = [np.array([c[0] + half, c[1] + dy, c[2] + dz]) for dy in (-0.8 * half, 0, 0.8 * half)
                        for dz in (-0.8 * half, 0, 0.8 * half)]
                if _hidden(origin, face, data.geom_xpos[g], model.geom_size[g]):
                    assert all(b not in v.blocks for v in low), f"the low camera saw {b} through the block in front"
                    assert not low[occ[1]].complete, "a hidden block, but the view claims to be complete"
        views = low
        if not all(v.complete for v in low):
            high = look("high")
            views = [h if not v.complete else v for v, h in zip(low, high, strict=True)]
        assert all(v.complete for v in views), [v.to_json() for v in views]
        seen = {b: c for v in views for b, c in v.blocks.items()}
        obs = {f"hold_{r}_{c}": any(b in seen and seen[b] == c for st_ in layout.stacks[r] for b in st_)
               for c in PALETTE[:n]}
        # (a) the observation selects exactly one event of the planner's sensing model: the true one
        em = belief.event_model(f"sense_table_{r}")

        truth = {f"hold_{r}_{c}": layout.has(r, c) for c in PALETTE[:n]}
        picked = [e for e in em.designated if _sat(em.pre[e], obs, task.props, task.agents)]
        true_e = [e for e in em.designated if _sat(em.pre[e], truth, task.props, task.agents)]
        assert len(picked) == 1 and picked == true_e, (r, obs, truth)


_FAST = settings(max_examples=6, deadline=None, suppress_health_check=list(HealthCheck), derandomize=True)
_SLOW = settings(max_examples=220, deadline=None, suppress_health_check=list(HealthCheck), derandomize=True)


@_FAST
@given(layouts())
def test_sensor_selects_the_true_sensing_event(case):
    check_layout(*case)


@pytest.mark.slow
@_SLOW
@given(layouts())
def test_sensor_selects_the_true_sensing_event_many_layouts(case):
    check_layout(*case)


def test_covered_blocks_are_seen_and_an_occluding_block_is_not_seen_through():
    stacks = {"robot1": (("a", "b", "c"), (), ()), "robot2": (("d",), (), ())}
    layout = Layout(MappingProxyType(stacks), MappingProxyType({"a": "red", "b": "black", "c": "red", "d": "black"}))
    check_layout(2, layout, ("robot1", 0, 0.09))
    # the mutation: a camera that sees through blocks must fail the same property
    with pytest.raises(AssertionError, match="through the block in front|claims to be complete"):
        check_layout(2, layout, ("robot1", 0, 0.09), see_through=True)


def test_the_colour_is_the_rendered_one():
    stacks = {"robot1": (("a", "b"), (), ()), "robot2": (("d",), (), ())}
    world = World.from_json(Layout(MappingProxyType(stacks), MappingProxyType(
        {"a": "red", "b": "black", "d": "black"})).to_world())
    scene = build_scene(world)
    data = mujoco.MjData(scene.model)
    mujoco.mj_forward(scene.model, data)
    xy = world.layout.stack_xy(0, 0, 3)
    site = scene.side_camera_site("robot1")
    v = sensing.look_side(scene.model, data, site, xy, table_z=0.0, block_size=0.04)
    assert v.blocks == {"a": "red", "b": "black"} and v.complete  # a is covered by b and seen anyway
    scene.model.geom_rgba[scene.model.geom("block/a").id] = (0.1, 0.3, 0.9, 1.0)
    assert sensing.look_side(scene.model, data, site, xy, table_z=0.0, block_size=0.04).blocks["a"] == "blue"


def test_a_top_block_sensor_fails_the_property(monkeypatch):
    """The old palm-camera reading (only the top block of a column) does not implement sense_table."""
    orig = sensing.look_side

    def top_only(*args, **kw):
        v = orig(*args, **kw)
        top = list(v.blocks.items())[-1:]  # rays go bottom → top: the last block seen is the highest
        return sensing.ColumnView(v.column, v.view, dict(top), v.rays, v.occluded)

    monkeypatch.setattr(sensing, "look_side", top_only)
    stacks = {"robot1": (("a", "b"), (), ()), "robot2": (("d",), (), ())}
    layout = Layout(MappingProxyType(stacks), MappingProxyType({"a": "red", "b": "black", "d": "black"}))
    with pytest.raises(AssertionError):
        check_layout(2, layout, None)


# -- the mission's own observation code over layouts reached after takes and hand-overs -------------------------
def _moved(layout: Layout, moves) -> list[tuple[Layout, dict]]:
    """The layouts a sequence of moves passes through: ("put", robot) — robot puts the top block of its
    first non-empty stack on the shared table; ("take", robot, stack) — robot takes the shared block onto
    its own stack (a hand-over when robot is not the robot it came from). With each layout, the truth:
    block ↦ the robot in front of which it stands (a shared block: the one it came from)."""
    stacks = {r: [list(s) for s in layout.stacks[r]] for r in ROBOTS}
    shared: list[str] = []
    stands = {b: r for r in ROBOTS for s in stacks[r] for b in s}
    out = []

    def snap():
        lay = Layout(MappingProxyType({r: tuple(tuple(s) for s in stacks[r]) for r in ROBOTS}),
                     MappingProxyType(dict(layout.colors)), tuple(shared),
                     MappingProxyType({b: stands[b] for b in shared}))
        out.append((lay, dict(stands)))

    snap()
    for mv in moves:
        if mv[0] == "put" and not shared:
            src = next((s for s in stacks[mv[1]] if s), None)
            if src is None:
                continue
            shared.append(src.pop())
        elif mv[0] == "take" and shared and len(stacks[mv[1]][mv[2]]) < 3:
            b = shared.pop()
            stacks[mv[1]][mv[2]].append(b)
            stands[b] = mv[1]
        else:
            continue
        snap()
    return out


def _task_for(n: int):
    one = Layout(MappingProxyType({"robot1": (("x",), (), ()), "robot2": (("y",), (), ())}),
                 MappingProxyType({"x": PALETTE[0], "y": PALETTE[0]}))
    inst = generate("alpha", n, layout=one)
    task, _, _ = epistemic_task(inst, macros=False)
    return task


_TASKS: dict[int, object] = {}


def check_reached(n, layout, moves, occ=None):
    """The mission's own code — ``Mission._stand`` over the states the moves pass through, then on the final
    poses; ``Mission._look`` (side cameras, high view where the low one is blocked) and
    ``Mission.observation`` — decides exactly the looking robot's ``hold`` fluents and every ``occup_by``, each
    as the layout has it, and selects the true event of the planner's ``sense_table``."""
    from types import SimpleNamespace

    from arms.executor import Executor
    from arms.mission import Mission, StepRecord
    from arms.world import initial_state

    task = _TASKS.get(n) or _TASKS.setdefault(n, _task_for(n))
    path = _moved(layout, moves)
    final, stands = path[-1]
    world = World.from_json(final.to_world())
    occluders = ()
    if occ is not None:
        xy = world.layout.stack_xy(ROBOTS.index(occ[0]), occ[1], 3)
        occluders = ((float(xy[0] + 0.10), float(xy[1]), occ[2]),)
    m = Mission(world, "alpha", SimpleNamespace(task=task, colours=PALETTE[:n]))
    m._occlusion_pending, m.pending = [], []
    for lay, _truth in path:  # the mission's ownership update, state by state as the loop sees them
        m._stand(initial_state(World.from_json(lay.to_world())))
    ex = Executor(world, occluders=occluders)
    m._stand(m._observe_state(ex, set())[0])
    belief = BeliefState(task, make_space(task))
    colour = dict(final.colors)
    for r in ROBOTS:
        rec = StepRecord(0, 0, "look", r, f"{r}: look()", True, "", {}, 0.0, float("nan"))
        obs = m.observation(m._look(ex, r, rec), r, task.props)
        truth = {}
        for p in task.props:
            kind, rest = ("occup_by", p[9:]) if p.startswith("occup_by_") else ("hold", p[5:])
            owner, c = rest.split("_", 1)
            if kind == "occup_by":
                truth[p] = any(stands[b] == owner and colour[b] == c for b in final.shared)
            elif owner == r:
                truth[p] = any(colour[b] == c for s in final.stacks[r] for b in s) or any(
                    stands[b] == r and colour[b] == c for b in final.shared)
        assert obs == truth, (r, moves, obs, truth)
        em = belief.event_model(f"sense_table_{r}")
        sensed = {p: obs[p] for p in obs if p.startswith(f"hold_{r}_")}
        rest = {q: False for q in task.props if q not in sensed}
        picked = [e for e in em.designated if _sat(em.pre[e], sensed | rest, task.props, task.agents)]
        true_e = [e for e in em.designated
                  if _sat(em.pre[e], {p: truth[p] for p in sensed} | rest, task.props, task.agents)]
        assert len(picked) == 1 and picked == true_e, (r, sensed)


#: a hand-over and back: robot1's black block goes to robot2's table, then robot2 puts it on the shared table
HANDOVER_START = Layout(MappingProxyType({"robot1": (("a0", "a1"), (), ()), "robot2": (("b0",), (), ())}),
                        MappingProxyType({"a0": "red", "a1": "black", "b0": "red"}))
HANDOVER_MOVES = (("put", "robot1"), ("take", "robot2", 0), ("put", "robot2"))


@st.composite
def reached(draw):
    n, layout, occ = draw(layouts())
    moves = draw(st.lists(st.one_of(st.tuples(st.just("put"), st.sampled_from(ROBOTS)),
                                    st.tuples(st.just("take"), st.sampled_from(ROBOTS), st.integers(0, 2))),
                          min_size=1, max_size=5))
    return n, layout, tuple(moves), occ


def test_the_missions_observation_after_a_hand_over():
    check_reached(2, HANDOVER_START, HANDOVER_MOVES)
    check_reached(2, HANDOVER_START, HANDOVER_MOVES[:2])


@settings(max_examples=8, deadline=None, suppress_health_check=list(HealthCheck), derandomize=True)
@given(reached())
def test_the_missions_observation_is_the_truth_after_takes(case):
    n, layout, moves, occ = case
    check_reached(n, layout, moves, occ)


@pytest.mark.slow
@settings(max_examples=220, deadline=None, suppress_health_check=list(HealthCheck), derandomize=True)
@given(reached())
def test_the_missions_observation_is_the_truth_after_takes_many_layouts(case):
    n, layout, moves, occ = case
    check_reached(n, layout, moves, occ)
