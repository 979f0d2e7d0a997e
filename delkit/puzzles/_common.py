"""Helpers shared by the puzzles: binary encodings of finite values and "knows which" formulas."""

from __future__ import annotations

from collections.abc import Iterable, Sequence

import numpy as np

from delkit.logic.formula import Formula, Kw, Prop, conj

__all__ = ["bit_props", "encode_bits", "knows_which", "value_of"]


def bit_props(name: str, values: Iterable[int]) -> tuple[str, ...]:
    """Proposition names ``name0, name1, …`` for the binary digits of the largest of ``values``."""
    width = max(1, int(max(values)).bit_length())
    return tuple(f"{name}{j}" for j in range(width))


def encode_bits(values: np.ndarray, width: int) -> np.ndarray:
    """Boolean matrix len(values) × width: column j is bit j of each value."""
    v = np.asarray(values, dtype=np.int64)
    return ((v[:, None] >> np.arange(width, dtype=np.int64)[None, :]) & 1).astype(bool)


def knows_which(agent: str, props: Sequence[str]) -> Formula:
    """⋀_p Kw_agent p: the agent knows the truth value of each of ``props`` (so it knows the encoded value)."""
    return conj(Kw(agent, Prop(p)) for p in props)


def value_of(valuation_rows: np.ndarray) -> np.ndarray:
    """Inverse of :func:`encode_bits`: the integer each boolean row encodes."""
    rows = np.asarray(valuation_rows, dtype=np.int64)
    return (rows << np.arange(rows.shape[-1], dtype=np.int64)).sum(axis=-1)
