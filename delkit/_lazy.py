"""A module object that imports its target on first attribute access (keeps start-up fast).

``sp = lazy_module("scipy.sparse")`` at the top of a module costs nothing until ``sp.csr_matrix`` is used,
so that commands that never touch scipy (``delkit plan``, ``delkit check``) do not pay its import (~0.1 s).
"""

from __future__ import annotations

import importlib
from types import ModuleType

TYPE_CHECKING = False  # typing.TYPE_CHECKING without importing typing (start-up: delkit._records)
if TYPE_CHECKING:
    from typing import Any

__all__ = ["lazy_module"]


class _LazyModule:
    __slots__ = ("_name", "_mod")

    def __init__(self, name: str) -> None:
        self._name = name
        self._mod: ModuleType | None = None

    def __getattr__(self, attr: str) -> Any:
        mod = self._mod
        if mod is None:
            mod = importlib.import_module(self._name)
            self._mod = mod
        return getattr(mod, attr)

    def __repr__(self) -> str:
        return f"<lazy module {self._name!r}{' (loaded)' if self._mod is not None else ''}>"


def lazy_module(name: str) -> Any:
    """A stand-in for ``import name`` that imports ``name`` when an attribute is first read."""
    return _LazyModule(name)
