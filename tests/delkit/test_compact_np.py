"""The numpy refinement (delkit.backends.compact_np) against the compact backend's Python one: the same canonical
output on any input — random models given as successor lists, and the products of random mA* updates."""

from __future__ import annotations

from hypothesis import given, settings
from hypothesis import strategies as st

import delkit.backends.compact as compact
from delkit.backends.compact import CompactEngine, _refine
from delkit.backends.compact_np import refine
from delkit.testing import event_models, kripke_models, refinement_inputs


@settings(max_examples=300, deadline=None)
@given(refinement_inputs())
def test_numpy_refinement_equals_python(model) -> None:
    val, dist, cls, points = model
    assert refine(val, dist, cls, points) == _refine(val, dist, cls, points)


def test_many_blocks_masks_beyond_63_bits() -> None:
    """A chain of 200 worlds (each world's successor the next one, valuations alike): 200 blocks, the
    masks are Python ints of up to 200 bits."""
    n = 200
    val = [0] * n
    dist = [[[w + 1] for w in range(n - 1)] + [[]]]
    cls = [list(range(n))]
    out = refine(val, dist, cls, [0])
    assert out == _refine(val, dist, cls, [0])
    assert len(out[1]) == n and max(out[2][0]).bit_length() > 63


@settings(max_examples=60, deadline=None)
@given(data=st.data())
def test_numpy_refinement_in_the_engine(data) -> None:
    """With the threshold at 0 every product is refined by numpy: the engine's results are those of the
    Python refinement."""
    P, A = ("p", "q"), ("a", "b", "c")
    m = data.draw(kripke_models(P, A, 5, frame=data.draw(st.sampled_from(["S5", "KD45", "K"])), designated="some"))
    em = data.draw(event_models(P, A, 3, frame=data.draw(st.sampled_from(["mA*", "K"]))))
    old = compact.NP_REFINE_MIN
    try:
        compact.NP_REFINE_MIN = 0
        e1 = CompactEngine(P, A)
        r1 = e1.apply(e1.from_kripke(m), em)
    finally:
        compact.NP_REFINE_MIN = old
    e2 = CompactEngine(P, A)
    r2 = e2.apply(e2.from_kripke(m), em)
    assert (r1 is None) == (r2 is None)
    if r1 is not None:
        assert (r1.val, r1.masks, r1.points, r1.key) == (r2.val, r2.masks, r2.points, r2.key)
