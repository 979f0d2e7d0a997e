"""Seeded sample models for the viewer's tests and benchmark (e.g. the 1,000-world page)."""

from __future__ import annotations

__all__ = ["random_s5"]


def random_s5(n_worlds: int = 1000, n_props: int = 10, agents: tuple[str, ...] = ("a", "b", "c"),
              class_size: int = 5, seed: int = 0):
    """An S5 model: random valuations, each agent's worlds cut into random classes of ``class_size``."""
    import numpy as np

    from delkit.models.kripke import KripkeModel

    rng = np.random.default_rng(seed)
    worlds = [{f"p{i}" for i in range(n_props) if rng.random() < 0.5} for _ in range(n_worlds)]
    rel = {}
    for a in agents:
        order = rng.permutation(n_worlds)
        rel[a] = [[int(w) for w in order[i:i + class_size]] for i in range(0, n_worlds, class_size)]
    return KripkeModel.build(worlds, rel, designated=[0])
