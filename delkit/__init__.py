"""delkit: dynamic epistemic logic for multi-agent robotics.

The core names are re-exported here::

    from delkit import parse, KripkeModel, product_update, public_announcement, contract, bisimilar
"""

from delkit.bisim import bisimilar, canonical_hash, contract
from delkit.compose import compose, compose_all
from delkit.errors import DelkitError, ModelError, ParseError, UnknownSymbolError
from delkit.events import (
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
from delkit.formula import (
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
from delkit.kripke import KripkeModel
from delkit.relation import Relation
from delkit.update import applicable, product_update, update_sequence

__version__ = "0.1.0"

__all__ = [
    "BOT", "TOP", "And", "Announce", "Bot", "C", "D", "DelkitError", "E", "EventModel", "Formula", "Iff",
    "Implies", "K", "KripkeModel", "Kw", "ModelError", "Not", "Or", "ParseError", "Prop", "Relation", "Top",
    "UnknownSymbolError", "Update", "action", "announcement", "applicable", "bisimilar", "canonical_hash",
    "compose", "compose_all", "contract", "ontic", "parse", "private_announcement", "product_update",
    "public_announcement", "semi_private_announcement", "sensing", "show", "skip", "update_sequence",
]
