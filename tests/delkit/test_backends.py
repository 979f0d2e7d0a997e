"""Differential tests of delkit's backends in one place: numpy (KripkeModel) ≡ compact (bit sets) ≡ BDDs.

Each property draws random models (S5, KD45, K; single- and multi-pointed), formulas and event models and
asks every backend the same question: truth of a formula, bisimilarity (canonical keys), and the product
update followed by contraction. The numpy backend is the reference.
"""

from __future__ import annotations

from hypothesis import given, settings
from hypothesis import strategies as st

from delkit.bisim import bisimilar, contract
from delkit.compact import CompactEngine
from delkit.formula import D, subformulas
from delkit.testing import event_models, formulas, kripke_models
from delkit.update import product_update

P, A = ("p", "q"), ("a", "b")
ENGINE = CompactEngine(P, A)
FRAMES = st.sampled_from(["S5", "KD45", "K"])


def _no_group_d(f) -> bool:
    """D of a group of ≥ 2 agents is not bisimulation-invariant: contracted backends may not preserve it."""
    return not any(isinstance(g, D) and len(g.group) > 1 for g in subformulas(f))


def _models(frame: str, designated: str = "some", max_worlds: int = 5):
    return kripke_models(P, A, max_worlds, frame=frame, designated=designated)


@settings(max_examples=120, deadline=None)
@given(data=st.data(), frame=FRAMES, f=formulas(P, A, 3, allow_dynamic=True).filter(_no_group_d))
def test_truth_compact_equals_numpy(data, frame, f) -> None:
    """φ holds in every designated world: the same answer on both backends (after the compact backend's
    contraction, so this also checks that contraction preserves every formula of the language but group D)."""
    m = data.draw(_models(frame))
    s = ENGINE.from_kripke(m)
    assert ENGINE.holds(s, f) == m.holds(f)
    # per world, through the round trip to an explicit model
    back = ENGINE.to_kripke(s)
    assert bisimilar(back, m)


@settings(max_examples=100, deadline=None)
@given(data=st.data(), frame=FRAMES)
def test_key_equal_iff_bisimilar(data, frame) -> None:
    m1 = data.draw(_models(frame, max_worlds=4))
    m2 = data.draw(_models(frame, max_worlds=4))
    k1, k2 = ENGINE.from_kripke(m1).key, ENGINE.from_kripke(m2).key
    assert (k1 == k2) == bisimilar(m1, m2)
    assert k1 == ENGINE.from_kripke(contract(m1)).key


@settings(max_examples=150, deadline=None)
@given(data=st.data(), frame=FRAMES, eframe=st.sampled_from(["S5", "KD45", "K", "mA*"]))
def test_update_compact_equals_numpy(data, frame, eframe) -> None:
    """apply(s, E) ≅ contract(M ⊗ E) for general event models (several designated events, any relations),
    on multi-pointed models; None exactly when some designated world has no designated event possible."""
    m = data.draw(_models(frame, max_worlds=4))
    em = data.draw(event_models(P, A, 3, frame=eframe))
    s = ENGINE.from_kripke(m)
    new = ENGINE.apply(s, em)
    ref = product_update(m, em)
    covered = {int(w) for w in m.designated if any(m.check(em.pre[e])[int(w)] for e in em.designated)}
    if covered != {int(w) for w in m.designated}:
        assert new is None
        return
    assert new is not None
    assert bisimilar(ENGINE.to_kripke(new), ref)
    assert new.key == ENGINE.from_kripke(ref).key
    f = data.draw(formulas(P, A, 2).filter(_no_group_d))
    assert ENGINE.holds(new, f) == ref.holds(f)
    assert sorted(ENGINE.inconsistent(new)) == sorted({ag for ag, _ in ref.inconsistent_agents()})


@settings(max_examples=60, deadline=None)
@given(data=st.data())
def test_truth_compact_equals_symbolic_on_s5(data) -> None:
    """The third backend: BDD knowledge structures agree with the compact one on S5 models."""
    from delkit.symbolic import from_kripke

    m = data.draw(_models("S5", designated="one", max_worlds=4))
    f = data.draw(formulas(P, A, 2, allow_common=True).filter(_no_group_d))
    ks, states = from_kripke(m)
    assert ks.truth(f, states[m.designated[0]]) == ENGINE.holds(ENGINE.from_kripke(m), f)
