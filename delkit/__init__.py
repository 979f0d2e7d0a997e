"""delkit: dynamic epistemic logic for multi-agent robotics.

The core names are re-exported here::

    from delkit import parse, KripkeModel, product_update, public_announcement, contract, bisimilar

The re-exports are resolved lazily (PEP 562): ``import delkit`` (and so every ``delkit`` command) does not
import numpy until a name that needs it is used.
"""

from __future__ import annotations

import importlib

TYPE_CHECKING = False  # typing.TYPE_CHECKING without importing typing (start-up: delkit._records)
if TYPE_CHECKING:
    from typing import Any

__version__ = "0.1.0"

_EXPORTS: dict[str, tuple[str, ...]] = {
    "delkit.models.bisimulation": ("bisimilar", "canonical_hash", "contract"),
    "delkit.models.compose": ("compose", "compose_all"),
    "delkit.errors": ("DelkitError", "ModelError", "ParseError", "UnknownSymbolError"),
    "delkit.models.events": ("EventModel", "action", "announcement", "ontic", "private_announcement",
                      "public_announcement", "semi_private_announcement", "sensing", "skip"),
    "delkit.logic.formula": ("BOT", "TOP", "And", "Announce", "Bot", "C", "D", "E", "Formula", "Iff", "Implies", "K",
                       "Kw", "Not", "Or", "Prop", "Top", "Update", "parse", "show"),
    "delkit.models.kripke": ("KripkeModel",),
    "delkit.models.relation": ("Relation",),
    "delkit.models.update": ("applicable", "product_update", "update_sequence"),
}
_WHERE = {name: mod for mod, names in _EXPORTS.items() for name in names}

__all__ = sorted(_WHERE)


def __getattr__(name: str) -> Any:
    mod = _WHERE.get(name)
    if mod is None:
        raise AttributeError(f"module 'delkit' has no attribute {name!r}")
    value = getattr(importlib.import_module(mod), name)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(__all__))


if TYPE_CHECKING:  # static analysers see the eager imports
    from delkit.errors import DelkitError, ModelError, ParseError, UnknownSymbolError  # noqa: F401
    from delkit.logic.formula import (  # noqa: F401
        BOT,
        TOP,
        And,
        Announce,
        Bot,
        C,
        D,
        E,
        Formula,
        Iff,
        Implies,
        K,
        Kw,
        Not,
        Or,
        Prop,
        Top,
        Update,
        parse,
        show,
    )
    from delkit.models.bisimulation import bisimilar, canonical_hash, contract  # noqa: F401
    from delkit.models.compose import compose, compose_all  # noqa: F401
    from delkit.models.events import (  # noqa: F401
        EventModel,
        action,
        announcement,
        ontic,
        private_announcement,
        public_announcement,
        semi_private_announcement,
        sensing,
        skip,
    )
    from delkit.models.kripke import KripkeModel  # noqa: F401
    from delkit.models.relation import Relation  # noqa: F401
    from delkit.models.update import applicable, product_update, update_sequence  # noqa: F401
