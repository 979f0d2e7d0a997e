"""The compact space's successors against the reference product update, state by state.

``CompactSpace.successors`` answers some actions without building the product: a sensing or announcement
that cannot change the state (the loop test), a commuting action whose successor is known from
transitions seen before (s·a = p·b·a ≅ p·a·b), and the ε-copy product of :mod:`delkit.backends.compact`. Every
successor it yields must have the key of ``contract(M ⊗ E)`` built by ``delkit.models.update`` (the numpy
reference) — checked here on the states a BFS expands, once the space's transition memory is filled.
"""

from __future__ import annotations

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from delkit.backends.compact import from_kripke
from delkit.models.bisimulation import contract
from planners.lang import load_task, shared_benchmarks
from planners.spaces import CompactSpace
from planners.task import apply_action

BENCH = shared_benchmarks()
MASTAR = None if BENCH is None else BENCH / "mastar"
# instances with oblivious announcements (Grapevine), sensing with partial observers (CB, Coin), ontic
# actions with oblivious agents (SC, CC)
FILES = ["Grapevine/Grapevine_3/Grapevine_3__pl_4.txt", "Grapevine/Grapevine_4/Grapevine_4__pl_4.txt",
         "Coin_In_The_Box/Coin_in_the_Box__pl_5.txt", "CB_simple/CB_oblivious__pl_6.txt",
         "SC/SC_4_2/SC_4_2__pl_8.txt", "CC/CC_2_2_3/CC_2_2_3__pl_8.txt"]
_TASKS: dict[str, object] = {}


def _task(name: str):
    if name not in _TASKS:
        _TASKS[name] = load_task(MASTAR / name)
    return _TASKS[name]


def reference_key(space: CompactSpace, s, name: str):
    """The key of the successor of ``s`` by ``name`` on the numpy reference (None: not applicable or a
    dead end: some agent believes ⊥ at a designated world)."""
    m = space.to_kripke(s)
    new = apply_action(space.task, space.task.action(name), m)
    if new is None or not new.designated:
        return None
    if not space.allow_inconsistent and new.inconsistent_agents():
        return None
    return from_kripke(contract(new)).key


def check_expansions(space: CompactSpace, skip: int, check: int) -> int:
    """BFS order: expand ``skip`` states (filling the transition memory), then check every successor of
    the next ``check`` states against :func:`reference_key`, and that no applicable action is missed.
    Returns the number of successors checked."""
    s0, k0 = space.initial()
    seen = {k0}
    frontier = [s0]
    done = checked = 0
    while frontier and done < skip + check:
        nxt = []
        for s in frontier:
            if done >= skip + check:
                break
            got = {}
            for name, new, key in space.successors(s):
                got[name] = key
                assert key == new.key
                if key not in seen:
                    seen.add(key)
                    nxt.append(new)
            if done >= skip:
                for act in space.task.actions:
                    ref = reference_key(space, s, act.name)
                    assert got.get(act.name) == ref, (act.name, done)
                    checked += ref is not None
            done += 1
        frontier = nxt
    return checked


@pytest.mark.skipif(BENCH is None, reason="../shared/benchmarks is not available")
@settings(max_examples=12, deadline=None)
@given(idx=st.integers(0, len(FILES) - 1), skip=st.integers(0, 60))
def test_successors_equal_the_reference_update(idx: int, skip: int) -> None:
    space = CompactSpace(_task(FILES[idx]))
    assert check_expansions(space, skip, 2) >= 0


@pytest.mark.skipif(BENCH is None, reason="../shared/benchmarks is not available")
def test_grapevine_shortcuts_fire_and_are_right() -> None:
    """On Grapevine_4 many successors come without a product (announcements the room's agents already
    know are loops, announcements in the two rooms commute) and every one is the reference's."""
    space = CompactSpace(_task(FILES[1]))
    engine = space.engine
    count = {"apply": 0, "yield": 0}
    apply, successors = engine.apply_compiled, space.successors

    def counting_apply(s, comp):
        count["apply"] += 1
        return apply(s, comp)

    def counting_successors(s):
        for out in successors(s):
            count["yield"] += 1
            yield out

    engine.apply_compiled = counting_apply  # type: ignore[method-assign]
    space.successors = counting_successors  # type: ignore[method-assign]
    assert check_expansions(space, 30, 3) > 0
    assert count["apply"] < 0.8 * count["yield"], count


def test_commuting_action_not_executable_after_the_other_is_not_predicted() -> None:
    """tell_q (executable while a does not know p) and tell_p commute as event models, but after tell_p
    a knows p: s·tell_p·tell_q does not exist although s·tell_q·tell_p does — the prediction from the
    known transitions must check tell_q's executability in s·tell_p."""
    from planners.lang.mastar import parse_mastar

    task = parse_mastar("""fluent p, q; action tell_q, tell_p; agent a, b;
        executable tell_q if -B(a, p); tell_q announces q; a observes tell_q;
        tell_p announces p; a observes tell_p;
        initially p, q; goal B(b, q);""", "commute.txt")
    space = CompactSpace(task)
    assert "tell_q" in space._commute
    assert check_expansions(space, 0, 4) > 0
